// Constraints adapted to the primary ones, the abridged total energy and the Dirac bracket of
// CEF Thm 3.28 / 7.4 in double; the twin of dcad/reference/adapted.hpp (same greedy choice of the
// rows of Φ, each step a decided rank).
#pragma once

#include "dcad/fast/dirac_bergmann.hpp"

namespace dcad::fast {

struct AdaptedConstraints {
  int s_prime = 0, s = 0;
  std::vector<int> chi, abridged;
  MatrixXd dirac_tensor;
  Truth certain = yes;
};

AdaptedConstraints adapted_constraints(const MatrixXd& w, const MatrixXd& constraints, const std::vector<bool>& primary,
                                       const Options& opt = {});
VectorXd abridged_field(const AdaptedConstraints& ad, const MatrixXd& constraints, const MatrixXd& hessian,
                        const VectorXd& gradient, const VectorXd& x, const VectorXd& lambda);

/// The Pontryagin system embedded in T*TQ (CEF App. A, §7): y = (q, v, p, ν), Ω = dq∧dp + dv∧dν,
/// primary ν = 0, leaf constraints κ·q = C for the rows κ of K, E extended independently of ν.
struct FoliatedEmbedding {
  MatrixXd omega, hessian, primary, leaf;
  VectorXd gradient;
};
FoliatedEmbedding tangent_cotangent_embedding(const PontryaginInput& in, const Options& opt = {});

/// §7 (7.1): D on S' = {primary = 0} with the presymplectic leaves S'_C = S' ∩ {leaf = C}, and E.
LinearSystem foliated_system(const FoliatedEmbedding& f, const Options& opt = {});
/// The CAD of (7.1) from M_0 = S'.
CadResult foliated_tower(const FoliatedEmbedding& f, const Options& opt = {});

/// [primary; secondary; leaf] and Theorem 3.28 / 7.4 on them, primary and leaf rows counted as primary.
struct AdaptedToPrimary {
  MatrixXd constraints;
  AdaptedConstraints adapted;
};
AdaptedToPrimary adapted_to_primary(const MatrixXd& w, const MatrixXd& primary, const MatrixXd& secondary,
                                    const MatrixXd& leaf, const Options& opt = {});

/// CEF §7 after (7.7): Λ_x for E_{C,T} = E + λ^i (φ_i − C_i), i over the primary then the leaf functions, at
/// x ∈ S — by Remark 7.3's route, not the reference's bracket equations: one solution X of the leaf-wise
/// equations (7.7) at x (the CAD's velocities of foliated_system) gives the λ with X = J (dE + λ^i a_i)
/// (least squares, checked), and the directions are the λ whose J λ^i a_i is tangent to S.
AffineSubspace foliated_multipliers(const FoliatedEmbedding& f, const CadResult& r, const MatrixXd& secondary,
                                    const VectorXd& x, const Options& opt = {});
/// (7.8) at x₀: J (dE(x₀) + λ^i a_i), λ over the primary then the leaf functions.
VectorXd foliated_field(const FoliatedEmbedding& f, const VectorXd& x, const VectorXd& lambda);

}  // namespace dcad::fast
