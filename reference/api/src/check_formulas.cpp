// `dcad check EQUATIONS DECK` (CONTRACT "Formulas for nonlinear results"): another tool's formulas for
// an expression-form or implicit-form case — the constraints of M_c and the equations of motion, e.g.
// from sympy.physics.mechanics, ModelingToolkit's structural_simplify, MATLAB's reduceDAEIndex or
// reduceDAEToODE — against dcad's at K points of M_c.  At each point: every one of their constraints
// vanishes (they hold on M_c); their constraints are as many as M_c needs (the rank of their Jacobian is
// the codimension of M_c: none missing); each of their equations equals dcad's rate (where dcad's is not
// free).  The points: dcad's point of M_c — exactly, where it is rational — and perturbations of it moved
// onto M_c by dcad's constraints, in double.  dcad's side: the expression form's chart (fast/chart.hpp);
// the implicit form's exact tower on formulas (reference/nonlinear/ide_formulas.hpp, as `dcad solve`
// prints its `formulas`).
#include "check_formulas.hpp"

#include "dcad/fast/chart.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/reference/pipeline/exact_place.hpp"
#include "dcad/reference/solve.hpp"

#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <random>

namespace dcad::api {

namespace ex = reference::expr;

namespace {

/// The rank of rows (numerical, relative tolerance), Gaussian elimination with full pivoting.
std::size_t rank_of(std::vector<std::vector<double>> m) {
  std::size_t r = 0;
  const std::size_t cols = m.empty() ? 0 : m[0].size();
  // rows, then columns, to a largest entry of 1 by powers of two (exact; the rank is unchanged): constraints
  // x5 − 2 x4² beside x1 + x2 − 4 x3 at x4 = 5.7e6 are graded, not dependent (an unscaled threshold at 1e-9 of
  // the largest entry took their rank one short)
  const auto unit = [](double mx) {
    int e = 0;
    std::frexp(mx, &e);
    return mx > 0 && std::isfinite(mx) ? std::ldexp(1.0, -e) : 1.0;
  };
  for (auto& row : m) {
    double mx = 0;
    for (double x : row) mx = std::max(mx, std::abs(x));
    for (double& x : row) x *= unit(mx);
  }
  for (std::size_t c = 0; c < cols; ++c) {
    double mx = 0;
    for (const auto& row : m) mx = std::max(mx, std::abs(row[c]));
    for (auto& row : m) row[c] *= unit(mx);
  }
  double scale = 0;
  for (const auto& row : m)
    for (double x : row) scale = std::max(scale, std::abs(x));
  for (std::size_t c = 0; c < cols && r < m.size(); ++c) {
    std::size_t p = r;
    for (std::size_t i = r; i < m.size(); ++i)
      if (std::abs(m[i][c]) > std::abs(m[p][c])) p = i;
    if (std::abs(m[p][c]) <= 1e-9 * scale) continue;
    std::swap(m[p], m[r]);
    for (std::size_t i = r + 1; i < m.size(); ++i) {
      const double f = m[i][c] / m[r][c];
      for (std::size_t j = c; j < cols; ++j) m[i][j] -= f * m[r][j];
    }
    ++r;
  }
  return r;
}

std::string point_text(const std::vector<std::string>& names, const std::vector<double>& at, std::size_t width) {
  std::string s;
  for (std::size_t i = 0; i < width && i < at.size(); ++i)
    s += (i ? ", " : "") + names[i] + " = " + io::float_text(at[i]);
  return s;
}

/// Their formulas: the constraints (each = 0 on M_c) and the equations (variable index, d/dt of it).
struct Theirs {
  std::vector<ex::Expr> constraints;
  std::vector<std::pair<std::size_t, ex::Expr>> equations;
};

/// `formulas` read: `rated` are the variables an equation may give d/dt of (by index).
Theirs read_theirs(const std::string& file, const nlohmann::json& f, const io::LagrangianCase& c,
                   const std::vector<std::size_t>& rated) {
  const std::vector<std::string> names = c.system.variable_names();
  const auto fail = [&](const std::string& path, const std::string& expected, const nlohmann::json& found) {
    throw io::InputError(file + ": " + path + ": expected " + expected + ", found " + found.dump());
  };
  if (!f.is_object()) fail("/formulas", "an object {constraints: [...], equations: {name: formula}}", f);
  Theirs t;
  if (f.contains("constraints")) {
    if (!f["constraints"].is_array())
      fail("/formulas/constraints", "an array of formulas (each = 0 on M_c)", f["constraints"]);
    for (std::size_t i = 0; i < f["constraints"].size(); ++i) {
      const std::string path = "/formulas/constraints/" + std::to_string(i);
      if (!f["constraints"][i].is_string()) fail(path, "a formula as a string", f["constraints"][i]);
      t.constraints.push_back(io::parse_case_formula(c, f["constraints"][i].get<std::string>(), file, path));
    }
  }
  if (f.contains("equations")) {
    const std::string what = c.system.implicit ? "a coordinate" : "a coordinate or velocity";
    if (!f["equations"].is_object())
      fail("/formulas/equations", "an object {" + what + ": d/dt of it}", f["equations"]);
    for (const auto& [name, e] : f["equations"].items()) {
      const std::string path = "/formulas/equations/" + name;
      std::optional<std::size_t> k;
      for (std::size_t i : rated)
        if (names[i] == name) k = i;
      if (!k) fail(path, what + " of " + c.file, nlohmann::json(name));
      if (!e.is_string()) fail(path, "a formula as a string", e);
      t.equations.emplace_back(*k, io::parse_case_formula(c, e.get<std::string>(), file, path));
    }
  }
  if (t.constraints.empty() && t.equations.empty()) fail("/formulas", "constraints or equations", f);
  return t;
}

/// dcad's side of the comparison, in the variables of LagrangianSystem (the time last, at `width`… the
/// point's last entry): the state columns compared are 0 … width−1.
struct Ours {
  std::size_t width = 0;              ///< state columns: (q, v) for the expression form, q for the implicit form
  long dim = 0;                       ///< dim M_c
  std::vector<double> at;             ///< dcad's point of M_c (width values, then the time)
  std::vector<char> free;             ///< per state column: its rate is free on M_c
  std::vector<ex::Expr> constraints;  ///< dcad's constraints of M_c, in order of the levels
  std::vector<long> levels;           ///< the M_k each cuts out
  std::vector<std::vector<ex::Expr>> gradients;  ///< ∂/∂(state columns) of each
  /// y (width values) moved onto M_c at time t, and dcad's formulas valid there; false if not reached.
  std::function<bool(std::vector<double>& y, double t)> onto;
  /// dcad's rates at (y, t), one per state column.
  std::function<void(const std::vector<double>& y, double t, std::vector<double>& rates)> rates;
};

/// The first of dcad's constraints that theirs (Jacobian `jac` at x) do not imply, by rank: "φ = 0 (M_k)", or "".
std::string first_not_implied(const Ours& us, const std::vector<std::vector<double>>& jac, const std::vector<double>& x,
                              const std::vector<std::string>& names) {
  const std::size_t w = us.width;
  std::vector<ex::Expr> flat;
  for (const auto& row : us.gradients) flat.insert(flat.end(), row.begin(), row.end());
  std::vector<double> dg(flat.size());
  fast::Tape(flat).evaluate(x.data(), dg.data());
  for (std::size_t i = 0; i < us.constraints.size(); ++i) {
    std::vector<std::vector<double>> more = jac;
    more.emplace_back(dg.begin() + static_cast<long>(i * w), dg.begin() + static_cast<long>((i + 1) * w));
    if (rank_of(more) > rank_of(jac))
      return ex::to_text(us.constraints[i], names) + " = 0 (M_" + std::to_string(us.levels[i]) + ")";
  }
  return "";
}

/// A point of M_c: x padded to the time's index (the formulas' arguments), y the state, t the time, `where` its text.
struct PointOfMc {
  const std::vector<double>& x;
  const std::vector<double>& y;
  double t;
  const std::string& where;
};

/// Their equations against dcad's velocities at a point of M_c (free directions skipped), each equation's first
/// disagreement recorded once (eq_bad).
void compare_rates(const Theirs& th, const Ours& us, const fast::Tape& eq_tape, const PointOfMc& at,
                   const std::vector<std::string>& names, std::vector<char>& eq_bad, Checked& out) {
  std::vector<double> theirs_v(th.equations.size()), ours;
  eq_tape.evaluate(at.x.data(), theirs_v.data());
  us.rates(at.y, at.t, ours);
  double rscale = 1;
  for (double v : ours) rscale = std::max(rscale, std::abs(v));
  for (std::size_t i = 0; i < th.equations.size(); ++i) {
    const std::size_t k2 = th.equations[i].first;
    if (us.free[k2] || eq_bad[i]) continue;
    if (!(std::abs(theirs_v[i] - ours[k2]) <= 1e-8 * rscale)) {
      eq_bad[i] = 1;
      out.disagreements.push_back("formulas.equations." + names[k2] + ": expected d/dt " + names[k2] + " = " +
                                  io::float_text(ours[k2]) + ", found " + io::float_text(theirs_v[i]) +
                                  " at the point of M_c " + at.where);
    }
  }
}

/// The comparison at `points` points of M_c: how many were reached.
/// A rank of their constraints short in double goes to `rank_short` (settled with the exact rank, settle_rank).
std::size_t compare_at_points(const Theirs& th, const Ours& us, const std::vector<std::string>& names, bool has_time,
                              std::size_t points, Checked& out, std::string& rank_short) {
  const std::size_t w = us.width;
  // their formulas and their gradients over the state columns, compiled (variables indexed as in the case:
  // a point is padded to the time's index)
  std::vector<ex::Expr> eq_formulas;
  for (const auto& [k, e] : th.equations) eq_formulas.push_back(e);
  const fast::Tape con_tape(th.constraints), eq_tape(eq_formulas);
  const std::size_t t_index = names.size() - 1, needed = w - static_cast<std::size_t>(us.dim);
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t used = 0;
  bool con_bad = false, rank_bad = false;
  std::vector<char> eq_bad(th.equations.size(), 0);
  for (std::size_t k = 0; k < 50 * points && used < points; ++k) {
    std::vector<double> y(us.at.begin(), us.at.begin() + static_cast<long>(w));
    double t = us.at.back();
    if (k > 0) {  // a perturbation moved onto M_c by dcad's constraints; kept where dcad's formulas hold
      // spread: relative 1/20 … 1 of each value (at least of 1): a case that starts at rest still gets points
      // with velocities of order 1, where a wrong velocity-dependent term shows
      const double size = std::array<double, 4>{0.05, 0.2, 0.5, 1.0}[k % 4];
      for (double& x : y) x += size * u(rng) * std::max(1.0, std::abs(x));
      if (has_time) t += size * u(rng) * std::max(1.0, std::abs(t));
      if (!us.onto(y, t)) continue;
    }
    ++used;
    std::vector<double> x(t_index + 1, 0.0);
    std::copy(y.begin(), y.end(), x.begin());
    x[t_index] = t;
    const std::string where =
        point_text(names, x, w) + (has_time ? ", " + names[t_index] + " = " + io::float_text(t) : "");
    double scale = 1;
    for (double v : y) scale = std::max(scale, std::abs(v));
    if (!th.constraints.empty()) {
      std::vector<double> phi(th.constraints.size()), g(th.constraints.size() * w);
      con_tape.jacobian(x.data(), w, phi.data(), g.data());
      std::vector<std::vector<double>> jac(th.constraints.size(), std::vector<double>(w));
      for (std::size_t i = 0; i < th.constraints.size(); ++i) {
        double gn = 0;
        for (std::size_t j = 0; j < w; ++j) gn = std::max(gn, std::abs(jac[i][j] = g[i * w + j]));
        if (!con_bad && !(std::abs(phi[i]) <= 1e-8 * std::max(gn * scale, 1e-300) + 1e-300)) {
          con_bad = true;
          out.disagreements.push_back("formulas.constraints[" + std::to_string(i) + "]: expected 0 on M_c, found " +
                                      io::float_text(phi[i]) + " at the point of M_c " + where);
        }
      }
      const std::size_t r = rank_of(jac);
      if (!rank_bad && r < needed) {
        rank_bad = true;
        const std::string missing = first_not_implied(us, jac, x, names);
        rank_short = "formulas.constraints: expected " + std::to_string(needed) +
                     " independent constraints (dim M_c = " + std::to_string(us.dim) + " in " + std::to_string(w) +
                     " state columns), found rank " + std::to_string(r) + " at " + where +
                     (missing.empty() ? "" : "; not implied: " + missing);
      }
    }
    if (!th.equations.empty()) compare_rates(th, us, eq_tape, {x, y, t, where}, names, eq_bad, out);
  }
  return used;
}

/// At the reference's rational point x of M_c (variables indexed as in the case, the time last) their
/// constraints must vanish and, for a unique motion, their equations equal the exact velocity `v` (per
/// state column), in rationals.  False if a formula is irrational there (nothing compared exactly).
/// `full_rank`: whether their constraints' gradients over the state columns have rank `needed` there, exactly
/// (`exact_short` says so where not; settle_rank reports it).
bool exact_point_check(const Theirs& th, const std::vector<reference::Rational>& x,
                       const std::vector<reference::Rational>* v, const std::vector<std::string>& names,
                       std::size_t width, std::size_t needed, std::optional<bool>& full_rank, std::string& exact_short,
                       Checked& out) {
  std::string where;
  for (std::size_t i = 0; i < width; ++i) where += (i ? ", " : "") + names[i] + " = " + x[i].str();
  std::vector<reference::Rational> values(th.constraints.size());  // their constraints' exact values at x
  try {
    {  // the rank in rationals (reference::rank: RREF, no threshold)
      reference::Matrix<reference::Rational> m(th.constraints.size(), width);
      for (std::size_t i = 0; i < th.constraints.size(); ++i) {
        const std::vector<reference::Rational> g =
            reference::pipeline::exact_gradient(th.constraints[i], x, width, &values[i]);
        for (std::size_t j = 0; j < width; ++j) m(i, j) = g[j];
      }
      const std::size_t r = static_cast<std::size_t>(reference::rank(m));
      full_rank = r >= needed;
      if (r < needed)
        exact_short = "expected " + std::to_string(needed) + " independent constraints, found rank " +
                      std::to_string(r) + " exactly at the point of M_c " + where;
    }
    for (std::size_t i = 0; i < th.constraints.size(); ++i) {
      const reference::Rational& val = values[i];
      if (val != 0)
        out.disagreements.push_back("formulas.constraints/" + std::to_string(i) + ": expected 0 on M_c, found " +
                                    val.str() + " exactly at the point of M_c " + where);
    }
    if (v)
      for (const auto& [k, e] : th.equations) {
        const reference::Rational val = reference::pipeline::exact_value(e, x);
        if (val != (*v)[k])
          out.disagreements.push_back("formulas.equations." + names[k] + ": expected d/dt " + names[k] + " = " +
                                      (*v)[k].str() + ", found " + val.str() + " exactly at the point of M_c " + where);
      }
  } catch (const reference::NotExactHere&) {
    return false;  // their formula is irrational there (sin(1/2)): the double points compare it
  } catch (const std::domain_error&) {
    return false;  // not differentiable there in jets (sqrt(t^4) at t = 0, a right formula): the double points compare
                   // it
  }
  return true;
}

/// A rank short in double where the exact rank at the rational point is full: the double points were too
/// ill-conditioned to tell (x5 − 2 x4² at x4 = 5.7e6 beside rows of order 1: condition 3e21), not a disagreement.
/// Short exactly: a disagreement (the double points' message names a constraint of dcad's theirs do not imply).
void settle_rank(const std::string& rank_short, const std::optional<bool>& full_rank, const std::string& exact_short,
                 Checked& out) {
  if (full_rank == false)
    out.disagreements.push_back(rank_short.empty() ? "formulas.constraints: " + exact_short
                                                   : rank_short + " (and " + exact_short + ")");
  else if (rank_short.empty())
    return;
  else if (full_rank == true)
    out.not_compared.push_back("the rank of formulas.constraints in double (short at a point: " + rank_short +
                               "; full exactly at the reference's rational point — ill-conditioned in double)");
  else
    out.disagreements.push_back(rank_short);
}

/// What was compared, and what not, once the points are done.
void summarize(const Theirs& th, const Ours& us, const std::vector<std::string>& names, bool exactly, std::size_t used,
               std::size_t points, Checked& out) {
  const std::string how =
      std::string(exactly ? " (exactly at the reference's rational point of M_c, and at " : " (at ") +
      std::to_string(used) + " points of M_c in double: 1e-8 relative)";
  if (!th.constraints.empty()) out.compared.push_back("formulas.constraints" + how);
  if (!th.equations.empty()) out.compared.push_back("formulas.equations" + how);
  for (const auto& [k, e] : th.equations)
    if (us.free[k])
      out.not_compared.push_back("formulas.equations." + names[k] +
                                 " (its rate is free on M_c: solutions are not unique)");
  if (used < points)
    out.not_compared.push_back("formulas at " + std::to_string(points - used) + " of the " + std::to_string(points) +
                               " points asked (no more points of M_c in dcad's chart were reached)");
  for (std::size_t i = 0; i < us.width; ++i) {
    bool given = false;
    for (const auto& [k2, e] : th.equations) given = given || k2 == i;
    if (!given && !th.equations.empty()) out.not_compared.push_back("formulas.equations." + names[i] + " (not given)");
  }
}

/// The expression form: dcad's chart near the double route's point of M_c (fast/chart.hpp); the exact
/// point is the reference's (or its rational place; not where an angle sits at 2*atan(t)).
void check_expression_formulas(const Theirs& th, const io::LagrangianCase& c, std::size_t points, Checked& out) {
  const reference::LagrangianSystem& s = c.system;
  const std::size_t n = s.n;
  const std::vector<std::string> names = s.variable_names();
  fast::Solution near;
  try {
    near = fast::solve_expression(c);
  } catch (const io::InputError& e) {
    out.not_compared.push_back(std::string("formulas (dcad reaches no point of M_c: ") + e.what() + ")");
    return;
  }
  if (!near.consistent || !near.pointwise || !near.pointwise->regular) {
    out.not_compared.push_back("formulas (the case has no regular point of M_c here: " +
                               (near.pointwise ? near.pointwise->why : std::string()) + ")");
    return;
  }
  Ours us;
  us.width = 2 * n;
  us.dim = near.dims().back();
  us.at.assign(near.pointwise->point.begin(), near.pointwise->point.begin() + static_cast<long>(2 * n));
  us.at.push_back(near.pointwise->time);
  fast::Chart ch;
  try {
    const std::vector<double> v(near.pointwise->velocity.begin(),
                                near.pointwise->velocity.begin() + static_cast<long>(2 * n));
    ch = fast::chart_near(s, us.at, near.dims(), near.pointwise->gauge.empty() ? &v : nullptr,
                          fast::pointwise_completion(s));
  } catch (const fast::ChartFailure& e) {
    out.not_compared.push_back(std::string("formulas (dcad has no chart of M_c here: ") + e.what() + ")");
    return;
  }
  const auto field = std::make_shared<fast::ChartField>(ch);
  us.free.assign(2 * n, 0);
  for (std::size_t i : ch.free) us.free[i] = 1;
  us.constraints = ch.constraints;
  us.gradients = ch.gradients;
  for (std::size_t k = 0; k < ch.levels.size(); ++k)
    for (std::size_t i = 0; i < ch.levels[k].size(); ++i) us.levels.push_back(static_cast<long>(k + 1));
  us.onto = [&ch, field](std::vector<double>& y, double t) {
    return fast::project_onto(ch.constraints, ch.gradients, y, t, 1e-14) && field->margin(y, t) >= 1e-6;
  };
  us.rates = [field, n](const std::vector<double>& y, double t, std::vector<double>& r) {
    r.assign(2 * n, 0.0);
    field->rates(y.data(), t, r.data());
  };
  std::string rank_short, exact_short;
  std::optional<bool> full_rank;
  const std::size_t used = compare_at_points(th, us, names, s.has_time, points, out, rank_short);
  bool exactly = false;
  try {
    io::Problem p;
    p.file = c.file;
    p.input = io::ExpressionCase{c};
    const dcad::Solution<reference::Rational> r = reference::solve(p);
    if (r.pointwise && r.consistent && r.pointwise->regular && r.pointwise->point_text.empty()) {
      std::vector<reference::Rational> x(r.pointwise->point.begin(),
                                         r.pointwise->point.begin() + static_cast<long>(2 * n));
      x.push_back(r.pointwise->time);
      const bool unique = r.solution_rank && *r.solution_rank == 0;
      exactly = exact_point_check(th, x, unique ? &r.pointwise->velocity : nullptr, names, 2 * n,
                                  2 * n - static_cast<std::size_t>(us.dim), full_rank, exact_short, out);
    }
  } catch (const std::exception&) {  // no exact point (the double points still compare)
  }
  settle_rank(rank_short, full_rank, exact_short, out);
  summarize(th, us, names, exactly, used, points, out);
}

/// dcad's formulas `f` (of the implicit case `c`, read back from their printed text) as the side the points
/// compare: constraints and their gradients, the rates, and the projection onto M_c where the formulas'
/// pivots hold (as at the exact point x0 = (q, v, t) of M_c, dimension `dim`).
Ours ours_of_formulas(const std::string& file, const io::LagrangianCase& c, const Formulas& f, long dim,
                      const std::vector<reference::Rational>& x0) {
  const std::size_t n = c.system.n;
  const std::vector<std::string> names = c.system.variable_names();
  const auto parse = [&](const std::string& text, const std::string& what) {
    return io::parse_case_formula(c, text, file + " (dcad's own " + what + ")", "");
  };
  Ours us;
  us.width = n;
  us.dim = dim;
  us.free.assign(n, 0);
  for (const std::string& name : f.free)
    for (std::size_t i = 0; i < n; ++i)
      if (names[i] == name) us.free[i] = 1;
  fast::Differentiator d;
  std::vector<std::vector<ex::Expr>> grads;  // over (q, v) for project_onto: the v entries 0
  for (std::size_t i = 0; i < f.constraints.size(); ++i) {
    us.constraints.push_back(parse(f.constraints[i], "constraint"));
    us.levels.push_back(f.levels[i]);
    us.gradients.emplace_back();
    for (std::size_t j = 0; j < n; ++j) us.gradients.back().push_back(d(us.constraints.back(), j));
    grads.push_back(us.gradients.back());
    grads.back().resize(2 * n, ex::number(0));
  }
  std::vector<ex::Expr> rates(n, ex::number(0)), valid;
  for (const auto& [name, e] : f.equations)
    for (std::size_t i = 0; i < n; ++i)
      if (names[i] == name) rates[i] = parse(e, "equation");
  for (const std::string& v : f.valid_where) valid.push_back(parse(v, "valid_where"));
  const auto rate_tape = std::make_shared<fast::Tape>(rates), valid_tape = std::make_shared<fast::Tape>(valid);
  us.at.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) us.at[i] = x0[i].convert_to<double>();
  us.at.push_back(x0[2 * n].convert_to<double>());
  const auto padded = [n](const std::vector<double>& y, double t) {  // (q, v = 0, t): the case's variable indices
    std::vector<double> x(2 * n + 1, 0.0);
    std::copy(y.begin(), y.begin() + static_cast<long>(n), x.begin());
    x[2 * n] = t;
    return x;
  };
  std::vector<double> valid0(valid.size());
  valid_tape->evaluate(padded(us.at, us.at.back()).data(), valid0.data());
  const std::vector<ex::Expr> cons = us.constraints;
  us.onto = [=](std::vector<double>& y, double t) {
    std::vector<double> yv(2 * n, 0.0);  // project_onto's (q, v): the v entries have no gradient and stay 0
    std::copy(y.begin(), y.end(), yv.begin());
    if (!fast::project_onto(cons, grads, yv, t, 1e-14)) return false;
    std::copy(yv.begin(), yv.begin() + static_cast<long>(n), y.begin());
    std::vector<double> val(valid.size());
    valid_tape->evaluate(padded(y, t).data(), val.data());
    for (std::size_t i = 0; i < val.size(); ++i)  // where the formulas' pivots hold (as the chart's margin)
      if (!(std::abs(val[i]) >= 1e-6 * std::abs(valid0[i]))) return false;
    return true;
  };
  us.rates = [=](const std::vector<double>& y, double t, std::vector<double>& out_r) {
    out_r.assign(n, 0.0);
    rate_tape->evaluate(padded(y, t).data(), out_r.data());
  };
  return us;
}

/// The implicit form: dcad's formulas are the exact route's on formulas (`dcad solve --json`'s `formulas`,
/// read back: what is printed is what is compared), decided at its exact point of M_c.
void check_implicit_formulas(const std::string& file, const Theirs& th, const io::Problem& p, std::size_t points,
                             Checked& out) {
  const io::LagrangianCase& c = p.expression();
  const reference::LagrangianSystem& s = c.system;
  const std::size_t n = s.n;
  const std::vector<std::string> names = s.variable_names();
  dcad::Solution<reference::Rational> r;
  try {
    r = reference::solve(p);
  } catch (const std::exception& e) {
    out.not_compared.push_back(std::string("formulas (the exact route reaches no point of M_c: ") + e.what() + ")");
    return;
  }
  if (r.certified.yes() && !r.consistent) {  // formulas of a nonempty M_c for a system that has none
    out.compared.push_back("formulas");
    out.disagreements.push_back(
        "formulas: expected none (M_c is empty: " + (r.pointwise ? r.pointwise->why : std::string()) + "), found " +
        std::to_string(th.constraints.size()) + " constraints and " + std::to_string(th.equations.size()) +
        " equations of motion");
    return;
  }
  if (!r.certified.yes() || !r.pointwise || !r.pointwise->formulas) {
    // nothing judged is no agreement (check.cpp's rule for a result whose every claim went uncompared)
    out.disagreements.push_back(
        "formulas: not judged — dcad has none for this case (" +
        (r.pointwise && !r.pointwise->formulas_why.empty() ? r.pointwise->formulas_why
                                                           : std::string("the exact route is not certified here")) +
        "); give `initial` where the exact route runs on formulas, or compare dims, steps and index");
    return;
  }
  std::vector<reference::Rational> x0(2 * n + 1, reference::Rational(0));
  for (std::size_t i = 0; i < n; ++i) x0[i] = r.pointwise->point[i];
  x0[2 * n] = r.pointwise->time;
  Ours us = ours_of_formulas(file, c, *r.pointwise->formulas, r.dims().back(), x0);
  std::string rank_short, exact_short;
  std::optional<bool> full_rank;
  const std::size_t used = compare_at_points(th, us, names, s.has_time, points, out, rank_short);
  std::vector<reference::Rational> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = r.pointwise->velocity[i];
  const bool unique = r.solution_rank && *r.solution_rank == 0;
  const bool exactly = exact_point_check(th, x0, unique ? &v : nullptr, names, n, n - static_cast<std::size_t>(us.dim),
                                         full_rank, exact_short, out);
  settle_rank(rank_short, full_rank, exact_short, out);
  summarize(th, us, names, exactly, used, points, out);
}

}  // namespace

void check_formulas(const std::string& file, const nlohmann::json& f, const io::Problem& p, std::size_t points,
                    Checked& out) {
  const io::LagrangianCase& c = p.expression();
  const std::size_t n = c.system.n;
  std::vector<std::size_t> rated;  // what an equation may give d/dt of: (q, v), or q for the implicit form
  for (std::size_t i = 0; i < (c.system.implicit ? n : 2 * n); ++i) rated.push_back(i);
  const Theirs th = read_theirs(file, f, c, rated);
  if (points == 0) throw io::InputError(file + ": --points: expected at least 1 point, found 0");
  if (c.system.implicit)
    check_implicit_formulas(file, th, p, points, out);
  else
    check_expression_formulas(th, c, points, out);
}

}  // namespace dcad::api
