// LC netlists: the SPICE subset of ../shared/CONTRACT.md, read exactly (values and suffixes to
// rationals).  Errors: InputError "FILE:LINE: expected …, found …".
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/reference/circuit.hpp"
#include "dcad/reference/rlc.hpp"
#include "dcad/io/waveform.hpp"

#include <optional>

namespace dcad::io {

struct Netlist {
  std::string file, title;
  reference::Circuit<Rational> circuit;
  std::vector<std::string> node_names;                  ///< non-ground nodes, in order of appearance
  std::vector<std::optional<Rational>> initial;         ///< IC= per branch (current for L, voltage for C)
  std::vector<std::string> warnings;                    ///< ignored dot-cards, non-physical values
  /// Every element, R, V, I and K included (YM §4); `circuit` holds the same branches with R and
  /// the sources as empty branches, and is the circuit only when !forced.
  reference::RlcCircuit<Rational> rlc;
  std::vector<Waveform> waveforms;  ///< per source (σ index), in netlist order
  std::vector<std::string> where;   ///< file:line of each branch
  bool forced = false;              ///< some R, I, K or nonzero V: the YM §4 route
};

bool is_netlist_file(const std::string& file);
Netlist read_netlist(const std::string& file);
/// A deck given as text, named `name` in messages; `.include`/`.lib` files are read from `directory`.
Netlist read_netlist_text(const std::string& text, const std::string& name, const std::string& directory);
/// SPICE value: number with optional suffix f p n u m k meg g t (case-insensitive), trailing unit
/// letters ignored ("10uF"); exact.  Throws std::invalid_argument.
Rational parse_spice_value(const std::string& text);
/// The case the circuit stands for: `pontryagin` with variables q_*, v_*, p_* (CONTRACT).  Without
/// `dense`, only the names (no n×n and 3n×3n matrices: for the graph route on large circuits).
CaseFile netlist_case(const Netlist& n, bool dense = true);

/// The dimensionless twin of a circuit: every L divided by L0 = 10^a, every C by C0 = 10^b, with
/// 10^a and 10^b the powers of ten nearest the geometric means (b one up if a + b is odd) and a + b
/// even, so that the time
/// unit T = √(L0 C0) = 10^m, m = (a + b)/2, is exact.  A solution of the twin gives one of the
/// circuit by t = T t̃, q = q̃, v = ṽ/T, p = (L0/T) p̃ (and ν = L0 ν̃ on T*TQ): the Lagrangian
/// becomes (C0 times) that of the twin (CEF §6: L = ½ vᵀΦv − ½ qᵀΨq), so the towers are equal and
/// the equations of motion correspond (x = S x̃, d/dt = T⁻¹ d/dt̃).  Exact (rational values).
struct Units {
  int a = 0, b = 0;  ///< L0 = 10^a, C0 = 10^b
  int m() const { return (a + b) / 2; }
};
Netlist dimensionless(const Netlist& n, Units& u);

}  // namespace dcad::io
