// Linear Dirac structures D ⊂ V ⊕ V*, V = Q^n, literally as in CEF §4.
// An element (v, α) is a vector of Q^{2n}: v in the first n coordinates, α in the last n.
#pragma once

#include "dcad/reference/symplectic.hpp"

namespace dcad::reference {

/// A subspace of Q^n ⊕ Q^n*.  Holds any subspace; `dirac_defect` says whether it is Dirac.
template <class T>
struct DiracStructure {
  Index n = 0;
  Subspace<T> d = Subspace<T>::zero(0);  ///< in Q^{2n}
};

/// ⟨⟨(v1, α1), (v2, α2)⟩⟩ = α1(v2) + α2(v1), as a 2n×2n matrix.  [CEF §4]
template <class T>
Matrix<T> pairing_form(Index n) {
  Matrix<T> p(2 * n, 2 * n);
  for (Index i = 0; i < n; ++i) p(i, n + i) = p(n + i, i) = T(1);
  return p;
}

/// D^⊥ with respect to ⟨⟨·,·⟩⟩.
template <class T>
Subspace<T> pairing_orthogonal(const DiracStructure<T>& d) {
  return Subspace<T>::solutions(d.d.basis() * pairing_form<T>(d.n));
}

/// Why D is not a Dirac structure by Lemma 4.1 (dim D = n and isotropic), or "" if it is one.
template <class T>
std::string dirac_defect(const DiracStructure<T>& d) {
  if (d.d.ambient() != 2 * d.n) return "a subspace of Q^" + std::to_string(2 * d.n);
  if (d.d.dim() != d.n)
    return "dim D = " + std::to_string(d.d.dim()) + " (a Dirac structure on Q^" + std::to_string(d.n) + " has dim " +
           std::to_string(d.n) + ")";
  const Matrix<T> g = d.d.basis() * pairing_form<T>(d.n) * d.d.basis().transpose();
  for (Index i = 0; i < g.rows(); ++i)
    for (Index j = 0; j < g.cols(); ++j)
      if (g(i, j) != 0)
        return "D is not isotropic: <<e" + std::to_string(i + 1) + ", e" + std::to_string(j + 1) +
               ">> != 0 for basis vectors e of D";
  return "";
}

/// D = D^⊥ (the definition).  [CEF §4]
template <class T>
bool is_dirac_by_definition(const DiracStructure<T>& d) {
  return d.d.ambient() == 2 * d.n && pairing_orthogonal(d) == d.d;
}

template <class T>
void require_dirac(const DiracStructure<T>& d, const std::string& fn) {
  const std::string why = dirac_defect(d);
  require(why.empty(), fn, "a Dirac structure (Lemma 4.1)", why);
}

/// D spanned by rows (v, α) of length 2n; validated.
template <class T>
DiracStructure<T> dirac_from_basis(const Matrix<T>& rows) {
  require(rows.cols() % 2 == 0, "dirac_from_basis", "rows (v, α) of even length 2n", shape(rows));
  DiracStructure<T> d{rows.cols() / 2, Subspace<T>::span(rows)};
  require_dirac(d, "dirac_from_basis");
  return d;
}

/// D_ω = {(v, α) : α = ω^♭(v)} = {(v, α) : α = Wᵀ v}.  [CEF §4]
template <class T>
DiracStructure<T> dirac_from_presymplectic(const Matrix<T>& w) {
  require_skew(w, "dirac_from_presymplectic");
  const Index n = w.rows();
  return {n, Subspace<T>::solutions(hstack(-w.transpose(), Matrix<T>::identity(n)))};
}

/// D = {v ⊕ α | v ∈ E, α(w) = ω(v, w) ∀ w ∈ E}, ω(u, w) = uᵀ W w.  [CEF Prop. 4.3, Thm 4.5]
template <class T>
DiracStructure<T> dirac_from_distribution(const Subspace<T>& e, const Matrix<T>& w) {
  require_skew(w, "dirac_from_distribution");
  require(w.rows() == e.ambient(), "dirac_from_distribution", "a form on Q^" + std::to_string(e.ambient()),
          "a " + shape(w) + " matrix");
  const Index n = w.rows();
  // Equations in (v, α):  γ(v) = 0 for γ ∈ E°;  α(w_j) − v ᵀ W w_j = 0 for the basis w_j of E.
  const Matrix<T> in_e = hstack(annihilator(e).basis(), Matrix<T>(annihilator(e).dim(), n));
  const Matrix<T> pairs = hstack(-(e.basis() * w.transpose()), e.basis());
  return {n, Subspace<T>::solutions(vstack(in_e, pairs))};
}

/// The graph {(P α, α)} of a skew bivector P.  [CONTRACT `poisson`]
template <class T>
DiracStructure<T> dirac_from_poisson(const Matrix<T>& p) {
  require_skew(p, "dirac_from_poisson");
  const Index n = p.rows();
  return {n, Subspace<T>::solutions(hstack(Matrix<T>::identity(n), -p))};
}

/// Projection (v, α) ↦ v, and (v, α) ↦ α, as matrices n × 2n.
template <class T>
Matrix<T> vector_part(Index n) {
  return hstack(Matrix<T>::identity(n), Matrix<T>(n, n));
}
template <class T>
Matrix<T> covector_part(Index n) {
  return hstack(Matrix<T>(n, n), Matrix<T>::identity(n));
}

/// E_D = projection of D on V.  [CEF Prop. 4.3]
template <class T>
Subspace<T> dirac_distribution(const DiracStructure<T>& d) {
  return map(vector_part<T>(d.n), d.d);
}

/// D^♭(X) = {α : (X, α) ∈ D}; empty unless X ∈ E_D.  [CEF §4]
template <class T>
AffineSubspace<T> dirac_flat(const DiracStructure<T>& d, const std::vector<T>& x) {
  // (X, α) ∈ D  ⇔  γ(X, α) = 0 for γ ∈ D°:  Γ_α α = −Γ_v X.
  const Matrix<T> g = annihilator(d.d).basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, d.n), ga = g.block(0, g.rows(), d.n, 2 * d.n);
  std::vector<T> rhs = (gv * Matrix<T>::column(x)).col(0);
  for (T& c : rhs) c = -c;
  return solve(ga, rhs);
}

