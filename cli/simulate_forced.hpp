// `dcad simulate` for decks with resistors, sources and couplings (simulate_forced.cpp).
#pragma once

#include "simulate.hpp"

namespace dcad::cli {

/// As simulate(), for deck.forced; `energy` (optional) receives the energy-balance CSV
/// t,E,P_dissipated,P_voltage_sources,P_current_sources,W_… (YM §4: dE/dt = ⟨F, q̇⟩ + reaction work).
SimulateSummary simulate_forced(const io::Netlist& deck, const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial,
                                const SimulateOptions& opt, std::ostream& out, std::ostream& log, std::ostream* energy);

}  // namespace dcad::cli
