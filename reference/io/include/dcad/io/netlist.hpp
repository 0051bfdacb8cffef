// LC netlists: the SPICE subset of ../shared/CONTRACT.md, read exactly (values and suffixes to
// rationals).  Errors: InputError "FILE:LINE: expected …, found …".
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/reference/circuit.hpp"
#include "dcad/reference/rlc.hpp"
#include "dcad/io/waveform.hpp"
#include "dcad/solution.hpp"
#include "dcad/units.hpp"

#include <optional>

namespace dcad::io {

struct Netlist {
  std::string file, title;
  reference::Circuit<Rational> circuit;
  std::vector<std::string> node_names;           ///< non-ground nodes, in order of appearance
  std::vector<std::optional<Rational>> initial;  ///< IC= per branch (current for L, voltage for C)
  std::vector<std::string> warnings;             ///< ignored dot-cards, non-physical values
  /// Every element, R, V, I and K included (YM §4); `circuit` holds the same branches with R and
  /// the sources as empty branches, and is the circuit only when !forced.
  reference::RlcCircuit<Rational> rlc;
  std::vector<Waveform> waveforms;  ///< per source (σ index), in netlist order
  std::vector<std::string> where;   ///< file:line of each branch
  bool forced = false;              ///< some R, I, K or nonzero V: the YM §4 route
  /// The deck's `.tran` (CONTRACT "Circuit initial state"): none, with `uic`, or without (the DC
  /// operating point); where it is, for messages.
  enum class Transient { none, uic, op };
  Transient tran = Transient::none;
  std::string tran_where;
  std::optional<Rational> tran_step, tran_stop;  ///< the .tran card's TSTEP and TSTOP where they are numbers
  /// `.ic v(node)=value` by node index (ground excluded): with uic capacitor voltages, without it the
  /// voltages the operating point holds.
  std::vector<std::pair<long, Rational>> node_ic;
  /// Non-empty when a group of coupled inductors has an inductance matrix that is not positive
  /// semidefinite (decided exactly; file:line and the couplings): `simulate` and `check` refuse the deck.
  std::string indefinite_inductance;
  /// Values that are irrational (sqrt, exp, pi … in an expression), each "file:line: {expr} …": used to 80
  /// significant digits, so the exact tiers solve a circuit within 1e-80 of the deck's, and say so.
  std::vector<std::string> rounded;
};

/// The note of a result on a deck with irrational values (Netlist::rounded), "" if none: what an exact
/// tier proves there is about the rounded circuit, so no tier says `certified` of the deck itself.
inline std::string rounded_note(const Netlist& n) {
  if (n.rounded.empty()) return "";
  std::string s = "not certified for the deck as written: " + std::to_string(n.rounded.size()) +
                  " irrational value(s) used to 80 significant digits (" + n.rounded.front();
  return s + (n.rounded.size() > 1 ? ", …)" : ")") + "; the answer is exact for that rounded circuit";
}

/// Whose deck it is, for the scale factors the SPICEs read differently: `1a` is 1e-18 in ngspice 40 on
/// (inpeval.c), HSPICE, LTspice and gnucap (ap_convert.cc), and 1 (a unit, amperes) in ngspice 39 and Xyce
/// without -hspice-ext (its PARSER/aAsAmp.cir); `1x` is 1e6 in HSPICE and Xyce (PARSER/scalingFactors.cir),
/// and 1 in ngspice and gnucap.  `strict`, the default, refuses both and names the dialects.  In Xyce's
/// dialect `$` is a character of names ($N_0001), not an inline comment as in ngspice and HSPICE.
enum class Dialect { strict, ngspice, ngspice39, xyce, hspice, gnucap };
/// The dialect of a name as `--dialect` takes it (strict ngspice ngspice39 xyce hspice gnucap).
std::optional<Dialect> dialect_named(const std::string& name);
struct ReadOptions {
  Dialect dialect = Dialect::strict;
};

bool is_netlist_file(const std::string& file);
/// The deck's graph facts (dcad/graph.hpp): counts, and the loops and cutsets by signed branch names —
/// for an LC deck CEF Thm 6.4's purely capacitive and Thm 6.8's empty loops; with resistors, sources or
/// couplings (YM §4) the CV loops, loops of voltage sources, LI cutsets and cutsets of current sources.
CircuitFacts circuit_facts(const Netlist& n);
Netlist read_netlist(const std::string& file, const ReadOptions& options = {});
/// A deck given as text, named `name` in messages; `.include`/`.lib` files are read from `directory`.
Netlist read_netlist_text(const std::string& text, const std::string& name, const std::string& directory,
                          const ReadOptions& options = {});
/// SPICE value, exact: a number with an optional scale factor as ngspice reads it (f p n u m mil k meg g
/// t, case-insensitive) and an optional unit ("10uF", "2.2kOhm").  Other trailing letters are ignored, as
/// ngspice does, and put in `*ignored` (the caller warns).  A leading `a` or `x` is read as `dialect` reads
/// it, and refused in the strict one.  Throws std::invalid_argument.
Rational parse_spice_value(const std::string& text, std::string* ignored = nullptr, Dialect dialect = Dialect::strict);
/// The case the circuit stands for: `pontryagin` with variables q_*, v_*, p_* (CONTRACT).  Without
/// `dense`, only the names (no n×n and 3n×3n matrices: for the graph route on large circuits).
CaseFile netlist_case(const Netlist& n, bool dense = true);

/// The exponents of the circuit's dimensionless twin (dcad/units.hpp), from its L and C values (exact
/// log10, any magnitude).
Units units_of(const Netlist& n);
/// The dimensionless twin, exactly: every L / L0, C / C0, R / R0 and mutual inductance / L0 (both the
/// LC `circuit` and the `rlc` elements).  The same graph, tower and sources; values near 1.
Netlist dimensionless(const Netlist& n, const Units& u);

}  // namespace dcad::io
