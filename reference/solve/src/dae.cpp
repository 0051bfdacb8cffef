// The linear DAE form by the reference (pipeline/dae.hpp).
#include "dcad/reference/pipeline/dae.hpp"

#include "dcad/reference/linear_ide.hpp"
#include "dcad/reference/pipeline/exact_place.hpp"
#include "dcad/reference/nonlinear/jet.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>

namespace dcad::reference::pipeline {

namespace ex = reference::expr;

Truth vanishes_identically(const ex::Expr& g, std::string& evidence) {
  if (ex::is_number(g)) {
    evidence = g->value == 0 ? "identically 0" : "the constant " + g->value.str();
    return g->value == 0 ? yes : no;
  }
  const auto value_at = [&](const Rational& t) { return exact_value(g, {t}); };  // NotExactHere where irrational
  const long d = ex::degree_in(g, [](std::size_t) { return true; });
  if (d >= 0) {  // a polynomial of degree ≤ d in t: zero iff zero at d + 1 points
    for (long s = 0; s <= d; ++s) {
      Rational v;
      try {
        v = value_at(Rational(s));
      } catch (const std::exception&) {  // a division by a polynomial that vanishes at s: not a polynomial after all
        evidence = "not decided (a quotient that vanishes at t = " + std::to_string(s) + ")";
        return unknown;
      }
      if (v != 0) {
        evidence = "at t = " + std::to_string(s) + " it is " + v.str();
        return no;
      }
    }
    evidence =
        "a polynomial of degree at most " + std::to_string(d) + " in t that vanishes at t = 0…" + std::to_string(d);
    return yes;
  }
  for (const Rational& at :
       {Rational(1), Rational(2), Rational(1, 2)}) {  // exact values where they are rational (1/t at t = 1)
    try {
      const Rational v = value_at(at);
      if (v != 0) {
        evidence = "at t = " + at.str() + " it is " + v.str();
        return no;
      }
    } catch (const std::exception&) {
    }
  }
  // analytic at 0 (sin, cos, exp have rational derivatives there): a nonzero Taylor coefficient proves g ≢ 0
  ex::Expr dk = g;
  for (int k = 0; k <= 8; ++k) {
    Rational v;
    try {
      v = exact_value(dk, {Rational(0)});
    } catch (const std::exception&) {
      break;  // not exact at 0 (or not defined there)
    }
    if (v != 0) {
      evidence = k == 0 ? "at t = 0 it is " + v.str()
                        : "its derivative of order " + std::to_string(k) + " at t = 0 is " + v.str();
      return no;
    }
    dk = ex::diff(dk, 0);
  }
  evidence =
      "not decided: a formula that is not a polynomial in t, whose first derivatives vanish at t = 0 (or are not exact "
      "there)";
  return unknown;
}

namespace {

/// The sources' jets as columns: u[d·s + k] = d^d/dt^d f_{rows[k]}, for the rows with f ≠ 0.
struct Jets {
  std::vector<std::size_t> rows;                ///< the equations with a source
  std::vector<std::vector<ex::Expr>> formulas;  ///< formulas[d][k]
  std::vector<std::string> names;               ///< column names, u's order
  Jets(const io::DaeCase& c, Index orders) {
    for (std::size_t i = 0; i < c.f.size(); ++i)
      if (!ex::is_number(c.f[i], 0)) rows.push_back(i);
    for (Index d = 0; d < orders; ++d) {
      formulas.emplace_back();
      for (std::size_t k = 0; k < rows.size(); ++k) {
        formulas[d].push_back(d == 0 ? c.f[rows[k]] : ex::diff(formulas[d - 1][k], 0));
        names.push_back(io::source_name(rows[k], static_cast<long>(d)));
      }
    }
  }
  const ex::Expr& at(Index column) const { return formulas[column / rows.size()][column % rows.size()]; }
};

}  // namespace

namespace {

/// The tower of CEF (1.6) with u's blocks as few as it uses: a result whose last block is used is recomputed with
/// twice as many (N + 2 always suffice: at most N + 1 steps, each one derivative more); `orders` set to them.
IdeTower<Rational> dae_tower(const io::DaeCase& c, const Matrix<Rational>& f, Index s, Index& orders) {
  using M = Matrix<Rational>;
  const Index n = c.variables.size();
  const auto uses_last_block = [&](const IdeTower<Rational>& t) {
    const auto any = [&](const M& g) {
      for (Index i = 0; i < g.rows(); ++i)
        for (Index j = s * (t.orders - 1); j < g.cols(); ++j)
          if (g(i, j) != 0) return true;
      return false;
    };
    if (t.orders == 0) return false;
    for (const IdeLevel<Rational>& l : t.levels)
      if (any(l.g) || any(l.conditions)) return true;
    return any(t.u_rate);
  };
  orders = s == 0 ? 0 : std::min<Index>(4, n + 2);
  IdeTower<Rational> t = linear_ide_tower(c.e, c.a, f, orders);
  while (orders > 0 && orders < n + 2 && uses_last_block(t)) {
    orders = std::min<Index>(2 * orders, n + 2);
    t = linear_ide_tower(c.e, c.a, f, orders);
  }
  return t;
}

/// Row i of a step's conditions, 0 = Σ c_j u_j(t), decided against the sources' formulas (identical formulas, two
/// equal sources, summed first); `k` the step it was found for.  nullopt for one in `seen` (found at an earlier
/// step: said once, not decided again).
std::optional<SourceCondition> dae_condition(const Matrix<Rational>& conditions, Index i, const Jets& jets,
                                             std::size_t k, std::set<std::string>& seen) {
  std::string text;
  std::map<std::string, std::pair<Rational, ex::Expr>> same;
  for (Index j = 0; j < conditions.cols(); ++j)
    if (conditions(i, j) != 0) {
      const Rational& q = conditions(i, j);
      auto& entry = same.try_emplace(ex::to_text(jets.at(j), {"t"}), Rational(0), jets.at(j)).first->second;
      entry.first += q;
      const std::string mag = abs(q) == 1 ? "" : Rational(abs(q)).str() + "*";
      text += (text.empty() ? (q < 0 ? "-" : "") : (q < 0 ? " - " : " + ")) + mag + jets.names[j];
    }
  if (!seen.insert(text).second) return std::nullopt;
  ex::Expr g = ex::number(0);
  for (const auto& [formula, term] : same)
    if (term.first != 0) g = ex::add(g, ex::mul(ex::number(term.first), term.second));
  SourceCondition sc;
  sc.text = text + " = 0";
  sc.holds = vanishes_identically(g, sc.evidence);
  if (sc.holds.yes() && ex::is_number(g, 0) && same.size() > 0) sc.evidence = "identical formulas cancel";
  sc.evidence = "found for M_" + std::to_string(k + 1) + "; " + sc.evidence;
  return sc;
}

/// x' = X x + K λ + S u on M_c: X = t.x_rate, K = t.gauge, S the columns of t.u_rate the output uses.
Motion<Rational> dae_motion(const IdeTower<Rational>& t, Index n, const std::vector<bool>& used,
                            const std::vector<std::size_t>& column, const std::vector<std::string>& jets) {
  Motion<Rational> mo;
  for (Index i = 0; i < n; ++i) mo.coordinates.push_back(i);
  mo.f_matrix.assign(n, std::vector<Rational>(n));
  mo.f.assign(n, Rational(0));
  mo.g.assign(n, std::vector<Rational>(t.gauge.cols()));
  mo.source_columns = jets;
  mo.s.assign(n, std::vector<Rational>(jets.size()));
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j < n; ++j) mo.f_matrix[i][j] = t.x_rate(i, j);
    for (Index j = 0; j < t.gauge.cols(); ++j) mo.g[i][j] = t.gauge(i, j);
    for (Index j = 0; j < static_cast<Index>(used.size()); ++j)
      if (used[j]) mo.s[i][column[j] - n] = t.u_rate(i, j);
  }
  return mo;
}

