// The pointwise CAD's run at one point with jets of one order (pointwise.hpp is the algorithm's entry
// and its description): M_1 from the constraints (first_level), then M_k → M_{k+1} (next_level) —
// the system for (ṡ, λ) eliminated at the point, its Fredholm candidates, the point moved onto them
// (move) or the new constraints' graph found by Newton's method on jets (graph).
#pragma once

#include "dcad/reference/nonlinear/pointwise/eliminate.hpp"
#include "dcad/reference/nonlinear/pointwise/system.hpp"

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>

namespace dcad::reference::pointwise_detail {

template <class T, class Decide>
class Run {
 public:
  using J = Jet<T>;
  Run(const LagrangianSystem& sys, const LagrangianDerivatives& der, const std::vector<bool>& fixed, Decide& decide,
      const std::function<T(const Rational&)>& constant, const std::vector<std::vector<std::size_t>>* plan,
      std::size_t& polished, std::size_t* constant_nudges = nullptr)
      : polished_(polished),
        constant_nudges_(constant_nudges),
        s_(sys),
        d_(der),
        fixed_(fixed),
        decide_(decide),
        constant_(constant),
        names_(sys.variable_names()),
        plan_(plan) {}

  enum class Outcome { Done, Moved, MoreOrder };

  /// One pass at `point` with jets to order K: the tower (Done), or a better point (Moved), or
  /// the jets ran out of order before the tower ended (MoreOrder).
  Outcome pass(std::vector<T>& point, long K, PointwiseResult<T>& out) {
    for (T& x : point) x = JetFunctions<T>::as_input(x);
    out = PointwiseResult<T>();
    out.order = K;
    out.dims.push_back(static_cast<long>(s_.implicit ? s_.n : 3 * s_.n));
    State st;
    if (s_.implicit)
      implicit_start(point, K, st);  // CEF (1.6): M_0 = Q, the first step is M_0 → M_1
    else if (!first_level(point, K, out, st))
      return Outcome::Done;
    for (std::size_t k = s_.implicit ? 0 : 1;; ++k)
      if (const std::optional<Outcome> o = next_level(k, point, K, out, st)) return *o;
  }

 private:
  /// M_k in its chart: the chart's coordinates (variable indices, time first if any), x = (q, v, t)
  /// as jets over them, and the level's record.
  struct State {
    std::vector<std::size_t> chart;
    std::vector<J> x;
    PointwiseLevel<T> level;
  };

  /// The implicit form's M_0 = Q: the chart is (t, q), every q a coordinate (the v entries of x are
  /// unused: the equations' velocities are the unknowns q̇ of the system, system.hpp).
  void implicit_start(const std::vector<T>& point, long K, State& st) {
    if (s_.has_time) st.chart.push_back(s_.t());
    for (std::size_t i = 0; i < s_.n; ++i) st.chart.push_back(s_.q(i));
    auto space = std::make_shared<const JetSpace>(st.chart.size(), static_cast<std::size_t>(K));
    st.x.assign(2 * s_.n + 1, J(space, T(0)));
    for (std::size_t j = 0; j < st.chart.size(); ++j) st.x[st.chart[j]] = J::variable(space, j, point[st.chart[j]]);
    if (!s_.has_time) st.x[s_.t()] = J(space, point[s_.t()]);
    st.level.dim = static_cast<long>(s_.n);
    st.level.chart = st.chart;
  }

  /// M_1 = {p = ∂L/∂v, a(t, q)·v + b = 0}: the dependent velocities (pivots nonzero at the point) and
  /// the graph over (t, q, free velocities).  False if the constraints' rank drops at the point.
  bool first_level(std::vector<T>& point, long K, PointwiseResult<T>& out, State& st) {
    for (std::size_t a = 0; a < s_.m(); ++a)  // a constraint that simplified to a nonzero number: M_1 = ∅
      if (expr::is_number(s_.constraints[a]) && s_.constraints[a]->value != 0) {
        out.consistent = false;
        out.dims.push_back(-1);
        out.steps = 1;
        out.why = "constraint " + std::to_string(a) + " is identically " + s_.constraints[a]->value.str() +
                  " (after expanding): M_1 is empty";
        finish_given(out, point);
        return false;
      }
    const std::vector<std::pair<std::size_t, std::size_t>> vp = velocity_pivots(point, out);
    if (vp.size() < s_.m()) {
      out.regular = false;
      out.why = "the constraints' velocity coefficients have rank " + std::to_string(vp.size()) + " < " +
                std::to_string(s_.m()) +
                " at the point (dependent constraints, or a point where Delta changes dimension)";
      finish_given(out, point);
      return false;
    }
    std::vector<char> dependent(2 * s_.n + 1, 0);
    for (const auto& pc : vp) dependent[pc.second] = 1;
    if (s_.has_time) st.chart.push_back(s_.t());
    for (std::size_t i = 0; i < s_.n; ++i) st.chart.push_back(s_.q(i));
    for (std::size_t i = 0; i < s_.n; ++i)
      if (!dependent[s_.v(i)]) st.chart.push_back(s_.v(i));
    auto space = std::make_shared<const JetSpace>(st.chart.size(), static_cast<std::size_t>(K));
    st.x.assign(2 * s_.n + 1, J());
    for (std::size_t j = 0; j < st.chart.size(); ++j) st.x[st.chart[j]] = J::variable(space, j, point[st.chart[j]]);
    if (!s_.has_time) st.x[s_.t()] = J(space, point[s_.t()]);
    for (std::size_t i = 0; i < s_.n; ++i)
      if (dependent[s_.v(i)]) st.x[s_.v(i)] = J(space, T(0));
    solve_dependent_velocities(vp, dependent, st.x, point);
    st.level.dim = static_cast<long>(st.chart.size() - (s_.has_time ? 1 : 0));
    st.level.chart = st.chart;
    out.dims.push_back(st.level.dim);
    return true;
  }

