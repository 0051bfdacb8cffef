// The expression form's pipeline around the pointwise CAD (reference/nonlinear/pointwise.hpp): where it starts,
// the check that given values lie on M_c, and its result as a Solution — written once over the number
// (the exact route here; the double route, the fast backend's dcad/fast/pointwise.hpp, uses the same).
#pragma once

#include "dcad/io/lagrangian_case.hpp"
#include "dcad/reference/nonlinear/pointwise.hpp"
#include "dcad/solution.hpp"

#include <functional>
#include <string>
#include <vector>

namespace dcad::reference::pipeline {

/// The starting values of (q, v, t) (LagrangianSystem's indices): the given ones (`fixed`), the others
/// 0; without `initial`, a fixed pseudo-random point of small rationals (a generic point, the same on
/// every run; `seed` picks another where that one is singular), t = 0.
constexpr int kStartSeeds = 4;
inline std::vector<Rational> start_point(const io::LagrangianCase& c, std::vector<bool>& fixed, int seed = 0) {
  const std::size_t w = 2 * c.system.n + 1;
  std::vector<Rational> x(w, 0);
  fixed.assign(w, false);
  for (std::size_t i = 0; i < w; ++i) {
    if (c.initial[i]) {
      x[i] = *c.initial[i];
      fixed[i] = true;
    } else if (!c.has_initial && i < 2 * c.system.n) {
      x[i] = Rational(static_cast<long>((i * 7 + 3 + 5 * static_cast<std::size_t>(seed)) % 11) - 5,
                      static_cast<long>(3 + (i + static_cast<std::size_t>(seed)) % 4));
    }
  }
  return x;
}

/// Given values must hold at the final point: a given value that the CAD had to change is not on M_c
/// (io::InputError naming it).  `text` prints a found value.
template <class T>
void check_given(const PointwiseResult<T>& r, const io::LagrangianCase& c,
                 const std::function<bool(const T&, const Rational&)>& same,
                 const std::function<std::string(const T&)>& text) {
  const std::vector<std::string> st = c.system.state_names();
  const std::size_t n = c.system.n;
  const auto bad = [&](std::size_t idx, const Rational& given, const T& found) {
    throw io::InputError(c.file + ": /initial/" + st[idx] + ": expected a value on M_c (the constraints give " +
                         st[idx] + " = " + text(found) + " with the other given values), found " + given.str());
  };
  if (!r.consistent || r.point.size() != 3 * n) return;  // no point of M_c to hold them against
  for (std::size_t i = 0; i < 2 * n; ++i)
    if (c.initial[i] && !same(r.point[i], *c.initial[i])) bad(i, *c.initial[i], r.point[i]);
  for (std::size_t i = 0; i < n; ++i)
    if (c.initial_p[i] && !same(r.point[2 * n + i], *c.initial_p[i]))
      bad(2 * n + i, *c.initial_p[i], r.point[2 * n + i]);
}

/// The pointwise algorithm's result at the point: the point, a velocity and the gauge, each step's
/// constraints (tangent equations at the point, solved for a coordinate) and pivots, from r.levels[skip]
/// on (the implicit form skips its M_0), so that levels[k] describes M_{k+1}.
template <class T>
Pointwise<T> pointwise_part(const PointwiseResult<T>& r, const io::LagrangianCase& c, const std::string& route,
                            std::size_t skip) {
  Pointwise<T> p;
  p.route = route;
  p.regular = r.regular;
  p.why = r.why;
  if (c.system.has_time) p.time_name = c.system.time_name;
  p.time = r.time;
  p.point = r.point;
  p.velocity = r.velocity;
  p.gauge = r.gauge;
  const std::vector<std::string> names = c.system.variable_names();
  for (std::size_t k = skip; k < r.levels.size(); ++k) {
    const PointwiseLevel<T>& l = r.levels[k];
    typename Pointwise<T>::Step step;
    step.dim = l.dim;
    for (const PointwiseConstraint<T>& con : l.added) {
      typename Pointwise<T>::Tangent t;
      t.solved_for = names[con.solved_for];
      for (const auto& [j, g] : con.gradient) t.terms.emplace_back(names[j], g);
      t.rhs = con.rhs;
      step.constraints.push_back(t);
    }
    for (const PointwisePivot<T>& pv : l.pivots) step.pivots.push_back({pv.row, pv.column, pv.value});
    p.levels.push_back(step);
  }
  p.order = r.order;
  p.checked_order = r.checked_order;
  p.moves = static_cast<long>(r.moves);
  return p;
}

/// The pointwise CAD's result as a Solution: dims, the tower's constraints (M_1 as formulas, the later
/// ones as tangent equations at the point), the point, a velocity and the gauge.
template <class T>
dcad::Solution<T> pointwise_solution(const PointwiseResult<T>& r, const io::LagrangianCase& c,
                                     const std::string& route) {
  dcad::Solution<T> out;
  out.file = c.file;
  out.name = c.name;
  out.variables = c.system.state_names();
  for (long d : r.dims) out.tower.push_back({d, {}});
  out.steps = static_cast<long>(r.steps);
  out.consistent = r.consistent;
  if (r.consistent && r.regular) out.solution_rank = static_cast<long>(r.solution_rank);
  Pointwise<T> p = pointwise_part(r, c, route, 0);
  {  // M_1 = {p = ∂L/∂v, a·v + b = 0} as formulas (symbolic derivatives of L)
    const std::vector<std::string> names = c.system.variable_names();
    const LagrangianDerivatives d = derivatives(c.system);
    const std::vector<std::string> st = c.system.state_names();
    for (std::size_t i = 0; i < c.system.n; ++i)
      p.first_constraints.push_back(st[2 * c.system.n + i] + " = " + expr::to_text(d.dl_dv[i], names));
    for (const auto& k : c.system.constraints) p.first_constraints.push_back(expr::to_text(k, names) + " = 0");
  }
  out.pointwise = p;
  return out;
}

/// io::InputError for what the pointwise CAD throws about the case's point, as the CLI reports it
/// (NotExactHere passes through: whether it is bad input depends on the backend).
template <class F>
auto pointwise_input_errors(const io::LagrangianCase& c, F f) {
  try {
    return f();
  } catch (const NotExactHere&) {  // the caller's (reference: bad input; certified: no exact tier here)
    throw;
  } catch (const PointwiseNoPoint& e) {
    if (!c.has_initial)  // the file gave no point: dcad's default start is not the user's input
      throw io::InputError(
          c.file + (c.system.implicit ? ": /implicit" : ": /lagrangian") +
          ": expected a system whose M_c dcad reaches from its default point (no `initial` given), found " + e.what() +
          "; give `initial` values near M_c");
    throw io::InputError(c.file + ": /initial: expected values that extend to a point of M_c, found " + e.what());
  } catch (const std::range_error&
               e) {  // the double route's values overflowed (its message names the formula and the point)
    throw io::InputError(c.file + ": " + e.what());
  } catch (const std::domain_error& e) {
    throw io::InputError(
        c.file + ": /initial: expected a point where the formulas are defined and differentiable, found " + e.what());
  } catch (const std::length_error& e) {
    throw io::InputError(c.file + (c.system.implicit ? ": /implicit" : ": /lagrangian") +
                         "/coordinates: expected a system whose tower fits in jets of at most 200000 monomials (and "
                         "20000000 products), found " +
                         std::to_string(c.system.n) + " coordinates: " + e.what());
  }
}

/// The exact route (Rational) at the case's point: NotExactHere where a formula is irrational there.
/// Without `initial`, dcad's default point is its own choice: where the exact route cannot run there,
/// it runs at a rational place near it (exact_place.hpp; `place` in the result says where).
dcad::Solution<Rational> solve_pointwise_exact(const io::LagrangianCase& c);

/// The reference backend's route: as solve_pointwise_exact, and where the given values allow no
/// exact run (an angle whose sine is irrational; positions that miss a holonomic constraint by their
/// rounding), at a rational place within 1e-6 (relative) of every given value, stated in `place` and
/// the note.  Given values further from every rational place are refused as before.
dcad::Solution<Rational> solve_pointwise_exact_near(const io::LagrangianCase& c);

}  // namespace dcad::reference::pipeline
