// The CAD of a Lagrangian system given by formulas, at a point (CEF §5–§6 for D̄_Δ, YM §4 forces,
// V §3 time dependence), by local reduction in the sense of Rabier–Rheinboldt.  Written once over
// the scalar T and a decision object: ExactDecisions<Rational> here (zero means == 0), a tolerance
// with evidence in fast/pointwise.hpp.
//
// M_1 = {p = ∂L/∂v, a(t,q)·v + b(t,q) = 0} (CEF (6.20), YM (5.2)–(5.3)), a graph over the chart
// (t, q, v_free).  On M_k, in a chart s (a subset of the variables t, q, v, the others being functions
// of s), the definition of the CAD,
//     M_{k+1} = {x ∈ M_k : some ẋ ∈ T_x M_k has (ẋ, dE(x) − F) ∈ D̄_Δ(x)}       [CEF Lemma 5.1, Remark 5.2]
// reads: the linear system for (ṡ, λ)
//     Dq·ṡ + ∂_t q = v                         (q̇ = v)
//     DP·ṡ + ∂_t P − aᵀλ = ∂L/∂q + F           (ṗ − ∂L/∂q − F ∈ Δ°, P = ∂L/∂v on M_k)
//     a·(Dq·ṡ + ∂_t q) + b = 0                 (q̇ ∈ Δ_aff)
// is solvable.  Near the point its rank is its rank at the point if, after eliminating with
// pivots that are nonzero at the point, the rest of the matrix vanishes on M_k; then the system is
// solvable iff the eliminated right-hand sides ψ (Fredholm) vanish: they are the new constraints.
// Everything is computed on jets (jet.hpp): the rest of the matrix and the ψ are series on M_k,
// so "vanishes on M_k" is a zero test of a series, known to the jet's order.  A point where a
// pivot or a constraint's differential vanishes although the series does not is singular (the
// rank drops there): it is reported, never used.  M_{k+1} is then the graph of the solved
// coordinates over the rest, found as series by Newton's method on jets.
//
// The point: values given by the user are kept; the others start at the given defaults and move
// by Newton steps onto each M_k in turn (exactly: the exact route stops if no rational point is
// reached, which happens only for constraints that are not affine in the coordinates it moves).
#pragma once

#include "dcad/reference/jet.hpp"
#include "dcad/reference/lagrangian_system.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dcad::reference {

/// Zero tests of the exact route: x == 0.  Pivots: the first nonzero candidate.  (The double
/// route, fast/pointwise.hpp, decides each number relative to the magnitude it was computed from.)
template <class T>
struct ExactDecisions {
  /// The step's data (the constant terms of its linear system), before its decisions.  A route in
  /// floating point uses it to see graded data, where no zero can be certain; here nothing.
  void step_data(const std::vector<T>&) {}
  bool zero(const T& x) { return x == 0; }
  bool zero(const Jet<T>& j) { return j.is_zero(); }
  /// A value taken as zero that one more Newton step could still make smaller (rounding routes).
  bool polish(const T&) { return false; }
  /// The index of the pivot among `values`, or values.size() if all are zero.
  std::size_t pivot(const std::vector<T>& values) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (values[i] != 0) return i;
    return values.size();
  }
};

template <class T>
struct PointwisePivot {
  std::string row, column;
  T value;
};

/// A constraint added at some step: solved for one chart coordinate; its tangent equation at the
/// point, Σ_j g_j s_j = rhs over the chart of the previous M_k (g of the solved coordinate is 1).
template <class T>
struct PointwiseConstraint {
  std::size_t solved_for = 0;  ///< a variable index (q, v or t of LagrangianSystem)
  std::vector<std::pair<std::size_t, T>> gradient;
  T rhs = T(0);
};

template <class T>
struct PointwiseLevel {
  long dim = 0;                      ///< dim M_k (at fixed time)
  std::vector<std::size_t> chart;    ///< its coordinates (variable indices), time first if any
  std::vector<PointwiseConstraint<T>> added;  ///< the constraints that cut M_k out of M_{k−1}
  std::vector<PointwisePivot<T>> pivots;      ///< of the (ṡ, λ) system on M_k
};

template <class T>
struct PointwiseResult {
  std::vector<long> dims;  ///< dim M_k, k = 0…c (−1: empty)
  std::size_t steps = 0;
  bool consistent = true;
  bool regular = true;     ///< false: a rank drops at the point (`why`); dims are then partial
  std::string why;
  std::size_t solution_rank = 0;
  std::vector<T> point;    ///< (q, v, p) at the point, 3n values
  T time = T(0);
  std::vector<T> velocity;               ///< ẋ at the point, one solution (3n)
  std::vector<std::vector<T>> gauge;     ///< a basis of the other solutions' differences (solution_rank rows)
  std::vector<std::vector<T>> tangent;   ///< a basis of T_x M_c (at fixed time) in x = (q, v, p): ∂x/∂s_j, s M_c's chart
  std::vector<PointwiseLevel<T>> levels; ///< levels[k] describes M_{k+1}
  long order = 0;          ///< jets were computed to this order
  long checked_order = 0;  ///< the last step's constraints vanish on M_c to this order
  std::size_t moves = 0;   ///< Newton steps that moved the given point onto M_c
  /// The coordinates solved for at each step: plan[0] the dependent velocities of M_1, plan[k] those
  /// of M_{k+1}.  Given back to pointwise_cad at a nearby point, the same choices are made there
  /// (where their pivots are nonzero): the projection onto M_c is then one fixed map.
  std::vector<std::vector<std::size_t>> plan;
};

/// Thrown when the point cannot be completed to a point of M_c (the exact route at a point with
/// irrational coordinates, or given values that conflict with a constraint).
struct PointwiseNoPoint : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

