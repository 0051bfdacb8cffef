// The equations of motion of an LC circuit on M_c without its 3n-dimensional system; the twin of
// dcad/reference/circuit_motion.hpp.  M_c = {q ∈ S, v ∈ V, p = φ v} comes from the graph route's
// equations (S: the q-equations, V: the v-equations); then q̇ = v, φ v̇ + ψ q ∈ Δ°, v̇ ∈ V
// (CEF (6.10)–(6.13), ERRATA sign of ψ) with orthonormal bases and decided ranks.
#pragma once

#include "dcad/fast/circuit.hpp"

namespace dcad::fast {

struct CircuitMotion {
  std::vector<int> coords;  ///< z = x[coords]: unless given, m well-conditioned variables (pivoted QR), in order
  MatrixXd f_matrix;        ///< ż = F z + G λ (no sources: f = 0)
  MatrixXd g;               ///< columns span the free directions; their number is the solution rank
  Truth certain = yes;
  std::vector<RankDecision> decisions;
};

/// `t` must be circuit_tower(g).  Throws std::invalid_argument for `coords` that do not parametrize M_c.
CircuitMotion circuit_motion(const CircuitGraph& g, const CircuitTower& t, std::vector<int> coords = {},
                             const Options& opt = {});

}  // namespace dcad::fast
