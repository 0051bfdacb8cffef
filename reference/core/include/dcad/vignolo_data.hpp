// The data of V's pointwise objects (Vignolo, "Presymplectic Lagrangian systems subject to non-holonomic
// constraints"), shared by the two twins: each names it in its own namespace, reference::VignoloPoint<T> and
// fast::VignoloPoint.  A point z = (t, q, q̇) of the velocity space j₁(𝒱_{n+1}) on the constraint
// submanifold 𝒜 and the values there of what V's objects at z are made of: the Lagrangian's first and
// second derivatives, and the affine constraints φ^σ = g^σ_i(t, q) q̇^i + g^σ_0(t, q) (V (2.6)–(2.7a)) with
// their first derivatives.  Every value is independent of the others at one point (a polynomial L and
// g of degree 2 realize any choice), so the properties draw them freely.
#pragma once

#include <cstddef>

namespace dcad {

/// Coordinates: j₁ = (t, q¹…qⁿ, q̇¹…q̇ⁿ), dimension 2n + 1; the Lagrangian bundle 𝓛(𝒱_{n+1}) adds u̇
/// (V §2.2), dimension 2n + 2.  Matrices (i, j) as named; g has one row per constraint (n − r of them).
template <class Scalar, class Mat, class Vec>
struct VignoloData {
  std::size_t n = 0;
  Vec qdot;     ///< q̇(z)
  Scalar lt{};  ///< ∂L/∂t
  Vec lq;       ///< ∂L/∂q^i
  Vec lv;       ///< ∂L/∂q̇^i, the momenta p_i
  Vec ltv;      ///< ∂²L/∂t∂q̇^i
  Mat lqv;      ///< (i, j): ∂²L/∂q^j∂q̇^i
  Mat lvv;      ///< (i, j): ∂²L/∂q̇^i∂q̇^j, V's Γ_ij (symmetric)
  Mat g;        ///< (σ, i): g^σ_i, rows independent (V (2.6)); 0 rows: no constraint
  Vec g0;       ///< g^σ_0; z ∈ 𝒜: g q̇ + g0 = 0 (V (2.7a))
  Vec phi_t;    ///< ∂φ^σ/∂t at z
  Mat phi_q;    ///< (σ, j): ∂φ^σ/∂q^j at z (∂φ^σ/∂q̇^i = g^σ_i)
};

}  // namespace dcad