namespace pointwise_detail {

/// Gaussian elimination on constant rows, pivots taken group by group: within a group the decision
/// object picks among all (row, column) candidates in column order — the exact route the first
/// nonzero, the double route the first that is at least 1/8 of the largest (threshold pivoting, so
/// that a chart is never built on a small pivot, like v_theta = v_x/(R cos phi) near phi = pi/2,
/// and is otherwise the preferred one) — and only when a group has no pivot left does the next come.  Returns the pivots (row, column); rows and rhs are reduced.
template <class T, class Decide>
std::vector<std::pair<std::size_t, std::size_t>> eliminate_constants(std::vector<std::vector<T>>& rows, std::vector<T>& rhs,
                                                                       const std::vector<std::vector<std::size_t>>& groups, Decide& decide) {
  std::vector<std::pair<std::size_t, std::size_t>> piv;
  std::vector<char> used(rows.size(), 0);
  std::vector<std::size_t> used_cols;
  for (const auto& group : groups)
    for (;;) {
      std::vector<std::pair<std::size_t, std::size_t>> cand;
      std::vector<T> vals;
      for (std::size_t c : group) {
        if (std::find(used_cols.begin(), used_cols.end(), c) != used_cols.end()) continue;
        for (std::size_t i = 0; i < rows.size(); ++i)
          if (!used[i]) {
            cand.emplace_back(i, c);
            vals.push_back(rows[i][c]);
          }
      }
      const std::size_t k = decide.pivot(vals);
      if (k == vals.size()) break;
      const auto [p, c] = cand[k];
      used[p] = 1;
      used_cols.push_back(c);
      piv.emplace_back(p, c);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (i == p || rows[i][c] == 0) continue;
        const T f = rows[i][c] / rows[p][c];
        for (std::size_t j = 0; j < rows[i].size(); ++j) rows[i][j] -= f * rows[p][j];
        rhs[i] -= f * rhs[p];
        rows[i][c] = T(0);
      }
    }
  return piv;
}

/// The same with one group: columns in `col_order`.
template <class T, class Decide>
std::vector<std::pair<std::size_t, std::size_t>> eliminate_constants(std::vector<std::vector<T>>& rows, std::vector<T>& rhs,
                                                                       const std::vector<std::size_t>& col_order, Decide& decide) {
  return eliminate_constants(rows, rhs, std::vector<std::vector<std::size_t>>{col_order}, decide);
}

/// Elimination of jet rows R (with right-hand sides h) by pivots nonzero at the point.  The rows
/// left without a pivot must vanish identically (else the rank drops at the point: `singular`);
/// their right-hand sides are the Fredholm candidates.
template <class T>
struct JetElimination {
  std::vector<std::pair<std::size_t, std::size_t>> pivots;
  std::vector<std::size_t> free_rows;
  std::vector<Jet<T>> candidates;
  std::string singular;  ///< empty if regular
};

template <class T, class Decide>
JetElimination<T> eliminate_jets(std::vector<std::vector<Jet<T>>> r, std::vector<Jet<T>> h, Decide& decide,
                                 const std::vector<std::string>& row_names, const std::vector<std::string>& col_names) {
  JetElimination<T> out;
  const std::size_t rows = r.size(), cols = rows ? r[0].size() : 0;
  std::vector<char> used(rows, 0);
  for (std::size_t c = 0; c < cols; ++c) {
    std::vector<std::size_t> cand;
    std::vector<T> vals;
    for (std::size_t i = 0; i < rows; ++i)
      if (!used[i]) {
        cand.push_back(i);
        vals.push_back(r[i][c].value());
      }
    const std::size_t k = decide.pivot(vals);
    if (k == vals.size()) continue;
    const std::size_t p = cand[k];
    used[p] = 1;
    out.pivots.emplace_back(p, c);
    const Jet<T> inv = r[p][c].reciprocal();
    for (std::size_t i = 0; i < rows; ++i) {
      if (used[i] || r[i][c].is_zero()) continue;
      const Jet<T> f = r[i][c] * inv;
      // every column: one skipped for want of a pivot is 0 at the point but not as a series
      for (std::size_t j = 0; j < cols; ++j) r[i][j] -= f * r[p][j];
      h[i] -= f * h[p];
    }
  }
  for (std::size_t i = 0; i < rows; ++i) {
    if (used[i]) continue;
    for (std::size_t c = 0; c < cols && out.singular.empty(); ++c)
      if (!decide.zero(r[i][c]))
        out.singular = "the rank of the system for (d/dt s, lambda) drops at the point: after the pivots, row " + row_names[i] +
                       " keeps a nonzero series in column " + col_names[c] + " that vanishes at the point";
    out.free_rows.push_back(i);
    out.candidates.push_back(h[i]);
  }
  return out;
}

}  // namespace pointwise_detail

/// The pointwise CAD of `sys` near `start` (values of q, v and t, indices as in LagrangianSystem;
/// `fixed[i]`: the user gave variable i, never move it).  `constant` turns exact input numbers into
/// T.  Jets are computed to order `order` and more if the tower needs it.  `plan`: another result's
/// plan, to make the same choice of solved coordinates where it works (simulate's projections).
template <class T, class Decide>
PointwiseResult<T> pointwise_cad(const LagrangianSystem& sys, std::vector<T> start, const std::vector<bool>& fixed,
                                 Decide& decide, const std::function<T(const Rational&)>& constant, long order = 3,
                                 std::size_t max_moves = 12, const std::vector<std::vector<std::size_t>>* plan = nullptr);

// ------------------------------------------------------------------------------------------------

namespace pointwise_detail {

template <class T, class Decide>
class Run {
 public:
  using J = Jet<T>;
  Run(const LagrangianSystem& sys, const LagrangianDerivatives& der, const std::vector<bool>& fixed, Decide& decide,
      const std::function<T(const Rational&)>& constant, const std::vector<std::vector<std::size_t>>* plan, std::size_t& polished)
      : polished_(polished), s_(sys), d_(der), fixed_(fixed), decide_(decide), constant_(constant), names_(sys.variable_names()), plan_(plan) {}

