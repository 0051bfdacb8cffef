// LC circuits on random connected multigraphs (CEF §6): Theorems 6.4, 6.6, 6.8 and the graph counts.
#include "support/gen.hpp"

#include "support/circuit_gen.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {

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
