// The CAD of an LC circuit without its 3n-dimensional system: the closed form of CEF §6 gives every
// M_j (j ≥ 1) as a product {(q, v, p) : q ∈ S_j, v ∈ V_j, p = φ v} of subspaces of Q^n, and the
// equations of motion on M_c follow from D̄_Δ directly.  Subspace operations in Q^n instead of Q^{3n},
// and no candidate constraints: a 116-branch circuit is a matter of milliseconds, not minutes.
// prop_circuit_motion.cpp holds every output equal to the generic CAD's (cad.hpp).
#pragma once

#include "dcad/reference/cad.hpp"
#include "dcad/reference/circuit.hpp"

#include <algorithm>

namespace dcad::reference {

/// M_j = {(q, v, p) : q ∈ S, v ∈ V, p = φ v}.
template <class T>
struct ProductStep {
  Subspace<T> s = Subspace<T>::zero(0), v = Subspace<T>::zero(0);
  Index dim() const { return s.dim() + v.dim(); }
  bool operator==(const ProductStep& o) const { return s == o.s && v == o.v; }
};

/// M_1, M_2, …, M_c by the closed form  [CEF §6 after (6.24); closed_form_m]:
/// S_1 = Q^n, V_1 = Δ;  S_{2k} = ψ⁻¹(φ(Δ_{k−1}) + Δ°), V_{2k} = Δ_{k−1};  S_{2k+1} = S_{2k}, V_{2k+1} = Δ_k,
/// Δ_0 = Δ = ker K, Δ_k = Δ ∩ ψ⁻¹(φ(Δ_{k−1}) + Δ°).  Stops at the first c with M_{c+1} = M_c.
template <class T>
std::vector<ProductStep<T>> circuit_tower(const Circuit<T>& c) {
  const Subspace<T> delta = kernel(kcl_matrix(c));
  std::vector<Subspace<T>> d{delta};  // Δ_0, Δ_1, …
  std::vector<ProductStep<T>> m{{Subspace<T>::whole(c.branches.size()), delta}};
  for (Index j = 2;; ++j) {
    const Index k = j / 2;
    ProductStep<T> next;
    if (j % 2 == 0) {
      next = {kvl_subspace(c, d[k - 1]), d[k - 1]};
    } else {
      if (d.size() <= k) d.push_back(intersection(delta, kvl_subspace(c, d[k - 1])));
      next = {m.back().s, d[k]};
    }
    if (next == m.back()) return m;
    m.push_back(next);
  }
}

/// Rows of `after` (a canonical basis) whose pivot is not a pivot of `before` ⊂ `after`: together
/// with `before` a basis of `after` (the pivots of a subspace are pivots of any larger one).
template <class T>
Matrix<T> new_rows(const Subspace<T>& before, const Subspace<T>& after) {
  const std::vector<Index> old = rref(before.basis()).pivots, now = rref(after.basis()).pivots;
  Matrix<T> out(0, after.ambient());
  for (Index i = 0; i < now.size(); ++i)
    if (std::find(old.begin(), old.end(), now[i]) == old.end())
      out = vstack(out, after.basis().block(i, i + 1, 0, after.ambient()));
  return out;
}

/// The equations each M_j adds, as rows [a | 0] of Q^{3n+1} (a·x = 0): M_1 adds p_i − φ_i v_i = 0 and
/// KCL (Δ° on v); later steps the new rows of S_j° on q and of V_j° on v.  Element j − 1 for M_j.
template <class T>
std::vector<Matrix<T>> circuit_tower_equations(const Circuit<T>& c, const std::vector<ProductStep<T>>& tower) {
  const Index n = c.branches.size();
  const Matrix<T> phi = inductance_matrix(c);
  std::vector<Matrix<T>> out;
  Subspace<T> ann_s = Subspace<T>::zero(n), ann_v = Subspace<T>::zero(n);
  for (Index j = 0; j < tower.size(); ++j) {
    const Subspace<T> as = annihilator(tower[j].s), av = annihilator(tower[j].v);
    const Matrix<T> ns = new_rows(ann_s, as), nv = new_rows(ann_v, av);
    const Index momentum = j == 0 ? n : 0;
    Matrix<T> rows(momentum + ns.rows() + nv.rows(), 3 * n + 1);
    for (Index i = 0; i < momentum; ++i) {
      rows(i, n + i) = -phi(i, i);
      rows(i, 2 * n + i) = T(1);
    }
    for (Index i = 0; i < ns.rows(); ++i)
      for (Index k = 0; k < n; ++k) rows(momentum + i, k) = ns(i, k);
    for (Index i = 0; i < nv.rows(); ++i)
      for (Index k = 0; k < n; ++k) rows(momentum + ns.rows() + i, n + k) = nv(i, k);
    out.push_back(rows);
    ann_s = as;
    ann_v = av;
  }
  return out;
}

/// Basis of M_j in Q^{3n}: rows (a, 0, 0) for a ∈ basis S, (0, b, φ b) for b ∈ basis V — already in
/// RREF order (pivots of S in the q-block, then those of V in the v-block).
template <class T>
Matrix<T> product_basis(const Circuit<T>& c, const ProductStep<T>& m) {
  const Index n = c.branches.size();
  const Matrix<T> phi = inductance_matrix(c);
  Matrix<T> rows(m.dim(), 3 * n);
  for (Index i = 0; i < m.s.dim(); ++i)
    for (Index j = 0; j < n; ++j) rows(i, j) = m.s.basis()(i, j);
  for (Index i = 0; i < m.v.dim(); ++i)
    for (Index j = 0; j < n; ++j) {
      rows(m.s.dim() + i, n + j) = m.v.basis()(i, j);
      rows(m.s.dim() + i, 2 * n + j) = phi(j, j) * m.v.basis()(i, j);
    }
  return rows;
}

/// ż = F z + G λ on M_c in the natural coordinates y = (a, b) of q = B_Sᵀ a, v = B_Vᵀ b, p = φ v
/// (B_S, B_V the canonical bases, as rows).  From D̄_Δ (CEF (6.10)–(6.13)) and E = p·v − L with
/// dE = (ψ q, p − φ v, v) (ERRATA): q̇ = v, ṗ + ψ q ∈ Δ°; on M_c also p = φ v and ẋ ∈ T M_c, so
/// v̇ ∈ V and φ v̇ + ψ q ∈ Δ°.  Hence ȧ = R b with B_Sᵀ R = B_Vᵀ, and ḃ = P a + K λ with
/// A P = −B_Δ ψ B_Sᵀ, A = B_Δ φ B_Vᵀ (B_Δ the basis of Δ: ξ ∈ Δ° ⟺ B_Δ ξ = 0), K = ker A.
/// Solvable for every a because M_c is invariant (CEF Thm 5.4); dim ker A is the solution rank.
template <class T>
struct CircuitMotion {
  Matrix<T> f;  ///< m × m, m = dim S + dim V: [[0, R], [P, 0]]
  Matrix<T> g;  ///< m × dim ker A: [0; K]
};

template <class T>
CircuitMotion<T> circuit_motion(const Circuit<T>& c, const ProductStep<T>& mc) {
  const Index ds = mc.s.dim(), dv = mc.v.dim();
  const Matrix<T> bs = mc.s.basis().transpose(), bv = mc.v.basis().transpose();  // n × ds, n × dv
  const Matrix<T> bd = kernel(kcl_matrix(c)).basis();
  Matrix<T> r, p;
  require(solve_particular(bs, bv, r), "circuit_motion", "V ⊂ S on M_c (q̇ = v tangent)",
          "V ⊄ S: a bug, please report it");
  const Matrix<T> a = bd * inductance_matrix(c) * bv;
  require(solve_particular(a, -(bd * elastance_matrix(c) * bs), p), "circuit_motion",
          "φ v̇ + ψ q ∈ Δ° solvable on M_c (CEF Thm 5.4)", "an inconsistent system: a bug, please report it");
  const Matrix<T> k = kernel(a).basis().transpose();  // dv × dim ker A
  CircuitMotion<T> out{Matrix<T>(ds + dv, ds + dv), Matrix<T>(ds + dv, k.cols())};
  for (Index i = 0; i < ds; ++i)
    for (Index j = 0; j < dv; ++j) out.f(i, ds + j) = r(i, j);
  for (Index i = 0; i < dv; ++i) {
    for (Index j = 0; j < ds; ++j) out.f(ds + i, j) = p(i, j);
    for (Index j = 0; j < k.cols(); ++j) out.g(ds + i, j) = k(i, j);
  }
  return out;
}

/// The same equations in coordinates z = x[coords] (default: the pivots of product_basis, which are
/// the reference's default_coordinates): z = T y with T = sel · Bᵀ, so F_z = T F T⁻¹, G_z = T G
/// (no sources: f = 0).  As ReducedEquations, to compare with reduced_equations.
template <class T>
ReducedEquations<T> circuit_reduced_equations(const Circuit<T>& c, const ProductStep<T>& mc,
                                              std::vector<Index> coords = {}) {
  const Matrix<T> b = product_basis(c, mc);
  const Index m = b.rows(), n3 = b.cols();
  if (coords.empty()) coords = rref(b).pivots;
  require(coords.size() == m, "circuit_reduced_equations", std::to_string(m) + " coordinates (dim M_c)",
          std::to_string(coords.size()));
  Matrix<T> t(m, m);
  for (Index i = 0; i < m; ++i) {
    require(coords[i] < n3, "circuit_reduced_equations", "variable indices below " + std::to_string(n3),
            std::to_string(coords[i]));
    for (Index j = 0; j < m; ++j) t(i, j) = b(j, coords[i]);
  }
  require(rank(t) == m, "circuit_reduced_equations", "coordinates that parametrize M_c", "variables that do not");
  const CircuitMotion<T> y = circuit_motion(c, mc);
  ReducedEquations<T> red;
  red.coords = coords;
  red.f_matrix = t * y.f * inverse(t);
  red.f.assign(m, T(0));
  red.g = t * y.g;
  return red;
}

}  // namespace dcad::reference