  enum class Outcome { Done, Moved, MoreOrder };

  /// One pass at `point` with jets to order K: the tower (Done), or a better point (Moved), or
  /// the jets ran out of order before the tower ended (MoreOrder).
  Outcome pass(std::vector<T>& point, long K, PointwiseResult<T>& out) {
    for (T& x : point) x = JetFunctions<T>::as_input(x);
    out = PointwiseResult<T>();
    out.order = K;
    const std::size_t n = s_.n;
    out.dims.push_back(static_cast<long>(3 * n));
    // ---- M_1: solve a(t, q) v_dep = −(a v_free + b) for m velocities (pivots nonzero at the point)
    std::vector<std::vector<T>> a0(s_.m(), std::vector<T>(2 * n + 1, T(0)));
    std::vector<T> b0(s_.m());
    for (std::size_t a = 0; a < s_.m(); ++a)
      for (std::size_t i = 0; i < n; ++i) a0[a][s_.v(i)] = value(d_.a[a][i], point);
    const auto vel_pref = preference(true, false);
    std::vector<std::vector<T>> a0r = a0;
    auto vp = eliminate_constants(a0r, b0, vel_pref, decide_);
    if (planned(0)) {
      std::vector<std::vector<T>> a0p = a0;
      std::vector<T> b0p = b0;
      const auto alt = eliminate_constants(a0p, b0p, (*plan_)[0], decide_);
      if (alt.size() == vp.size()) vp = alt;
    }
    out.plan.emplace_back();
    for (const auto& pc : vp) out.plan.back().push_back(pc.second);
    if (vp.size() < s_.m()) {
      out.regular = false;
      out.why = "the constraints' velocity coefficients have rank " + std::to_string(vp.size()) + " < " + std::to_string(s_.m()) +
                " at the point (dependent constraints, or a point where Delta changes dimension)";
      out.point.assign(3 * n, T(0));  // the point as given: (q, v, p = ∂L/∂v)
      for (std::size_t i = 0; i < 2 * n; ++i) out.point[i] = point[i];
      for (std::size_t i = 0; i < n; ++i) out.point[2 * n + i] = value(d_.dl_dv[i], point);
      out.time = point[s_.t()];
      return Outcome::Done;
    }
    std::vector<char> dependent(2 * n + 1, 0);
    for (const auto& pc : vp) dependent[pc.second] = 1;
    std::vector<std::size_t> chart;
    if (s_.has_time) chart.push_back(s_.t());
    for (std::size_t i = 0; i < n; ++i) chart.push_back(s_.q(i));
    for (std::size_t i = 0; i < n; ++i)
      if (!dependent[s_.v(i)]) chart.push_back(s_.v(i));
    auto space = std::make_shared<const JetSpace>(chart.size(), static_cast<std::size_t>(K));
    std::vector<J> x(2 * n + 1);
    for (std::size_t j = 0; j < chart.size(); ++j) x[chart[j]] = J::variable(space, j, point[chart[j]]);
    if (!s_.has_time) x[s_.t()] = J(space, point[s_.t()]);
    for (std::size_t i = 0; i < n; ++i)
      if (dependent[s_.v(i)]) x[s_.v(i)] = J(space, T(0));
    {  // Σ_{dep} a_ai v_i = −b_a − Σ_{free} a_ai v_i, eliminated with the pivots chosen above
      std::vector<std::vector<J>> r(s_.m());
      std::vector<J> h(s_.m());
      std::vector<std::size_t> dep_cols;
      for (const auto& pc : vp) dep_cols.push_back(pc.second);
      for (std::size_t a = 0; a < s_.m(); ++a) {
        h[a] = -eval(d_.b[a], x);
        for (std::size_t i = 0; i < n; ++i) {
          const J c = eval(d_.a[a][i], x);
          if (dependent[s_.v(i)]) continue;
          h[a] -= c * x[s_.v(i)];
        }
        for (std::size_t col : dep_cols) r[a].push_back(eval(d_.a[a][col - n], x));
      }
      const std::vector<J> sol = solve_square(r, h);
      for (std::size_t k = 0; k < dep_cols.size(); ++k) {
        x[dep_cols[k]] = sol[k];
        point[dep_cols[k]] = sol[k].value();
      }
    }
    PointwiseLevel<T> lvl;
    lvl.dim = static_cast<long>(chart.size() - (s_.has_time ? 1 : 0));
    lvl.chart = chart;
    out.dims.push_back(lvl.dim);
    // ---- M_k → M_{k+1}
    for (std::size_t k = 1;; ++k) {
      System sys = build(x, chart);
      {
        std::vector<T> data;
        for (const auto& row : sys.r)
          for (const J& v : row) data.push_back(v.value());
        for (const J& v : sys.h) data.push_back(v.value());
        decide_.step_data(data);
      }
      JetElimination<T> e = eliminate_jets(sys.r, sys.h, decide_, sys.row_names, sys.col_names);
      for (const auto& pc : e.pivots) lvl.pivots.push_back({sys.row_names[pc.first], sys.col_names[pc.second], sys.r[pc.first][pc.second].value()});
      if (!e.singular.empty()) {
        out.levels.push_back(lvl);
        out.regular = false;
        out.why = "on M_" + std::to_string(k) + ": " + e.singular;
        out.steps = out.dims.size() - 1;
        finish(out, point, x);
        return Outcome::Done;
      }
      // values at the point: all zero, or move the point onto M_{k+1}
      bool on = true, polish = false;
      for (const J& c : e.candidates) {
        on = on && decide_.zero(c.value());
        polish = polish || decide_.polish(c.value());
      }
      if (on && polish && e.candidates.size() && polished_ < 4) {  // within the error bound, but Newton can do better
        ++polished_;
        on = false;
      }
      long ord = std::numeric_limits<long>::max();
      for (const J& c : e.candidates) ord = std::min(ord, c.order());
      if (e.candidates.empty()) ord = K;
      if (!on) {
        if (ord < 1) return Outcome::MoreOrder;
        if (move(e.candidates, chart, x, point, k, out)) return Outcome::Moved;
        out.levels.push_back(lvl);
        finish(out, point, x);
        return Outcome::Done;  // inconsistent (out says so)
      }
      if (ord < 1) return Outcome::MoreOrder;
      // the new independent constraints: gradients in the non-time chart coordinates
      const auto cols = chart_preference(chart);
      std::vector<std::vector<T>> g(e.candidates.size(), std::vector<T>(chart.size(), T(0)));
      for (std::size_t i = 0; i < e.candidates.size(); ++i)
        for (std::size_t j = 0; j < chart.size(); ++j) g[i][j] = e.candidates[i].gradient(j);
      std::vector<std::vector<T>> gr = g;
      std::vector<T> zero_rhs(g.size(), T(0));
      auto gp = eliminate_constants(gr, zero_rhs, cols, decide_);
      if (planned(k) && !gp.empty()) {  // the plan's coordinates, if they carry the same rank
        std::vector<std::vector<T>> gq = g;
        std::vector<T> zq(g.size(), T(0));
        const auto alt = eliminate_constants(gq, zq, positions_in(chart, (*plan_)[k]), decide_);
        if (alt.size() == gp.size()) {
          gp = alt;
          gr = gq;
        }
      }
      if (gp.empty()) {  // M_{k+1} = M_k: every candidate must vanish on M_k
        out.levels.push_back(lvl);
        for (std::size_t i = 0; i < e.candidates.size(); ++i) {
          if (decide_.zero(e.candidates[i])) continue;
          if (time_only(g[i], chart)) {
            if (out.consistent) out.dims.push_back(-1);
            out.consistent = false;
            out.why = "step " + std::to_string(k) + " gives a condition on the time alone: M_" + std::to_string(k + 1) +
                      "(t) is empty at generic times";
          } else {
            out.regular = false;
            out.why = "on M_" + std::to_string(k) + ": a constraint vanishes with its differential at the point but not identically";
          }
        }
        out.steps = out.dims.size() - 1;
        out.checked_order = ord;
        if (out.consistent && out.regular) solutions(sys, x, chart, out);
        finish(out, point, x);
        return Outcome::Done;
      }
      // M_{k+1}: the graph of the pivot coordinates over the others
      std::vector<std::size_t> sel_rows, dep_idx;
      for (const auto& pc : gp) {
        sel_rows.push_back(pc.first);
        dep_idx.push_back(pc.second);
      }
      PointwiseLevel<T> next;
      // reduced rows (Gauss–Jordan): each has 1 pivot among the solved coordinates, so it names the one it is solved for
      for (std::size_t r = 0; r < gp.size(); ++r) next.added.push_back(tangent(gr[sel_rows[r]], chart, dep_idx[r], point));
      out.plan.emplace_back();
      for (std::size_t j : dep_idx) out.plan.back().push_back(chart[j]);
      std::vector<std::size_t> new_chart;
      std::vector<char> is_dep(chart.size(), 0);
      for (std::size_t j : dep_idx) is_dep[j] = 1;
      for (std::size_t j = 0; j < chart.size(); ++j)
        if (!is_dep[j]) new_chart.push_back(chart[j]);
      auto nspace = std::make_shared<const JetSpace>(new_chart.size(), static_cast<std::size_t>(K));
      std::vector<J> subs(chart.size());
      for (std::size_t j = 0, u = 0; j < chart.size(); ++j)
        subs[j] = is_dep[j] ? J(nspace, point[chart[j]]) : J::variable(nspace, u++, point[chart[j]]);
      newton_graph(e.candidates, sel_rows, dep_idx, g, subs, ord);
      for (const J& c : e.candidates)
        if (!decide_.zero(c.compose(subs))) {
          out.levels.push_back(lvl);
          out.regular = false;
          out.why = "on M_" + std::to_string(k + 1) + ": a constraint of step " + std::to_string(k) +
                    " vanishes with its differential at the point but not identically on M_" + std::to_string(k + 1);
          out.steps = out.dims.size() - 1;
          finish(out, point, x);
          return Outcome::Done;
        }
      for (J& xi : x) xi = xi.compose(subs);
      out.levels.push_back(lvl);
      chart = new_chart;
      next.chart = chart;
      next.dim = static_cast<long>(chart.size() - (s_.has_time ? 1 : 0));
      out.dims.push_back(next.dim);
      lvl = next;
      if (lvl.dim < 0) throw std::logic_error("pointwise_cad: negative dimension");
    }
  }

