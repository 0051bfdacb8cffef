// Dirac's theory of constraints in double; the twin of dcad/reference/dirac_bergmann.hpp.  Same
// conventions ({f, g} = df ᵀ J dg, J = (Wᵀ)^{-1}); a different route: the known constraints are kept
// as orthonormal rows, the secondary ones come from a decided left null space, and the second class
// constraints are the orthogonal complement of the first class ones in the constraint span.
#pragma once

#include "dcad/fast/cad.hpp"

namespace dcad::fast {

struct ConstrainedSystem {
  MatrixXd omega, hessian;
  VectorXd gradient;
  MatrixXd primary;  ///< rows [a_i | b_i]
};

/// J = (Wᵀ)⁻¹ ({f, g} = dfᵀ J dg); std::invalid_argument if W is certainly degenerate, and `certain` &=
/// the verdict of its nondegeneracy.
MatrixXd poisson_tensor(const MatrixXd& w, const Options& opt, Truth& certain);

struct DiracBergmannResult {
  std::vector<AffineSubspace> tower;
  MatrixXd constraints;  ///< orthonormal gradient rows with right-hand sides, [a | b]
  bool consistent = true;
  Truth certain = yes;
};
DiracBergmannResult dirac_bergmann(const ConstrainedSystem& s, const Options& opt = {});

/// Λ^(c)_x for the given primary rows (decided).
AffineSubspace multipliers(const ConstrainedSystem& s, const DiracBergmannResult& r, const VectorXd& x,
                           const Options& opt = {});

struct ConstraintClasses {
  int s = 0;
  MatrixXd first;         ///< orthonormal rows [a | b] of ψ
  MatrixXd second;        ///< orthonormal rows [a | b] of χ (complement of ψ in the constraint span)
  MatrixXd dirac_tensor;  ///< J* = J − J Gᵀ Σ⁻¹ G J
  Truth certain = yes;
};
ConstraintClasses classify_constraints(const MatrixXd& w, const MatrixXd& constraints, const Options& opt = {});

/// Gotay–Nester's setting for (N, Ω, E, M): D_{(T M, Ω)} with E (the twin of the reference's).
LinearSystem gotay_nester_system(const ConstrainedSystem& s, const Options& opt = {});
/// The Gotay–Nester algorithm: the CAD of gotay_nester_system(s) from M_0 = M  [CEF §2.2].
CadResult gotay_nester(const ConstrainedSystem& s, const Options& opt = {});
/// The equations the tower added after M_0, rows [a | b], in order.
MatrixXd secondary_constraints(const CadResult& r);

/// A second class submanifold through S chosen by V (CEF Lemma 3.23 (d)): V^Ω = T S^V, χ′ (rows [a | b],
/// a orthonormal spanning V^♭), Σ′ = [{χ′_i, χ′_j}], and the Dirac tensor — by another route than the
/// reference's Dirac formula: the Poisson tensor of Ω restricted to the symplectic V^Ω,
/// J* = Q (Qᵀ Wᵀ Q)⁻¹ Qᵀ (Q orthonormal), which Lemma 3.23 (e) says it is (X_{(χ),F} = X_{F|S^χ}).
struct SecondClassChoice {
  Subspace tangent = Subspace::zero(0);
  MatrixXd chi, sigma, dirac_tensor;
  Truth certain = yes;  ///< (3.12) and V^Ω's nondegeneracy decided certainly
};
/// std::invalid_argument where V is certainly no complement of ker ω in (TS)^Ω (CEF (3.12)).
SecondClassChoice second_class_choice(const MatrixXd& w, const AffineSubspace& s, const Subspace& v,
                                      const Options& opt = {});

/// CEF Def 3.22: is S (direction TS) a first class constraint submanifold (coisotropic)?  Another route
/// than the reference's definition: the bracket matrix A J Aᵀ of orthonormal defining covectors A of TS
/// is decided zero (2s = 0: every constraint first class).  unknown where the rank decision is not certain.
Truth is_first_class_submanifold(const MatrixXd& w, const Subspace& ts, const Options& opt = {});

/// f(x) = ½ xᵀ A x + bᵀ x + c (A symmetric).
struct QuadraticFunction {
  MatrixXd a;
  VectorXd b;
  double c = 0;
};
/// CEF Remark 2.2 by its ideal side, not the reference's restriction: f ≈ 0 on M_c = {φ = 0} (rows [a | β] of
/// independent constraints) exactly when f = ν^i φ_i for affine ν^i(x) = N_i·x + ν0_i — the matching of f's
/// coefficients, a linear system in (N, ν0), decided solvable.  unknown where that decision is not certain.
Truth weakly_zero(const MatrixXd& constraints, const QuadraticFunction& f, const Options& opt = {});

}  // namespace dcad::fast
