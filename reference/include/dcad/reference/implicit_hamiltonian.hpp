// Implicit Hamiltonian systems (YM §3, from "Implicit Hamiltonian Systems" to Thm 3.19) for linear data,
// literally:
//   H(q, p) = ½ pᵀ A p + qᵀ B p + ½ qᵀ C q + a·q + b·p on T*Q = Q^{2n}, z = (q, p), Δ = ker K;
//   Hamilton's equations i_X Ω = dH, locally q̇ = ∂H/∂p, ṗ = −∂H/∂q  [YM Prop 3.11, (3.40)];
//   (H, Δ, X) is an implicit Hamiltonian system when (X, dH) ∈ D_Δ  [YM Def 3.12, (3.47)];
//   in coordinates q̇ = ∂H/∂p ∈ Δ, ṗ + ∂H/∂q ∈ Δ°  [YM Prop 3.14, (3.41)];
//   the Hamilton–d'Alembert principle in phase space: (q̇ − ∂H/∂p)·δp + (−ṗ − ∂H/∂q)·δq = 0 for all
//   δq ∈ Δ, δp, with q̇ ∈ Δ  [YM (3.42)–(3.43), Prop 3.15];
//   its intrinsic form χ(X)·w = (τ*dH)·w for the variations w, where χ(X)·w = Ω♭(X)·u = −ṗ δq + q̇ δp and
//   u = Tτ(w) = (δq, δp) ranges over Δ_{T*Q}  [YM (3.46), (3.48)–(3.52), Props 3.16–3.18] — as the proof of
//   Prop 3.18 lets it range; read literally, 𝒥 = ℐ ∩ TΔ_P ties (δq, δp) to T P, and (3.46) is then weaker than
//   (3.47) where H's A is degenerate on the directions P leaves (the gap hamilton_pontryagin.hpp shows for
//   Prop 3.5, which an invertible A does not close: A = diag(1, −1) is degenerate on Δ = span(1, 1));
//   and Thm 3.19: the principle, the intrinsic system and (X, dH) ∈ D_Δ are equivalent.
// The multipliers' term μ_a ω^a = ṗ + ∂H/∂q ∈ Δ° ("Coordinate Representation" after Prop 3.15) is the
// constraint force; at a point it is free in Δ°, and the CAD on (D_Δ, H) (CEF (1.1)) fixes it on M_c.
#pragma once

#include "dcad/hamiltonian_data.hpp"
#include "dcad/reference/implicit_lagrangian.hpp"