  /// The point as given: (q, v, p = ∂L/∂v) and the time.
  void finish_given(PointwiseResult<T>& out, const std::vector<T>& point) {
    const std::size_t n = s_.n;
    if (s_.implicit) return finish_implicit(out, point);
    out.point.assign(3 * n, T(0));
    for (std::size_t i = 0; i < 2 * n; ++i) out.point[i] = point[i];
    for (std::size_t i = 0; i < n; ++i) out.point[2 * n + i] = value(d_.dl_dv[i], point);
    out.time = point[s_.t()];
  }

  /// The pivots (constraint, velocity) of a(t, q) at the point: the preferred dependent velocities, or
  /// the plan's where they carry the same rank.
  std::vector<std::pair<std::size_t, std::size_t>> velocity_pivots(const std::vector<T>& point,
                                                                   PointwiseResult<T>& out) {
    std::vector<std::vector<T>> a0(s_.m(), std::vector<T>(2 * s_.n + 1, T(0)));
    std::vector<T> b0(s_.m());
    for (std::size_t a = 0; a < s_.m(); ++a)
      for (std::size_t i = 0; i < s_.n; ++i) a0[a][s_.v(i)] = value(d_.a[a][i], point);
    std::vector<std::vector<T>> a0r = a0;
    auto vp = eliminate_constants(a0r, b0, preference(true, false), decide_);
    if (planned(0)) {
      std::vector<std::vector<T>> a0p = a0;
      std::vector<T> b0p = b0;
      const auto alt = eliminate_constants(a0p, b0p, (*plan_)[0], decide_);
      if (alt.size() == vp.size()) vp = alt;
    }
    out.plan.emplace_back();
    for (const auto& pc : vp) out.plan.back().push_back(pc.second);
    return vp;
  }

  /// Σ_{dep} a_ai v_i = −b_a − Σ_{free} a_ai v_i, as series, with the pivots chosen.
  void solve_dependent_velocities(const std::vector<std::pair<std::size_t, std::size_t>>& vp,
                                  const std::vector<char>& dependent, std::vector<J>& x, std::vector<T>& point) {
    std::vector<std::vector<J>> r(s_.m());
    std::vector<J> h(s_.m());
    std::vector<std::size_t> dep_cols;
    for (const auto& pc : vp) dep_cols.push_back(pc.second);
    for (std::size_t a = 0; a < s_.m(); ++a) {
      h[a] = -eval(d_.b[a], x);
      for (std::size_t i = 0; i < s_.n; ++i) {
        const J c = eval(d_.a[a][i], x);
        if (dependent[s_.v(i)]) continue;
        h[a] -= c * x[s_.v(i)];
      }
      for (std::size_t col : dep_cols) r[a].push_back(eval(d_.a[a][col - s_.n], x));
    }
    const std::vector<J> sol = solve_square(r, h);
    for (std::size_t k = 0; k < dep_cols.size(); ++k) {
      x[dep_cols[k]] = sol[k];
      point[dep_cols[k]] = sol[k].value();
    }
  }

  /// M_k → M_{k+1}: nothing while the tower goes on; else how the pass ends.
  std::optional<Outcome> next_level(std::size_t k, std::vector<T>& point, long K, PointwiseResult<T>& out, State& st) {
    const MotionSystem<T> sys = motion_system<T>(
        s_, d_, st.x, st.chart, names_, [&](const expr::Expr& e, const std::vector<J>& x) { return eval(e, x); });
    step_data(sys);
    JetElimination<T> e = eliminate_jets(sys.r, sys.h, decide_, sys.row_names, sys.col_names);
    for (std::size_t k = 0; k < e.pivots.size();
         ++k)  // the pivot as used (after the eliminations before it), not the raw entry
      st.level.pivots.push_back(
          {sys.row_names[e.pivots[k].first], sys.col_names[e.pivots[k].second], e.pivot_values[k]});
    if (!e.singular.empty()) return singular(out, st, point, "on M_" + std::to_string(k) + ": " + e.singular);
    long ord = std::numeric_limits<long>::max();  // to which order the candidates are known
    for (const J& c : e.candidates) ord = std::min(ord, c.order());
    if (e.candidates.empty()) ord = K;
    if (!on_next_level(e)) {  // values at the point not all zero: move the point onto M_{k+1}
      if (ord < 1) return Outcome::MoreOrder;
      if (const Outcome m = move(e.candidates, st.chart, st.x, point, k, K, out); m != Outcome::Done) return m;
      out.levels.push_back(st.level);
      finish(out, point, st.x);
      return Outcome::Done;  // inconsistent (out says so)
    }
    if (ord < 1) return Outcome::MoreOrder;
    return new_level(k, point, K, out, st, sys, e, ord);
  }

