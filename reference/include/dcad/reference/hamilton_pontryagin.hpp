// YM §3's variational framework on the Pontryagin bundle TQ ⊕ T*Q for linear data, literally:
//   the Hamilton–Pontryagin integrand (3.4)/(3.11) at (x, ẋ) in the direction w = (δq, δv, δp):
//     (∂L/∂q − ṗ)·δq + (∂L/∂v − p)·δv + (q̇ − v)·δp;
//   its intrinsic form ((Tpr_{T*Q})*χ − τ*dE)(x, ẋ)·w with χ(z, ż)·u = Ω♭(ż)·u = −ṗ δq + q̇ δp
//   (YM (3.48)) on Tpr_{T*Q}(x, ẋ) = (q, p, q̇, ṗ), and dE of E = p·v − L  [YM Prop 3.2];
//   the intrinsic implicit Euler–Lagrange equations (3.10): that form vanishes for every w  [YM Prop 3.3];
//   the intrinsic Lagrange–d'Alembert–Pontryagin equations (3.17): x ∈ 𝒦 (3.14), (x, ẋ) ∈ 𝒞 = ℬ ∩ T𝒦,
//   and the form vanishes on w ∈ 𝒢 (3.15), whose base parts Tτ(w) = (δq, δv, δp) range over 𝒞(x):
//   δq ∈ Δ, δv ∈ Δ, δp = Bᵀ δq + A δv  [YM Prop 3.5];
//   the vertical lift X̃ = (q̇, 0, ṗ) of a partial vector field X = (q̇, ṗ), the intrinsic implicit Lagrangian
//   system (3.18)/(3.21) read as Prop 3.6's proof reads it, (3.22), with δv and δp free, and the condition
//   (3.24) (X, 𝔇L) ∈ D_Δ: Thm 3.8 says the three are one.
// Prop 3.5 calls (3.17) equivalent to the LDAP equations (3.13).  On 𝒞 it reads, for δq, δv ∈ Δ and
// u = q̇ − v: u·(Bᵀ δq + A δv) + (∂L/∂q − ṗ)·δq = 0, i.e. u ∈ Δ, A u ∈ Δ° and ∂L/∂q − ṗ + B u ∈ Δ°, while
// (3.13) is u = 0 with ∂L/∂q − ṗ ∈ Δ°.  They agree where A is nondegenerate on Δ (L regular on Δ — which an
// invertible A does not imply: diag(1, −1) on Δ = span(1, 1)).  Where it
// is not, a u ≠ 0 with A u ∈ Δ° and (B − Bᵀ) u ∈ A Δ + Δ° (always, when B is symmetric — LC circuits have
// B = 0) gives a rate in 𝒞 satisfying (3.17) and not (3.13): the intrinsic equations lose q̇ = v there
// (prop_ym_variational plants such rates).
#pragma once

#include "dcad/reference/implicit_lagrangian.hpp"

