// The reference's forced route (YM §4 forces and affine constraints, moving M_k(t) as in V §3):
// netlists with resistors, sources and couplings, and `pontryagin` cases with `forces`.  Exact
// (mpq_rational); the source conditions the tower finds are decided against the deck's waveforms.
#pragma once

#include "dcad/io/netlist.hpp"
#include "dcad/reference/forced.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/reference/rlc_state.hpp"
#include "dcad/solution.hpp"

#include <string>
#include <vector>

namespace dcad::reference::pipeline {

/// Largest number of branches the forced route takes (exact arithmetic on 3n variables with jets).
constexpr std::size_t kForcedBranches = 60;

/// The forced system of a `pontryagin` case with `forces`: E = p·v − L, D̄_Δ, and F on the q-rows.
ForcedSystem<Rational> forced_system(const io::CaseFile& c);

/// Names of the jet columns [1 | σ⁽⁰⁾ | σ⁽¹⁾ | …] of a forced deck: "1", "V1(t)", "V1'(t)", "V1''(t)", "d4V1/dt4(t)".
std::vector<std::string> jet_names(const std::vector<io::Waveform>& w, long orders);

/// Whether a source condition b + Σ c_{j,d} σ_j^{(d)}(t) = 0 (a row [b | σ⁽⁰⁾ | σ⁽¹⁾ | …]) holds for all
/// t ≥ 0: exactly where the waveforms allow (DC values, equal waveforms that cancel); no with a proof — the
/// combination sampled in double (breakpoints, their midpoints, spread times) points at its largest values,
/// and an Arb ball of the exact combination at one of those exact times excludes 0 (PULSE and PWL exact
/// rationals there; SIN, EXP, SFFM rigorous balls: src/source_balls.hpp); otherwise unknown, with the
/// evidence.  kConditionFails only words the evidence (values that agree to it look equal in double).
SourceCondition decide_condition(const Matrix<Rational>& row, const std::vector<io::Waveform>& w);
constexpr double kConditionFails = 1e-9;

/// The graph route's answer (dcad/rlc_graph.hpp) with its conditions on the sources decided against the
/// waveforms: the first M_k whose condition fails is empty (dims end in −1 there).  No equations.
struct GraphForced {
  std::vector<long> dims;
  long steps = 0, solution_rank = 0;
  bool consistent = true;
  std::vector<SourceCondition> conditions;
  Truth certified = unknown;  ///< yes: the graph's theorems and every condition decided exactly (graph_forced)
};
/// Whether the graph route holds: every C and R positive and the inductance matrix Φ positive
/// definite (every L positive; couplings with |k| < 1 on a pair, decided exactly per coupled group).
bool graph_route_holds(const RlcCircuit<Rational>& c);
/// Some mutual inductance k√(L_a L_b) is irrational and was rounded (80 digits): the dense route is
/// then exact for the rounded circuit only — not certified (kRoundedCoupling says why).
bool rounded_coupling(const RlcCircuit<Rational>& c);
constexpr const char* kRoundedCoupling =
    "a mutual inductance k*sqrt(Lx*Ly) is irrational and was rounded to 80 digits: the dense route is exact for the "
    "rounded circuit, "
    "whose tower may differ from the deck's (a singular coupling matrix reads as regular)";
/// The graph route on a deck where graph_route_holds; exact at any size (topology and ±1 rows).
GraphForced graph_forced(const io::Netlist& deck);

/// The deck's state equations (dcad/reference/rlc_state.hpp) in N (exact for Rational), where the
/// graph route holds.
template <class N>
StateEquations<N> deck_state_equations(const io::Netlist& deck) {
  RlcCircuit<N> c;
  c.nodes = deck.rlc.nodes;
  c.sources = deck.rlc.sources;
  for (const RlcBranch<Rational>& b : deck.rlc.branches)
    c.branches.push_back({b.name, b.kind, b.from, b.to, static_cast<N>(b.value), b.source});
  for (const Mutual<Rational>& mu : deck.rlc.mutuals)
    c.mutuals.push_back({mu.a, mu.b, static_cast<N>(mu.m), {}, mu.rounded});
  std::vector<std::string> sources;
  for (const io::Waveform& w : deck.waveforms) sources.push_back(w.element + "(t)");
  return state_equations<N>(c, deck.node_names, sources);
}

/// The graph route's answer as a Solution of either twin: dims, conditions, verdict, and the state
/// equations at any size (the tower's own equations come from the dense route only).
template <class N>
dcad::Solution<N> graph_solution(const io::Netlist& deck, const std::vector<std::string>& variables,
                                 const std::string& note) {
  const GraphForced g = graph_forced(deck);
  dcad::Solution<N> s;
  for (long d : g.dims) s.tower.push_back({d, {}});
  s.steps = g.steps;
  s.consistent = g.consistent;
  if (g.consistent) s.solution_rank = g.solution_rank;
  s.source_conditions = g.conditions;
  for (const io::Waveform& w : deck.waveforms) s.source_names.push_back(w.element);
  s.certified = g.certified;
  s.trace = exact_trace(s.dims(), DecidedBy::graph,
                        "cycle ranks of subgraphs (YM §4; C, R > 0, Φ positive definite): "
                        "no rank decided");
  s.variables = variables;
  s.file = deck.file;
  s.name = deck.title;
  s.note = note;
  if (g.consistent) s.state = deck_state_equations<N>(deck);
  if (s.certified.unknown()) s.note += "; a source condition could not be decided exactly (see sources.conditions)";
  return s;
}

/// The exact forced CAD of a netlist with R, V, I or K: the dense route up to kForcedBranches branches,
/// the graph route beyond where it holds (tower and source conditions; no equations), else InputError.
dcad::Solution<Rational> solve_forced(const io::Netlist& deck, const std::vector<std::string>& variables);
/// The same for a `pontryagin` case with `forces` (no sources).
dcad::Solution<Rational> solve_forced(const io::CaseFile& c);

}  // namespace dcad::reference::pipeline
