// V's objects at a point z of 𝒜 ⊂ j₁(𝒱_{n+1}) in double; the twin of dcad/reference/vignolo.hpp.
// Different routes: j₂, τ(𝒜) and χ(𝒜) by their parametrizations (V (2.3), (2.10), (2.12)) instead of the
// defining equations; Ω_l as l*Ω̃_l (V §2.2) instead of V §3.4's expression; the problems on 𝓛(𝒜) through
// Ω̃_l = dφ_l ∧ dt + π*Ω_l, solved on j₁ and lifted (the route of V (3.4) and Prop 3.5); 𝒫 by Thm 3.1's
// formula 𝒫(X) = X − η_σ X_{dφ^σ} − λ_σ X_{ν^σ}; 𝒪_l by (3.17b).  Each subspace says whether its rank
// decisions were certain.
#pragma once

#include "dcad/fast/symplectic.hpp"
#include "dcad/vignolo_data.hpp"

namespace dcad::fast {

/// The point and its data (dcad/vignolo_data.hpp).
using VignoloPoint = VignoloData<double, MatrixXd, VectorXd>;

/// ω^i = dq^i − q̇^i dt, rows  [V §2.1].
MatrixXd contact_forms(const VignoloPoint& d);
/// j₂ at z: ∂/∂t + q̇^i ∂/∂q^i + Z^i ∂/∂q̇^i  [V (2.3)].
AffineSubspace dynamical_flows(const VignoloPoint& d);
/// C_z(j₁), spanned by the ω^i  [V §2.1].
Subspace contact_bundle(const VignoloPoint& d, const Options& opt = {});
/// q̇ + ker g: 𝒜's velocities over π(z)  [V (2.7b)–(2.8)].
AffineSubspace constraint_velocities(const VignoloPoint& d, const Options& opt = {});
/// T_z𝒜 = ker dφ.
Subspace constraint_tangent(const VignoloPoint& d, const Options& opt = {});
/// τ_z(𝒜) = ∂/∂t + q̇^i ∂/∂q^i + (w + ψ_A Z^A) ∂/∂q̇^i with w making it tangent to 𝒜  [V (2.10)].
AffineSubspace tau_constraint(const VignoloPoint& d, const Options& opt = {});
/// χ_z(𝒜) = span{g^σ_i ω^i}  [V (2.12)].
Subspace chetaev_bundle(const VignoloPoint& d, const Options& opt = {});
/// Ω_l = l*Ω̃_l  [V §2.2].
MatrixXd poincare_cartan(const VignoloPoint& d);
/// Ω̃_l by blocks  [V (2.19)].
MatrixXd lagrangian_bundle_form(const VignoloPoint& d);
/// dL at z over (t, q, q̇).
VectorXd lagrangian_differential(const VignoloPoint& d);
/// l_* for l: u̇ = L, (2n+2) × (2n+1).
MatrixXd section_tangent(const VignoloPoint& d);
/// dφ_l = du̇ − dL.
VectorXd trivialization_differential(const VignoloPoint& d);
/// X_l = X + X(L) ∂/∂u̇  [V (2.17)].
VectorXd bundle_horizontal_lift(const VignoloPoint& d, const VectorXd& x);
/// J̃(X)  [V (2.18)].
VectorXd vertical_endomorphism(const VignoloPoint& d, const VectorXd& x);
/// dφ^σ on 𝓛, rows.
MatrixXd bundle_constraint_differentials(const VignoloPoint& d);
/// ν^σ = −g^σ_i ω^i on 𝓛, rows (V §3.1).
MatrixXd chetaev_forms(const VignoloPoint& d);
/// (2.13), with (3.9) if `chetaev_condition`  [V (2.13), (3.9)].
AffineSubspace lagrange_chetaev_fields(const VignoloPoint& d, bool chetaev_condition, const Options& opt = {});
/// (3.3), with (3.9) if `chetaev_condition`: on j₁ through Ω̃_l = dφ_l ∧ dt + π*Ω_l, then lifted  [V (3.3), (3.4)].
AffineSubspace nonholonomic_fields(const VignoloPoint& d, bool chetaev_condition, const Options& opt = {});
/// (2.20), the same way.
AffineSubspace unconstrained_fields(const VignoloPoint& d, const Options& opt = {});
/// (3.7)'s summands  [V Prop 3.1].
struct ConstrainedSplitting {
  Subspace chetaev_complement = Subspace::zero(0);
  Subspace tangent_complement = Subspace::zero(0);
  Subspace constrained = Subspace::zero(0);
};
ConstrainedSplitting constrained_splitting(const VignoloPoint& d, const Options& opt = {});
/// 𝒫(X) = X − η_σ X_{dφ^σ} − λ_σ X_{ν^σ} with ⟨𝒫(X), ν^γ⟩ = ⟨𝒫(X), dφ^γ⟩ = 0  [V (3.8), Thm 3.1]; Γ and
/// C = g Γ⁻¹ gᵀ invertible (decided in double), else std::invalid_argument.
VectorXd constrained_projection(const VignoloPoint& d, const VectorXd& x);
/// TM_0 ∩ χ̂(𝒜)° at z ∈ M_0 = l(𝒜)  [V (3.10)].
Subspace first_level_directions(const VignoloPoint& d, const Options& opt = {});
/// z ∈ M_1, decided by (3.15): dφ_l vanishes on (TM_0 ∩ χ̂°)^⊥ ∩ χ̂°  [V (3.12), (3.15)].
Truth in_first_constraint_manifold(const VignoloPoint& d, const Options& opt = {});
/// (TM_0 ∩ χ̂(𝒜)°)^⊥ ∩ χ̂(𝒜)°  [V (3.15), k = 0].
Subspace first_constraint_directions(const VignoloPoint& d, const Options& opt = {});
/// 𝒪_l = {V^i ∂/∂q̇^i : Γ V = 0, g V = 0}  [V (3.17)].
Subspace sode_obstruction(const VignoloPoint& d, const Options& opt = {});
/// 𝒪̃_l = {Ṽ^i (∂L/∂q̇^i ∂/∂u̇ + ∂/∂q̇^i) : Ṽ ∈ 𝒪_l}  [V (3.21)].
Subspace lifted_sode_obstruction(const VignoloPoint& d, const Options& opt = {});

}  // namespace dcad::fast