namespace dcad::reference {

template <class T>
void require_bundle_vectors(const PontryaginInput<T>& in, std::initializer_list<const std::vector<T>*> vs,
                            const std::string& fn) {
  for (const std::vector<T>* v : vs)
    require(v->size() == 3 * in.n, fn, "vectors (q, v, p) of length 3n = " + std::to_string(3 * in.n),
            "length " + std::to_string(v->size()));
}

/// The coordinate integrand of the Hamilton–Pontryagin principle (3.11) at (x, ẋ), in direction w.
template <class T>
T hamilton_pontryagin_integrand(const PontryaginInput<T>& in, const std::vector<T>& x, const std::vector<T>& xdot,
                                const std::vector<T>& w) {
  require_bundle_vectors(in, {&x, &xdot, &w}, "hamilton_pontryagin_integrand");
  const Index n = in.n;
  const std::vector<T> q(x.begin(), x.begin() + n), v(x.begin() + n, x.begin() + 2 * n);
  const std::vector<T> lq = dirac_differential(in, Matrix<T>(n, n), Matrix<T>(n, n), q, v);  // (−∂L/∂q, v)
  const std::vector<T> lv = legendre(in, q, v);                                              // ∂L/∂v
  T s(0);
  for (Index i = 0; i < n; ++i)
    s += (-lq[i] - xdot[2 * n + i]) * w[i] + (lv[i] - x[2 * n + i]) * w[n + i] + (xdot[i] - x[n + i]) * w[2 * n + i];
  return s;
}

/// ((Tpr_{T*Q})*χ − τ*dE)(x, ẋ)·w: χ through Ω♭ on T*Q's part of ẋ, E = p·v − L as the CAD's energy
/// (pontryagin_system's Hessian and gradient)  [YM Prop 3.2, (3.4)].
template <class T>
T intrinsic_hamilton_pontryagin(const PontryaginInput<T>& in, const std::vector<T>& x, const std::vector<T>& xdot,
                                const std::vector<T>& w) {
  require_bundle_vectors(in, {&x, &xdot, &w}, "intrinsic_hamilton_pontryagin");
  const Index n = in.n;
  std::vector<T> zdot(xdot.begin(), xdot.begin() + n), u(w.begin(), w.begin() + n);  // Tpr_{T*Q}: (q̇, ṗ), (δq, δp)
  zdot.insert(zdot.end(), xdot.begin() + 2 * n, xdot.end());
  u.insert(u.end(), w.begin() + 2 * n, w.end());
  const std::vector<T> chi = omega_flat(zdot);
  const LinearSystem<T> e = pontryagin_system(in);
  const std::vector<T> de = energy_differential(e, x);
  T s(0);
  for (Index i = 0; i < 2 * n; ++i) s += chi[i] * u[i];
  for (Index i = 0; i < 3 * n; ++i) s -= de[i] * w[i];
  return s;
}

/// (3.10): the intrinsic form vanishes for every w (the standard basis of T(TQ ⊕ T*Q))  [YM Prop 3.3].
template <class T>
bool satisfies_intrinsic_euler_lagrange(const PontryaginInput<T>& in, const std::vector<T>& x,
                                        const std::vector<T>& xdot) {
  for (Index j = 0; j < 3 * in.n; ++j) {
    std::vector<T> w(3 * in.n);
    w[j] = T(1);
    if (intrinsic_hamilton_pontryagin(in, x, xdot, w) != T(0)) return false;
  }
  return true;
}

/// 𝒞(x) = ℬ ∩ T_x𝒦: {(δq, δv, δp) : δq ∈ Δ, δv ∈ Δ, δp = Bᵀ δq + A δv}  [YM (3.14)–(3.15)].
template <class T>
Subspace<T> ldap_variations(const PontryaginInput<T>& in) {
  const Index n = in.n;
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  const Index d = delta.dim();
  Matrix<T> rows(2 * d, 3 * n);
  const Matrix<T> bq = delta.basis() * in.qv, av = delta.basis() * in.vv;  // rows (Bᵀ δq)ᵀ, (A δv)ᵀ
  for (Index i = 0; i < d; ++i)
    for (Index j = 0; j < n; ++j) {
      rows(i, j) = delta.basis()(i, j);
      rows(i, 2 * n + j) = bq(i, j);
      rows(d + i, n + j) = delta.basis()(i, j);
      rows(d + i, 2 * n + j) = av(i, j);
    }
  return Subspace<T>::span(rows);
}

/// (3.17) at (x, ẋ): x ∈ 𝒦, ẋ ∈ 𝒞(x), and the intrinsic form vanishes on 𝒞(x)'s basis  [YM Prop 3.5].
template <class T>
bool satisfies_intrinsic_ldap(const PontryaginInput<T>& in, const std::vector<T>& x, const std::vector<T>& xdot) {
  require_bundle_vectors(in, {&x, &xdot}, "satisfies_intrinsic_ldap");
  const Index n = in.n;
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  const std::vector<T> q(x.begin(), x.begin() + n), v(x.begin() + n, x.begin() + 2 * n);
  if (!contains(delta, v) || std::vector<T>(x.begin() + 2 * n, x.end()) != legendre(in, q, v)) return false;  // 𝒦
  const Subspace<T> c = ldap_variations(in);
  if (!contains(c, xdot)) return false;
  for (Index r = 0; r < c.dim(); ++r)
    if (intrinsic_hamilton_pontryagin(in, x, xdot, c.basis().row(r)) != T(0)) return false;
  return true;
}

/// The vertical lift X̃(x) = (q̇, 0, ṗ) of a partial vector field's value X(x) = (q̇, ṗ)  [YM §3, before Prop 3.6].
template <class T>
std::vector<T> vertical_lift(const std::vector<T>& x) {
  const Index n = x.size() / 2;
  std::vector<T> out(x.begin(), x.begin() + n);
  out.resize(2 * n);
  out.insert(out.end(), x.begin() + n, x.end());
  return out;
}

/// The intrinsic implicit Lagrangian system (3.18)/(3.21) as Prop 3.6's proof evaluates it, (3.22): v ∈ Δ and
/// the intrinsic form at X̃(x) vanishes for δq in Δ's basis and every δv, δp of the standard basis (free, as the
/// proof takes them — not tied by T𝒦 as in (3.17)).
template <class T>
bool satisfies_intrinsic_implicit_lagrangian(const PontryaginInput<T>& in, const std::vector<T>& x,
                                             const std::vector<T>& field) {
  require(field.size() == 2 * in.n, "satisfies_intrinsic_implicit_lagrangian",
          "X = (q̇, ṗ) of length 2n = " + std::to_string(2 * in.n), "length " + std::to_string(field.size()));
  const Index n = in.n;
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  if (!contains(delta, std::vector<T>(x.begin() + n, x.begin() + 2 * n))) return false;
  const std::vector<T> lifted = vertical_lift(field);
  Matrix<T> rows(delta.dim() + 2 * n, 3 * n);
  for (Index i = 0; i < delta.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(i, j) = delta.basis()(i, j);
  for (Index j = 0; j < 2 * n; ++j) rows(delta.dim() + j, n + j) = T(1);
  for (Index r = 0; r < rows.rows(); ++r)
    if (intrinsic_hamilton_pontryagin(in, x, lifted, rows.row(r)) != T(0)) return false;
  return true;
}

/// (3.24): v ∈ Δ, p = FL(q, v) and (X, 𝔇L(q, v)) ∈ D_Δ(q, p)  [YM Prop 3.7, Thm 3.8 (c)].
template <class T>
bool satisfies_implicit_lagrangian_condition(const PontryaginInput<T>& in, const std::vector<T>& x,
                                             const std::vector<T>& field) {
  require_bundle_vectors(in, {&x}, "satisfies_implicit_lagrangian_condition");
  const Index n = in.n;
  const std::vector<T> q(x.begin(), x.begin() + n), v(x.begin() + n, x.begin() + 2 * n);
  const Subspace<T> delta = in.k.rows() ? kernel(in.k) : Subspace<T>::whole(n);
  if (!contains(delta, v) || std::vector<T>(x.begin() + 2 * n, x.end()) != legendre(in, q, v)) return false;
  std::vector<T> pair = field;
  const std::vector<T> dl = dirac_differential(in, Matrix<T>(n, n), Matrix<T>(n, n), q, v);
  pair.insert(pair.end(), dl.begin(), dl.end());
  return contains(induced_dirac(in.k, n).d, pair);
}

}  // namespace dcad::reference