namespace dcad::reference {

template <class T>
using HamiltonianInput = HamiltonianData<Matrix<T>, std::vector<T>>;  // dcad/hamiltonian_data.hpp

template <class T>
void require_hamiltonian(const HamiltonianInput<T>& in, const std::string& fn) {
  const Index n = in.n;
  const std::string sq = std::to_string(n) + "x" + std::to_string(n);
  require(in.pp.rows() == n && in.pp.cols() == n, fn, "pp (A) " + sq, shape(in.pp));
  require(in.qp.rows() == n && in.qp.cols() == n, fn, "qp (B) " + sq, shape(in.qp));
  require(in.qq.rows() == n && in.qq.cols() == n, fn, "qq (C) " + sq, shape(in.qq));
  require(is_symmetric(in.pp) && is_symmetric(in.qq), fn, "symmetric pp and qq", "an asymmetric one");
  require(in.q.size() == n && in.p.size() == n, fn, "q and p of length " + std::to_string(n),
          "lengths " + std::to_string(in.q.size()) + " and " + std::to_string(in.p.size()));
  require(in.k.rows() == 0 || in.k.cols() == n, fn, "k with " + std::to_string(n) + " columns", shape(in.k));
}

template <class T>
void require_phase_point(const HamiltonianInput<T>& in, const std::vector<T>& z, const std::string& fn,
                         const char* what) {
  require(z.size() == 2 * in.n, fn, std::string(what) + " of length 2n = " + std::to_string(2 * in.n),
          "length " + std::to_string(z.size()));
}

/// dH(z) = (∂H/∂q, ∂H/∂p) = (B p + C q + a, A p + Bᵀ q + b).
template <class T>
std::vector<T> hamiltonian_differential(const HamiltonianInput<T>& in, const std::vector<T>& z) {
  require_hamiltonian(in, "hamiltonian_differential");
  require_phase_point(in, z, "hamiltonian_differential", "z");
  const Index n = in.n;
  const Matrix<T> q = Matrix<T>::column(std::vector<T>(z.begin(), z.begin() + n));
  const Matrix<T> p = Matrix<T>::column(std::vector<T>(z.begin() + n, z.end()));
  const std::vector<T> hq = (in.qp * p + in.qq * q).col(0), hp = (in.pp * p + in.qp.transpose() * q).col(0);
  std::vector<T> out(2 * n);
  for (Index i = 0; i < n; ++i) {
    out[i] = hq[i] + in.q[i];
    out[n + i] = hp[i] + in.p[i];
  }
  return out;
}

/// Δ = ker K (the whole Q^n when K has no rows).
template <class T>
Subspace<T> hamiltonian_distribution(const HamiltonianInput<T>& in) {
  return in.k.rows() ? kernel(in.k) : Subspace<T>::whole(in.n);
}

/// The Hamiltonian vector field X_H: the solution of i_X Ω = dH, Ω♭'s matrix inverted  [YM Prop 3.11, (3.40)].
template <class T>
std::vector<T> hamilton_field(const HamiltonianInput<T>& in, const std::vector<T>& z) {
  const Index m = 2 * in.n;
  Matrix<T> flat(m, m);  // column j: Ω♭(e_j)
  for (Index j = 0; j < m; ++j) {
    std::vector<T> e(m);
    e[j] = T(1);
    const std::vector<T> c = omega_flat(e);
    for (Index i = 0; i < m; ++i) flat(i, j) = c[i];
  }
  return (inverse(flat) * Matrix<T>::column(hamiltonian_differential(in, z))).col(0);
}

/// {X : (X, dH(z)) ∈ D_Δ(z)}, from the equations of D_Δ (its annihilator)  [YM Def 3.12].
template <class T>
AffineSubspace<T> implicit_hamiltonian_fields(const HamiltonianInput<T>& in, const std::vector<T>& z) {
  const std::vector<T> dh = hamiltonian_differential(in, z);
  const Matrix<T> g = annihilator(induced_dirac(in.k, in.n).d).basis();
  const Index m = 2 * in.n;
  std::vector<T> rhs = (g.block(0, g.rows(), m, 2 * m) * Matrix<T>::column(dh)).col(0);
  for (T& c : rhs) c = -c;
  return solve(g.block(0, g.rows(), 0, m), rhs);
}

/// Whether (X, dH(z)) ∈ D_Δ(z)  [YM (3.47)].
template <class T>
bool in_induced_dirac(const HamiltonianInput<T>& in, const std::vector<T>& z, const std::vector<T>& x) {
  require_phase_point(in, x, "in_induced_dirac", "X");
  std::vector<T> pair = x;
  const std::vector<T> dh = hamiltonian_differential(in, z);
  pair.insert(pair.end(), dh.begin(), dh.end());
  return contains(induced_dirac(in.k, in.n).d, pair);
}

/// (3.41): q̇ = ∂H/∂p, q̇ ∈ Δ, ṗ + ∂H/∂q ∈ Δ°  [YM Prop 3.14].
template <class T>
bool satisfies_implicit_hamiltonian(const HamiltonianInput<T>& in, const std::vector<T>& z, const std::vector<T>& x) {
  require_phase_point(in, x, "satisfies_implicit_hamiltonian", "X");
  const Index n = in.n;
  const std::vector<T> dh = hamiltonian_differential(in, z);
  const std::vector<T> qd(x.begin(), x.begin() + n);
  std::vector<T> force(n);
  for (Index i = 0; i < n; ++i) {
    if (qd[i] != dh[n + i]) return false;
    force[i] = x[n + i] + dh[i];
  }
  const Subspace<T> delta = hamiltonian_distribution(in);
  return contains(delta, qd) && contains(annihilator(delta), force);
}

/// The Hamilton–d'Alembert principle's integrand (3.43) vanishes for every δq in Δ's basis and every δp
/// of the standard basis, and q̇ ∈ Δ  [YM Prop 3.15].
template <class T>
bool satisfies_hamilton_dalembert(const HamiltonianInput<T>& in, const std::vector<T>& z, const std::vector<T>& x) {
  require_phase_point(in, x, "satisfies_hamilton_dalembert", "X");
  const Index n = in.n;
  const std::vector<T> dh = hamiltonian_differential(in, z);
  const Subspace<T> delta = hamiltonian_distribution(in);
  if (!contains(delta, std::vector<T>(x.begin(), x.begin() + n))) return false;
  for (Index j = 0; j < n; ++j)  // δq = 0, δp = e_j: q̇_j − ∂H/∂p_j
    if (x[j] - dh[n + j] != T(0)) return false;
  for (Index r = 0; r < delta.dim(); ++r) {  // δp = 0, δq = a basis vector of Δ: (−ṗ − ∂H/∂q)·δq
    T s(0);
    for (Index i = 0; i < n; ++i) s += (-x[n + i] - dh[i]) * delta.basis()(r, i);
    if (s != T(0)) return false;
  }
  return true;
}

/// The intrinsic implicit Hamiltonian system (3.46) at X: X ∈ Δ_{T*Q} and χ(X)·w = (τ*dH)·w for every w,
/// evaluated as (3.50)–(3.52) do, χ(X)·w = Ω♭(X)·u and (τ*dH)·w = dH·u with u = Tτ(w) over a basis of
/// Δ_{T*Q} = (Tπ_Q)⁻¹(Δ)  [YM Props 3.16–3.18].
template <class T>
bool satisfies_intrinsic_implicit_hamiltonian(const HamiltonianInput<T>& in, const std::vector<T>& z,
                                              const std::vector<T>& x) {
  require_phase_point(in, x, "satisfies_intrinsic_implicit_hamiltonian", "X");
  const Index n = in.n;
  const Subspace<T> delta = hamiltonian_distribution(in);
  Matrix<T> rows(delta.dim() + n, 2 * n);  // Δ_{T*Q}: (δq, 0) for δq in Δ's basis, (0, e_j)
  for (Index i = 0; i < delta.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(i, j) = delta.basis()(i, j);
  for (Index j = 0; j < n; ++j) rows(delta.dim() + j, n + j) = T(1);
  if (!contains(Subspace<T>::span(rows), x)) return false;                         // X(z) ∈ Δ_{T*Q}
  const std::vector<T> chi = omega_flat(x), dh = hamiltonian_differential(in, z);  // Ω♭(X) = (−ṗ, q̇)
  for (Index r = 0; r < rows.rows(); ++r) {
    T lhs(0), rhs(0);
    for (Index j = 0; j < 2 * n; ++j) {
      lhs += chi[j] * rows(r, j);
      rhs += dh[j] * rows(r, j);
    }
    if (lhs != rhs) return false;
  }
  return true;
}

/// The constraint force μ_a ω^a = ṗ + ∂H/∂q of a field X at z (in Δ° when X solves (3.41)).
template <class T>
std::vector<T> hamiltonian_constraint_force(const HamiltonianInput<T>& in, const std::vector<T>& z,
                                            const std::vector<T>& x) {
  require_phase_point(in, x, "hamiltonian_constraint_force", "X");
  const std::vector<T> dh = hamiltonian_differential(in, z);
  std::vector<T> f(in.n);
  for (Index i = 0; i < in.n; ++i) f[i] = x[in.n + i] + dh[i];
  return f;
}

/// The implicit Hamiltonian system as a Dirac dynamical system (CEF (1.1)) on Q^{2n}: D_Δ and E = H, for the
/// CAD, which fixes the constraint forces on M_c.
template <class T>
LinearSystem<T> implicit_hamiltonian_system(const HamiltonianInput<T>& in) {
  require_hamiltonian(in, "implicit_hamiltonian_system");
  const Index n = in.n;
  LinearSystem<T> s{induced_dirac(in.k, n), Matrix<T>(2 * n, 2 * n), std::vector<T>(2 * n)};
  for (Index i = 0; i < n; ++i) {
    s.gradient[i] = in.q[i];
    s.gradient[n + i] = in.p[i];
    for (Index j = 0; j < n; ++j) {
      s.hessian(i, j) = in.qq(i, j);
      s.hessian(i, n + j) = in.qp(i, j);
      s.hessian(n + j, i) = in.qp(i, j);
      s.hessian(n + i, n + j) = in.pp(i, j);
    }
  }
  return s;
}

/// The Legendre transform of a hyperregular L (A invertible): H(q, p) = p·v − L(q, v) at p = ∂L/∂v, i.e.
/// A_H = A⁻¹, B_H = −B A⁻¹, C_H = B A⁻¹ Bᵀ − C, a_H = B A⁻¹ b − a, b_H = −A⁻¹ b (the constant dropped),
/// with the same Δ  [YM §3: "optimizes first over v" turns the LDAP principle into Hamilton–d'Alembert].
template <class T>
HamiltonianInput<T> legendre_hamiltonian(const PontryaginInput<T>& l) {
  require(l.vv.rows() == l.n && l.vv.cols() == l.n && determinant(l.vv) != T(0), "legendre_hamiltonian",
          "an invertible vv (a hyperregular L)", "a singular one");
  const Matrix<T> ai = inverse(l.vv), bai = l.qv * ai;
  HamiltonianInput<T> h{l.n, l.k, ai, Matrix<T>(l.n, l.n) - bai, bai * l.qv.transpose() - l.qq, {}, {}};
  const std::vector<T> bab = (bai * Matrix<T>::column(l.v)).col(0), aib = (ai * Matrix<T>::column(l.v)).col(0);
  for (Index i = 0; i < l.n; ++i) {
    h.q.push_back(bab[i] - l.q[i]);
    h.p.push_back(-aib[i]);
  }
  return h;
}

}  // namespace dcad::reference
