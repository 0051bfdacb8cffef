// dcad::api: each entry point dispatches once and maps what the twins throw onto the three error channels.
#include "dcad/api.hpp"

#include "dcad/fast/solve.hpp"
#include "dcad/reference/nonlinear/pointwise.hpp"
#include "formulas.hpp"
#include "guarded.hpp"

#include <cmath>

namespace dcad::api {

int exit_code(const std::exception& e) noexcept {
  if (dynamic_cast<const UsageError*>(&e)) return 2;
  if (dynamic_cast<const std::invalid_argument*>(&e)) return 1;  // io::InputError, a precondition on the input
  return 4;
}

Backend backend_named(const std::string& name) {
  if (name == "certified") return Backend::certified;
  if (name == "reference") return Backend::reference;
  if (name == "fast") return Backend::fast;
  throw UsageError("backend: expected reference, fast or certified, found \"" + name + "\"");
}

Parts parts_named(const std::string& list) {
  if (list == "all") return {};
  Parts p = Parts::none();
  if (list == "none") return p;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = list.find(',', start);
    const std::string w = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (w == "final")
      p.final_constraints = true;
    else if (w == "reduced")
      p.reduced = true;
    else if (w == "classes")
      p.classes = true;
    else if (w == "adapted")
      p.adapted = true;
    else
      throw UsageError(
          "--with: expected all, none or a comma-separated list of final, reduced, classes, adapted; found '" + w +
          "'");
    if (comma == std::string::npos) return p;
    start = comma + 1;
  }
}

namespace {

/// The certified tier where no exact tier can run (the expression form at an irrational point):
/// double precision, not certified, and the note says why.
certified::Solution not_certified(const io::Problem& p, const reference::NotExactHere& e) {
  const fast::Solution f = p.form() == io::Form::implicit ? fast::solve_implicit(p.expression())
                           : p.form() == io::Form::dae    ? fast::solve(p)
                                                          : fast::solve_expression(p.expression());
  certified::Solution s = map_numbers<certified::Number>(f, [](double x) {
    return certified::Number{false, reference::Rational(0), x, HUGE_VAL};
  });  // no enclosure
  s.backend = Backend::certified;
  s.exact = false;
  s.certified = unknown;
  s.note = std::string("the exact route cannot run here (") + e.what() + "): double precision" +
           (f.note.empty() ? "" : "; " + f.note);
  return s;
}

}  // namespace

namespace {

/// The expression form's formulas on a chart, where the result is consistent and regular; for the
/// certified tier where its point is not the given values (a rational place, or double precision), the
/// values at the given point in balls on that chart.
void attach_formulas(const io::Problem& p, Backend backend, Solved& s) {
  std::visit(
      [&](auto& r) {
        if (!r.pointwise || !r.consistent || !r.pointwise->regular) return;
        auto f = chart_for(p.expression(), r.dims(), r.solution_rank);
        if (auto* ok = std::get_if<Charted>(&f)) {
          r.pointwise->formulas = formulas_of(p.expression(), ok->chart);
          const bool elsewhere = !r.pointwise->place.empty() || !r.exact;
          if (backend == Backend::certified && p.expression().has_initial && elsewhere)
            r.pointwise->at_given =
                at_given(p.expression(), *ok, !r.pointwise->place.empty(), r.certified.yes() || ok->fast_certain);
        } else {
          r.pointwise->formulas_why = std::get<std::string>(f);
        }
      },
      s);
}

Solved solve_form(const io::Problem& p, Backend backend, const Parts& parts) {
  return guarded(p, [&]() -> Solved {
    switch (backend) {
      case Backend::reference: return reference::solve(p, parts);
      case Backend::fast: return fast::solve(p, parts);
      case Backend::certified: try { return certified::solve(p, parts);
        } catch (const reference::NotExactHere& e) {
          return not_certified(p, e);
        }
    }
    throw InternalError("solve: unknown backend");
  });
}

}  // namespace

Solved solve(const io::Problem& p, Backend backend, const Parts& parts) {
  Solved s = solve_form(p, backend, parts);
  std::visit(
      [&](const auto& r) {  // a tower that cannot be one is dcad's bug: never an answer (issue 51)
        if (const std::optional<std::string> why = r.broken_invariant())
          throw InternalError("solve: the " + std::string(backend_name(r.backend)) +
                              " backend's answer breaks a tower's invariant: " + *why + "; please report it");
      },
      s);
  if (p.form() == io::Form::expression)
    guarded(p, [&]() {
      attach_formulas(p, backend, s);
      return 0;
    });
  return s;
}

io::Printed printed(const Solved& s) {
  return std::visit([](const auto& x) { return io::printed(x); }, s);
}

}  // namespace dcad::api
