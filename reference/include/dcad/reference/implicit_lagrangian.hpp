// Implicit Lagrangian systems (YM §3–§5, CEF Def. 6.1) for linear data, literally:
//   T*Q = Q^{2n} with z = (q, p), Ω = dq ∧ dp;  Δ_{T*Q} = (Tπ_Q)⁻¹(Δ) = {(δq, δp) : δq ∈ Δ};
//   the induced Dirac structure D_Δ(z) = {(w, α) : w ∈ Δ_{T*Q}, α − Ω♭ w ∈ Δ_{T*Q}°}  [YM (3.23)];
//   the Dirac differential 𝔇L(q, v) = (−∂L/∂q, v) ∈ T*_{(q,p)} T*Q, p = ∂L/∂v  [YM §3];
//   an implicit Lagrangian system with forces (L, F, Δ, X): (X, 𝔇L − π*F) ∈ D_Δ  [YM (4.7)],
//   whose coordinate form is the Lagrange–d'Alembert–Pontryagin equations (4.3):
//     q̇ = v ∈ Δ,  ṗ − ∂L/∂q − F ∈ Δ°,  p = ∂L/∂v;
//   the restriction of a Dirac structure to a subspace N, D_N = σ(D ∩ (N × M*))  [YM Prop. 5.2];
//   the constrained Dirac structure D_P = restriction of D_Δ to P = FL(Δ)  [YM §5].
#pragma once

#include "dcad/reference/system.hpp"

