// `dcad solve` on netlists with resistors, sources and mutual inductance: the CAD of the forced
// system (YM §4) with time-dependent affine constraint submanifolds (V §3), reference/forced.hpp.
// The source conditions the tower finds (loops of voltage sources, cutsets of current sources) are
// decided against the deck's waveforms; the report names the loops and cutsets that constrain
// the circuit (CV loops on q, LI cutsets on v) by element.
#pragma once

#include "dcad/io/netlist.hpp"
#include "solve.hpp"

namespace dcad::cli {

/// Whether a source condition b + Σ c_{j,d} σ_j^{(d)}(t) = 0 holds for all t ≥ 0.
struct ConditionVerdict {
  enum class Holds { yes, no, uncertain } holds = Holds::yes;
  std::string text;      ///< "V1(t) - V2(t) = 0"
  std::string evidence;  ///< why (exact, or the time and value where it fails)
};

struct ForcedReport {
  SolveReport report;
  std::vector<ConditionVerdict> conditions;
  nlohmann::json circuit;  ///< the CONTRACT `circuit` object plus the named loops and cutsets
  std::string circuit_text;
  std::vector<std::string> names;         ///< variables, then the jet columns (for equation text)
  std::vector<std::string> source_names;  ///< σ, in order
  /// ż = F z + f + S u_src + G λ: S over the jet columns (V1(t), V1'(t), …); empty without sources
  std::vector<std::vector<std::string>> source_terms;
  std::vector<std::string> source_columns;
};

/// Largest number of branches the forced route takes (exact arithmetic on 3n variables with jets).
constexpr std::size_t kForcedBranches = 60;

ForcedReport solve_forced(const io::Netlist& n, const std::string& backend);
/// A `pontryagin` case with `forces` (F(q, v) = F_q q + F_v v, YM §4): the same route, no sources.
ForcedReport solve_forced_case(const io::CaseFile& c, const std::string& backend);
/// The forced system of a `pontryagin` case with `forces`: E = p·v − L, D̄_Δ, and F on the q-rows.
reference::ForcedSystem<io::Rational> case_forced_system(const io::CaseFile& c);
nlohmann::json to_json(const ForcedReport& r, const io::CaseFile& c);
std::string to_text(const ForcedReport& r, const io::CaseFile& c);

/// Names of the jet columns [1 | σ⁽⁰⁾ | σ⁽¹⁾ | …] of a forced deck: "1", "V1(t)", "V1'(t)", "V1''(t)", "d3V1/dt3(t)".
std::vector<std::string> jet_names(const std::vector<io::Waveform>& w, long orders);
ConditionVerdict decide_condition(const io::QMatrix& row, const std::vector<io::Waveform>& w);

}  // namespace dcad::cli
