// The graph route for RLC circuits with sources (CEF §6 extended by YM §4's forces and affine
// constraints): the tower of the circuit's forced system (dcad/reference/rlc.hpp) from cycle ranks of
// subgraphs, without forming the 3n-dimensional system.  Topology only (dcad::core: no arithmetic);
// it holds when every C and R is positive and the inductance matrix Φ is positive definite (every L
// positive, couplings with |k| < 1): the inductors enter only through the currents an LI cutset
// leaves to them, a system in Φ⁻¹-weighted node potentials that is solvable for Φ > 0 — then it decides
// nothing, and the callers (fast, and the exact backends beyond the dense route's size) use it at any
// size.  The conditions on the sources it names are decided against the waveforms by the caller.
//
// Notation: G the circuit's graph, Z(H) the cycle rank of a subgraph H (graph::cycle_rank),
// H1 = G without inductors and current sources, H1[S] its subgraph of the kinds S.  Variables
// (q, v, p) ∈ R^{3n}; Δ = {v : KCL, v_I = 0}, so dim Δ = Z(G − I).
//   M_1 = {p = Φ v, v ∈ Δ + Z σ(t)}:                       d1 = n + Z(G − I),
//         and one condition Σ ±I_b(t) = 0 per cutset made of current sources only;
//   M_2 = M_1 ∩ {KVL on every loop of H1: Σ ±(q_b/C_b + R_b v_b + V_b(t)) = 0}:
//         a loop ℓ gives no equation iff ℓ_C = 0 and R ℓ_R ⊥ Δ; ℓ itself lies in Δ and ℓᵀRℓ > 0
//         unless ℓ_R = 0, so exactly the loops of H1[V, W] give none — each is a condition
//         Σ ±V_b(t) = 0 instead:                          d2 = d1 − (Z(H1) − Z(H1[V,W]));
//   M_3 = M_2 ∩ {d/dt of the loops without resistor: Σ ±(v_b/C_b + V̇_b(t)) = 0} (a resistor's
//         v̇_R absorbs the others' derivatives); v = ℓ ∈ Δ shows them independent:
//                                                        d3 = d2 − (Z(H1[C,V,W]) − Z(H1[V,W]));
//   M_4 = M_3.  The currents around loops of voltage sources and wires are free: the solution rank
//   is Z(H1[V, W]) (CEF Thm 6.8's empty loops, with sources).
// For LC circuits (no R, V, I) this is CEF Thms 6.4, 6.6 and 6.8.  proptests/prop_forced.cpp checks
// every count against the exact dense route (reference::forced_tower) on random circuits
// (GraphRouteIsTheDenseRoute, GraphRouteHoldsThroughPositiveDefiniteCouplings).
#pragma once

#include "dcad/graph.hpp"

#include <vector>

namespace dcad::rlc {

enum class Kind { inductor, capacitor, resistor, voltage, current, wire };

struct Branch {
  Kind kind = Kind::wire;
  long from = -1, to = -1;  ///< node indices, −1 = ground; current flows from → to
};

struct Tower {
  std::vector<long> dims;  ///< dim M_0 … M_c when every condition on the sources holds
  int steps = 0;
  long solution_rank = 0;
  /// M_1's conditions: Σ sign·I_b(t) = 0 over each cutset made of current sources only
  std::vector<graph::Cutset> current_cutsets;
  /// M_2's conditions: Σ sign·V_b(t) = 0 over each fundamental loop of voltage sources and wires
  /// (wires contribute nothing; a loop of wires alone is no condition and is left out)
  std::vector<graph::Loop> voltage_loops;
};

inline std::vector<graph::Edge> edges(const std::vector<Branch>& branches) {
  std::vector<graph::Edge> out;
  out.reserve(branches.size());
  for (const Branch& b : branches) out.push_back({b.from, b.to});
  return out;
}

/// The branches whose kind is one of `kinds`.
inline std::vector<bool> of_kinds(const std::vector<Branch>& branches, std::initializer_list<Kind> kinds) {
  std::vector<bool> out(branches.size(), false);
  for (std::size_t b = 0; b < branches.size(); ++b)
    for (Kind k : kinds) out[b] = out[b] || branches[b].kind == k;
  return out;
}

/// The tower of a circuit with positive L, C, R and no coupling (see above).  O(n + loop lengths).
inline Tower tower(std::size_t nodes, const std::vector<Branch>& branches) {
  using K = Kind;
  const std::vector<graph::Edge> e = edges(branches);
  const auto z = [&](std::initializer_list<Kind> kinds) {
    return static_cast<long>(graph::cycle_rank(nodes, e, of_kinds(branches, kinds)));
  };
  const long n = static_cast<long>(branches.size());
  const long z_vw = z({K::voltage, K::wire});
  const long d0 = 3 * n, d1 = n + z({K::inductor, K::capacitor, K::resistor, K::voltage, K::wire});
  const long d2 = d1 - (z({K::capacitor, K::resistor, K::voltage, K::wire}) - z_vw);
  const long d3 = d2 - (z({K::capacitor, K::voltage, K::wire}) - z_vw);
  Tower t;
  t.dims = {d0, d1};
  if (d2 < d1) t.dims.push_back(d2);
  if (d3 < d2) t.dims.push_back(d3);
  t.steps = static_cast<int>(t.dims.size()) - 1;
  t.solution_rank = z_vw;
  const std::vector<bool> current = of_kinds(branches, {K::current});
  t.current_cutsets = graph::cutsets(nodes, e, current, current);
  for (graph::Loop& l :
       graph::fundamental_loops(nodes, e, of_kinds(branches, {K::voltage, K::wire}), of_kinds(branches, {K::wire}))) {
    bool source = false;
    for (const graph::LoopBranch& lb : l) source = source || branches[lb.branch].kind == K::voltage;
    if (source) t.voltage_loops.push_back(std::move(l));
  }
  return t;
}

}  // namespace dcad::rlc