  /// The decision object sees the step's data (the constant terms of its linear system) first.
  void step_data(const MotionSystem<T>& sys) {
    std::vector<T> data;
    for (const auto& row : sys.r)
      for (const J& v : row) data.push_back(v.value());
    for (const J& v : sys.h) data.push_back(v.value());
    decide_.step_data(data);
  }

  /// Every candidate vanishes at the point (unless one more Newton step could still improve a value
  /// taken as zero: rounding routes, a bounded number of times per call).
  bool on_next_level(const JetElimination<T>& e) {
    bool on = true, polish = false;
    for (const J& c : e.candidates) {
      on = on && decide_.zero(c.value());
      polish = polish || decide_.polish(c.value());
    }
    if (on && polish && e.candidates.size() && polished_ < 4) {
      ++polished_;
      return false;
    }
    return on;
  }

  std::optional<Outcome> singular(PointwiseResult<T>& out, const State& st, const std::vector<T>& point,
                                  const std::string& why) {
    out.levels.push_back(st.level);
    out.regular = false;
    out.why = why;
    out.steps = out.dims.size() - 1;
    finish(out, point, st.x);
    return Outcome::Done;
  }

  /// The candidates' independent differentials (over the non-time chart coordinates, the plan's if
  /// they carry the same rank): none — M_c = M_k, the tower ends (last_level) — or the graph of
  /// M_{k+1} over the remaining coordinates (graph).
  std::optional<Outcome> new_level(std::size_t k, std::vector<T>& point, long K, PointwiseResult<T>& out, State& st,
                                   const MotionSystem<T>& sys, JetElimination<T>& e, long ord) {
    const std::vector<std::size_t>& chart = st.chart;
    std::vector<std::vector<T>> g(e.candidates.size(), std::vector<T>(chart.size(), T(0)));
    for (std::size_t i = 0; i < e.candidates.size(); ++i)
      for (std::size_t j = 0; j < chart.size(); ++j) g[i][j] = e.candidates[i].gradient(j);
    std::vector<std::vector<T>> gr = g;
    std::vector<T> zero_rhs(g.size(), T(0));
    auto gp = eliminate_constants(gr, zero_rhs, chart_preference(chart), decide_);
    if (planned(k) && !gp.empty()) {  // the plan's coordinates, if they carry the same rank
      std::vector<std::vector<T>> gq = g;
      std::vector<T> zq(g.size(), T(0));
      const auto alt = eliminate_constants(gq, zq, positions_in(chart, (*plan_)[k]), decide_);
      if (alt.size() == gp.size()) {
        gp = alt;
        gr = gq;
      }
    }
    if (gp.empty()) {
      // the implicit form, exactly: the last candidates are zero to their known order only; a condition
      // that vanishes at the point to a higher order (x = t⁶ at t = 0, (x − 1/5)⁴ at x = 1/5) looks like
      // zero there — checked to order 6 while the jets stay small (at most 5,000 monomials)
      if (s_.implicit && std::is_same_v<T, Rational> && ord < 6 && K + 2 <= static_cast<long>(2 * s_.n + 6) &&
          small_jets(s_.n + (s_.has_time ? 1 : 0), static_cast<std::size_t>(K + 2)))
        return Outcome::MoreOrder;
      return last_level(k, point, out, st, sys, e, g, ord);
    }
    return graph(k, point, K, out, st, e, g, gr, gp, ord);
  }

  /// M_{k+1} = M_k: every candidate must vanish on M_k (else inconsistent, or the point is singular);
  /// the solutions at the point.
  std::optional<Outcome> last_level(std::size_t k, const std::vector<T>& point, PointwiseResult<T>& out, State& st,
                                    const MotionSystem<T>& sys, const JetElimination<T>& e,
                                    const std::vector<std::vector<T>>& g, long ord) {
    out.levels.push_back(st.level);
    for (std::size_t i = 0; i < e.candidates.size(); ++i) {
      if (decide_.zero(e.candidates[i])) continue;
      if (time_only(g[i], st.chart)) {
        if (out.consistent) out.dims.push_back(-1);
        out.consistent = false;
        out.why = "step " + std::to_string(k) + " gives a condition on the time alone: M_" + std::to_string(k + 1) +
                  "(t) is empty at generic times";
      } else {
        out.regular = false;
        out.why = "on M_" + std::to_string(k) +
                  ": a constraint vanishes with its differential at the point but not identically";
      }
    }
    out.steps = out.dims.size() - 1;
    out.checked_order = ord;
    if (out.consistent && out.regular) solutions(sys, st.x, st.chart, out);
    finish(out, point, st.x);
    return Outcome::Done;
  }