/// The exact route takes dense rational matrices only (io::DaeCase's limits); std::invalid_argument beyond.
void require_dense(const io::DaeCase& c) {
  if (!c.dense)
    throw std::invalid_argument("E and A are " + std::to_string(c.rows) + " × " + std::to_string(c.variables.size()) +
                                ": the exact route (CEF (1.6) on dense rational matrices) takes at most " +
                                std::to_string(io::DaeCase::dense_limit) + " entries (m·N) and " +
                                std::to_string(io::DaeCase::dense_side) +
                                " rows or columns; `dcad solve --backend fast` takes the sparse route (simulate and "
                                "check need the exact tower)");
}

/// The jet columns (of u's `u`) any output of the tower uses: G, the fresh G, the conditions, the rate of u.
std::vector<bool> used_jets(const IdeTower<Rational>& t, Index u) {
  std::vector<bool> used(u, false);
  const auto mark = [&](const Matrix<Rational>& g) {
    for (Index i = 0; i < g.rows(); ++i)
      for (Index j = 0; j < g.cols(); ++j)
        if (g(i, j) != 0) used[j] = true;
  };
  for (const IdeLevel<Rational>& l : t.levels) mark(l.g), mark(l.fresh_g), mark(l.conditions);
  mark(t.u_rate);
  return used;
}

}  // namespace

