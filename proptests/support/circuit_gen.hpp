// Random LC circuits for the properties (CEF §6): connected multigraphs with parallel branches.
#pragma once

#include "gen.hpp"

#include "dcad/fast/circuit.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/reference/circuit.hpp"

namespace dcad::test {

using reference::Branch;
using reference::BranchKind;
using reference::Circuit;

/// A connected multigraph on `nodes` + ground: a random spanning tree, then extra (possibly parallel)
/// branches.  Kinds: inductor, capacitor or (if `empty`) empty; values L ∈ {1, 2, 3}, C ∈ {1/2, 1, 2, 3},
/// with random signs if `signed_values`.
inline reference::Circuit<Q> random_circuit(bool empty, bool signed_values) {
  Circuit<Q> c;
  c.nodes = pick_size(1, 5);
  const auto branch = [&](long from, long to) {
    Branch<Q> b;
    b.name = "B" + std::to_string(c.branches.size() + 1);
    b.from = from;
    b.to = to;
    const int k = *rc::gen::inRange(0, empty ? 3 : 2);
    b.kind = k == 0 ? BranchKind::inductor : k == 1 ? BranchKind::capacitor : BranchKind::empty;
    if (b.kind == BranchKind::inductor) b.value = Q(*rc::gen::inRange(1, 4));
    if (b.kind == BranchKind::capacitor) b.value = *rc::gen::element(Q(1) / Q(2), Q(1), Q(2), Q(3));
    if (signed_values && *rc::gen::arbitrary<bool>()) b.value = -b.value;
    if (*rc::gen::arbitrary<bool>()) std::swap(b.from, b.to);
    c.branches.push_back(b);
  };
  for (long v = 0; v < static_cast<long>(c.nodes); ++v) branch(v, *rc::gen::inRange<long>(-1, v));  // tree to ground
  const int extra = *rc::gen::inRange(0, 6);
  for (int e = 0; e < extra; ++e) {
    const long u = *rc::gen::inRange<long>(-1, c.nodes), w = *rc::gen::inRange<long>(-1, c.nodes);
    if (u != w) branch(u, w);
  }
  if (empty && *rc::gen::inRange(0, 3) == 0) {  // a wire parallel to some branch: often an empty loop
    const Branch<Q> base = c.branches[*rc::gen::inRange<std::size_t>(0, c.branches.size())];
    Branch<Q> wire{"W" + std::to_string(c.branches.size() + 1), BranchKind::empty, base.from, base.to, Q(0)};
    c.branches.push_back(wire);
    if (*rc::gen::arbitrary<bool>())
      c.branches.push_back(
          Branch<Q>{"W" + std::to_string(c.branches.size() + 1), BranchKind::empty, base.to, base.from, Q(0)});
  }
  return c;
}

/// The same circuit for dcad::fast, its values rounded by fast::to_double_values (exact.hpp); with
/// `opt`, what their heights and spread leave certain is recorded there, as the CLI does.
inline fast::CircuitGraph fast_graph(const Circuit<Q>& c, fast::Options* opt = nullptr) {
  std::vector<Q> values;
  for (const Branch<Q>& b : c.branches) values.push_back(b.value);
  fast::Options ignored;
  const std::vector<double> d = fast::to_double_values(values, opt ? *opt : ignored);
  fast::CircuitGraph g;
  g.nodes = c.nodes;
  for (std::size_t i = 0; i < c.branches.size(); ++i)
    g.branches.push_back({c.branches[i].kind, c.branches[i].from, c.branches[i].to, d[i]});
  return g;
}

/// CEF Remark 6.7's circuit: an inductor, a capacitor C and a capacitor −C in parallel (the CAD stops at M_5).
inline reference::Circuit<Q> remark_6_7_circuit() {
  Circuit<Q> c;
  c.nodes = 1;
  c.branches = {{"L", BranchKind::inductor, 0, -1, Q(1)},
                {"C1", BranchKind::capacitor, 0, -1, Q(2)},
                {"C2", BranchKind::capacitor, 0, -1, Q(-2)}};
  return c;
}

/// Two capacitors 3 and −3 across one node pair (the elastances cancel), an inductor alone on another node
/// and an empty branch: a tower of length 5 (a shrunk counterexample of CircuitClosedForm.EqualsGenericCad).
inline reference::Circuit<Q> cancelling_capacitors_circuit() {
  Circuit<Q> c;
  c.nodes = 3;
  c.branches = {{"E", BranchKind::empty, 0, -1, Q(0)},
                {"L1", BranchKind::inductor, 1, -1, Q(1)},
                {"L2", BranchKind::inductor, 2, -1, Q(1)},
                {"C1", BranchKind::capacitor, 1, -1, Q(3)},
                {"C2", BranchKind::capacitor, -1, 1, Q(-3)}};
  return c;
}

}  // namespace dcad::test
