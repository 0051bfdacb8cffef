// LC circuits as Lagrangian systems on the Pontryagin bundle (CEF §6): branches with inductance
// L_i ≥ 0 (0 = none), capacitance C_i (∞ = none, i.e. 1/C_i = 0) or neither (an empty branch),
// KCL from the reduced incidence matrix, φ = diag(L_i), Ψ = diag(1/C_i), L(q, v) = ½ vᵀΦv − ½ qᵀΨq.
#pragma once

#include "dcad/graph.hpp"
#include "dcad/reference/system.hpp"

namespace dcad::reference {

using dcad::BranchKind;  // dcad/types.hpp (via system.hpp)

template <class T>
struct Branch {
  std::string name;
  BranchKind kind = BranchKind::empty;
  long from = -1, to = -1;  ///< node indices; −1 is ground; current flows from → to
  T value = T(0);           ///< L (inductor) or C (capacitor)
};

template <class T>
struct Circuit {
  std::size_t nodes = 0;  ///< non-ground nodes 0 … nodes−1
  std::vector<Branch<T>> branches;
};

/// Reduced incidence matrix of any branches with `from`/`to` node indices (−1 = ground): row = non-ground
/// node, +1 where a branch leaves it, −1 where it enters.  KCL: K v = 0.
template <class T, class Branches>
Matrix<T> incidence_matrix(std::size_t nodes, const Branches& branches) {
  Matrix<T> k(nodes, branches.size());
  for (Index b = 0; b < branches.size(); ++b) {
    if (branches[b].from >= 0) k(branches[b].from, b) += T(1);
    if (branches[b].to >= 0) k(branches[b].to, b) -= T(1);
  }
  return k;
}

template <class T>
Matrix<T> kcl_matrix(const Circuit<T>& c) {
  return incidence_matrix<T>(c.nodes, c.branches);
}

/// The `pontryagin` data of the circuit: Δ = ker K, A = Φ, C = −Ψ.  [CEF §6, ERRATA]
template <class T>
PontryaginInput<T> circuit_lagrangian(const Circuit<T>& c) {
  const Index n = c.branches.size();
  PontryaginInput<T> in;
  in.n = n;
  in.k = kcl_matrix(c);
  in.vv = Matrix<T>(n, n);
  in.qq = Matrix<T>(n, n);
  in.qv = Matrix<T>(n, n);
  in.q.assign(n, T(0));
  in.v.assign(n, T(0));
  for (Index b = 0; b < n; ++b) {
    if (c.branches[b].kind == BranchKind::inductor) in.vv(b, b) = c.branches[b].value;
    if (c.branches[b].kind == BranchKind::capacitor) in.qq(b, b) = -T(1) / c.branches[b].value;
  }
  return in;
}

/// Cycle rank (edges − vertices + components, ground included) of the subgraph of the branches
/// with keep(kind) — union–find, no arithmetic (dcad/graph.hpp).
template <class T, class Keep>
Index cycle_rank(const Circuit<T>& c, Keep keep) {
  std::vector<graph::Edge> edges;
  std::vector<bool> kept;
  for (const Branch<T>& b : c.branches) {
    edges.push_back({b.from, b.to});
    kept.push_back(keep(b.kind));
  }
  return graph::cycle_rank(c.nodes, edges, kept);
}

/// Independent KVL equations of purely capacitive loops that constrain q (CEF Thm 6.4): loops of
/// the non-inductive subgraph modulo the loops of empty branches (which give 0 = 0).
template <class T>
Index kvlpc_count(const Circuit<T>& c) {
  return cycle_rank(c, [](BranchKind k) { return k != BranchKind::inductor; }) -
         cycle_rank(c, [](BranchKind k) { return k == BranchKind::empty; });
}

/// Dimension of the cycle space of the empty subgraph (the non-uniqueness of CEF Thm 6.8).
template <class T>
Index empty_loop_count(const Circuit<T>& c) {
  return cycle_rank(c, [](BranchKind k) { return k == BranchKind::empty; });
}

/// φ = diag(L_i) and ψ = diag(1/C_i) (ψ with the sign of the proofs in CEF §6, see ERRATA).
template <class T>
Matrix<T> inductance_matrix(const Circuit<T>& c) {
  Matrix<T> phi(c.branches.size(), c.branches.size());
  for (Index b = 0; b < c.branches.size(); ++b)
    if (c.branches[b].kind == BranchKind::inductor) phi(b, b) = c.branches[b].value;
  return phi;
}

template <class T>
Matrix<T> elastance_matrix(const Circuit<T>& c) {
  Matrix<T> psi(c.branches.size(), c.branches.size());
  for (Index b = 0; b < c.branches.size(); ++b)
    if (c.branches[b].kind == BranchKind::capacitor) psi(b, b) = T(1) / c.branches[b].value;
  return psi;
}

/// ψ⁻¹(φ(U) + Δ°), the q-part of the closed form.  [CEF §6, (6.24) and after]
template <class T>
Subspace<T> kvl_subspace(const Circuit<T>& c, const Subspace<T>& u) {
  const Subspace<T> delta = kernel(kcl_matrix(c));
  return preimage(elastance_matrix(c), sum(map(inductance_matrix(c), u), annihilator(delta)));
}

/// Δ_k = Δ ∩ ψ⁻¹(φ(Δ_{k−1}) + Δ°), Δ_0 = Δ.  [CEF §6, after (6.24)]
template <class T>
Subspace<T> delta_k(const Circuit<T>& c, Index k) {
  const Subspace<T> delta = kernel(kcl_matrix(c));
  return k == 0 ? delta : intersection(delta, kvl_subspace(c, delta_k(c, k - 1)));
}

/// {(q, v, p) : q ∈ S, v ∈ V, p = φ v} ⊂ Q^{3n}.
template <class T>
Subspace<T> pontryagin_product(const Circuit<T>& c, const Subspace<T>& s, const Subspace<T>& v) {
  const Index n = c.branches.size();
  const Matrix<T> phi = inductance_matrix(c);
  Matrix<T> rows(s.dim() + v.dim(), 3 * n);
  for (Index i = 0; i < s.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(i, j) = s.basis()(i, j);
  for (Index i = 0; i < v.dim(); ++i)
    for (Index j = 0; j < n; ++j) {
      rows(s.dim() + i, n + j) = v.basis()(i, j);
      for (Index l = 0; l < n; ++l) rows(s.dim() + i, 2 * n + j) += phi(j, l) * v.basis()(i, l);
    }
  return Subspace<T>::span(rows);
}

/// The closed form of M_j, j ≥ 1 [CEF §6]: M_1 = {p = φ v, v ∈ Δ};
/// M_{2k−1} = {q ∈ ψ⁻¹(φ(Δ_{k−2}) + Δ°), p = φ v, v ∈ Δ_{k−1}} (k ≥ 2);
/// M_{2k} = {q ∈ ψ⁻¹(φ(Δ_{k−1}) + Δ°), p = φ v, v ∈ Δ_{k−1}} (k ≥ 1).
template <class T>
Subspace<T> closed_form_m(const Circuit<T>& c, Index j) {
  const Index n = c.branches.size();
  if (j == 1) return pontryagin_product(c, Subspace<T>::whole(n), delta_k(c, 0));
  const Index k = (j + 1) / 2;
  if (j % 2 == 1) return pontryagin_product(c, kvl_subspace(c, delta_k(c, k - 2)), delta_k(c, k - 1));
  return pontryagin_product(c, kvl_subspace(c, delta_k(c, k - 1)), delta_k(c, k - 1));
}

/// Condition (*) of CEF Lemma 6.5 (b), literally: for each δ ∈ Δ there is δ_1 ∈ Δ_1 with φ(δ) − φ(δ_1) ∈ Δ°,
/// i.e. φ(Δ) ⊆ φ(Δ_1) + Δ°.  Lemma 6.5 (b): it holds exactly when Δ_1 = Δ_2; Theorem 6.6: it holds when every
/// branch has L > 0 or a finite C > 0.
template <class T>
bool condition_star(const Circuit<T>& c) {
  const Subspace<T> delta = delta_k(c, 0);
  const Matrix<T> phi = inductance_matrix(c);
  return contains(sum(map(phi, delta_k(c, 1)), annihilator(delta)), map(phi, delta));
}

/// Γ = [η_1 … η_b] (columns): the KVLPC loops of CEF Theorem 6.4 — of a basis of the non-inductive loop
/// currents (φ(Δ) + Δ°)° = φ(Δ)° ∩ Δ, those whose elastance rows ηᵀψ extend the ones kept (empty loops give
/// ηᵀψ = 0 and drop out), so the equations η(ψq) = 0 are independent.
template <class T>
Matrix<T> kvlpc_loops(const Circuit<T>& c) {
  const Subspace<T> delta = delta_k(c, 0);
  const Matrix<T> phi = inductance_matrix(c), psi = elastance_matrix(c);
  const Subspace<T> loops = intersection(annihilator(map(phi, delta)), delta);
  Matrix<T> kept(0, c.branches.size()), rows(0, c.branches.size());
  for (Index i = 0; i < loops.dim(); ++i) {
    const Matrix<T> eta = loops.basis().block(i, i + 1, 0, loops.ambient());
    if (rank(vstack(rows, eta * psi)) == rows.rows()) continue;
    rows = vstack(rows, eta * psi);
    kept = vstack(kept, eta);
  }
  return kept.transpose();
}

/// The equations of the leaf x₀ + W̃_c of an LC circuit in T*TE, variables (q, v, p, ν) ∈ Q^{4n}, rows [a | b]
/// (CEF §6 after Theorem 6.8): κ(q) = κ(q₀), η(ψq) = 0, p − φv = 0, κ(v) = 0, η(ψv) = 0, ν = 0 — K the KCL
/// rows, Γ the KVLPC loops.
template <class T>
Matrix<T> leaf_equations(const Circuit<T>& c, const std::vector<T>& q0) {
  const Index n = c.branches.size();
  const Matrix<T> k = kcl_matrix(c), gpsi = kvlpc_loops(c).transpose() * elastance_matrix(c);
  const Matrix<T> phi = inductance_matrix(c), id = Matrix<T>::identity(n);
  const auto row = [&](const Matrix<T>& q, const Matrix<T>& v, const Matrix<T>& p, const Matrix<T>& nu,
                       const Matrix<T>& b) { return hstack(hstack(hstack(q, v), hstack(p, nu)), b); };
  const auto zero = [&](const Matrix<T>& like) { return Matrix<T>(like.rows(), n); };
  const auto none = [&](const Matrix<T>& like) { return Matrix<T>(like.rows(), 1); };
  Matrix<T> rows = row(k, zero(k), zero(k), zero(k), k * Matrix<T>::column(q0));
  rows = vstack(rows, row(gpsi, zero(gpsi), zero(gpsi), zero(gpsi), none(gpsi)));
  rows = vstack(rows, row(zero(id), -phi, id, zero(id), none(id)));
  rows = vstack(rows, row(zero(k), k, zero(k), zero(k), none(k)));
  rows = vstack(rows, row(zero(gpsi), gpsi, zero(gpsi), zero(gpsi), none(gpsi)));
  return vstack(rows, row(zero(id), zero(id), zero(id), id, none(id)));
}

/// T*TE's canonical form dq ∧ dp + dv ∧ dν on (q, v, p, ν) ∈ Q^{4n} (CEF Appendix A; {q_i, p_j} = δ_ij).
template <class T>
Matrix<T> cotangent_of_tangent_form(Index n) {
  Matrix<T> w(4 * n, 4 * n);
  for (Index i = 0; i < n; ++i) {
    w(i, 2 * n + i) = w(n + i, 3 * n + i) = T(1);
    w(2 * n + i, i) = w(3 * n + i, n + i) = T(-1);
  }
  return w;
}

/// Σ = [{ε_i, ε_j}] of leaf_equations in CEF's block form (after Theorem 6.8), from K, Γ, φ and ψ:
///   [0 0 K 0 0 0; 0 0 Γᵀψ 0 0 0; −Kᵀ −ψΓ 0 0 0 −φ; 0 0 0 0 0 K; 0 0 0 0 0 Γᵀψ; 0 0 φ −Kᵀ −ψΓ 0].
template <class T>
Matrix<T> leaf_sigma_block_form(const Circuit<T>& c) {
  const Index n = c.branches.size();
  const Matrix<T> k = kcl_matrix(c), psi = elastance_matrix(c), phi = inductance_matrix(c);
  const Matrix<T> gpsi = kvlpc_loops(c).transpose() * psi;
  const Index a = k.rows(), b = gpsi.rows();
  const std::vector<Index> at{0, a, a + b, a + b + n, 2 * a + b + n, 2 * a + 2 * b + n, 2 * a + 2 * b + 2 * n};
  Matrix<T> sigma(at.back(), at.back());
  const auto put = [&](Index bi, Index bj, const Matrix<T>& m) {
    for (Index i = 0; i < m.rows(); ++i)
      for (Index j = 0; j < m.cols(); ++j) sigma(at[bi] + i, at[bj] + j) = m(i, j);
  };
  put(0, 2, k);
  put(1, 2, gpsi);
  put(2, 0, -k.transpose());
  put(2, 1, -gpsi.transpose());
  put(2, 5, -phi);
  put(3, 5, k);
  put(4, 5, gpsi);
  put(5, 2, phi);
  put(5, 3, -k.transpose());
  put(5, 4, -gpsi.transpose());
  return sigma;
}

}  // namespace dcad::reference
