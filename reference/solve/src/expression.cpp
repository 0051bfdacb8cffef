// The expression form by the exact pointwise CAD (the one translation unit that instantiates
// reference/nonlinear/pointwise.hpp on mpq_rational).
#include "dcad/reference/nonlinear/calculus.hpp"
#include "dcad/reference/nonlinear/ide_formulas.hpp"
#include "dcad/reference/nonlinear/polynomial.hpp"
#include "dcad/reference/pipeline/exact_place.hpp"
#include "dcad/reference/pipeline/implicit.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"

#include <cmath>

#include <exception>
#include <functional>
#include <sstream>
#include <unordered_map>

namespace dcad::reference::pipeline {

namespace {

PointwiseResult<Rational> run(const LagrangianSystem& s, const std::vector<Rational>& start,
                              const std::vector<bool>& fixed) {
  ExactDecisions<Rational> decide;
  return pointwise_cad<Rational>(s, start, fixed, decide, [](const Rational& q) { return q; });
}

/// The CAD at `start`, or, where the exact route cannot run there (an irrational value of a formula,
/// given values that miss M_c by their rounding), at a rational place near it (exact_place.hpp).
/// The first failure is what is thrown if no place is found; `placed` says where it ran.
using Runner = std::function<PointwiseResult<Rational>(const LagrangianSystem&, const std::vector<Rational>&,
                                                       const std::vector<bool>&)>;

PointwiseResult<Rational> run_or_place(const io::LagrangianCase& c, const std::vector<Rational>& start,
                                       const std::vector<bool>& fixed, bool given, std::optional<ExactPlace>& placed,
                                       const Runner& run = pipeline::run) {
  std::exception_ptr first;
  std::string first_what;
  try {
    return run(c.system, start, fixed);
  } catch (const NotExactHere& e) {
    first = std::current_exception();
    first_what = e.what();
  } catch (const PointwiseNoPoint& e) {
    first = std::current_exception();
    first_what = e.what();
  }
  std::string why;
  std::optional<ExactPlace> pl = exact_place(c, start, given, why);
  const auto fail = [&](const std::string& reason) {
    if (reason.empty()) std::rethrow_exception(first);
    try {
      std::rethrow_exception(first);
    } catch (const NotExactHere&) {
      throw NotExactHere(first_what + "; no rational place near it: " + reason);
    } catch (const PointwiseNoPoint&) {
      throw PointwiseNoPoint(first_what + "; no rational place near it: " + reason);
    }
  };
  if (!pl) fail(why);
  try {
    PointwiseResult<Rational> r;
    try {
      r = run(pl->system, pl->start, pl->fixed);
    } catch (const PointwiseNoPoint&) {  // the given velocities typed short: free them too
      if (pl->loosen.empty()) throw;
      for (std::size_t i : pl->loosen) pl->fixed[i] = false;
      r = run(pl->system, pl->start, pl->fixed);
    }
    placed = std::move(pl);
    return r;
  } catch (const NotExactHere& e) {
    fail(pl->not_exact.empty() ? std::string(e.what()) : pl->not_exact);
  } catch (const PointwiseNoPoint& e) {
    fail(e.what());
  }
  throw std::logic_error("run_or_place: unreachable");
}

std::string approx(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

/// The place as lines of the result; given values the CAD moved further than their rounding are not
/// near (false: the caller reports the given values as off M_c).
bool describe_place(const ExactPlace& pl, const PointwiseResult<Rational>& r, const io::LagrangianCase& c,
                    Pointwise<Rational>& p) {
  const std::vector<std::string> st = c.system.state_names();
  const std::size_t n = c.system.n;
  const auto near = [](const Rational& given, double found) {
    const double g = given.convert_to<double>();
    return std::abs(found - g) <= 1e-6 * std::max(1.0, std::abs(g));
  };
  bool ok = true;
  for (const PlacedAngle& g : pl.angles) {
    const double phi =
        2 * std::atan(g.tan_half.convert_to<double>()) + 2 * std::acos(-1.0) * static_cast<double>(g.turns);
    const std::string at =
        "2*atan(" + g.tan_half.str() + ")" +
        (g.turns == 0 ? "" : (g.turns > 0 ? " + " : " - ") + std::to_string(2 * std::labs(g.turns)) + "*pi");
    p.point_text.emplace_back(g.q, at);
    std::string line = st[g.q] + " = " + at + " = " + approx(phi) + "…: cos " + st[g.q] + " = " + g.cos.str() +
                       ", sin " + st[g.q] + " = " + g.sin.str();
    if (c.initial[g.q]) {
      line += " (given " + c.initial[g.q]->str() + ", moved by " +
              approx(std::abs(phi - c.initial[g.q]->convert_to<double>())) + ")";
      ok = ok && near(*c.initial[g.q], phi);
    }
    p.place.push_back(line);
  }
  for (const std::string& h : pl.landed) p.place.push_back("positions on " + h);
  const auto moved = [&](std::size_t i, const Rational& given) {
    if (r.point[i] == given) return;
    bool angle = false;
    for (const PlacedAngle& g : pl.angles) angle = angle || g.q == i;
    if (angle) return;
    p.place.push_back(st[i] + ": given " + given.str() + ", here " + r.point[i].str() + " (moved by " +
                      approx(std::abs((r.point[i] - given).convert_to<double>())) + ")");
    ok = ok && near(given, r.point[i].convert_to<double>());
  };
  if (r.consistent && r.point.size() == 3 * n) {
    for (std::size_t i = 0; i < 2 * n; ++i)
      if (c.initial[i]) moved(i, *c.initial[i]);
    for (std::size_t i = 0; i < n; ++i)
      if (c.initial_p[i]) moved(2 * n + i, *c.initial_p[i]);
  }
  return ok;
}

/// The implicit form's CEF (1.6) at `start`, exactly: on the formulas (ide_formulas.hpp) where they decide
/// every step by identities, else on jets (pointwise.hpp), which settle what the formulas leave open (a
/// singular point, a formula vanishing on M_k only) to their order.  `formulas` says which ran.
PointwiseResult<Rational> run_implicit(const LagrangianSystem& s, const std::vector<Rational>& start,
                                       const std::vector<bool>& fixed, ImplicitRoute route,
                                       std::optional<IdeFormulas>& formulas, std::string& open) {
  formulas.reset();
  open.clear();
  if (route != ImplicitRoute::jets) {
    std::variant<IdeFormulas, IdeUndecided> f = ide_on_formulas(s, start, fixed);
    if (std::holds_alternative<IdeFormulas>(f)) {
      formulas = std::move(std::get<IdeFormulas>(f));
      return formulas->result;
    }
    const IdeUndecided& u = std::get<IdeUndecided>(f);
    if (route == ImplicitRoute::formulas) throw FormulasUndecided(u.why);
    // no rational point reached: the jets' Newton steps land where the formulas' do not at small sizes (other
    // pivots), but beyond 30 coordinates they take long to fail the same way — the caller's rational place next
    if (u.no_point && s.n > 30) throw PointwiseNoPoint(u.why);
    if (!u.no_point) open = u.why;  // a zero test no identity settles: the jets settle it to their order only
  }
  return run(s, start, fixed);
}

/// The formula route's tower as the CONTRACT's `formulas` (the constraints of every M_k and the equations of
/// motion on M_c, in the case's names), or why not: formulas that print as trees of more than 200,000 nodes
/// (a chain's multipliers, solved by back substitution, print each other's formulas again and again).
void attach_implicit_formulas(const IdeFormulas& f, const io::LagrangianCase& c, Pointwise<Rational>& p) {
  const LagrangianSystem& s = c.system;
  constexpr double kCap = 2e5;
  std::unordered_map<const expr::ExprNode*, double> memo;
  double total = 0;
  for (const auto& level : f.levels)
    for (const expr::Expr& e : level) total += expr::tree_size(e, memo, kCap);
  for (const expr::Expr& e : f.rates) total += expr::tree_size(e, memo, kCap);
  for (const auto& v : f.valid_where) total += expr::tree_size(v.formula, memo, kCap);
  if (total >= kCap) {
    p.formulas_why = "the formulas are too large to print (more than " + std::to_string(static_cast<long>(kCap)) +
                     " operations written out as trees); the tower and the point are exact as reported";
    return;
  }
  const std::vector<std::string> names = s.variable_names();
  Formulas out;
  for (std::size_t k = 0; k < f.levels.size(); ++k)
    for (const expr::Expr& e : f.levels[k]) {
      out.constraints.push_back(expr::to_text(e, names));
      out.levels.push_back(static_cast<long>(k + 1));
    }
  for (std::size_t i = 0; i < s.n; ++i) out.equations.emplace_back(names[s.q(i)], expr::to_text(f.rates[i], names));
  for (std::size_t i : f.free) out.free.push_back(names[i]);
  std::vector<bool> solved(2 * s.n + 1, false);
  for (const auto& level : f.solved)
    for (std::size_t i : level) {
      solved[i] = true;
      out.solved.push_back(names[i]);
    }
  for (std::size_t i = 0; i < s.n; ++i)
    if (!solved[s.q(i)]) out.kept.push_back(names[s.q(i)]);
  for (const auto& v : f.valid_where) {
    out.valid_where.push_back(expr::to_text(v.formula, names));
    out.valid_where_why.push_back(v.what);
  }
  out.decided =
      "exactly at the point (the tower's): every pivot a nonzero rational there, every zero test an identity of the "
      "formulas; the "
      "formulas hold near it on M_c wherever valid_where does not vanish";
  p.formulas = out;
}

/// Every equation is affine in the coordinates (the time and the derivatives enter anyhow): every M_k(t)
/// is then an affine subspace, one component.
bool affine_in_coordinates(const LagrangianSystem& s) {
  for (const expr::Expr& e : s.constraints) {
    const long d = expr::degree_in(e, [&](std::size_t i) { return i < s.n; });
    if (d < 0 || d > 1) return false;
  }
  return true;
}

/// The implicit form's tower again from a nearby point (every coordinate and the time moved by small
/// distinct rationals, nothing held): a condition that vanishes at the first point only to the jets'
/// order — x = t⁶ at t = 0, (x − 1/5)⁴ at x = 1/5 — gives another tower there.  Why they differ, or ""
/// (the same tower, or no exact run there: an irrational value, no rational point reached).
std::string second_look(const io::LagrangianCase& c, const PointwiseResult<Rational>& r) {
  const LagrangianSystem& s = c.system;
  std::vector<Rational> start(2 * s.n + 1, Rational(0));
  for (std::size_t i = 0; i < s.n && i < r.point.size(); ++i)
    start[s.q(i)] = r.point[i] + Rational(1, static_cast<long>(7 + 2 * i));
  start[s.t()] = r.time + (s.has_time ? Rational(1, 3) : Rational(0));
  PointwiseResult<Rational> o;
  try {
    o = run(s, start, std::vector<bool>(start.size(), false));
  } catch (const NotExactHere&) {
    return "";
  } catch (const PointwiseNoPoint&) {
    return "";
  }
  if (!o.regular) return "";
  if (o.dims == r.dims && o.consistent == r.consistent && (!r.consistent || o.solution_rank == r.solution_rank))
    return "";
  const auto dims = [](const std::vector<long>& d) {
    std::string t;
    for (long x : d) t += (t.empty() ? "" : ", ") + std::to_string(x);
    return "[" + t + "]";
  };
  return "from a nearby point (every value and the time moved by 1/3 or less) the tower is " + dims(o.dims) +
         (o.consistent ? "" : " (inconsistent)") + ", here " + dims(r.dims) + (r.consistent ? "" : " (inconsistent)") +
         ": a condition vanishes at this point only to the jets' order (not a generic point of its component)";
}

}  // namespace

dcad::Solution<Rational> solve_pointwise_exact(const io::LagrangianCase& c) {
  std::vector<bool> fixed;
  PointwiseResult<Rational> r;
  std::optional<ExactPlace> placed;
  for (int seed = 0; seed < kStartSeeds;
       ++seed) {  // a default point that is singular is not the generic answer: another one
    const std::vector<Rational> start = start_point(c, fixed, seed);
    placed.reset();
    // dcad's own point is its choice: where the exact route cannot run there, a rational place near it
    r = c.has_initial ? run(c.system, start, fixed) : run_or_place(c, start, fixed, false, placed);
    if (r.regular || c.has_initial) break;
  }
  check_given<Rational>(
      r, c, [](const Rational& a, const Rational& b) { return a == b; }, [](const Rational& q) { return q.str(); });
  dcad::Solution<Rational> out = pointwise_solution(r, c, "pointwise exact");
  if (placed) describe_place(*placed, r, c, *out.pointwise);
  out.certified = r.regular ? yes : unknown;  // a singular point decides no tower
  return out;
}

dcad::Solution<Rational> solve_pointwise_exact_near(const io::LagrangianCase& c) {
  if (!c.has_initial) return solve_pointwise_exact(c);
  std::vector<bool> fixed;
  const std::vector<Rational> start = start_point(c, fixed);
  std::optional<ExactPlace> placed;
  const PointwiseResult<Rational> r = run_or_place(c, start, fixed, true, placed);
  if (!placed) {
    check_given<Rational>(
        r, c, [](const Rational& a, const Rational& b) { return a == b; }, [](const Rational& q) { return q.str(); });
    dcad::Solution<Rational> out = pointwise_solution(r, c, "pointwise exact");
    out.certified = r.regular ? yes : unknown;
    return out;
  }
  if (!r.regular)  // a place that is a singular point says nothing about the given values' component
    throw NotExactHere("the rational place near the given values is a singular point (" + r.why + ")");
  dcad::Solution<Rational> out = pointwise_solution(r, c, "pointwise exact");
  if (!describe_place(*placed, r, c, *out.pointwise)) {  // the given values are not M_c's rounded: as at them
    std::string lines;
    for (const std::string& l : out.pointwise->place) lines += (lines.empty() ? "" : "; ") + l;
    throw PointwiseNoPoint("the nearest rational place of M_c moves given values by more than 1e-6 (relative): " +
                           lines);
  }
  out.certified = r.regular ? yes : unknown;
  out.note =
      "exact at a rational place near the given values (`place`), not at them: the tower, steps and solution rank are "
      "generic on the "
      "component (CEF §5), the point and velocity are the place's";
  return out;
}

std::optional<std::string> empty_m1_proof(const LagrangianSystem& s) {
  std::vector<std::size_t> rows;  // the equations without derivatives: M_1 lies in their common zeros
  for (std::size_t i = 0; i < s.constraints.size(); ++i) {
    bool free_of_v = true;
    for (std::size_t j = 0; j < s.n && free_of_v; ++j) free_of_v = !expr::depends_on(s.constraints[i], s.v(j));
    if (free_of_v) rows.push_back(i);
  }
  if (rows.size() < 2) return std::nullopt;  // one equation: a nonzero constant is caught by the route itself
  expr::Canonical canon;
  std::vector<expr::Canonical::Poly> polys;
  std::map<expr::Canonical::Mono, Index> column;  // the constant monomial (empty) sorts first: put it last below
  try {
    for (std::size_t i : rows) {
      polys.push_back(canon.of(s.constraints[i]));
      for (const auto& [mono, coef] : polys.back())
        if (!mono.empty()) column.emplace(mono, static_cast<Index>(column.size()));
    }
  } catch (const std::length_error&) {
    return std::nullopt;  // too large to expand: no proof either way
  }
  const Index k = static_cast<Index>(column.size()), m = static_cast<Index>(rows.size());
  Matrix<Rational> a(m, k + 1 + m);  // [nonconstant monomials | constant | identity]: the combination rides along
  for (Index r = 0; r < m; ++r) {
    for (const auto& [mono, coef] : polys[static_cast<std::size_t>(r)]) a(r, mono.empty() ? k : column.at(mono)) = coef;
    a(r, k + 1 + r) = 1;
  }
  const Rref<Rational> e = rref(a);
  for (Index r = 0; r < static_cast<Index>(e.pivots.size()); ++r) {
    if (e.pivots[static_cast<std::size_t>(r)] != k) continue;  // its first nonzero is the constant: 0 = c ≠ 0
    std::string combo;
    for (Index i = 0; i < m; ++i) {
      const Rational& y = e.r(r, k + 1 + i);
      if (y == 0) continue;
      combo += (combo.empty() ? "" : " + ") + std::string("(") + y.str() + ")·equation " +
               std::to_string(rows[static_cast<std::size_t>(i)] + 1);
    }
    return "M_1 = ∅: " + combo + " is the constant " + e.r(r, k).str() +
           " wherever the equations are defined, so no point (at any time) satisfies them all";
  }
  return std::nullopt;
}

dcad::Solution<Rational> solve_implicit_exact(const io::LagrangianCase& c, ImplicitRoute route) {
  if (const auto proof = empty_m1_proof(c.system)) {  // whatever `initial` says: the system has no point at all
    PointwiseResult<Rational> r;
    r.dims = {static_cast<long>(c.system.n), -1};
    r.steps = 1;
    r.consistent = false;
    r.why = *proof;
    r.time = c.initial[c.system.t()].value_or(Rational(0));
    dcad::Solution<Rational> out = implicit_solution(r, c, "pointwise exact");
    out.certified = yes;
    out.note = *proof;
    return out;
  }
  std::vector<bool> fixed;
  PointwiseResult<Rational> r;
  std::optional<IdeFormulas> formulas;
  std::optional<ExactPlace> placed;
  std::string open;  // what the formulas left open where the jets ran
  const Runner implicit_run = [&](const LagrangianSystem& s, const std::vector<Rational>& start,
                                  const std::vector<bool>& held) {
    return run_implicit(s, start, held, route, formulas, open);
  };
  try {
    for (int seed = 0; seed < kStartSeeds;
         ++seed) {  // a default point that is singular is not the generic answer: another one
      // without `initial` the point is dcad's choice: where no rational point of M_c is reached from it (x² + y² = 1
      // from a random rational point), a rational place of the same component (exact_place.hpp: positions put on
      // the equations without derivatives, angles on rational points of the circle)
      const std::vector<Rational> start = start_point(c, fixed, seed);
      placed.reset();
      r = c.has_initial ? implicit_run(c.system, start, fixed)
                        : run_or_place(c, start, fixed, false, placed, implicit_run);
      if (r.regular || c.has_initial) break;
    }
  } catch (const NotExactHere&) {
    // dcad's own default point made a formula irrational (sin 29/20): the given values (if any) and 0 for
    // the others, where sin, cos and exp are rational, is dcad's choice too
    std::vector<Rational> zero = start_point(c, fixed);
    for (std::size_t i = 0; i < zero.size(); ++i)
      if (!fixed[i]) zero[i] = 0;
    placed.reset();
    r = run_implicit(c.system, zero, fixed, route, formulas, open);
  }
  check_given_implicit<Rational>(
      r, c, [](const Rational& a, const Rational& b) { return a == b; }, [](const Rational& q) { return q.str(); });
  dcad::Solution<Rational> out = implicit_solution(r, c, formulas ? "formulas exact" : "pointwise exact");
  out.certified = r.regular ? yes : unknown;                  // a singular point decides no tower
  const bool translated = placed && !placed->angles.empty();  // the formulas are then in the translated angles
  if (placed) describe_place(*placed, r, c, *out.pointwise);
  if (formulas && r.consistent && !translated)
    attach_implicit_formulas(*formulas, c, *out.pointwise);
  else if (r.consistent && r.regular)
    out.pointwise->formulas_why =
        translated ? "the exact route ran at a rational place with its angles translated (`place`): no formulas"
                   : "the exact route ran on jets (the formulas left a decision open): no formulas";
  if (r.regular && !r.consistent && (!c.has_initial || r.moves > 0) && !affine_in_coordinates(c.system)) {
    out.certified =
        unknown;  // x (1 − y) = 0 is two lines: the completion reached y = 1, where v_y = 1 fails; x = 0 has solutions
    out.note = "not certified: inconsistent on the component of M_k that the completion reached from " +
               std::string(c.has_initial ? "the given values" : "dcad's default point") +
               "; a nonlinear M_k may have other components";
    return out;
  }
  if (r.regular && !formulas) {  // the formulas' decisions are identities and open conditions: they hold near the point
    const std::string differs = second_look(c, r);
    if (!differs.empty()) {
      out.certified = unknown;
      out.note = "not certified: " + differs;
    } else if (!open.empty()) {
      // what the formulas could not prove as an identity the jets took as zero to their order only: y^8 = 0,
      // x (exp(t) − its Taylor polynomial of degree 7) looked like 0 = 0 there (the review of issue 30)
      out.certified = unknown;
      out.note = "not certified: a zero test no identity of the formulas settles (" + open +
                 ") was taken by the jets to order " + std::to_string(r.checked_order) + " only";
    }
  }
  return out;
}

}  // namespace dcad::reference::pipeline
