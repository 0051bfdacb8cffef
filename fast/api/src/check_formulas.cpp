// `dcad check EQUATIONS DECK` (CONTRACT "Formulas for nonlinear results"): another tool's formulas for
// an expression-form case — the constraints of M_c and the equations of motion, e.g. from sympy.physics.
// mechanics, ModelingToolkit's structural_simplify or MATLAB's reduceDAEToODE — against dcad's chart at
// K points of M_c.  At each point: every one of their constraints vanishes (they hold on M_c); their
// constraints are as many as M_c needs (rank of their Jacobian = 2n − dim M_c: none missing); each of
// their equations equals dcad's rate (where dcad's is not free).  The points: the case's point of M_c
// and perturbations of it moved onto M_c by dcad's constraints (fast/chart.hpp), in double.
#include "check_formulas.hpp"

#include "dcad/fast/chart.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/reference/pipeline/exact_place.hpp"
#include "dcad/reference/solve.hpp"

#include <array>
#include <cmath>
#include <random>

namespace dcad::api {

namespace ex = reference::expr;

namespace {

/// The rank of rows (numerical, relative tolerance), Gaussian elimination with full pivoting.
std::size_t rank_of(std::vector<std::vector<double>> m) {
  std::size_t r = 0;
  const std::size_t cols = m.empty() ? 0 : m[0].size();
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

std::string point_text(const std::vector<std::string>& names, const std::vector<double>& at) {
  std::string s;
  for (std::size_t i = 0; i < at.size() && i < names.size(); ++i) s += (i ? ", " : "") + names[i] + " = " + io::float_text(at[i]);
  return s;
}

}  // namespace

namespace {

/// CONTRACT: "exactly where the point is rational".  At the exact tiers' point of M_c (the case's, or
/// the rational place near it; not where an angle sits at 2*atan(t)) their constraints must vanish and,
/// for a unique motion, their equations equal the exact velocity, in rationals.  False if there is no
/// such point (nothing compared exactly).
bool exact_point_check(const io::LagrangianCase& c, const std::vector<ex::Expr>& theirs, const std::vector<std::pair<std::size_t, ex::Expr>>& eqs,
                       Checked& out) {
  const std::size_t n = c.system.n;
  dcad::Solution<reference::Rational> r;
  try {
    io::Problem p;
    p.form = io::Form::expression;
    p.expression = c;
    r = reference::solve(p);
  } catch (const std::exception&) {
    return false;  // no exact point (the double points still compare)
  }
  if (!r.pointwise || !r.consistent || !r.pointwise->regular || !r.pointwise->point_text.empty()) return false;
  const auto& pw = *r.pointwise;
  std::vector<reference::Rational> x(pw.point.begin(), pw.point.begin() + static_cast<long>(2 * n));
  x.push_back(pw.time);
  const std::vector<std::string> names = c.system.variable_names();
  std::string where;
  for (std::size_t i = 0; i < 2 * n; ++i) where += (i ? ", " : "") + names[i] + " = " + x[i].str();
  try {
    for (std::size_t i = 0; i < theirs.size(); ++i) {
      const reference::Rational v = reference::pipeline::exact_value(theirs[i], x);
      if (v != 0)
        out.disagreements.push_back("formulas.constraints/" + std::to_string(i) + ": expected 0 on M_c, found " + v.str() + " exactly at the point of M_c " + where);
    }
    if (r.solution_rank && *r.solution_rank == 0)
      for (const auto& [k, e] : eqs) {
        const reference::Rational v = reference::pipeline::exact_value(e, x);
        if (v != pw.velocity[k])
          out.disagreements.push_back("formulas.equations." + names[k] + ": expected d/dt " + names[k] + " = " + pw.velocity[k].str() + ", found " + v.str() +
                                      " exactly at the point of M_c " + where);
      }
  } catch (const reference::NotExactHere&) {
    return false;  // their formula is irrational there (sin(1/2)): the double points compare it
  }
  return true;
}

}  // namespace

void check_formulas(const std::string& file, const nlohmann::json& f, const io::Problem& p, std::size_t points, Checked& out) {
  const io::LagrangianCase& c = p.expression;
  const reference::LagrangianSystem& s = c.system;
  const std::size_t n = s.n;
  const std::vector<std::string> names = s.variable_names();
  const auto fail = [&](const std::string& path, const std::string& expected, const nlohmann::json& found) {
    throw io::InputError(file + ": " + path + ": expected " + expected + ", found " + found.dump());
  };
  if (!f.is_object()) fail("/formulas", "an object {constraints: [...], equations: {name: formula}}", f);
  std::vector<ex::Expr> theirs;
  if (f.contains("constraints")) {
    if (!f["constraints"].is_array()) fail("/formulas/constraints", "an array of formulas (each = 0 on M_c)", f["constraints"]);
    for (std::size_t i = 0; i < f["constraints"].size(); ++i) {
      const std::string path = "/formulas/constraints/" + std::to_string(i);
      if (!f["constraints"][i].is_string()) fail(path, "a formula as a string", f["constraints"][i]);
      theirs.push_back(io::parse_case_formula(c, f["constraints"][i].get<std::string>(), file, path));
    }
  }
  std::vector<std::pair<std::size_t, ex::Expr>> eqs;  // (variable index, formula)
  if (f.contains("equations")) {
    if (!f["equations"].is_object()) fail("/formulas/equations", "an object {coordinate or velocity: d/dt of it}", f["equations"]);
    for (const auto& [name, e] : f["equations"].items()) {
      const std::string path = "/formulas/equations/" + name;
      std::size_t k = 2 * n;
      for (std::size_t i = 0; i < 2 * n; ++i)
        if (names[i] == name) k = i;
      if (k == 2 * n) fail(path, "a coordinate or velocity of " + c.file, nlohmann::json(name));
      if (!e.is_string()) fail(path, "a formula as a string", e);
      eqs.emplace_back(k, io::parse_case_formula(c, e.get<std::string>(), file, path));
    }
  }
  if (theirs.empty() && eqs.empty()) fail("/formulas", "constraints or equations", f);
  if (points == 0) throw io::InputError(file + ": --points: expected at least 1 point, found 0");
  // dcad's chart at the case's point of M_c
  fast::Solution near;
  try {
    near = fast::solve_expression(c);
  } catch (const io::InputError& e) {
    out.not_compared.push_back(std::string("formulas (dcad reaches no point of M_c: ") + e.what() + ")");
    return;
  }
  if (!near.consistent || !near.pointwise || !near.pointwise->regular) {
    out.not_compared.push_back("formulas (the case has no regular point of M_c here: " + (near.pointwise ? near.pointwise->why : std::string()) + ")");
    return;
  }
  std::vector<double> at(near.pointwise->point.begin(), near.pointwise->point.begin() + static_cast<long>(2 * n));
  at.push_back(near.pointwise->time);
  fast::Chart ch;
  try {
    const std::vector<double> v(near.pointwise->velocity.begin(), near.pointwise->velocity.begin() + static_cast<long>(2 * n));
    ch = fast::chart_near(s, at, near.dims(), near.pointwise->gauge.empty() ? &v : nullptr);
  } catch (const fast::ChartFailure& e) {
    out.not_compared.push_back(std::string("formulas (dcad has no chart of M_c here: ") + e.what() + ")");
    return;
  }
  const fast::ChartField field(ch);
  std::vector<char> free(2 * n, 0);
  for (std::size_t i : ch.free) free[i] = 1;
  // their formulas and their gradients over (q, v), compiled
  fast::Differentiator d;
  std::vector<ex::Expr> grads;
  for (const ex::Expr& e : theirs)
    for (std::size_t j = 0; j < 2 * n; ++j) grads.push_back(d(e, j));
  std::vector<ex::Expr> eq_formulas;
  for (const auto& [k, e] : eqs) eq_formulas.push_back(e);
  const fast::Tape con_tape(theirs), grad_tape(grads), eq_tape(eq_formulas);
  const std::size_t needed = 2 * n - static_cast<std::size_t>(near.dims().back());
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t used = 0;
  bool con_bad = false, rank_bad = false;
  std::vector<char> eq_bad(eqs.size(), 0);
  for (std::size_t k = 0; k < 50 * points && used < points; ++k) {
    std::vector<double> y(at.begin(), at.end() - 1);
    double t = at.back();
    if (k > 0) {  // a perturbation moved onto M_c by dcad's constraints; kept where dcad's chart holds
      // spread: relative 1/20 … 1 of each value (at least of 1): a case that starts at rest still gets points
      // with velocities of order 1, where a wrong velocity-dependent term shows
      const double size = std::array<double, 4>{0.05, 0.2, 0.5, 1.0}[k % 4];
      for (double& x : y) x += size * u(rng) * std::max(1.0, std::abs(x));
      if (s.has_time) t += size * u(rng) * std::max(1.0, std::abs(t));
      if (!fast::project_onto(ch.constraints, ch.gradients, y, t, 1e-14) || field.margin(y, t) < 1e-6) continue;
    }
    ++used;
    std::vector<double> x(y);
    x.push_back(t);
    const std::string where = point_text(names, x);
    double scale = 1;
    for (double v : y) scale = std::max(scale, std::abs(v));
    if (!theirs.empty()) {
      std::vector<double> phi(theirs.size()), g(grads.size());
      con_tape.evaluate(x.data(), phi.data());
      grad_tape.evaluate(x.data(), g.data());
      std::vector<std::vector<double>> jac(theirs.size(), std::vector<double>(2 * n));
      for (std::size_t i = 0; i < theirs.size(); ++i) {
        double gn = 0;
        for (std::size_t j = 0; j < 2 * n; ++j) gn = std::max(gn, std::abs(jac[i][j] = g[i * 2 * n + j]));
        if (!con_bad && !(std::abs(phi[i]) <= 1e-8 * std::max(gn * scale, 1e-300) + 1e-300)) {
          con_bad = true;
          out.disagreements.push_back("formulas.constraints[" + std::to_string(i) + "]: expected 0 on M_c, found " + io::float_text(phi[i]) +
                                      " at the point of M_c " + where);
        }
      }
      const std::size_t r = rank_of(jac);
      if (!rank_bad && r < needed) {
        rank_bad = true;
        // which of dcad's constraints theirs do not imply (by rank)
        std::string missing;
        std::vector<double> dg(ch.gradients.size() * 2 * n);
        std::vector<ex::Expr> flat;
        for (const auto& row : ch.gradients) flat.insert(flat.end(), row.begin(), row.end());
        fast::Tape(flat).evaluate(x.data(), dg.data());
        std::size_t level = 0, seen = 0;
        for (std::size_t i = 0; i < ch.constraints.size(); ++i) {
          while (level < ch.levels.size() && seen + ch.levels[level].size() <= i) seen += ch.levels[level++].size();
          std::vector<std::vector<double>> more = jac;
          more.emplace_back(dg.begin() + static_cast<long>(i * 2 * n), dg.begin() + static_cast<long>((i + 1) * 2 * n));
          if (rank_of(more) > rank_of(jac)) {
            missing = ex::to_text(ch.constraints[i], names) + " = 0 (M_" + std::to_string(level + 1) + ")";
            break;
          }
        }
        out.disagreements.push_back("formulas.constraints: expected " + std::to_string(needed) + " independent constraints (dim M_c = " +
                                    std::to_string(near.dims().back()) + " in " + std::to_string(2 * n) + " coordinates and velocities), found rank " +
                                    std::to_string(r) + " at " + where + (missing.empty() ? "" : "; not implied: " + missing));
      }
    }
    if (!eqs.empty()) {
      std::vector<double> theirs_v(eqs.size()), ours(2 * n);
      eq_tape.evaluate(x.data(), theirs_v.data());
      field.rates(y.data(), t, ours.data());
      double rscale = 1;
      for (double v : ours) rscale = std::max(rscale, std::abs(v));
      for (std::size_t i = 0; i < eqs.size(); ++i) {
        const std::size_t k2 = eqs[i].first;
        if (free[k2] || eq_bad[i]) continue;
        if (!(std::abs(theirs_v[i] - ours[k2]) <= 1e-8 * rscale)) {
          eq_bad[i] = 1;
          out.disagreements.push_back("formulas.equations." + names[k2] + ": expected d/dt " + names[k2] + " = " + io::float_text(ours[k2]) + ", found " +
                                      io::float_text(theirs_v[i]) + " at the point of M_c " + where);
        }
      }
    }
  }
  const bool exactly = exact_point_check(c, theirs, eqs, out);
  const std::string how = std::string(exactly ? " (exactly at the reference's rational point of M_c, and at " : " (at ") + std::to_string(used) +
                          " points of M_c in double: 1e-8 relative)";
  if (!theirs.empty()) out.compared.push_back("formulas.constraints" + how);
  if (!eqs.empty()) out.compared.push_back("formulas.equations" + how);
  for (std::size_t i = 0; i < eqs.size(); ++i)
    if (free[eqs[i].first]) out.not_compared.push_back("formulas.equations." + names[eqs[i].first] + " (its rate is free on M_c: solutions are not unique)");
  if (used < points) out.not_compared.push_back("formulas at " + std::to_string(points - used) + " of the " + std::to_string(points) + " points asked (no more points of M_c in dcad's chart were reached)");
  for (std::size_t i = 0; i < 2 * n; ++i) {
    bool given = false;
    for (const auto& [k2, e] : eqs) given = given || k2 == i;
    if (!given && !eqs.empty()) out.not_compared.push_back("formulas.equations." + names[i] + " (not given)");
  }
}

}  // namespace dcad::api
