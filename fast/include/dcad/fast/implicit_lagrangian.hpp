// YM's implicit Lagrangian systems at a point, in double; the twin of dcad/reference/implicit_lagrangian.hpp's
// fields (without forces).  A different route: the reference intersects with the equations of D_Δ; fast solves
// q̇ = v, K q̇ = 0, Nᵀ ṗ = Nᵀ ∂L/∂q (N an orthonormal basis of Δ = ker K) with its rank decisions.
#pragma once

#include "dcad/fast/cad.hpp"

namespace dcad::fast {

/// p = ∂L/∂v = A v + Bᵀ q + b (the Legendre transform FL).
VectorXd legendre(const PontryaginInput& in, const VectorXd& q, const VectorXd& v);

/// 𝔇L(q, v) = (−∂L/∂q, v) ∈ T*_{(q, p)} T*Q  [YM §3].
VectorXd dirac_differential(const PontryaginInput& in, const VectorXd& q, const VectorXd& v);

/// The partial vector fields X(q, v, p) = (q̇, ṗ) at p = FL(q, v): {X : (X, 𝔇L) ∈ D_Δ} — q̇ = v ∈ Δ,
/// ṗ − ∂L/∂q ∈ Δ° (YM (3.24), Prop 3.7); empty when v ∉ Δ.
AffineSubspace implicit_lagrangian_fields(const PontryaginInput& in, const VectorXd& q, const VectorXd& v,
                                          const Options& opt = {});

}  // namespace dcad::fast
