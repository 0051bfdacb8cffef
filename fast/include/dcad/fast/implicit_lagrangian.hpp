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

/// B_P^♯ of YM (5.9) by its definition B_P = B|_{T*P × T*P}: the canonical brackets {f, g} = ∂_q f·∂_p g − ∂_p f·∂_q g
/// of P's coordinate functions (r^α, s^a, p̃_α), p̃_α = p_{r^α} − A^b_α(q) p_{s^b} = ∂L_c/∂u^α, at (q, p) — a
/// different route from the reference's entries with the curvature K.  q and p ordered (r, s); `a` = A(q)
/// (m × (n − m)); `da[i]` = ∂A/∂q^i for the n coordinates (r, s); `p` = (p_r, p_s).  std::invalid_argument on sizes
/// or values that are not finite.
MatrixXd constrained_poisson_tensor(const MatrixXd& a, const std::vector<MatrixXd>& da, const VectorXd& p);

/// dω^b(hor y, hor z) of the connection's one-forms ω^b = ds^b + A^b_α dr^α at q (YM Prop 5.1's right side), by the
/// Lie bracket of the horizontal lifts hor y = (y, −A y): every ω^b annihilates them, so dω(X, Y) = X ω(Y) − Y ω(X)
/// − ω([X, Y]) leaves −ω^b([hor y, hor z]), and for constant y, z the bracket has no r part and the s part
/// D(−A z)·hor y − D(−A y)·hor z — a different route from the reference's dω by its coordinates.  `a` = A(q)
/// (m × (n − m)), `da[i]` = ∂A/∂q^i for the n coordinates (r, s); y, z of n − m.  std::invalid_argument on sizes or
/// values that are not finite.
VectorXd horizontal_form_differential(const MatrixXd& a, const std::vector<MatrixXd>& da, const VectorXd& y,
                                      const VectorXd& z);

}  // namespace dcad::fast
