// The linear system for (ṡ, λ) on M_k in its chart s (pointwise.hpp's header), as jets:
//     Dq·ṡ + ∂_t q = v                         (q̇ = v)
//     DP·ṡ + ∂_t P − aᵀλ = ∂L/∂q + F           (ṗ − ∂L/∂q − F ∈ Δ°, P = ∂L/∂v on M_k)
//     a·(Dq·ṡ + ∂_t q) + b = 0                 (q̇ ∈ Δ_aff)
// CEF Lemma 5.1 / Remark 5.2 for D̄_Δ (6.10)–(6.13), YM (4.3) with forces, V §3 with the time.
// The implicit form (LagrangianSystem::implicit, CEF (1.6)) has the last rows only, with q the state and
// no λ: φ_a(t, q, q̇) = a(t, q)·q̇ + b(t, q) = 0 for q̇ = Dq·ṡ + ∂_t q ∈ T M_k (tangency includes ∂_t).
#pragma once

#include "dcad/reference/nonlinear/lagrangian_system.hpp"

#include <string>
#include <vector>

namespace dcad::reference::pointwise_detail {

template <class T>
struct MotionSystem {
  std::vector<std::vector<Jet<T>>> r;  ///< rows over (ṡ for the non-time chart coordinates, λ)
  std::vector<Jet<T>> h;               ///< right-hand sides
  std::vector<std::string> row_names, col_names;
  std::vector<Jet<T>> p;                    ///< P = ∂L/∂v on M_k
  std::vector<std::vector<Jet<T>>> dq, dp;  ///< ∂q_i/∂s_j, ∂P_i/∂s_j (non-time chart coordinates)
  std::vector<Jet<T>> tq, tp;               ///< ∂q_i/∂t, ∂P_i/∂t
};

/// The implicit form's system: a(t, q)·(Dq·ṡ + ∂_t q) + b(t, q) = 0, rows over ṡ (no λ, no momenta).
template <class T, class Eval>
MotionSystem<T> implicit_system(const LagrangianSystem& s, const LagrangianDerivatives& d, const std::vector<Jet<T>>& x,
                                const std::vector<std::size_t>& moving, std::size_t tpos,
                                const std::vector<std::size_t>& chart, const std::vector<std::string>& names,
                                Eval eval) {
  using J = Jet<T>;
  const std::size_t n = s.n;
  const J zero(x[0].space(), T(0));
  MotionSystem<T> sys;
  sys.dq.assign(n, {});
  sys.tq.assign(n, zero);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j : moving) sys.dq[i].push_back(x[s.q(i)].derivative(j));
    if (tpos < chart.size()) sys.tq[i] = x[s.q(i)].derivative(tpos);
  }
  for (std::size_t j : moving) sys.col_names.push_back("d/dt " + names[chart[j]]);
  for (std::size_t c = 0; c < s.m(); ++c) {
    std::vector<J> row(moving.size(), zero);
    J rhs = -eval(d.b[c], x);
    for (std::size_t i = 0; i < n; ++i) {
      const J a = eval(d.a[c][i], x);
      if (a.is_zero()) continue;
      for (std::size_t j = 0; j < moving.size(); ++j) row[j] += a * sys.dq[i][j];
      rhs -= a * sys.tq[i];
    }
    sys.r.push_back(row);
    sys.h.push_back(rhs);
    sys.row_names.push_back("equation " + std::to_string(c + 1));
  }
  return sys;
}

/// The system at the jets x (q, v, t over the chart); `eval` evaluates a formula on jets.
template <class T, class Eval>
MotionSystem<T> motion_system(const LagrangianSystem& s, const LagrangianDerivatives& d, const std::vector<Jet<T>>& x,
                              const std::vector<std::size_t>& chart, const std::vector<std::string>& names, Eval eval) {
  using J = Jet<T>;
  const std::size_t n = s.n, m = s.m();
  MotionSystem<T> sys;
  std::vector<std::size_t> moving;  // chart positions of the non-time coordinates
  std::size_t tpos = chart.size();
  for (std::size_t j = 0; j < chart.size(); ++j) {
    if (chart[j] == s.t())
      tpos = j;
    else
      moving.push_back(j);
  }
  std::vector<J> lq(n), f(n), b(m);
  std::vector<std::vector<J>> a(m, std::vector<J>(n));
  const J zero(x[0].space(), T(0));
  if (s.implicit) return implicit_system<T>(s, d, x, moving, tpos, chart, names, eval);
  sys.p.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    sys.p[i] = eval(d.dl_dv[i], x);
    lq[i] = eval(d.dl_dq[i], x);
    f[i] = s.forces.empty() ? zero : eval(s.forces[i], x);
  }
  for (std::size_t c = 0; c < m; ++c) {
    b[c] = eval(d.b[c], x);
    for (std::size_t i = 0; i < n; ++i) a[c][i] = eval(d.a[c][i], x);
  }
  sys.dq.assign(n, {});
  sys.dp.assign(n, {});
  sys.tq.assign(n, zero);
  sys.tp.assign(n, zero);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j : moving) {
      sys.dq[i].push_back(x[s.q(i)].derivative(j));
      sys.dp[i].push_back(sys.p[i].derivative(j));
    }
    if (tpos < chart.size()) {
      sys.tq[i] = x[s.q(i)].derivative(tpos);
      sys.tp[i] = sys.p[i].derivative(tpos);
    }
  }
  const std::vector<std::string> st = s.state_names();
  for (std::size_t j : moving) sys.col_names.push_back("d/dt " + names[chart[j]]);
  for (std::size_t c = 0; c < m; ++c) sys.col_names.push_back("lambda_" + std::to_string(c + 1));
  const std::size_t w = moving.size() + m;
  for (std::size_t i = 0; i < n; ++i) {  // q̇ = v
    std::vector<J> row(w, zero);
    for (std::size_t j = 0; j < moving.size(); ++j) row[j] = sys.dq[i][j];
    sys.r.push_back(row);
    sys.h.push_back(x[s.v(i)] - sys.tq[i]);
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

}  // namespace dcad::reference::pointwise_detail
