// LC circuits on random connected multigraphs (CEF §6): Theorems 6.4, 6.6, 6.8 and the graph counts.
#include "support/gen.hpp"

#include "dcad/reference/circuit.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {

/// A connected multigraph on `nodes` + ground: a random spanning tree, then extra (possibly parallel)
/// branches.  Kinds: inductor, capacitor or (if `empty`) empty; values L ∈ {1, 2, 3}, C ∈ {1/2, 1, 2, 3},
/// with random signs if `signed_values`.
Circuit<Q> random_circuit(bool empty, bool signed_values) {
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
    if (*rc::gen::arbitrary<bool>()) c.branches.push_back(Branch<Q>{"W" + std::to_string(c.branches.size() + 1), BranchKind::empty, base.to, base.from, Q(0)});
  }
  return c;
}

CadResult<Q> cad(const Circuit<Q>& c) { return constraint_tower(pontryagin_system(circuit_lagrangian(c))); }

}  // namespace

// Thm 6.6 (every branch has L > 0 or finite C > 0): the CAD stops at M_1 or M_3, and at M_3 iff there
// is a purely capacitive loop; Thm 6.4: codim M_2 in M_1 = the number of independent KVLPC equations.
RC_GTEST_PROP(Circuit, Theorems6_4_6_6, ()) {
  const Circuit<Q> c = random_circuit(false, false);
  const CadResult<Q> r = cad(c);
  const Index pc = kvlpc_count(c);
  RC_TAG("c = " + std::to_string(r.steps));
  RC_ASSERT(r.consistent);
  RC_ASSERT(r.steps == 1u || r.steps == 3u);
  RC_ASSERT((r.steps == 3) == (pc > 0));
  const long codim = r.steps >= 2 ? r.tower[1].dim() - r.tower[2].dim() : 0;
  RC_ASSERT(codim == static_cast<long>(pc));
}

// With empty branches (L ≥ 0, C ∈ (0, ∞]): still c ∈ {1, 3} and c = 3 iff a purely capacitive loop;
// Thm 6.4's count; Thm 6.8: the leaves x + W_c are symplectic iff there are no empty loops, and the
// solution rank is the number of independent empty loops.
RC_GTEST_PROP(Circuit, Theorem6_8_EmptyBranches, ()) {
  const Circuit<Q> c = random_circuit(true, false);
  const CadResult<Q> r = cad(c);
  const Index pc = kvlpc_count(c), empty = empty_loop_count(c);
  RC_TAG("c = " + std::to_string(r.steps));
  RC_CLASSIFY(empty > 0, "empty loops");
  RC_ASSERT(r.consistent);
  RC_ASSERT(r.steps == 1u || r.steps == 3u);
  RC_ASSERT((r.steps == 3) == (pc > 0));
  const long codim = r.steps >= 2 ? r.tower[1].dim() - r.tower[2].dim() : 0;
  RC_ASSERT(codim == static_cast<long>(pc));
  const LinearSystem<Q> s = pontryagin_system(circuit_lagrangian(c));
  const bool symplectic = form_kernel(restrict_form(dirac_form(s.d), r.final_step().w)).dim() == 0;
  RC_ASSERT(symplectic == (empty == 0));
  RC_ASSERT(r.solution_rank == empty);
}

// Signed values (CEF Remark 6.7): no theorem bounds c, but the tower is a consistent, strictly
// decreasing chain with c ≤ 3n, and empty loops still give exactly that much non-uniqueness.
RC_GTEST_PROP(Circuit, SignedValues, ()) {
  const Circuit<Q> c = random_circuit(true, true);
  const CadResult<Q> r = cad(c);
  RC_TAG("c = " + std::to_string(r.steps));
  RC_ASSERT(r.consistent);  // x = 0 is always a solution of the homogeneous system
  RC_ASSERT(r.steps <= 3 * c.branches.size());
  for (Index k = 1; k < r.tower.size(); ++k) RC_ASSERT(r.tower[k].dim() < r.tower[k - 1].dim());
}