 private:
  struct System {
    std::vector<std::vector<J>> r;
    std::vector<J> h;
    std::vector<std::string> row_names, col_names;
    std::vector<J> p;                    ///< P = ∂L/∂v on M_k
    std::vector<std::vector<J>> dq, dp;  ///< ∂q_i/∂s_j, ∂P_i/∂s_j (non-time chart coordinates)
    std::vector<J> tq, tp;               ///< ∂q_i/∂t, ∂P_i/∂t
  };

  /// e at the point (constant jets: the scalar functions of JetFunctions, exact or not at all).
  T value(const expr::Expr& e, const std::vector<T>& point) {
    static const auto none = std::make_shared<const JetSpace>(0, 0);
    std::vector<J> c;
    for (const T& v : point) c.push_back(J(none, v));
    return eval(e, c).value();
  }
  J eval(const expr::Expr& e, const std::vector<J>& x) {
    const auto& sp = x[0].space();
    return expr::evaluate<J>(e, x, [&](const Rational& q) { return J(sp, constant_(q)); });
  }

  /// Variable indices in groups, in the order to prefer them as *dependent* coordinates: free
  /// velocities, given velocities, free positions, given positions (later before earlier inside).
  std::vector<std::vector<std::size_t>> preference(bool velocities, bool positions) const {
    std::vector<std::vector<std::size_t>> out;
    for (int kind = 0; kind < 2; ++kind) {
      if ((kind == 0 && !velocities) || (kind == 1 && !positions)) continue;
      for (int pass = 0; pass < 2; ++pass) {
        out.emplace_back();
        for (std::size_t i = s_.n; i-- > 0;) {
          const std::size_t var = kind == 0 ? s_.v(i) : s_.q(i);
          if (fixed_[var] == (pass == 1)) out.back().push_back(var);
        }
      }
    }
    return out;
  }
  /// The same groups as chart positions (never the time); `movable`: only coordinates not given.
  std::vector<std::vector<std::size_t>> chart_preference(const std::vector<std::size_t>& chart, bool movable = false) const {
    std::vector<std::vector<std::size_t>> out;
    for (const auto& group : preference(true, true)) {
      out.emplace_back();
      for (std::size_t var : group)
        for (std::size_t j = 0; j < chart.size(); ++j)
          if (chart[j] == var && !(movable && fixed_[var])) out.back().push_back(j);
    }
    return out;
  }
  bool time_only(const std::vector<T>& grad, const std::vector<std::size_t>& chart) {
    bool t_nonzero = false;
    for (std::size_t j = 0; j < chart.size(); ++j) {
      if (chart[j] == s_.t()) t_nonzero = !decide_.zero(grad[j]);
      else if (!decide_.zero(grad[j])) return false;
    }
    return t_nonzero;
  }