dcad::Solution<Rational> dae_result(const io::DaeCase& c, Backend backend) {
  dcad::Solution<Rational> out;
  out.backend = backend;
  out.exact = true;
  out.file = c.file;
  out.name = c.name;
  out.variables = c.variables;
  out.algorithm = Algorithm::implicit_equation;
  return out;
}

dcad::Solution<Rational> solve_dae(const io::DaeCase& c) {
  using M = Matrix<Rational>;
  require_dense(c);
  const Index n = c.variables.size(), m = c.equations();
  const Jets probe(c, 0);
  const Index s = probe.rows.size();
  M f(m, s);  // F: the sources' rows
  for (Index k = 0; k < s; ++k) f(probe.rows[k], k) = 1;
  Index orders = 0;
  const IdeTower<Rational> t = dae_tower(c, f, s, orders);
  const Jets jets(c, orders);

  dcad::Solution<Rational> out = dae_result(c, Backend::reference);
  for (std::size_t k = 0; k < s; ++k)
    out.source_names.push_back(io::source_name(jets.rows[k], 0) + " = " +
                               ex::to_text(c.f[jets.rows[k]], {c.time_name.empty() ? "t" : c.time_name}));
  // the jet columns any output uses, in u's order
  const Index u = s * orders;
  const std::vector<bool> used = used_jets(t, u);
  std::vector<std::size_t> column(u, 0);
  for (Index j = 0; j < u; ++j)
    if (used[j]) {
      column[j] = n + out.jets.size();
      out.jets.push_back(jets.names[j]);
    }
  const auto equation = [&](const M& cx, const M& gu, Index i) {  // C x − G u = 0
    Equation<Rational> e;
    for (Index j = 0; j < n; ++j)
      if (cx(i, j) != 0) e.terms.emplace_back(j, cx(i, j));
    for (Index j = 0; j < u; ++j)
      if (gu(i, j) != 0) e.terms.emplace_back(column[j], -gu(i, j));
    return e;
  };
  out.tower.push_back({static_cast<long>(n), {}});
  bool certain = true;
  std::set<std::string> seen;
  for (std::size_t k = 0; k < t.levels.size(); ++k) {
    const IdeLevel<Rational>& l = t.levels[k];
    bool empty = false, open = false;                  // a condition of this step fails; one is undecided
    for (Index i = 0; i < l.conditions.rows(); ++i) {  // 0 = Σ c_j u_j(t): decided against f
      const std::optional<SourceCondition> sc = dae_condition(l.conditions, i, jets, k, seen);
      if (!sc) continue;  // found again at a later step: said once
      if (sc->holds.no()) empty = true;
      if (sc->holds.unknown()) open = true;
      out.source_conditions.push_back(*sc);
    }
    // an undecided condition leaves the tower undecided from here — unless another of the same step fails:
    // then M_{k+1} = ∅ whatever the undecided one does
    if (open && !empty) certain = false;
    if (empty) {  // no velocity exists anywhere on M_k for generic t: M_{k+1} = ∅
      out.tower.push_back({-1, {}});
      out.consistent = false;
      out.steps = static_cast<long>(k + 1);
      break;
    }
    if (l.fresh_c.rows() == 0) {  // nothing new: M_{k+1} = M_k = M_c
      out.steps = static_cast<long>(k);
      break;
    }
    Level<Rational> level;
    level.dim = static_cast<long>(l.dim());
    for (Index i = 0; i < l.fresh_c.rows(); ++i) level.constraints.push_back(equation(l.fresh_c, l.fresh_g, i));
    out.tower.push_back(level);
  }
  if (out.consistent) {
    const IdeLevel<Rational>& last = t.levels.back();
    out.solution_rank = static_cast<long>(t.solution_rank());
    std::vector<Equation<Rational>> fin;
    for (Index i = 0; i < last.c.rows(); ++i) fin.push_back(equation(last.c, last.g, i));
    out.final_constraints = fin;
    out.motion = dae_motion(t, n, used, column, out.jets);
  }
  if (c.e.rows() == c.e.cols()) out.regular_pencil = regular_pencil(c.e, c.a);
  out.certified = certain ? yes : unknown;
  out.note =
      "CEF (1.6) on E x' = A x + f(t), exact (reference/linear_ide.hpp): M_k(t) = {C x = G u(t)}, u the sources' jets";
  if (!certain) out.note += "; a condition on the sources was not decided (source_conditions)";
  return out;
}

}  // namespace dcad::reference::pipeline
