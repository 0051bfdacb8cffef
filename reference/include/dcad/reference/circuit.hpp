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

}  // namespace dcad::reference
