// The reference's forced route (YM §4 forces and affine constraints, moving M_k(t) as in V §3):
// netlists with resistors, sources and couplings, and `pontryagin` cases with `forces`.  Exact
// (mpq_rational); the source conditions the tower finds are decided against the deck's waveforms.
#pragma once

#include "dcad/io/netlist.hpp"
#include "dcad/reference/forced.hpp"
#include "dcad/reference/rational.hpp"
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
/// t ≥ 0: exactly where the waveforms allow (DC values, equal waveforms that cancel); otherwise no when
/// the combination, evaluated in double at the breakpoints, their midpoints and 97 spread times, exceeds
/// kConditionFails × its largest term (far above the rounding of the evaluation), else unknown.
SourceCondition decide_condition(const Matrix<Rational>& row, const std::vector<io::Waveform>& w);
constexpr double kConditionFails = 1e-9;

/// The exact forced CAD of a netlist with R, V, I or K (at most kForcedBranches branches: InputError).
dcad::Solution<Rational> solve_forced(const io::Netlist& deck, const std::vector<std::string>& variables);
/// The same for a `pontryagin` case with `forces` (no sources).
dcad::Solution<Rational> solve_forced(const io::CaseFile& c);

}  // namespace dcad::reference::pipeline
