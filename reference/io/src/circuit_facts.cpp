#include "dcad/graph.hpp"
#include "dcad/io/netlist.hpp"

#include <algorithm>
#include <functional>

namespace dcad::io {

namespace {

using reference::BranchKind;
using reference::RlcKind;

template <class Branches>
std::vector<graph::Edge> edges_of(const Branches& branches) {
  std::vector<graph::Edge> e;
  for (const auto& b : branches) e.push_back({b.from, b.to});
  return e;
}

template <class Branches, class Kind>
std::vector<bool> which(const Branches& branches, const std::function<bool(Kind)>& kind) {
  std::vector<bool> out;
  for (const auto& b : branches) out.push_back(kind(b.kind));
  return out;
}

template <class Branches>
std::vector<std::string> signed_names(const Branches& branches, const graph::Loop& l) {
  std::vector<std::string> names;
  for (const graph::LoopBranch& lb : l) names.push_back((lb.sign > 0 ? "+" : "-") + branches[lb.branch].name);
  return names;
}

/// The LC deck's fundamental loops of the non-inductive subgraph (forest through the empty branches
/// first): purely capacitive (CEF Thm 6.4) and empty (Thm 6.8).
void lc_loops(const Netlist& n, CircuitFacts& f) {
  const auto& br = n.circuit.branches;
  const std::function<bool(BranchKind)> keep = [](BranchKind k) { return k != BranchKind::inductor; };
  const std::function<bool(BranchKind)> prefer = [](BranchKind k) { return k == BranchKind::empty; };
  for (const graph::Loop& l :
       graph::fundamental_loops(n.circuit.nodes, edges_of(br), which(br, keep), which(br, prefer)))
    (br[l.front().branch].kind == BranchKind::capacitor ? f.pc_loop_branches : f.empty_loop_branches)
        .push_back(signed_names(br, l));
}

std::function<bool(RlcKind)> is(std::initializer_list<RlcKind> ks) {
  const std::vector<RlcKind> kinds(ks);
  return [kinds](RlcKind k) { return std::find(kinds.begin(), kinds.end(), k) != kinds.end(); };
}

/// Loops of the subgraph `keep` through a branch of kind `through`, by a forest that takes `prefer` first.
std::vector<std::vector<std::string>> rlc_loops(const Netlist& n, const std::function<bool(RlcKind)>& keep,
                                                const std::function<bool(RlcKind)>& prefer, RlcKind through) {
  const auto& br = n.rlc.branches;
  std::vector<std::vector<std::string>> out;
  for (const graph::Loop& l : graph::fundamental_loops(n.rlc.nodes, edges_of(br), which(br, keep), which(br, prefer)))
    if (std::any_of(l.begin(), l.end(), [&](const graph::LoopBranch& b) { return br[b.branch].kind == through; }))
      out.push_back(signed_names(br, l));
  return out;
}

std::vector<std::vector<std::string>> rlc_cutsets(const Netlist& n, const std::function<bool(RlcKind)>& in,
                                                  const std::function<bool(RlcKind)>& must) {
  const auto& br = n.rlc.branches;
  std::vector<std::vector<std::string>> out;
  for (const graph::Cutset& c : graph::cutsets(n.rlc.nodes, edges_of(br), which(br, in), which(br, must)))
    out.push_back(signed_names(br, c));
  return out;
}

}  // namespace

CircuitFacts circuit_facts(const Netlist& n) {
  CircuitFacts f;
  f.forced = n.forced;
  if (n.forced) {
    f.branches = static_cast<long>(n.rlc.branches.size());
    f.nodes = static_cast<long>(n.rlc.nodes) + 1;
    const auto wire = is({RlcKind::wire});
    f.empty_loops =
        static_cast<long>(graph::cycle_rank(n.rlc.nodes, edges_of(n.rlc.branches), which(n.rlc.branches, wire)));
    for (const auto& b : n.rlc.branches) {
      long* count[] = {&f.inductors, &f.capacitors, &f.resistors, &f.voltage_sources, &f.current_sources, &f.wires};
      ++*count[static_cast<int>(b.kind)];
    }
    f.couplings = static_cast<long>(n.rlc.mutuals.size());
    f.cv_loops = rlc_loops(n, is({RlcKind::capacitor, RlcKind::voltage, RlcKind::wire}),
                           is({RlcKind::voltage, RlcKind::wire}), RlcKind::capacitor);
    f.source_loops = rlc_loops(n, is({RlcKind::voltage, RlcKind::wire}), wire, RlcKind::voltage);
    f.li_cutsets = rlc_cutsets(n, is({RlcKind::inductor, RlcKind::current}), is({RlcKind::inductor}));
    f.source_cutsets = rlc_cutsets(n, is({RlcKind::current}), is({RlcKind::current}));
    return f;
  }
  f.branches = static_cast<long>(n.circuit.branches.size());
  f.nodes = static_cast<long>(n.circuit.nodes) + 1;
  f.empty_loops = static_cast<long>(reference::empty_loop_count(n.circuit));
  f.kvlpc_graph = static_cast<long>(reference::kvlpc_count(n.circuit));
  if (!n.indefinite_inductance.empty()) f.physical = false;  // couplings that make Φ indefinite
  for (const auto& b : n.circuit.branches) {
    if (b.value < 0) f.physical = false;
    if (b.kind == BranchKind::empty) f.has_empty_branch = true;
    f.branch_names.push_back(b.name);
    f.branch_kinds.push_back(b.kind);
  }
  lc_loops(n, f);
  return f;
}

}  // namespace dcad::io
