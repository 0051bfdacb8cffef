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

}  // namespace dcad::fast
