#include "circuit_report.hpp"

#include "dcad/graph.hpp"

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

/// The fundamental loops of the non-inductive subgraph (forest through the empty branches first):
/// purely capacitive (first) and empty (second), each as signed branch names.  Graph facts only.
std::pair<std::vector<std::vector<std::string>>, std::vector<std::vector<std::string>>> named_loops(const io::Netlist& n) {
  std::vector<graph::Edge> edges;
  std::vector<bool> keep, prefer;
  for (const auto& b : n.circuit.branches) {
    edges.push_back({b.from, b.to});
    keep.push_back(b.kind != BranchKind::inductor);
    prefer.push_back(b.kind == BranchKind::empty);
  }
  std::pair<std::vector<std::vector<std::string>>, std::vector<std::vector<std::string>>> out;
  for (const graph::Loop& l : graph::fundamental_loops(n.circuit.nodes, edges, keep, prefer)) {
    std::vector<std::string> names;
    for (const graph::LoopBranch& lb : l) names.push_back((lb.sign > 0 ? "+" : "-") + n.circuit.branches[lb.branch].name);
    (n.circuit.branches[l.front().branch].kind == BranchKind::capacitor ? out.first : out.second).push_back(names);
  }
  return out;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& x : names) s += (s.empty() ? "" : " ") + x;
  return s;
}

}  // namespace

nlohmann::json circuit_json(const io::Netlist& n, const SolveReport& r) {
  return {{"branches", n.circuit.branches.size()},
          {"nodes", n.circuit.nodes + 1},
          {"pc_loops", pc_loops(r)},
          {"empty_loops", reference::empty_loop_count(n.circuit)},
          {"kvlpc_graph", reference::kvlpc_count(n.circuit)},
          {"physical", physical(n)},
          {"pc_loop_branches", named_loops(n).first},
          {"empty_loop_branches", named_loops(n).second}};
}

std::string circuit_text(const io::Netlist& n, const SolveReport& r) {
  std::ostringstream o;
  o << "  circuit \"" << n.title << "\": " << n.circuit.branches.size() << " branches, " << n.circuit.nodes + 1
    << " nodes (ground included)\n    branches:";
  for (const auto& b : n.circuit.branches)
    o << " " << b.name << (b.kind == BranchKind::inductor ? " (inductive)" : b.kind == BranchKind::capacitor ? " (capacitive)" : " (empty)");
  o << "\n    purely capacitive loops: " << pc_loops(r) << " independent KVLPC equation(s) on q (the M_2 constraints, CEF Thm 6.4)"
    << "; graph count " << reference::kvlpc_count(n.circuit) << "\n";
  const auto [pc, empty_loops] = named_loops(n);
  for (std::size_t i = 0; i < pc.size(); ++i)
    o << "      KVL loop " << i + 1 << ": " << joined(pc[i]) << "  (sum of ±q/C over its capacitors = 0 on M_2, ±v/C on M_3)\n";
  const std::size_t empty = reference::empty_loop_count(n.circuit);
  o << "    empty loops: " << empty << (empty ? " (their loop currents are free: non-uniqueness, CEF Thm 6.8)" : "") << "\n";
  for (std::size_t i = 0; i < empty_loops.size(); ++i) o << "      empty loop " << i + 1 << ": " << joined(empty_loops[i]) << "\n";
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