  /// Square jet system r·z = h with pivots nonzero at the point (Gauss–Jordan on jets).
  std::vector<J> solve_square(std::vector<std::vector<J>> r, std::vector<J> h) {
    const std::size_t n = r.size();
    for (std::size_t c = 0; c < n; ++c) {
      std::size_t p = c;
      std::vector<T> vals;
      for (std::size_t i = c; i < n; ++i) vals.push_back(r[i][c].value());
      p = c + largest(vals);
      if (p >= n) throw std::logic_error("pointwise_cad: singular square system after a rank check");
      std::swap(r[p], r[c]);
      std::swap(h[p], h[c]);
      const J inv = r[c][c].reciprocal();
      for (std::size_t j = c; j < n; ++j) r[c][j] = r[c][j] * inv;
      h[c] = h[c] * inv;
      for (std::size_t i = 0; i < n; ++i) {
        if (i == c || r[i][c].is_zero()) continue;
        const J f = r[i][c];
        for (std::size_t j = c; j < n; ++j) r[i][j] -= f * r[c][j];
        h[i] -= f * h[c];
      }
    }
    return h;
  }

  /// The linear system for (ṡ, λ) on M_k (header comment), as jets in the chart.
  System build(const std::vector<J>& x, const std::vector<std::size_t>& chart) {
    const std::size_t n = s_.n, m = s_.m();
    System sys;
    std::vector<std::size_t> moving;  // chart positions of the non-time coordinates
    std::size_t tpos = chart.size();
    for (std::size_t j = 0; j < chart.size(); ++j) {
      if (chart[j] == s_.t()) tpos = j;
      else moving.push_back(j);
    }
    std::vector<J> p(n), lq(n), f(n), b(m);
    std::vector<std::vector<J>> a(m, std::vector<J>(n));
    for (std::size_t i = 0; i < n; ++i) {
      p[i] = eval(d_.dl_dv[i], x);
      lq[i] = eval(d_.dl_dq[i], x);
      f[i] = s_.forces.empty() ? J(x[0].space(), T(0)) : eval(s_.forces[i], x);
    }
    for (std::size_t c = 0; c < m; ++c) {
      b[c] = eval(d_.b[c], x);
      for (std::size_t i = 0; i < n; ++i) a[c][i] = eval(d_.a[c][i], x);
    }
    const J zero(x[0].space(), T(0));
    sys.p = p;
    sys.dq.assign(n, {});
    sys.dp.assign(n, {});
    sys.tq.assign(n, zero);
    sys.tp.assign(n, zero);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j : moving) {
        sys.dq[i].push_back(x[s_.q(i)].derivative(j));
        sys.dp[i].push_back(p[i].derivative(j));
      }
      if (tpos < chart.size()) {
        sys.tq[i] = x[s_.q(i)].derivative(tpos);
        sys.tp[i] = p[i].derivative(tpos);
      }
    }
    const std::vector<std::string> st = s_.state_names();
    for (std::size_t j : moving) sys.col_names.push_back("d/dt " + names_[chart[j]]);
    for (std::size_t c = 0; c < m; ++c) sys.col_names.push_back("lambda_" + std::to_string(c + 1));
    const std::size_t w = moving.size() + m;
    for (std::size_t i = 0; i < n; ++i) {  // q̇ = v
      std::vector<J> row(w, zero);
      for (std::size_t j = 0; j < moving.size(); ++j) row[j] = sys.dq[i][j];
      sys.r.push_back(row);
      sys.h.push_back(x[s_.v(i)] - sys.tq[i]);
      sys.row_names.push_back("d/dt " + st[i] + " = " + st[n + i]);
    }
    for (std::size_t i = 0; i < n; ++i) {  // ṗ − ∂L/∂q − F − aᵀλ = 0
      std::vector<J> row(w, zero);
      for (std::size_t j = 0; j < moving.size(); ++j) row[j] = sys.dp[i][j];
      for (std::size_t c = 0; c < m; ++c) row[moving.size() + c] = -a[c][i];
      sys.r.push_back(row);
      sys.h.push_back(lq[i] + f[i] - sys.tp[i]);
      sys.row_names.push_back("d/dt " + st[2 * n + i]);
    }
    for (std::size_t c = 0; c < m; ++c) {  // a·q̇ + b = 0
      std::vector<J> row(w, zero);
      J rhs = -b[c];
      for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = 0; j < moving.size(); ++j) row[j] += a[c][i] * sys.dq[i][j];
        rhs -= a[c][i] * sys.tq[i];
      }
      sys.r.push_back(row);
      sys.h.push_back(rhs);
      sys.row_names.push_back("constraint " + std::to_string(c + 1));
    }
    return sys;
  }

  /// Σ_j g_j s_j = Σ_j g_j s_j(point), scaled so that the solved coordinate has coefficient 1.
  PointwiseConstraint<T> tangent(const std::vector<T>& g, const std::vector<std::size_t>& chart, std::size_t solved,
                                 const std::vector<T>& point) {
    PointwiseConstraint<T> c;
    c.solved_for = chart[solved];
    const T scale = g[solved];
    for (std::size_t j = 0; j < chart.size(); ++j)
      if (!decide_.zero(g[j])) {
        c.gradient.emplace_back(chart[j], g[j] / scale);
        c.rhs += g[j] / scale * point[chart[j]];
      }
    return c;
  }

  /// subs[dep] as series over the new chart with ψ_sel(subs) = 0: Newton's method with the
  /// Jacobian at the point (each iteration gains at least one order).
  void newton_graph(const std::vector<J>& cand, const std::vector<std::size_t>& rows, const std::vector<std::size_t>& dep,
                    const std::vector<std::vector<T>>& g, std::vector<J>& subs, long ord) {
    const std::size_t r = rows.size();
    std::vector<std::vector<T>> jac(r, std::vector<T>(r));
    for (std::size_t i = 0; i < r; ++i)
      for (std::size_t k = 0; k < r; ++k) jac[i][k] = g[rows[i]][dep[k]];
    const std::vector<std::vector<T>> inv = inverse(jac);
    for (long it = 0; it <= ord + 1; ++it) {
      std::vector<J> res;
      for (std::size_t i = 0; i < r; ++i) res.push_back(cand[rows[i]].compose(subs));
      for (std::size_t k = 0; k < r; ++k)
        for (std::size_t i = 0; i < r; ++i)
          if (!decide_.zero(inv[k][i])) subs[dep[k]] -= res[i] * J(res[i].space(), inv[k][i]);
    }
    for (std::size_t k = 0; k < r; ++k) subs[dep[k]].set_order(ord);
    if constexpr (JetFunctions<T>::tracks_error) {
      // Newton corrects its own errors, which a running bound cannot see (it would compound them
      // over the iterations): the solution's error is that of its last residual through J⁻¹.
      const std::size_t known = subs[0].space()->count_up_to(static_cast<std::size_t>(std::max(ord, 0L)));
      for (std::size_t k = 0; k < r; ++k)
        for (std::size_t c = 0; c < known; ++c)
          subs[dep[k]].set_coefficient(c, JetFunctions<T>::with_error(subs[dep[k]].coefficient(c), T(0)));
      std::vector<J> res;
      for (std::size_t i = 0; i < r; ++i) res.push_back(cand[rows[i]].compose(subs));
      for (std::size_t k = 0; k < r; ++k)
        for (std::size_t c = 0; c < known; ++c)
          subs[dep[k]].set_coefficient(c, JetFunctions<T>::with_error(subs[dep[k]].coefficient(c), absolute_sum(inv[k], res, c)));
    }
  }

  /// Σ_i |inv_i| (|res_i[c]| + err): a bound of J⁻¹·res at coefficient c (for tracked scalars).
  T absolute_sum(const std::vector<T>& inv_row, const std::vector<J>& res, std::size_t c) {
    T s(0);
    for (std::size_t i = 0; i < inv_row.size(); ++i) {
      const T x = inv_row[i] * res[i].coefficient(c);
      s = s + JetFunctions<T>::with_error(T(0), x);
    }
    return s;
  }

  std::vector<std::vector<T>> inverse(std::vector<std::vector<T>> a) {
    const std::size_t n = a.size();
    std::vector<std::vector<T>> inv(n, std::vector<T>(n, T(0)));
    for (std::size_t i = 0; i < n; ++i) inv[i][i] = T(1);
    for (std::size_t c = 0; c < n; ++c) {
      std::vector<T> vals;
      for (std::size_t i = c; i < n; ++i) vals.push_back(a[i][c]);
      const std::size_t p = c + largest(vals);
      if (p >= n) throw std::logic_error("pointwise_cad: singular Jacobian after a rank check");
      std::swap(a[p], a[c]);
      std::swap(inv[p], inv[c]);
      const T d = a[c][c];
      for (std::size_t j = 0; j < n; ++j) {
        a[c][j] /= d;
        inv[c][j] /= d;
      }
      for (std::size_t i = 0; i < n; ++i) {
        if (i == c || a[i][c] == 0) continue;
        const T f = a[i][c];
        for (std::size_t j = 0; j < n; ++j) {
          a[i][j] -= f * a[c][j];
          inv[i][j] -= f * inv[c][j];
        }
      }
    }
    return inv;
  }

  /// The point is not on M_{k+1}: one Newton step on the candidates in the coordinates that may
  /// move.  False (and `out` says why) if no move can satisfy them: M_{k+1} is empty near here.
  bool move(const std::vector<J>& cand, const std::vector<std::size_t>& chart, const std::vector<J>& x, std::vector<T>& point,
            std::size_t k, PointwiseResult<T>& out) {
    std::vector<std::vector<T>> g(cand.size(), std::vector<T>(chart.size(), T(0)));
    std::vector<T> rhs(cand.size());
    for (std::size_t i = 0; i < cand.size(); ++i) {
      rhs[i] = -cand[i].value();
      for (std::size_t j = 0; j < chart.size(); ++j) g[i][j] = cand[i].gradient(j);
    }
    // a Newton step changes, for each constraint, the movable coordinate it depends on most (complete
    // pivoting by magnitude, in both routes): preferring velocities, as charts do, would fix the
    // pendulum's multiplier constraint mu = m (v² − g y)/|q|² by changing v instead of mu
    std::vector<std::size_t> movable;
    if (planned(k)) {  // the plan's solved coordinates: the projection is the graph map of its chart
      for (std::size_t j : positions_in(chart, (*plan_)[k]))
        if (!fixed_[chart[j]]) movable.push_back(j);
    } else {
      for (const auto& group : chart_preference(chart, true)) movable.insert(movable.end(), group.begin(), group.end());
    }
    std::vector<std::vector<T>> gr = g;
    Largest largest{decide_};
    const auto piv = eliminate_constants(gr, rhs, movable, largest);
    std::vector<char> prow(cand.size(), 0);
    for (const auto& pc : piv) prow[pc.first] = 1;
    std::size_t rank_all = 0;  // the rank of the candidates' differentials over every coordinate but the time
    {
      std::vector<std::vector<T>> ga = g;
      std::vector<T> za(g.size(), T(0));
      std::vector<std::size_t> all;
      for (const auto& group : chart_preference(chart)) all.insert(all.end(), group.begin(), group.end());
      rank_all = eliminate_constants(ga, za, all, decide_).size();
    }
    for (std::size_t i = 0; i < cand.size(); ++i) {
      if (prow[i] || decide_.zero(rhs[i])) continue;
      bool constant = true;  // the candidate is a nonzero constant near the point: M_{k+1} = ∅
      for (const auto& [idx, c] : cand[i].entries()) constant = constant && (idx == 0 || decide_.zero(c));
      std::vector<T> gi = g[i];
      if (constant) {
        out.consistent = false;
        out.dims.push_back(-1);
        out.steps = out.dims.size() - 1;
        out.why = "step " + std::to_string(k) + " requires 0 = " + JetFunctions<T>::text(cand[i].value()) + ": M_" + std::to_string(k + 1) +
                  " is empty";
        return false;
      }
      if (time_only(gi, chart)) {
        out.consistent = false;
        out.dims.push_back(-1);
        out.steps = out.dims.size() - 1;
        out.why = "step " + std::to_string(k) + " gives a condition on the time alone, violated at t = " + JetFunctions<T>::text(point[s_.t()]) +
                  ": M_" + std::to_string(k + 1) + "(t) is empty there";
        return false;
      }
      if (piv.size() < rank_all) {  // the constraints need more freedom than the movable coordinates give
        std::string given;
        for (std::size_t j = 0; j < chart.size(); ++j)
          if (fixed_[chart[j]] && !decide_.zero(g[i][j])) given += (given.empty() ? "" : ", ") + names_[chart[j]];
        throw PointwiseNoPoint("the given values (" + given + ") violate a constraint of M_" + std::to_string(k + 1) + " (residual " +
                               JetFunctions<T>::text(cand[i].value()) + ") that no other coordinate can satisfy");
      }
      // otherwise a redundant candidate: it vanishes on M_{k+1}, where the independent ones bring the point
    }
    std::vector<T> delta(chart.size(), T(0));
    // each constraint moves its pivot coordinate: exactly, a constraint affine in it lands in one step
    for (const auto& pc : piv) delta[pc.second] = rhs[pc.first] / gr[pc.first][pc.second];
    if constexpr (JetFunctions<T>::tracks_error) {
      // rounding routes: the minimum-norm step instead (δ minus its part in ker A, A the independent
      // constraints' gradients over the movable coordinates), a smooth projection — the pivot
      // coordinates flip between nearby points, and so would the projected vector field
      std::vector<std::vector<T>> nulls;  // ker A from the reduced rows: one vector per free column
      for (std::size_t f : movable) {
        if (std::any_of(piv.begin(), piv.end(), [&](const auto& pc) { return pc.second == f; })) continue;
        std::vector<T> v(chart.size(), T(0));
        v[f] = T(1);
        for (const auto& pc : piv) v[pc.second] = -gr[pc.first][f] / gr[pc.first][pc.second];
        nulls.push_back(v);
      }
      if (!nulls.empty()) {
        std::vector<std::vector<T>> ntn(nulls.size(), std::vector<T>(nulls.size(), T(0)));
        std::vector<T> ntd(nulls.size(), T(0));
        for (std::size_t i = 0; i < nulls.size(); ++i)
          for (std::size_t j = 0; j < chart.size(); ++j) {
            ntd[i] += nulls[i][j] * delta[j];
            for (std::size_t l = 0; l < nulls.size(); ++l) ntn[i][l] += nulls[i][j] * nulls[l][j];
          }
        const std::vector<std::vector<T>> inv = inverse(ntn);
        for (std::size_t i = 0; i < nulls.size(); ++i) {
          T w(0);
          for (std::size_t l = 0; l < nulls.size(); ++l) w += inv[i][l] * ntd[l];
          for (std::size_t j = 0; j < chart.size(); ++j) delta[j] -= nulls[i][j] * w;
        }
      }
    }
    std::vector<T> next = point;
    for (std::size_t v = 0; v < x.size(); ++v) next[v] = x[v].at(delta);
    for (std::size_t v = 0; v < x.size(); ++v)
      if (fixed_[v]) next[v] = point[v];
    point = next;
    return true;
  }

  /// The solution rank and the velocities at the point, from the final system's constant terms:
  /// z = (ṡ, λ) solves R z = h; ẋ = Σ_j ∂x/∂s_j ṡ_j + ∂x/∂t for every coordinate of x = (q, v, p).
  void solutions(const System& sys, const std::vector<J>& x, const std::vector<std::size_t>& chart, PointwiseResult<T>& out) {
    const std::size_t n = s_.n, rows = sys.r.size(), w = rows ? sys.r[0].size() : s_.m(), ms = w - s_.m();
    std::vector<std::vector<T>> r(rows, std::vector<T>(w));
    std::vector<T> h(rows);
    for (std::size_t i = 0; i < rows; ++i) {
      h[i] = sys.h[i].value();
      for (std::size_t j = 0; j < w; ++j) r[i][j] = sys.r[i][j].value();
    }
    std::vector<std::size_t> cols(w);
    for (std::size_t j = 0; j < w; ++j) cols[j] = j;
    const auto piv = eliminate_constants(r, h, cols, decide_);
    std::vector<char> is_piv(w, 0);
    std::vector<T> z(w, T(0));
    for (const auto& pc : piv) {
      z[pc.second] = h[pc.first] / r[pc.first][pc.second];
      is_piv[pc.second] = 1;
    }
    const auto full = [&](const std::vector<T>& zz, bool with_time) {
      std::vector<T> v(3 * n, T(0));
      for (std::size_t var = 0; var < 3 * n; ++var) {
        const J& f = var < 2 * n ? x[var] : sys.p[var - 2 * n];
        std::size_t jj = 0;
        for (std::size_t j = 0; j < chart.size(); ++j) {
          if (chart[j] == s_.t()) {
            if (with_time) v[var] += f.derivative(j).value();
          } else {
            v[var] += f.derivative(j).value() * zz[jj++];
          }
        }
      }
      return v;
    };
    out.velocity = full(z, true);
    out.tangent.clear();
    for (std::size_t j = 0; j < ms; ++j) {
      std::vector<T> e(ms + s_.m(), T(0));
      e[j] = T(1);
      out.tangent.push_back(full(e, false));
    }
    std::vector<std::vector<T>> dirs;
    for (std::size_t f = 0; f < w; ++f) {  // the kernel of R, one vector per free column
      if (is_piv[f]) continue;
      std::vector<T> k(w, T(0));
      k[f] = T(1);
      for (const auto& pc : piv) k[pc.second] = -r[pc.first][f] / r[pc.first][pc.second];
      dirs.push_back(full(k, false));
    }
    std::vector<std::vector<T>> rr = dirs;  // the ẋ-directions they span
    std::vector<T> zr(rr.size(), T(0));
    std::vector<std::size_t> xcols(3 * n);
    for (std::size_t j = 0; j < 3 * n; ++j) xcols[j] = j;
    out.gauge.clear();
    for (const auto& pc : eliminate_constants(rr, zr, xcols, decide_)) out.gauge.push_back(dirs[pc.first]);
    out.solution_rank = out.gauge.size();
  }

  /// The point (q, v, p = ∂L/∂v) and the time.
  void finish(PointwiseResult<T>& out, const std::vector<T>& point, const std::vector<J>& x) {
    const std::size_t n = s_.n;
    out.point.assign(3 * n, T(0));
    for (std::size_t i = 0; i < 2 * n; ++i) out.point[i] = point[i];
    for (std::size_t i = 0; i < n; ++i) out.point[2 * n + i] = eval(d_.dl_dv[i], x).value();
    out.time = point[s_.t()];
  }

  /// The largest value (no decision: for square systems whose rank was decided already), or
  /// values.size() if all are exactly 0.
  static std::size_t largest(const std::vector<T>& v) {
    std::size_t best = v.size();
    for (std::size_t i = 0; i < v.size(); ++i)
      if (JetFunctions<T>::magnitude(v[i]) > 0 && (best == v.size() || JetFunctions<T>::magnitude(v[i]) > JetFunctions<T>::magnitude(v[best]))) best = i;
    return best;
  }

  /// Pivots by largest magnitude (any nonzero pivot is exact; this one is the best conditioned).
  struct Largest {
    Decide& d;
    std::size_t pivot(const std::vector<T>& v) {
      std::size_t best = v.size();
      for (std::size_t i = 0; i < v.size(); ++i)
        if (JetFunctions<T>::magnitude(v[i]) > 0 && (best == v.size() || JetFunctions<T>::magnitude(v[i]) > JetFunctions<T>::magnitude(v[best]))) best = i;
      return best == v.size() || d.zero(v[best]) ? v.size() : best;
    }
  };

  bool planned(std::size_t k) const { return plan_ && k < plan_->size() && !(*plan_)[k].empty(); }
  /// The chart positions of the variables `vars` (those in the chart).
  static std::vector<std::size_t> positions_in(const std::vector<std::size_t>& chart, const std::vector<std::size_t>& vars) {
    std::vector<std::size_t> out;
    for (std::size_t v : vars)
      for (std::size_t j = 0; j < chart.size(); ++j)
        if (chart[j] == v) out.push_back(j);
    return out;
  }

  std::size_t& polished_;  ///< Newton steps taken only to polish, over the whole call (bounded)
  const LagrangianSystem& s_;
  const LagrangianDerivatives& d_;
  const std::vector<bool>& fixed_;
  Decide& decide_;
  std::function<T(const Rational&)> constant_;
  std::vector<std::string> names_;
  const std::vector<std::vector<std::size_t>>* plan_ = nullptr;
};

}  // namespace pointwise_detail

