// CEF §3.2 for a linear constrained Hamiltonian system (N, Ω, E, M), literally: the gauge directions of
// the final constraint set M_c, the quotient M̄_c = M_c / K_c with its symplectic form (Lemma 3.9 (a)),
// and the equation of motion passed to it, (3.8) — the gauge-free ODE on the physical states.
//   ω   = Ω|_{TM}, ω_c = Ω|_{TM_c}                        (CEF §3.2, before Assumption 3.8)
//   K_c = ker ω_c = TM_c ∩ (TM_c)^Ω                       (Assumption 3.8)
//   K̃_c = ker ω ∩ TM_c ⊆ K_c, of dimension d^(c)        ((3.5), Theorem 3.19)
// Coordinates of M̄_c: z_i = Ω(b_i, x) for b_1 … b_m a basis of a complement of K_c in TM_c (the rows
// of TM_c's basis that extend K_c's, in order).  On TM_c the map y ↦ (Ω(b_i, y))_i has kernel exactly
// K_c: Ω(b, k) = 0 for k ∈ K_c, and Ω(b, y) = 0 for every b (and every k) puts y in K_c.
#pragma once

#include "dcad/reference/dirac_bergmann.hpp"

namespace dcad::reference {

template <class T>
struct GaugeQuotient {
  Subspace<T> tangent = Subspace<T>::zero(0);         ///< TM_c
  Subspace<T> gauge = Subspace<T>::zero(0);           ///< K_c = ker ω_c  [Assumption 3.8]
  Subspace<T> physical_gauge = Subspace<T>::zero(0);  ///< K̃_c = ker ω ∩ TM_c  [(3.5), Thm 3.19]
  Matrix<T> complement;                               ///< rows b_i: a basis of a complement of K_c in TM_c
  Matrix<T> coordinates;                              ///< rows C = B W: z = C x, M̄_c's coordinates (z_i = Ω(b_i, x))
  Matrix<T> form;        ///< ω̄_c in z: ω_c(y, y') = (C y)ᵀ form (C y') for y, y' ∈ TM_c  [Lemma 3.9 (a)]
  std::vector<T> point;  ///< a point x₀ of M_c
  Matrix<T> section;     ///< S: x(z) = x₀ + S (z − C x₀) lies on M_c with C x(z) = z
  Matrix<T> field;       ///< X̄(z) = field z + offset: the unique solution of (3.8)
  std::vector<T> offset;
  Matrix<T> tilde_coordinates;  ///< C̃: z̃ = C̃ x, coordinates of M̃_c = M_c / K̃_c  [Thm 3.19, Lemma 3.20]
  Matrix<T> fibration;          ///< P: z̄ = P z̃, the submersion p_{K_c K̃_c}: M̃_c → M̄_c  [Thm 3.19]
};

/// The rows of `candidates` (in order) that extend the row space of `start` to the span of both.
template <class T>
Matrix<T> extending_rows(const Matrix<T>& start, const Matrix<T>& candidates) {
  Matrix<T> acc = start, out(0, candidates.cols());
  for (Index i = 0; i < candidates.rows(); ++i) {
    const Matrix<T> row = candidates.block(i, i + 1, 0, candidates.cols());
    const Matrix<T> more = vstack(acc, row);
    if (rank(more) == rank(acc)) continue;
    acc = more;
    out = vstack(out, row);
  }
  return out;
}

/// M̃_c = M_c / K̃_c (Thm 3.19): coordinates z̃_i = Ω(t_i, x) for the vectors t_i of TM's basis whose functionals,
/// restricted to TM_c, extend the ones kept — on TM_c their common kernel is TM_c ∩ (TM)^Ω = K̃_c; and the
/// fibration P with C y = P C̃ y on TM_c (it exists because K̃_c ⊆ K_c, (3.5)), solved column by column.
template <class T>
void tilde_quotient(const Matrix<T>& w, const Subspace<T>& tm, GaugeQuotient<T>& q) {
  const Matrix<T> functionals = tm.basis() * w, d = q.tangent.basis();
  Matrix<T> kept(0, w.cols());
  for (Index i = 0; i < functionals.rows(); ++i) {
    const Matrix<T> more = vstack(kept, functionals.block(i, i + 1, 0, functionals.cols()));
    if (rank(more * d.transpose()) > rank(kept * d.transpose())) kept = more;
  }
  q.tilde_coordinates = kept;
  const Matrix<T> m = (kept * d.transpose()).transpose(), nt = (q.coordinates * d.transpose()).transpose();
  q.fibration = Matrix<T>(q.coordinates.rows(), kept.rows());
  for (Index i = 0; i < nt.cols(); ++i) {
    const AffineSubspace<T> row = solve(m, nt.block(0, nt.rows(), i, i + 1).col(0));
    require(!row.empty, "gauge_quotient", "K̃_c ⊆ K_c (CEF (3.5))", "a fibration that does not exist");
    for (Index j = 0; j < kept.rows(); ++j) q.fibration(i, j) = row.point[j];
  }
}

/// M̄_c = M_c / K_c and (3.8) on it, from the Dirac–Bergmann tower r of s (consistent).  Ē_c(z) = E(x(z))
/// (well defined: dE(x) vanishes on K_c at every x ∈ M_c, Lemma 3.20 (d)); (3.8) reads
/// ω̄_c(X̄, ·) = dĒ_c, i.e. formᵀ X̄ = Sᵀ (H x(z) + g), solved with form's inverse.  [CEF Lemma 3.9, (3.8)]
template <class T>
GaugeQuotient<T> gauge_quotient(const ConstrainedSystem<T>& s, const DiracBergmannResult<T>& r) {
  require(r.consistent && !r.tower.empty(), "gauge_quotient", "a consistent tower (M_c nonempty)", "an empty M_c");
  const Matrix<T>& w = s.omega;
  GaugeQuotient<T> q;
  q.tangent = r.tower.back().direction;
  const Subspace<T> tm = kernel(gradients(s.primary));
  q.gauge = form_kernel(restrict_form(w, q.tangent));
  q.physical_gauge = intersection(form_kernel(restrict_form(w, tm)), q.tangent);
  q.complement = extending_rows(q.gauge.basis(), q.tangent.basis());
  q.coordinates = q.complement * w;
  const Matrix<T> g = q.coordinates * q.complement.transpose();  // [Ω(b_i, b_j)], nondegenerate
  const Matrix<T> g_inv = inverse(g);
  q.form = g_inv.transpose();
  q.point = r.tower.back().point;
  q.section = q.complement.transpose() * g_inv;  // C S = G G⁻¹ = I
  // Ē_c(z) = ½ x(z)ᵀ H x(z) + gᵀ x(z), x(z) = (x₀ − S C x₀) + S z: dĒ_c = Sᵀ H S z + Sᵀ (H (x₀ − S C x₀) + g)
  std::vector<T> base = q.point;
  const std::vector<T> scx = (q.section * q.coordinates * Matrix<T>::column(q.point)).col(0);
  for (Index i = 0; i < base.size(); ++i) base[i] -= scx[i];
  std::vector<T> de0 = (s.hessian * Matrix<T>::column(base)).col(0);
  for (Index i = 0; i < de0.size(); ++i) de0[i] += s.gradient[i];
  const Matrix<T> lhs_inv = inverse(q.form.transpose());
  q.field = lhs_inv * q.section.transpose() * s.hessian * q.section;
  q.offset = (lhs_inv * q.section.transpose() * Matrix<T>::column(de0)).col(0);
  tilde_quotient(w, tm, q);
  return q;
}

/// X̄(z) = field z + offset.
template <class T>
std::vector<T> quotient_field(const GaugeQuotient<T>& q, const std::vector<T>& z) {
  std::vector<T> out = (q.field * Matrix<T>::column(z)).col(0);
  for (Index i = 0; i < out.size(); ++i) out[i] += q.offset[i];
  return out;
}

/// The linear first class functions f = α·x of M_c (CEF Def 3.10 ff., R^(c) among the linear functions):
/// the covectors α whose Hamiltonian field X_f = J α is tangent to M_c.  Those that also vanish along TM_c
/// are its first class constraints, I^(c).
template <class T>
Subspace<T> first_class_covectors(const Matrix<T>& w, const Subspace<T>& tmc) {
  return preimage(poisson_tensor(w), tmc);
}

/// (p_{K_c})_* f for a first class f = α·x (CEF Lemma 3.13 (a)): the ᾱ with f|_{M_c} = ᾱ·z + const, i.e.
/// ᾱ·(C y) = α·y for every y ∈ TM_c — solved over TM_c's basis; it exists because α vanishes on K_c.
template <class T>
std::vector<T> push_forward(const GaugeQuotient<T>& q, const std::vector<T>& alpha) {
  const Matrix<T>& y = q.tangent.basis();
  const std::vector<T> rhs = (y * Matrix<T>::column(alpha)).col(0);
  const AffineSubspace<T> bar = solve(y * q.coordinates.transpose(), rhs);
  require(!bar.empty, "push_forward", "a first class function (α vanishing on K_c, Lemma 3.13 (a))",
          "α that does not vanish on K_c");
  return bar.point;
}

}  // namespace dcad::reference
