// `dcad simulate` for decks with resistors, sources and couplings (simulate_forced.cpp).
#pragma once

#include "simulate.hpp"

namespace dcad::cli {

/// As simulate(), for deck.forced; `energy` (optional) receives the energy-balance CSV
/// t,E,P_forces,P_sources,P_constraints,W_… (YM §4: dE/dt = ⟨F x + Bσ, q̇⟩ + the work of the reactions
/// of affine constraints; for circuits −P_forces is what the resistors dissipate).
SimulateSummary simulate_forced(const io::Netlist& deck, const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial,
                                const SimulateOptions& opt, std::ostream& out, std::ostream& log, std::ostream* energy);

/// As simulate_forced, for a `pontryagin` case with `forces` (no sources).
SimulateSummary simulate_forced_case(const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                                     std::ostream& out, std::ostream& log, std::ostream* energy);

}  // namespace dcad::cli
