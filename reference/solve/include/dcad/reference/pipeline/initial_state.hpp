// A netlist's initial state as SPICE defines it, and the jump onto M_c at t = 0 (CONTRACT "Circuit
// initial state").  Exact, on the dense forced system (dcad/reference/rlc.hpp), at most
// kForcedBranches branches where an operating point or a jump must be computed.
//   - uic: the IC= values and `.ic` node voltages, everything else 0 (ngspice's "use initial conditions");
//   - op: the DC operating point at t = 0 — capacitors open, inductors shorted, sources at their value
//     at 0, `.ic` node voltages held — solved exactly as KCL, the branch laws and u = potential
//     differences; a non-unique one (floating nodes, loops of inductors) takes its free parts as small
//     as possible and says so.
// The state is the circuit just before t = 0: charges q and flux linkages p = Φ i.  M_c(0+) is reached
// by the jump circuit theory allows: impulsive currents obey KCL (q⁺ − q⁻ ∈ Δ = ker K_I) and pass no
// inductor, impulsive voltages obey KVL (Δp on inductors, R Δq on resistors, 0 on capacitors and
// sources: in Δ° = row K_I); currents are whatever M_c needs.  Of the points of M_c(0+) so reachable
// the nearest to the state before is taken.
#pragma once

#include "dcad/initial_rule.hpp"
#include "dcad/io/netlist.hpp"
#include "dcad/reference/rational.hpp"

#include <optional>
#include <string>
#include <vector>

namespace dcad::reference::pipeline {

using dcad::InitialRule;  // dcad/initial_rule.hpp

struct Jump {
  std::string variable;
  Rational from, to;
  std::string constraint;  ///< an equation of M_c(0+) the state before violated, involving the variable
};

struct InitialState {
  std::string rule;                     ///< which rule, and why ("uic: .tran … uic at deck.cir:9")
  std::vector<Rational> before, after;  ///< (q, v, p) just before t = 0 and on M_c(0+)
  std::vector<Jump> jumps;              ///< every charge, flux linkage or inductor current that jumped
  std::vector<std::string> notes;       ///< a non-unique operating point, a jump beyond the dense size
  bool computed = true;                 ///< false: `after` is `before`, unchecked (larger LC decks, uic)
};

/// The state `simulate` and `check` start a netlist from.  `variables`: q_*, v_*, p_* names.  Throws
/// io::InputError when no operating point exists, when no impulse reaches M_c (naming the constraint),
/// and when an operating point or a jump beyond kForcedBranches branches would be needed.
InitialState initial_state(const io::Netlist& deck, InitialRule rule, const std::vector<std::string>& variables);

}  // namespace dcad::reference::pipeline