template <class T, class Decide>
PointwiseResult<T> pointwise_cad(const LagrangianSystem& sys, std::vector<T> start, const std::vector<bool>& fixed,
                                 Decide& decide, const std::function<T(const Rational&)>& constant, long order,
                                 std::size_t max_moves, const std::vector<std::vector<std::size_t>>* plan) {
  const LagrangianDerivatives der = derivatives(sys);
  PointwiseResult<T> out;
  std::size_t moves = 0, polished = 0;
  for (long K = order;;) {
    pointwise_detail::Run<T, Decide> run(sys, der, fixed, decide, constant, plan, polished);
    const auto o = run.pass(start, K, out);
    if (o == pointwise_detail::Run<T, Decide>::Outcome::Done) {
      out.moves = moves;
      return out;
    }
    if (o == pointwise_detail::Run<T, Decide>::Outcome::MoreOrder) {
      K += 2;
      if (K > static_cast<long>(2 * sys.n + 6)) throw std::logic_error("pointwise_cad: the tower needs jets beyond order 2n+6");
      continue;
    }
    if (++moves > max_moves)
      throw PointwiseNoPoint("no point of M_c was reached from the given values in " + std::to_string(max_moves) +
                             " Newton steps (the exact route needs a point with rational coordinates: give values on M_c)");
  }
}

}  // namespace dcad::reference
