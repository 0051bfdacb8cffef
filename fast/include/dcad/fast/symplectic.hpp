// Linear symplectic and presymplectic algebra in double; the twin of dcad/reference/symplectic.hpp
// (same names, same conventions: Ω(u, w) = uᵀ W w, X^♭ = Wᵀ X).
#pragma once

#include "dcad/fast/subspace.hpp"

namespace dcad::fast {

/// Skew (exactly: W + Wᵀ = 0 in double, which holds for any input read as a skew matrix) and finite.
void require_skew(const MatrixXd& w, const std::string& fn);
/// Skew and nondegenerate; a nondegeneracy that is uncertain is reported by `is_symplectic`.
Truth is_symplectic(const MatrixXd& w, const Options& opt = {});
/// Skew, and not certainly degenerate (std::invalid_argument naming `fn` otherwise): the verdict of its
/// nondegeneracy, yes or unknown — a result computed with W⁻¹ is certain only if it is yes.
Truth require_symplectic(const MatrixXd& w, const std::string& fn, const Options& opt = {});

VectorXd flat(const MatrixXd& w, const VectorXd& x);
/// α^♯ for a certainly nondegenerate W (std::invalid_argument otherwise).
VectorXd sharp(const MatrixXd& w, const VectorXd& alpha);
Subspace symplectic_complement(const MatrixXd& w, const Subspace& v, const Options& opt = {});

/// ω(u, w) = uᵀ M w on `space`.
struct PresymplecticForm {
  Subspace space = Subspace::zero(0);
  MatrixXd matrix;
  double scale = 0;  ///< magnitude of the data ω was computed from: the scale of its rank decisions
};
PresymplecticForm restrict_form(const MatrixXd& w, const Subspace& v);
PresymplecticForm restrict_form(const PresymplecticForm& f, const Subspace& u, const Options& opt = {});
/// [ω(q_i, q_j)] in the orthonormal basis q of the domain.
MatrixXd gram(const PresymplecticForm& f);
RankDecision form_rank(const PresymplecticForm& f, const Options& opt = {});
Subspace orthogonal(const PresymplecticForm& f, const Subspace& w, const Options& opt = {});
Subspace form_kernel(const PresymplecticForm& f, const Options& opt = {});
/// ω^♭(W) as {α ∈ (R^n)* : α|_V ∈ ω^♭(W)} (contains V°).
Subspace flat(const PresymplecticForm& f, const Subspace& w, const Options& opt = {});

struct NormalFormBasis {
  int s = 0;
  MatrixXd x;      ///< rows X_1 … X_r
  MatrixXd alpha;  ///< rows α_i = X_i^♭
  Truth certain = yes;
};
/// Lemma 3.1 by a pivoted symplectic Gram–Schmidt (largest |Ω(X_i, X_j)| first).
NormalFormBasis normal_form_basis(const MatrixXd& w, const Subspace& v, const Options& opt = {});

struct RestrictedSolution {
  AffineSubspace lambda;
  AffineSubspace x;
};
/// Lemmas 3.5–3.6: solutions of i_X ω = β|_V through (3.1), with γ an orthonormal basis of V°.
RestrictedSolution solve_restricted(const MatrixXd& w, const Subspace& v, const VectorXd& beta,
                                    const Options& opt = {});
/// {X ∈ V : ω(X, ·) = β on V} through the Gram matrix.
AffineSubspace solve_on_subspace(const PresymplecticForm& f, const VectorXd& beta, const Options& opt = {});

}  // namespace dcad::fast