  /// M_{k+1}: the graph of the pivot coordinates over the others, by Newton's method on jets; the
  /// constraints it adds (their tangent equations at the point, each solved for its pivot).
  std::optional<Outcome> graph(std::size_t k, const std::vector<T>& point, long K, PointwiseResult<T>& out, State& st,
                               JetElimination<T>& e, const std::vector<std::vector<T>>& g,
                               const std::vector<std::vector<T>>& gr,
                               const std::vector<std::pair<std::size_t, std::size_t>>& gp, long ord) {
    const std::vector<std::size_t>& chart = st.chart;
    std::vector<std::size_t> sel_rows, dep_idx;
    for (const auto& pc : gp) {
      sel_rows.push_back(pc.first);
      dep_idx.push_back(pc.second);
    }
    PointwiseLevel<T> next;
    // reduced rows (Gauss–Jordan): each has 1 pivot among the solved coordinates, so it names the one it is solved for
    for (std::size_t r = 0; r < gp.size(); ++r)
      next.added.push_back(tangent(gr[sel_rows[r]], chart, dep_idx[r], point));
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
      if (!decide_.zero(c.compose(subs)))
        return singular(out, st, point,
                        "on M_" + std::to_string(k + 1) + ": a constraint of step " + std::to_string(k) +
                            " vanishes with its differential at the point but not identically on M_" +
                            std::to_string(k + 1));
    for (J& xi : st.x) xi = xi.compose(subs);
    out.levels.push_back(st.level);
    st.chart = new_chart;
    next.chart = new_chart;
    next.dim = static_cast<long>(new_chart.size() - (s_.has_time ? 1 : 0));
    out.dims.push_back(next.dim);
    st.level = next;
    if (st.level.dim < 0) throw std::logic_error("pointwise_cad: negative dimension");
    return std::nullopt;
  }

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
    // exactly, multipliers first (μ and v_μ: every candidate is affine in them, so a step along one
    // lands, and a chart that solves for them keeps the others free to move without leaving M_k)
    const bool exact = std::is_same_v<T, Rational>;
    if (exact) {
      out.emplace_back();
      for (std::size_t i = s_.n; i-- > 0;)
        if (multiplier(s_.q(i))) {
          if (velocities && !fixed_[s_.v(i)]) out.back().push_back(s_.v(i));
          if (positions && !fixed_[s_.q(i)]) out.back().push_back(s_.q(i));
        }
    }
    for (int kind = 0; kind < 2; ++kind) {
      if ((kind == 0 && !velocities) || (kind == 1 && !positions)) continue;
      for (int pass = 0; pass < 2; ++pass) {
        out.emplace_back();
        for (std::size_t i = s_.n; i-- > 0;) {
          const std::size_t var = kind == 0 ? s_.v(i) : s_.q(i);
          if (fixed_[var] == (pass == 1) && !(exact && !fixed_[var] && multiplier(s_.q(i)))) out.back().push_back(var);
        }
      }
    }
    return out;
  }
  /// The same groups as chart positions (never the time); `movable`: only coordinates not given.
  std::vector<std::vector<std::size_t>> chart_preference(const std::vector<std::size_t>& chart,
                                                         bool movable = false) const {
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
      if (chart[j] == s_.t())
        t_nonzero = !decide_.zero(grad[j]);
      else if (!decide_.zero(grad[j]))
        return false;
    }
    return t_nonzero;
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
  void newton_graph(const std::vector<J>& cand, const std::vector<std::size_t>& rows,
                    const std::vector<std::size_t>& dep, const std::vector<std::vector<T>>& g, std::vector<J>& subs,
                    long ord) {
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
          subs[dep[k]].set_coefficient(
              c, JetFunctions<T>::with_error(subs[dep[k]].coefficient(c), absolute_sum(inv[k], res, c)));
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

  /// The point is not on M_{k+1}: one Newton step on the candidates in the coordinates that may
  /// move (Moved).  Done (and `out` says why) if no move can satisfy them: M_{k+1} is empty near
  /// here; MoreOrder if the jets are too short to tell.
  Outcome move(const std::vector<J>& cand, const std::vector<std::size_t>& chart, const std::vector<J>& x,
               std::vector<T>& point, std::size_t k, long K, PointwiseResult<T>& out) {
    Step st = newton_step(cand, chart, k);
    const Reach reach = reachable(cand, chart, point, k, K, st, out);
    if (reach == Reach::empty) return Outcome::Done;
    if (reach == Reach::more_order) return Outcome::MoreOrder;
    std::vector<T> delta = step_of(st, chart);
    if (reach == Reach::critical)  // Newton cannot leave a critical point of a combination: start from a nearby point
      for (std::size_t j : st.movable) delta[j] += constant_(Rational(1, 3));
    std::vector<T> next = point;
    if constexpr (std::is_same_v<T, Rational>) {
      // exactly, only the pivot coordinates move: the chart's graphs are truncated series, whose
      // values would take the point off the lower M_k by their remainder (the next pass checks every
      // level again; a coordinate affine in the candidates lands in one step)
      for (std::size_t j = 0; j < chart.size(); ++j) next[chart[j]] += delta[j];
    } else {
      for (std::size_t v = 0; v < x.size(); ++v) next[v] = x[v].at(delta);
    }
    for (std::size_t v = 0; v < x.size(); ++v)
      if (fixed_[v]) next[v] = point[v];
    point = next;
    return Outcome::Moved;
  }

  /// The linearized candidates g·δ = −ψ at the point, reduced on the coordinates that may move.
  struct Step {
    std::vector<std::vector<T>> g, gr;  ///< gradients over the chart, and reduced
    std::vector<std::vector<T>> comb;   ///< row i of gr (and rhs) is Σ_j comb[i][j] · (candidate j)
    std::vector<T> rhs;                 ///< −ψ, reduced
    std::vector<std::size_t> movable;   ///< chart positions the step may change
    std::vector<std::pair<std::size_t, std::size_t>> piv;  ///< (candidate, coordinate) pivots
    std::size_t rank_all = 0;                              ///< rank of the gradients over every coordinate but the time
  };

  Step newton_step(const std::vector<J>& cand, const std::vector<std::size_t>& chart, std::size_t k) {
    Step st;
    std::vector<std::vector<T>>& g = st.g;
    std::vector<T>& rhs = st.rhs;
    g.assign(cand.size(), std::vector<T>(chart.size(), T(0)));
    rhs.resize(cand.size());
    for (std::size_t i = 0; i < cand.size(); ++i) {
      rhs[i] = -cand[i].value();
      for (std::size_t j = 0; j < chart.size(); ++j) g[i][j] = cand[i].gradient(j);
    }
    // a Newton step changes, for each constraint, the movable coordinate it depends on most (complete
    // pivoting by magnitude, in both routes): preferring velocities, as charts do, would fix the
    // pendulum's multiplier constraint mu = m (v² − g y)/|q|² by changing v instead of mu
    std::vector<std::size_t>& movable = st.movable;
    if (planned(k)) {  // the plan's solved coordinates: the projection is the graph map of its chart
      for (std::size_t j : positions_in(chart, (*plan_)[k]))
        if (!fixed_[chart[j]]) movable.push_back(j);
    } else {
      for (const auto& group : chart_preference(chart, true)) movable.insert(movable.end(), group.begin(), group.end());
    }
    // the reduction carries the identity along, so that each reduced row names its combination of candidates
    std::vector<std::vector<T>> aug = g;
    for (std::size_t i = 0; i < aug.size(); ++i) {
      aug[i].resize(chart.size() + cand.size(), T(0));
      aug[i][chart.size() + i] = T(1);
    }
    Largest<T, Decide> largest{decide_};
    if constexpr (std::is_same_v<T, Rational>) {
      // exactly, a step lands only along a coordinate every candidate is affine in (no δ_j², δ_j³, …
      // term): those first (the spherical pendulum's μ|q|² − |v|² + g z = 0 is solved for μ, not v_z)
      std::vector<std::vector<std::size_t>> groups(2);
      for (std::size_t j : movable) groups[affine_along(cand, j) || multiplier(chart[j]) ? 0 : 1].push_back(j);
      // the implicit form: the coordinates in the charts' own order (the ones the next chart solves for
      // move): by magnitude, 2 x1 − x2 = 0 moved x1, which M_2's chart over x1 then moved back, forever
      // (prop_dae's LinearFormEqualsImplicitFormOnLinearData)
      if (s_.implicit)
        st.piv = eliminate_constants(aug, rhs, groups, decide_);
      else
        st.piv = eliminate_constants(aug, rhs, groups, largest);
    } else {
      st.piv = eliminate_constants(aug, rhs, movable, largest);
    }
    st.gr.assign(cand.size(), {});
    st.comb.assign(cand.size(), {});
    for (std::size_t i = 0; i < aug.size(); ++i) {
      st.gr[i].assign(aug[i].begin(), aug[i].begin() + static_cast<std::ptrdiff_t>(chart.size()));
      st.comb[i].assign(aug[i].begin() + static_cast<std::ptrdiff_t>(chart.size()), aug[i].end());
    }
    std::vector<std::vector<T>> ga = g;
    std::vector<T> za(g.size(), T(0));
    std::vector<std::size_t> all;
    for (const auto& group : chart_preference(chart)) all.insert(all.end(), group.begin(), group.end());
    st.rank_all = eliminate_constants(ga, za, all, decide_).size();
    return st;
  }

  /// A multiplier coordinate (L affine in it, its velocity nowhere, no constraint or force with it):
  /// the Euler–Lagrange equations, and the candidates they give, are affine in it.  (Jets at the last
  /// levels are known to order 1 only, where affine_along cannot tell.)
  bool multiplier(std::size_t var) const {
    if (var >= s_.n && var < 2 * s_.n)
      return multiplier(var - s_.n);  // v_μ: the candidates are affine in it too (d/dt of affine in μ)
    if (var >= s_.n) return false;
    if (multiplier_.empty()) multiplier_.assign(s_.n, -1);  // once per coordinate: L may be a large DAG
    if (multiplier_[var] < 0) multiplier_[var] = is_multiplier(var) ? 1 : 0;
    return multiplier_[var] == 1;
  }
  bool is_multiplier(std::size_t var) const {
    if (expr::degree_in(s_.lagrangian, [&](std::size_t i) { return i == var; }) != 1 ||
        expr::depends_on(s_.lagrangian, s_.v(var)))
      return false;
    for (const auto& c : s_.constraints)
      if (expr::depends_on(c, var) || expr::depends_on(c, s_.v(var))) return false;
    for (const auto& f : s_.forces)
      if (expr::depends_on(f, var) || expr::depends_on(f, s_.v(var))) return false;
    return true;
  }

  /// No candidate that does not vanish at the point has a term δ_j^k, k ≥ 2, in its jet (chart
  /// position j; the ones that vanish are redundant or stay satisfied: their rows get no pivot).
  static bool affine_along(const std::vector<J>& cand, std::size_t j) {
    for (const J& c : cand) {
      if (c.value() == 0) continue;
      if (c.order() < 2) return false;  // affinity unknown (the multiplier rule may still tell)
      for (const auto& [idx, coef] : c.entries()) {
        const auto& e = c.space()->exponents(idx);
        if (e[j] < 2 || coef == 0) continue;
        bool pure = true;
        for (std::size_t m = 0; m < e.size(); ++m) pure = pure && (m == j || e[m] == 0);
        if (pure) return false;
      }
    }
    return true;
  }

  /// Whether the step can bring the point onto M_{k+1}: a candidate without a pivot must vanish there
  /// or be redundant; a nonzero constant, or a condition on the time alone, makes M_{k+1} empty (false,
  /// `out` says why); given values that no other coordinate can meet are bad input (PointwiseNoPoint).
  enum class Reach { go, empty, critical, more_order };
  Reach reachable(const std::vector<J>& cand, const std::vector<std::size_t>& chart, const std::vector<T>& point,
                  std::size_t k, long K, const Step& st, PointwiseResult<T>& out) {
    const std::vector<std::vector<T>>& g = st.g;
    std::vector<char> prow(cand.size(), 0);
    for (const auto& pc : st.piv) prow[pc.first] = 1;
    bool critical = false;
    for (std::size_t i = 0; i < cand.size(); ++i) {
      if (prow[i] || decide_.zero(st.rhs[i])) continue;
      // the combination of candidates this reduced row is (ψ₂ − ψ₁ for x² + y² = 1 and x² + y² = 4):
      // a nonzero constant near the point makes M_{k+1} empty
      J comb = cand[i] * J(cand[i].space(), T(0));
      for (std::size_t j = 0; j < cand.size(); ++j)
        if (!decide_.zero(st.comb[i][j])) comb += cand[j] * J(cand[j].space(), st.comb[i][j]);
      bool constant = true, flat = true;
      for (const auto& [idx, c] : comb.entries()) constant = constant && (idx == 0 || decide_.zero(c));
      for (std::size_t j = 0; j < chart.size(); ++j)
        flat = flat && (chart[j] == s_.t() || decide_.zero(comb.gradient(j)));
      std::vector<T> gi(chart.size(),
                        T(0));  // the combination's differential (x − 1 − t and x combine to −1 − t: the time alone)
      for (std::size_t j = 0; j < chart.size(); ++j) gi[j] = comb.gradient(j);
      // constant to the jets' order only: lam² x at lam = 0 looks constant to order 1, as −10 (a certified
      // "0 = −10" for a pendulum whose multiplier enters squared): below order 6, once, a nearby point first
      // (a true constant — x² + y² − 1 against x² + y² − 4 — is constant there too and decided then; the
      // implicit form's constants are decided by the formulas, ide_formulas.hpp, before the jets run)
      if (constant && comb.order() < 6 && !st.movable.empty() && constant_nudges_ && *constant_nudges_ == 0) {
        ++*constant_nudges_;
        critical = true;
        continue;
      }
      if (constant) return empty_by_constant(k, comb, out);
      if (flat && st.piv.empty()) {  // every candidate's differential vanishes here: a critical point, not a verdict
        critical = true;
        continue;
      }
      if (time_only(gi, chart)) {
        out.consistent = false;
        out.dims.push_back(-1);
        out.steps = out.dims.size() - 1;
        out.why = "step " + std::to_string(k) +
                  " gives a condition on the time alone, violated at t = " + JetFunctions<T>::text(point[s_.t()]) +
                  ": M_" + std::to_string(k + 1) + "(t) is empty there";
        return Reach::empty;
      }
      if (st.piv.empty() &&
          involves(comb, st.movable)) {  // the coordinates that may move enter only at second order here
        critical = true;                 // (x² + y² = 1 with x given, y at 0): from a nearby point
        continue;
      }
      if (st.piv.size() < st.rank_all) {  // the constraints need more freedom than the movable coordinates give
        if (const std::optional<Reach> r = constant_over_all(cand, chart, k, K, st, out)) return *r;
        std::string given;
        for (std::size_t j = 0; j < chart.size(); ++j)
          if (fixed_[chart[j]] && !decide_.zero(g[i][j])) given += (given.empty() ? "" : ", ") + names_[chart[j]];
        throw PointwiseNoPoint("the given values (" + given + ") violate a constraint of M_" + std::to_string(k + 1) +
                               " (residual " + JetFunctions<T>::text(cand[i].value()) +
                               ") that no other coordinate can satisfy");
      }
      // otherwise a redundant candidate: it vanishes on M_{k+1}, where the independent ones bring the point
    }
    return critical && !st.movable.empty() ? Reach::critical : Reach::go;
  }

  /// M_{k+1} is empty: `comb`, a combination of its constraints, is a nonzero constant.
  Reach empty_by_constant(std::size_t k, const J& comb, PointwiseResult<T>& out) {
    out.consistent = false;
    out.dims.push_back(-1);
    out.steps = out.dims.size() - 1;
    out.why = "step " + std::to_string(k) + " requires 0 = " + JetFunctions<T>::text(comb.value()) +
              " (its constraints combined): M_" + std::to_string(k + 1) + " is empty";
    return Reach::empty;
  }

  /// Given values that the movable coordinates cannot bring onto M_{k+1}: the candidates reduced over
  /// every coordinate of the chart, given ones too.  A combination that none of them moves and that is a
  /// nonzero constant makes M_{k+1} empty whatever was given (x² + y² = 1 beside x² + y² = 4 with x and y
  /// given: 0 = 3, an inconsistent system, not a bad given value); nothing otherwise.  A constant to the
  /// jets' low order only (no nearby point can be tried: the given values stay) asks for longer jets.
  std::optional<Reach> constant_over_all(const std::vector<J>& cand, const std::vector<std::size_t>& chart,
                                         std::size_t k, long K, const Step& st, PointwiseResult<T>& out) {
    std::vector<std::vector<T>> aug = st.g;
    std::vector<T> rhs(cand.size());
    for (std::size_t i = 0; i < aug.size(); ++i) {
      rhs[i] = -cand[i].value();
      aug[i].resize(chart.size() + cand.size(), T(0));
      aug[i][chart.size() + i] = T(1);
    }
    std::vector<std::size_t> all(chart.size());
    for (std::size_t j = 0; j < chart.size(); ++j) all[j] = j;
    std::vector<char> prow(cand.size(), 0);
    for (const auto& pc : eliminate_constants(aug, rhs, all, decide_)) prow[pc.first] = 1;
    for (std::size_t i = 0; i < cand.size(); ++i) {
      if (prow[i] || decide_.zero(rhs[i])) continue;
      J comb = cand[i] * J(cand[i].space(), T(0));
      for (std::size_t j = 0; j < cand.size(); ++j)
        if (!decide_.zero(aug[i][chart.size() + j])) comb += cand[j] * J(cand[j].space(), aug[i][chart.size() + j]);
      bool constant = true;
      for (const auto& [idx, c] : comb.entries()) constant = constant && (idx == 0 || decide_.zero(c));
      if (!constant) continue;
      if (comb.order() < 6 && K + 2 <= static_cast<long>(2 * s_.n + 6)) return Reach::more_order;
      return empty_by_constant(k, comb, out);
    }
    return std::nullopt;
  }

  /// Jets in d variables to order k have at most 5,000 monomials.
  static bool small_jets(std::size_t d, std::size_t k) {
    double r = 1;
    for (std::size_t i = 1; i <= k; ++i) r = r * static_cast<double>(d + i) / static_cast<double>(i);
    return r <= 5000;
  }

  /// Some nonzero coefficient of `jet` is of a monomial in one of the chart positions `positions`.
  bool involves(const J& jet, const std::vector<std::size_t>& positions) {
    for (const auto& [idx, c] : jet.entries()) {
      if (idx == 0 || decide_.zero(c)) continue;
      const auto& e = jet.space()->exponents(idx);
      for (std::size_t j : positions)
        if (e[j] > 0) return true;
    }
    return false;
  }

  /// δ: each constraint moves its pivot coordinate (exactly, a constraint affine in it lands in one
  /// step); on rounding routes the minimum-norm step instead.
  std::vector<T> step_of(const Step& st, const std::vector<std::size_t>& chart) {
    const auto& piv = st.piv;
    const auto& gr = st.gr;
    const auto& rhs = st.rhs;
    std::vector<T> delta(chart.size(), T(0));
    // each constraint moves its pivot coordinate: exactly, a constraint affine in it lands in one step
    for (const auto& pc : piv) delta[pc.second] = rhs[pc.first] / gr[pc.first][pc.second];
    if constexpr (JetFunctions<T>::tracks_error) {
      // rounding routes: the minimum-norm step instead (δ minus its part in ker A, A the independent
      // constraints' gradients over the movable coordinates), a smooth projection — the pivot
      // coordinates flip between nearby points, and so would the projected vector field
      std::vector<std::vector<T>> nulls;  // ker A from the reduced rows: one vector per free column
      for (std::size_t f : st.movable) {
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
    return delta;
  }

  /// The solution rank and the velocities at the point, from the final system's constant terms:
  /// z = (ṡ, λ) solves R z = h; ẋ = Σ_j ∂x/∂s_j ṡ_j + ∂x/∂t for every coordinate of x = (q, v, p).
  void solutions(const MotionSystem<T>& sys, const std::vector<J>& x, const std::vector<std::size_t>& chart,
                 PointwiseResult<T>& out) {
    // the implicit form: x = q, z = ṡ (no λ); rows may be none (no equation): w = the chart's non-time size
    const std::size_t n = s_.n, lambdas = s_.implicit ? 0 : s_.m(), nx = s_.implicit ? n : 3 * n;
    const std::size_t w = rows_width(sys, chart, lambdas), rows = sys.r.size(), ms = w - lambdas;
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
      std::vector<T> v(nx, T(0));
      for (std::size_t var = 0; var < nx; ++var) {
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
      std::vector<T> e(ms + lambdas, T(0));
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
    std::vector<std::size_t> xcols(nx);
    for (std::size_t j = 0; j < nx; ++j) xcols[j] = j;
    out.gauge.clear();
    for (const auto& pc : eliminate_constants(rr, zr, xcols, decide_)) out.gauge.push_back(dirs[pc.first]);
    out.solution_rank = out.gauge.size();
  }

  /// The width of the system's rows: the non-time chart coordinates and the multipliers.
  std::size_t rows_width(const MotionSystem<T>& sys, const std::vector<std::size_t>& chart, std::size_t lambdas) const {
    if (!sys.r.empty()) return sys.r[0].size();
    std::size_t w = lambdas;
    for (std::size_t c : chart) w += c == s_.t() ? 0 : 1;
    return w;
  }

  /// The point (q, v, p = ∂L/∂v) and the time.
  void finish(PointwiseResult<T>& out, const std::vector<T>& point, const std::vector<J>& x) {
    const std::size_t n = s_.n;
    if (s_.implicit) return finish_implicit(out, point);
    out.point.assign(3 * n, T(0));
    for (std::size_t i = 0; i < 2 * n; ++i) out.point[i] = point[i];
    for (std::size_t i = 0; i < n; ++i) out.point[2 * n + i] = eval(d_.dl_dv[i], x).value();
    out.time = point[s_.t()];
  }

  /// The implicit form's point: q and the time.
  void finish_implicit(PointwiseResult<T>& out, const std::vector<T>& point) {
    out.point.assign(point.begin(), point.begin() + static_cast<std::ptrdiff_t>(s_.n));
    out.time = point[s_.t()];
  }

  bool planned(std::size_t k) const { return plan_ && k < plan_->size() && !(*plan_)[k].empty(); }
  /// The chart positions of the variables `vars` (those in the chart).
  static std::vector<std::size_t> positions_in(const std::vector<std::size_t>& chart,
                                               const std::vector<std::size_t>& vars) {
    std::vector<std::size_t> out;
    for (std::size_t v : vars)
      for (std::size_t j = 0; j < chart.size(); ++j)
        if (chart[j] == v) out.push_back(j);
    return out;
  }

  mutable std::vector<signed char> multiplier_;  ///< multiplier(q_i), computed once (−1: not yet)
  std::size_t& polished_;                        ///< Newton steps taken only to polish, over the whole call (bounded)
  std::size_t* constant_nudges_;  ///< nearby points tried for a combination constant to low order only, over the whole
                                  ///< call (one)
  const LagrangianSystem& s_;
  const LagrangianDerivatives& d_;
  const std::vector<bool>& fixed_;
  Decide& decide_;
  std::function<T(const Rational&)> constant_;
  std::vector<std::string> names_;
  const std::vector<std::vector<std::size_t>>* plan_ = nullptr;
};

}  // namespace dcad::reference::pointwise_detail