/// D^♭(W) = ∪_{X ∈ W} D^♭(X) = projection on V* of D ∩ (W ⊕ V*); W ⊆ E_D.  [CEF §4]
template <class T>
Subspace<T> dirac_flat(const DiracStructure<T>& d, const Subspace<T>& w) {
  require(contains(dirac_distribution(d), w), "dirac_flat", "W ⊆ E_D", "a W not contained in E_D");
  const Subspace<T> w_plus_dual = preimage(vector_part<T>(d.n), w);  // W ⊕ V*
  return map(covector_part<T>(d.n), intersection(d.d, w_plus_dual));
}

/// ω_D(v, w) = α(w) for v ⊕ α ∈ D, on E_D; the matrix places [ω_D(b_i, b_j)] (b = canonical basis
/// of E_D) at the pivot coordinates of b, so uᵀ M w = ω_D(u, w) on E_D.  [CEF Prop. 4.3]
template <class T>
PresymplecticForm<T> dirac_form(const DiracStructure<T>& d) {
  const Subspace<T> e = dirac_distribution(d);
  const Matrix<T>& b = e.basis();
  const Rref<T> piv = rref(b);  // b is already reduced; this reads off its pivot columns
  // one α_i ∈ D^♭(b_i) for every basis vector b_i of E_D at once: Γ_α α_i = −Γ_v b_i (as in dirac_flat)
  const Matrix<T> g = annihilator(d.d).basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, d.n), ga = g.block(0, g.rows(), d.n, 2 * d.n);
  Matrix<T> alphas;                                         // column i: α_i
  solve_particular(ga, -(gv * b.transpose()), alphas);      // consistent: b_i ∈ E_D
  const Matrix<T> om = alphas.transpose() * b.transpose();  // (i, j) = α_i(b_j)
  Matrix<T> m(d.n, d.n);
  for (Index i = 0; i < b.rows(); ++i)
    for (Index j = 0; j < b.rows(); ++j) m(piv.pivots[i], piv.pivots[j]) = om(i, j);
  return {e, m};
}

/// W^D = {X ∈ V : D^♭(Y)(X) = {0} ∀ Y ∈ W}: every α with (Y, α) ∈ D, Y ∈ W, kills X.  [CEF §4]
template <class T>
Subspace<T> dirac_orthogonal(const DiracStructure<T>& d, const Subspace<T>& w) {
  const Subspace<T> pairs = intersection(d.d, preimage(vector_part<T>(d.n), w));  // D ∩ (W ⊕ V*)
  return Subspace<T>::solutions(pairs.basis() * covector_part<T>(d.n).transpose());
}

/// D comes from a presymplectic form on V iff E_D = V.  [CEF §4, after Prop. 4.3]
template <class T>
bool is_presymplectic(const DiracStructure<T>& d) {
  return dirac_distribution(d).dim() == d.n;
}

/// D is the graph of a bivector iff it meets V ⊕ 0 only in 0 (then α ↦ v is a map P, skew by isotropy).
template <class T>
bool is_poisson(const DiracStructure<T>& d) {
  return map(covector_part<T>(d.n), d.d).dim() == d.n;
}

/// The bivector P of a Poisson D: v = P α for every (v, α) ∈ D.
template <class T>
Matrix<T> poisson_bivector(const DiracStructure<T>& d) {
  require(is_poisson(d), "poisson_bivector", "D ∩ (V ⊕ 0) = 0", "a Dirac structure with vectors v ⊕ 0");
  Matrix<T> p(d.n, d.n);
  const Matrix<T> g = annihilator(d.d).basis();
  for (Index j = 0; j < d.n; ++j) {
    // v with (v, e_j) ∈ D: solve Γ_v v = −Γ_α e_j.
    const Matrix<T> gv = g.block(0, g.rows(), 0, d.n), ga = g.block(0, g.rows(), d.n, 2 * d.n);
    std::vector<T> rhs = ga.col(j), v;
    for (T& c : rhs) c = -c;
    solve_particular(gv, rhs, v);
    for (Index i = 0; i < d.n; ++i) p(i, j) = v[i];
  }
  return p;
}

}  // namespace dcad::reference
