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

// CEF Lemma 6.5 on random circuits with signed values and empty branches: (b) condition (*) gives Δ_1 = Δ_2 —
// the direction its proof proves; the converse it calls easily verified fails (Lemma6_5_ConverseFails) —; (c) (*)
// and M_4 = M_5 give M_3 = M_4 (closed forms, which equal the CAD's M_k: CircuitClosedForm.EqualsGenericCad).
// Theorem 6.6: with L > 0 or a finite C > 0 on every branch, (*) holds.
RC_GTEST_PROP(Circuit, Lemma6_5_ConditionStar, ()) {
  const Circuit<Q> c = random_circuit(true, true);
  const bool star = condition_star(c);
  RC_CLASSIFY(!star, "condition (*) fails");
  if (star) RC_ASSERT(delta_k(c, 1) == delta_k(c, 2));
  if (star && closed_form_m(c, 4) == closed_form_m(c, 5)) RC_ASSERT(closed_form_m(c, 3) == closed_form_m(c, 4));
  RC_ASSERT(condition_star(random_circuit(false, false)));
}

// CEF Lemma 6.5 (b) says Δ_1 = Δ_2 is equivalent to condition (*); its proof shows (*) ⇒ Δ_1 = Δ_2 and calls the
// converse easily verified.  It fails: Lemma6_5_ConditionStar's shrunk counterexample (seed 439678990,
// cases/regression-lemma-6-5b-converse.cir) — L 1 on node 0 with a wire beside it, and across nodes 1–0 C 1, L −1,
// L 1, C −1 — has Δ_1 = Δ_2 (dim 3: v_C2 = v_C5 and v_L3 = −v_L4) while φ(Δ) ∌ e_L3 ⊄ φ(Δ_1) + Δ°, so (*) fails;
// its CAD still stops at M_3 (dims 18, 10, 9, 8): (*) is sufficient for that (Lemma 6.5 (c)), not necessary.
TEST(Circuit, Lemma6_5_ConverseFails) {
  Circuit<Q> c;
  c.nodes = 2;
  c.branches = {{"L1", BranchKind::inductor, 0, -1, Q(1)},  {"C2", BranchKind::capacitor, 1, 0, Q(1)},
                {"L3", BranchKind::inductor, 1, 0, Q(-1)},  {"L4", BranchKind::inductor, 1, 0, Q(1)},
                {"C5", BranchKind::capacitor, 0, 1, Q(-1)}, {"W6", BranchKind::empty, 0, -1, Q(0)}};
  EXPECT_EQ(delta_k(c, 1), delta_k(c, 2));
  EXPECT_EQ(delta_k(c, 1).dim(), 3u);
  EXPECT_FALSE(condition_star(c));
  EXPECT_EQ(cad(c).steps, 3);
}

// Remark 6.7's circuit (L, C and −C in parallel) and two capacitors 3 and −3 across one node pair with an
// inductor elsewhere: condition (*) fails, Δ_1 ≠ Δ_2, and the CAD runs past M_3 (to M_5) — Lemma 6.5 (b)
// where it bites.
TEST(Circuit, Lemma6_5_ConditionFailsPastM3) {
  for (const Circuit<Q>& c : {remark_6_7_circuit(), cancelling_capacitors_circuit()}) {
    EXPECT_FALSE(condition_star(c));
    EXPECT_FALSE(delta_k(c, 1) == delta_k(c, 2));
    EXPECT_EQ(cad(c).steps, 5);
  }
}

// CEF §6 after Theorem 6.8, for every physical circuit (empty branches too): the leaf x₀ + W̃_c is cut out of
// T*TE regularly by κ(q) = κ(q₀), η(ψq) = 0, p − φv = 0, κ(v) = 0, η(ψv) = 0, ν = 0 (independent rows, b =
// Theorem 6.4's KVLPC count), and the matrix of their brackets in dq∧dp + dv∧dν is the printed block form Σ,
// for any circuit; Σ is nondegenerate — every constraint second class, the leaf symplectic — exactly when
// there is no empty loop (Theorem 6.8).
RC_GTEST_PROP(Circuit, Section6_SigmaBlockForm, ()) {
  const Circuit<Q> c = random_circuit(true, false);
  const Index n = c.branches.size();
  const QM rows = leaf_equations(c, integer_vector(n));
  const QM a = gradients(rows);
  const QM sigma = a * poisson_tensor(cotangent_of_tangent_form<Q>(n)) * a.transpose();
  RC_TAG("b = " + std::to_string(kvlpc_loops(c).cols()) + ", empty loops " + std::to_string(empty_loop_count(c)));
  RC_ASSERT(kvlpc_loops(c).cols() == kvlpc_count(c));
  RC_ASSERT(rank(a) == a.rows());
  RC_ASSERT(sigma == leaf_sigma_block_form(c));
  RC_ASSERT((rank(sigma) == sigma.rows()) == (empty_loop_count(c) == 0));
}
