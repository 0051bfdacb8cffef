// CEF §3.2's quotient M̄_c = M_c / K_c in double; the twin of dcad/reference/quotient.hpp.  A different
// route: K_c and a complement of it in TM_c are the null and the row space of the Gram matrix of Ω on an
// orthonormal basis of TM_c (one SVD, its rank decided), and (3.8) is not solved through ω̄_c's inverse
// but read off (3.4) itself: for a solution X at x ∈ M_c and b ∈ TM_c, Ω(b, X) = −Ω(X, b) = −dE(x)·b,
// so z' = C X = −B (H x + g) — the same field, the reference's formᵀ⁻¹ Sᵀ (H x(z) + g) by another road.
#pragma once

#include "dcad/fast/dirac_bergmann.hpp"

namespace dcad::fast {

struct GaugeQuotient {
  Subspace tangent = Subspace::zero(0);         ///< TM_c
  Subspace gauge = Subspace::zero(0);           ///< K_c = ker ω_c  [CEF Assumption 3.8]
  Subspace physical_gauge = Subspace::zero(0);  ///< K̃_c = ker ω ∩ TM_c  [CEF (3.5), Thm 3.19]
  MatrixXd complement;                          ///< orthonormal rows b_i spanning TM_c ⊖ K_c
  MatrixXd coordinates;                         ///< C = B W: z = C x  [CEF Lemma 3.9]
  MatrixXd form;     ///< ω̄_c in z: ω_c(y, y') = (C y)ᵀ form (C y')  [CEF Lemma 3.9 (a)]
  VectorXd point;    ///< a point x₀ of M_c
  MatrixXd section;  ///< S: x(z) = x₀ + S (z − C x₀), C S = I
  MatrixXd field;    ///< X̄(z) = field z + offset, the solution of CEF (3.8)
  VectorXd offset;
  MatrixXd tilde_coordinates;  ///< C̃: z̃ = C̃ x on M̃_c = M_c / K̃_c — orthonormal rows spanning TM_c ⊖ K̃_c
  MatrixXd fibration;          ///< P = C C̃ᵀ: z̄ = P z̃ (K̃_c ⊆ K_c, so C kills what C̃ drops)  [CEF Thm 3.19]
  Truth certain = yes;         ///< every rank decision behind it certain (the tower's too)
};

/// M̄_c and (3.8) from the fast Dirac–Bergmann tower r of s (consistent; std::invalid_argument else).
GaugeQuotient gauge_quotient(const ConstrainedSystem& s, const DiracBergmannResult& r, const Options& opt = {});

/// X̄(z) = field z + offset.
inline VectorXd quotient_field(const GaugeQuotient& q, const VectorXd& z) { return q.field * z + q.offset; }

/// The linear first class functions α·x of M_c (CEF Def 3.10 ff.): J α ∈ TM_c (a decided preimage).
Subspace first_class_covectors(const MatrixXd& w, const Subspace& tmc, const Options& opt = {});

/// (p_{K_c})_* (α·x) (CEF Lemma 3.13 (a)) by the section: f(x(z)) = (Sᵀ α)·z + const, so ᾱ = Sᵀ α — the
/// reference solves ᾱ·(C y) = α·y over TM_c instead.
inline VectorXd push_forward(const GaugeQuotient& q, const VectorXd& alpha) { return q.section.transpose() * alpha; }

}  // namespace dcad::fast
