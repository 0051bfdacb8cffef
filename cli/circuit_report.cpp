#include "circuit_report.hpp"

#include <sstream>

namespace dcad::cli {

namespace {

using reference::BranchKind;

/// codim M_2 in M_1: the KVLPC equations that constrain q (CONTRACT `pc_loops`, CEF Thm 6.4).
long pc_loops(const SolveReport& r) { return r.consistent && r.dims.size() > 2 ? r.dims[1] - r.dims[2] : 0; }

bool physical(const io::Netlist& n) {
  for (const auto& b : n.circuit.branches)
    if (b.value < 0) return false;
  return true;
}

bool has_empty_branch(const io::Netlist& n) {
  for (const auto& b : n.circuit.branches)
    if (b.kind == BranchKind::empty) return true;
  return false;
}

}  // namespace

nlohmann::json circuit_json(const io::Netlist& n, const SolveReport& r) {
  return {{"branches", n.circuit.branches.size()},
          {"nodes", n.circuit.nodes + 1},
          {"pc_loops", pc_loops(r)},
          {"empty_loops", reference::empty_loop_count(n.circuit)},
          {"kvlpc_graph", reference::kvlpc_count(n.circuit)},
          {"physical", physical(n)}};
}

std::string circuit_text(const io::Netlist& n, const SolveReport& r) {
  std::ostringstream o;
  o << "  circuit \"" << n.title << "\": " << n.circuit.branches.size() << " branches, " << n.circuit.nodes + 1
    << " nodes (ground included)\n    branches:";
  for (const auto& b : n.circuit.branches)
    o << " " << b.name << (b.kind == BranchKind::inductor ? " (inductive)" : b.kind == BranchKind::capacitor ? " (capacitive)" : " (empty)");
  o << "\n    purely capacitive loops: " << pc_loops(r) << " independent KVLPC equation(s) on q (the M_2 constraints, CEF Thm 6.4)"
    << "; graph count " << reference::kvlpc_count(n.circuit) << "\n";
  const std::size_t empty = reference::empty_loop_count(n.circuit);
  o << "    empty loops: " << empty << (empty ? " (their loop currents are free: non-uniqueness, CEF Thm 6.8)" : "") << "\n";
  if (physical(n) && !has_empty_branch(n))
    o << "    CEF Thm 6.6 (L, C > 0, no empty branch): c ∈ {1, 3}, c = 3 iff a purely capacitive loop exists — here c = " << r.steps << "\n";
  if (physical(n))
    o << "    CEF Thm 6.8 (L ≥ 0, C > 0): the leaves x + W_c are symplectic iff there are no empty loops — here "
      << (empty ? "not symplectic" : "symplectic") << "\n";
  else
    o << "    negative L or C: not physical (CEF Remark 6.7), no theorem bounds c\n";
  for (const std::string& w : n.warnings) o << "    warning: " << w << "\n";
  return o.str();
}

}  // namespace dcad::cli