namespace dcad::reference {

/// Ω♭ on T*Q: Ω((a, b), (c, d)) = a·d − b·c, so i_{(q̇, ṗ)} Ω = (−ṗ, q̇).
template <class T>
std::vector<T> omega_flat(const std::vector<T>& w) {
  const Index n = w.size() / 2;
  std::vector<T> out(2 * n);
  for (Index i = 0; i < n; ++i) {
    out[i] = -w[n + i];
    out[n + i] = w[i];
  }
  return out;
}

/// D_Δ ⊂ T(T*Q) ⊕ T*(T*Q) for Δ = ker K, as a DiracStructure on Q^{2n}  [YM (3.23)].
template <class T>
DiracStructure<T> induced_dirac(const Matrix<T>& k, Index n) {
  const Subspace<T> delta = k.rows() ? kernel(k) : Subspace<T>::whole(n);
  Matrix<T> rows(delta.dim() + n, 2 * n), w(2 * n, 2 * n);
  for (Index i = 0; i < delta.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(i, j) = delta.basis()(i, j);
  for (Index i = 0; i < n; ++i) {
    rows(delta.dim() + i, n + i) = T(1);
    w(i, n + i) = T(1);
    w(n + i, i) = T(-1);
  }
  return dirac_from_distribution(Subspace<T>::span(rows), w);  // E = Δ_{T*Q}, ω = Ω|_E  [CEF Prop. 4.3]
}

/// 𝔇L(q, v) − π*F(q, v) = (−∂L/∂q − F, v) for the quadratic L of a PontryaginInput and the linear
/// force F(q, v) = F_q q + F_v v (n×n each).
template <class T>
std::vector<T> dirac_differential(const PontryaginInput<T>& in, const Matrix<T>& fq, const Matrix<T>& fv,
                                  const std::vector<T>& q, const std::vector<T>& v) {
  const Index n = in.n;
  const Matrix<T> cq = Matrix<T>::column(q), cv = Matrix<T>::column(v);
  // ∂L/∂q = B v + C q + a
  const std::vector<T> dlq = (in.qv * cv + in.qq * cq).col(0), force = (fq * cq + fv * cv).col(0);
  std::vector<T> out(2 * n);
  for (Index i = 0; i < n; ++i) {
    out[i] = -(dlq[i] + in.q[i]) - force[i];
    out[n + i] = v[i];
  }
  return out;
}

/// p = ∂L/∂v = A v + Bᵀ q + b  (the Legendre transform FL).
template <class T>
std::vector<T> legendre(const PontryaginInput<T>& in, const std::vector<T>& q, const std::vector<T>& v) {
  std::vector<T> p = (in.vv * Matrix<T>::column(v) + in.qv.transpose() * Matrix<T>::column(q)).col(0);
  for (Index i = 0; i < in.n; ++i) p[i] += in.v[i];
  return p;
}

/// The partial vector fields X(q, v, p) = (q̇, ṗ) of the implicit Lagrangian system (L, F, Δ, X)
/// at (q, v) with v ∈ Δ, p = FL(q, v): {X : (X, 𝔇L − π*F) ∈ D_Δ(q, p)}  [YM (4.7)].
template <class T>
AffineSubspace<T> implicit_lagrangian_fields(const PontryaginInput<T>& in, const Matrix<T>& fq, const Matrix<T>& fv,
                                             const std::vector<T>& q, const std::vector<T>& v) {
  const DiracStructure<T> d = induced_dirac(in.k, in.n);
  // (X, β) ∈ D ⇔ Γ_v X = −Γ_α β for the equations Γ = annihilator of D w.r.t. the plain pairing
  const Matrix<T> g = annihilator(d.d).basis();
  const Index m = 2 * in.n;
  const std::vector<T> beta = dirac_differential(in, fq, fv, q, v);
  std::vector<T> rhs = (g.block(0, g.rows(), m, 2 * m) * Matrix<T>::column(beta)).col(0);
  for (T& c : rhs) c = -c;
  return solve(g.block(0, g.rows(), 0, m), rhs);
}

/// (4.3) at (x, ẋ): q̇ = v, v ∈ Δ, p = ∂L/∂v, ṗ − ∂L/∂q − F ∈ Δ°.  [YM Prop. 4.1]
template <class T>
bool satisfies_ldap(const PontryaginInput<T>& in, const Matrix<T>& fq, const Matrix<T>& fv, const std::vector<T>& x,
                    const std::vector<T>& xdot) {
  const Index n = in.n;
  const std::vector<T> q(x.begin(), x.begin() + n), v(x.begin() + n, x.begin() + 2 * n), p(x.begin() + 2 * n, x.end());
  const std::vector<T> qd(xdot.begin(), xdot.begin() + n), pd(xdot.begin() + 2 * n, xdot.end());
  if (qd != v || p != legendre(in, q, v)) return false;
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  if (!contains(delta, v)) return false;
  const std::vector<T> beta = dirac_differential(in, fq, fv, q, v);  // −∂L/∂q − F
  std::vector<T> r(n);
  for (Index i = 0; i < n; ++i) r[i] = pd[i] + beta[i];
  return contains(annihilator(delta), r);
}

/// D_N = σ(D ∩ (N × M*)) in the coordinates of N's canonical basis B (rows): (c, β) with
/// w = cB ∈ N and β = B α = α|_N.  [YM Prop. 5.2]
template <class T>
DiracStructure<T> restrict_dirac(const DiracStructure<T>& d, const Subspace<T>& n_sub) {
  const Index n = d.n, k = n_sub.dim();
  if (k == 0) return DiracStructure<T>{0, Subspace<T>::zero(0)};  // the zero space: D_N = {0}
  const Matrix<T>& b = n_sub.basis();
  // D ∩ (N × M*): elements λ·G with v-part in N, i.e. (λ G_v) · annihilator(N) = 0
  const Matrix<T>& g = d.d.basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, n), ga = g.block(0, g.rows(), n, 2 * n);
  const Matrix<T> ann = annihilator(n_sub).basis();
  const Matrix<T> lam =
      ann.rows() ? nullspace(ann * gv.transpose()) : Matrix<T>::identity(g.rows());  // rows λ: (λ G_v)·ann = 0
  const Matrix<T> w = lam * gv, alpha = lam * ga;
  // coordinates c of w in B: solve cB = w (B in RREF: c = w at the pivot columns)
  const std::vector<Index> piv = rref(b).pivots;
  Matrix<T> rows(lam.rows(), 2 * k);
  const Matrix<T> restricted = alpha * b.transpose();  // β_j = α(b_j)
  for (Index i = 0; i < lam.rows(); ++i)
    for (Index j = 0; j < k; ++j) {
      rows(i, j) = w(i, piv[j]);
      rows(i, k + j) = restricted(i, j);
    }
  return DiracStructure<T>{k, Subspace<T>::span(rows)};
}

/// T P for the constraint momentum space P = FL(Δ) = {(q, A v + Bᵀ q + b) : v ∈ Δ} ⊂ T*Q:
/// span{(δq, Bᵀ δq + A δv) : δq ∈ Qⁿ, δv ∈ Δ}.  [YM §5]
template <class T>
Subspace<T> constraint_momentum_tangent(const PontryaginInput<T>& in) {
  const Index n = in.n;
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  Matrix<T> rows(n + delta.dim(), 2 * n);
  for (Index i = 0; i < n; ++i) {  // δq = e_i: δp = Bᵀ e_i, i.e. row i of B
    rows(i, i) = T(1);
    for (Index j = 0; j < n; ++j) rows(i, n + j) = in.qv(i, j);
  }
  const Matrix<T> av = delta.basis() * in.vv;  // rows (A δv)ᵀ, A symmetric
  for (Index i = 0; i < delta.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(n + i, n + j) = av(i, j);
  return Subspace<T>::span(rows);
}

/// D_P: the restriction of the induced Dirac structure D_Δ to P, in the coordinates of T P's
/// canonical basis.  [YM §5, "constrained Dirac structure"; Prop. 5.2]
template <class T>
DiracStructure<T> constrained_dirac(const PontryaginInput<T>& in) {
  return restrict_dirac(induced_dirac(in.k, in.n), constraint_momentum_tangent(in));
}

/// The constrained partial vector fields X_P at (q, v), v ∈ Δ, in T P's basis coordinates:
/// {X_P : (X_P, 𝔇L_c) ∈ D_P} with 𝔇L_c = 𝔇L|_{T P}  [YM Def. 5.4, (5.12)].
template <class T>
AffineSubspace<T> implicit_constrained_fields(const PontryaginInput<T>& in, const std::vector<T>& q,
                                              const std::vector<T>& v) {
  const Subspace<T> tp = constraint_momentum_tangent(in);
  const DiracStructure<T> dp = constrained_dirac(in);
  const std::vector<T> dl = dirac_differential(in, Matrix<T>(in.n, in.n), Matrix<T>(in.n, in.n), q, v);
  const std::vector<T> dlc = (tp.basis() * Matrix<T>::column(dl)).col(0);  // 𝔇L restricted to T P
  const Index k = tp.dim();
  const Matrix<T> g = annihilator(dp.d).basis();
  std::vector<T> rhs = (g.block(0, g.rows(), k, 2 * k) * Matrix<T>::column(dlc)).col(0);
  for (T& c : rhs) c = -c;
  return solve(g.block(0, g.rows(), 0, k), rhs);
}

/// X = X_P + X_V with X_P ∈ T P and X_V ∈ V = {(0, η) : η ∈ Δ°} (Marle: T_P(T*Q) = T P ⊕ V when L
/// is regular on Δ): the coordinates of X_P in T P's basis.  [YM (5.11)]
template <class T>
std::vector<T> constrained_part(const PontryaginInput<T>& in, const std::vector<T>& x) {
  const Index n = in.n;
  const Subspace<T> tp = constraint_momentum_tangent(in);
  const Subspace<T> ann = annihilator(in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n));
  Matrix<T> cols(2 * n, tp.dim() + ann.dim());
  for (Index i = 0; i < tp.dim(); ++i)
    for (Index j = 0; j < 2 * n; ++j) cols(j, i) = tp.basis()(i, j);
  for (Index i = 0; i < ann.dim(); ++i)
    for (Index j = 0; j < n; ++j) cols(n + j, tp.dim() + i) = ann.basis()(i, j);
  std::vector<T> c;
  require(solve_particular(cols, x, c), "constrained_part", "a vector of T P ⊕ V", "one outside");
  c.resize(tp.dim());
  return c;
}

}  // namespace dcad::reference
