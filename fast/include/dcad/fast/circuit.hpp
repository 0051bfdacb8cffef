// The graph route for LC circuits (CEF §6): the constraint tower of the circuit's `pontryagin`
// system from spanning forests and fundamental loops, without forming the 3n×3n system.
//
// Variables x = (q, v, p) ∈ R^{3n}, n = branches: q_b = index b, v_b = n + b, p_b = 2n + b.
// CEF §6 (after (6.24)) gives the tower in closed form with Δ_0 = Δ = ker K,
//   Δ_k = Δ ∩ ψ⁻¹(φ(Δ_{k−1}) + Δ°),  S_k = ψ⁻¹(φ(Δ_k) + Δ°),
//   M_1 = {p = φ v, v ∈ Δ},  M_{2k} = {q ∈ S_{k−1}, p = φ v, v ∈ Δ_{k−1}},  M_{2k+1} = {q ∈ S_{k−1}, p = φ v, v ∈ Δ_k}
// (our ψ = +diag(1/C_i), see ERRATA).  Two routes to it:
//  * physical (every L > 0, every C > 0, empty branches allowed) — combinatorial, no rank decision:
//    KCL per node (cutsets), and by Thm 6.4 S_0 is KVL on the purely capacitive loops, i.e. one
//    equation Σ ±q_i/C_i = 0 per fundamental loop of the non-inductive subgraph that closes through a
//    capacitor (the forest spans the empty subgraph first, so the other fundamental loops are the
//    empty loops).  Thm 6.6: Δ_2 = Δ_1, so c = 3 if there is such a loop and c = 1 otherwise; the
//    solution rank is the number of independent empty loops (Thm 6.8).  O(n + total loop length).
//  * signed values (CEF Remark 6.7) — the closed form above with Δ in loop coordinates
//    (a ↦ Bᵀ a, B the fundamental-loop matrix, m×n), each rank decided by decide_rank.
// `proptests/prop_circuit_graph.cpp` checks both against the generic CAD (reference and fast).
#pragma once

#include <algorithm>
#include <cmath>

#include "dcad/fast/rank.hpp"
#include "dcad/graph.hpp"
#include "dcad/lc_graph.hpp"
#include "dcad/types.hpp"

#include <cstddef>
#include <vector>

namespace dcad::fast {

using dcad::BranchKind;  // dcad/types.hpp: the reference's type
using graph::Loop;       // dcad/graph.hpp: the topology every route shares
using graph::LoopBranch;
using CircuitBranch = lc::Branch<double>;  ///< kind, nodes (−1 = ground), L or C
using Term = lc::Term<double>;
using SparseRow = lc::Row<double>;  ///< Σ coeff·x_var = 0

struct CircuitGraph {
  std::size_t nodes = 0;  ///< non-ground nodes 0 … nodes−1
  std::vector<CircuitBranch> branches;
};

/// `opt` itself if already assessed (rank.hpp), else a copy assessed on the element values as the exact
/// conversion assesses them (dcad/fast/exact.hpp's to_double_values): their magnitudes, with 1, spanning
/// more than 1/nonzero_factor leave no rank deficiency certain (graded values).
inline Options assessed_values(const Options& opt, const CircuitGraph& g) {
  if (opt.input_assessed) return opt;
  Options out = opt;
  double lo = 1, hi = 1;
  for (const CircuitBranch& b : g.branches)
    if (b.value != 0 && std::isfinite(b.value))
      lo = std::min(lo, std::abs(b.value)), hi = std::max(hi, std::abs(b.value));
  if (hi / lo > 1 / out.nonzero_factor) out.input_well_scaled = false;
  out.input_assessed = true;
  return out;
}

/// The tower (dcad/lc_graph.hpp's, in double) and how it was reached.
struct CircuitTower : lc::Tower<double> {
  bool physical = true;  ///< the combinatorial route was taken
  Truth certain = yes;
  std::vector<RankDecision> decisions;  ///< signed route only
};

/// Throws std::invalid_argument for a node index out of range or a value that is not finite and
/// nonzero (for L and C).
CircuitTower circuit_tower(const CircuitGraph& g, const Options& opt = {});

/// No negative L or C: then circuit_tower takes the combinatorial route and decides nothing.
bool is_physical(const CircuitGraph& g);

/// CEF Lemma 6.5's condition (*): for each δ ∈ Δ some δ_1 ∈ Δ_1 has φ(δ) − φ(δ_1) ∈ Δ°.  By the route of
/// Theorem 6.6's proof, not the reference's annihilators: in an orthonormal basis of Δ (from the fundamental
/// loops), A = P_Δ φ|_Δ and B = P_Δ ψ|_Δ; Δ_1 = {c : B c ∈ im A} and (*) says A Δ_1 = im A.  Lemma 6.5 (b):
/// it holds exactly when Δ_1 = Δ_2.  unknown where a rank decision is not certain.
Truth condition_star(const CircuitGraph& g, const Options& opt = {});

/// Σ = [{ε_i, ε_j}] of the equations of the leaf x₀ + W̃_c of a physical LC circuit in T*TE, variables
/// (q, v, p, ν) (CEF §6 after Theorem 6.8: κ(q), η(ψq), p − φv, κ(v), η(ψv), ν).  Another route than the
/// reference's block formula: the brackets a_i J a_jᵀ of its own rows, K one per node and Γ the graph's
/// fundamental purely capacitive loops.  `second_class`: Σ decided nondegenerate (every constraint second
/// class, the leaf symplectic — Theorem 6.8: exactly when there is no empty loop).  std::invalid_argument for
/// a circuit that is not physical (a negative L or C).
struct LeafBrackets {
  MatrixXd sigma;
  RankDecision decision;
  Truth second_class = unknown;
};
LeafBrackets leaf_brackets(const CircuitGraph& g, const Options& opt = {});

}  // namespace dcad::fast
