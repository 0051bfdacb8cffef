// Two further routes to the tower of an LC circuit, each equal to the generic CAD (CEF §5) on the
// circuit's `pontryagin` system: the closed form of CEF §6 via Δ_k (reference, exact), and the
// graph route of dcad::fast::circuit_tower (forests and fundamental loops; loop coordinates for
// signed values).
#include "support/case_json.hpp"
#include "support/circuit_gen.hpp"
#include "support/convert.hpp"
#include "support/tally.hpp"

#include "dcad/fast/cad.hpp"
#include "dcad/fast/circuit.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

namespace {

ref::CadResult<Q> generic(const Circuit<Q>& c) {
  return ref::constraint_tower(ref::pontryagin_system(ref::circuit_lagrangian(c)));
}

/// Every equation of the graph route up to M_k vanishes on the exact M_k (relative 1e-12).
bool rows_vanish_on(const fast::CircuitTower& t, std::size_t k, const QSub& m) {
  const Eigen::MatrixXd basis = to_double(m.basis());
  for (std::size_t j = 1; j <= k; ++j)
    for (const fast::SparseRow& row : t.equations[j]) {
      double big = 0;
      for (const fast::Term& term : row) big = std::max(big, std::abs(term.coeff));
      for (Eigen::Index i = 0; i < basis.rows(); ++i) {
        double s = 0, size = 0;
        for (const fast::Term& term : row) {
          s += term.coeff * basis(i, static_cast<Eigen::Index>(term.var));
          size += std::abs(term.coeff * basis(i, static_cast<Eigen::Index>(term.var)));
        }
        if (std::abs(s) > 1e-12 * std::max(size, big)) return false;
      }
    }
  return true;
}

/// The graph route's M_k equals the exact one: same dimension and its equations vanish there.
void check_against_generic(const Circuit<Q>& c, const std::string& family) {
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const ref::CadResult<Q> r = generic(c);
  const fast::CircuitTower t = fast::circuit_tower(fast_graph(c));
  RC_CLASSIFY(t.physical, "physical route");
  RC_TAG("c = " + std::to_string(r.steps));
  bool same_dims = t.dims.size() == r.tower.size();
  for (std::size_t k = 0; same_dims && k < t.dims.size(); ++k) same_dims = t.dims[k] == r.tower[k].dim();
  if (t.physical) RC_ASSERT(t.certain.yes());  // combinatorial: nothing to be uncertain about
  RC_ASSERT(!tally(family + ": dims of M_k", t.certain.yes(), same_dims));
  RC_ASSERT(!tally(family + ": solution rank", t.certain.yes(), t.solution_rank == static_cast<long>(r.solution_rank)));
  if (!same_dims) return;
  for (std::size_t k = 1; k < t.dims.size(); ++k)
    RC_ASSERT(!tally(family + ": M_k equations", t.certain.yes(), rows_vanish_on(t, k, r.tower[k].m.direction)));
}

}  // namespace

// CEF §6 (after (6.24)): the closed form of M_j via Δ_k equals the CAD's M_j for j = 1 … c + 1
// (M_{c+1} = M_c), on random circuits with signed values and empty branches — every case of §6.
RC_GTEST_PROP(CircuitClosedForm, EqualsGenericCad, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  RC_LOG() << "nodes " << c.nodes
           << "; branches {kind (0 L, 1 C, 2 empty), from, to, value}: ";  // a falsified circuit, to keep as a test
  for (const auto& b : c.branches)
    RC_LOG() << "{" << static_cast<int>(b.kind) << ", " << b.from << ", " << b.to << ", Q(\"" << b.value << "\")} ";
  const ref::CadResult<Q> r = generic(c);
  RC_TAG("c = " + std::to_string(r.steps));
  for (Index j = 1; j <= r.steps + 1; ++j)
    RC_ASSERT(ref::closed_form_m(c, j) == r.tower[std::min(j, r.steps)].m.direction);
}

// The shrunk circuit on which the closed form's odd M_{2k−1} needs v ∈ Δ_{k−1}, not a later Δ: two
// capacitors 3 and −3 across one node pair (the elastances cancel), an inductor alone on another node
// and an empty branch — a tower of length 5 (0.4 % of random circuits, so 200 cases rarely meet one).
// Killed by: Δ_{k+1} in place of Δ_{k−1} (a mutation survivor; the property above finds it after ~1400
// cases).
TEST(CircuitClosedForm, CancellingCapacitorsTowerOfFive) {
  const Circuit<Q> c = cancelling_capacitors_circuit();
  const ref::CadResult<Q> r = generic(c);
  EXPECT_EQ(r.steps, 5);
  for (Index j = 1; j <= r.steps + 1; ++j)
    EXPECT_TRUE(ref::closed_form_m(c, j) == r.tower[std::min(j, r.steps)].m.direction) << j;
}

// The graph route = the generic exact CAD: physical circuits (L, C > 0, empty branches) by
// Theorems 6.4, 6.6, 6.8 and forests; signed values by loop coordinates.
RC_GTEST_PROP(CircuitGraphRoute, PhysicalEqualsGenericCad, ()) {
  check_against_generic(random_circuit(true, false), "physical");
}

RC_GTEST_PROP(CircuitGraphRoute, SignedEqualsGenericCad, ()) {
  check_against_generic(random_circuit(true, true), "signed");
}

// The loops the report names are loops: each loop current satisfies KCL (K η = 0, so η ∈ Δ); purely
// capacitive loops have a capacitor and no inductor; empty loops only empty branches; their counts
// are the cycle-rank counts (CONTRACT `empty_loops`, Thm 6.4's KVLPC count).
RC_GTEST_PROP(CircuitGraphRoute, LoopsAreLoops, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  const fast::CircuitTower t = fast::circuit_tower(fast_graph(c));
  const QM k = ref::kcl_matrix(c);
  const auto check = [&](const fast::Loop& loop, bool pc) {
    std::vector<Q> eta(c.branches.size(), Q(0));
    bool capacitor = false;
    for (const fast::LoopBranch& lb : loop) {
      eta[lb.branch] += Q(lb.sign);
      const BranchKind kind = c.branches[lb.branch].kind;
      RC_ASSERT(kind != BranchKind::inductor);
      if (!pc) RC_ASSERT(kind == BranchKind::empty);
      capacitor = capacitor || kind == BranchKind::capacitor;
    }
    RC_ASSERT(capacitor == pc);
    for (Index i = 0; i < k.rows(); ++i) {
      Q s(0);
      for (Index b = 0; b < k.cols(); ++b) s += k(i, b) * eta[b];
      RC_ASSERT(s == Q(0));
    }
  };
  for (const fast::Loop& l : t.pc_loops) check(l, true);
  for (const fast::Loop& l : t.empty_loops) check(l, false);
  RC_ASSERT(static_cast<Index>(t.pc_loops.size()) == ref::kvlpc_count(c));
  RC_ASSERT(static_cast<Index>(t.empty_loops.size()) == ref::empty_loop_count(c));
}

// The graph route = the generic fast CAD on the same doubles, wherever both are certain.
RC_GTEST_PROP(CircuitGraphRoute, EqualsGenericFastCad, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  const ref::PontryaginInput<Q> in = ref::circuit_lagrangian(c);
  fast::Options opt;
  const fast::LinearSystem s =
      fast::pontryagin_system({in.n, to_double(in.k, &opt), to_double(in.vv, &opt), to_double(in.qv, &opt),
                               to_double(in.qq, &opt), to_double(in.q), to_double(in.v)},
                              opt);
  const fast::CadResult f = fast::constraint_tower(s, opt);
  const fast::CircuitTower t = fast::circuit_tower(fast_graph(c));
  const bool certain = f.certain.yes() && t.certain.yes();
  bool same = f.tower.size() == t.dims.size() && f.solution_rank == t.solution_rank;
  for (std::size_t k = 0; same && k < t.dims.size(); ++k) same = f.tower[k].dim() == t.dims[k];
  RC_ASSERT(!tally("graph vs generic fast: tower and solution rank", certain, same));
}

// CEF Lemma 6.5's condition (*) by both twins on random circuits with signed values: fast's verdict (Theorem
// 6.6's route: P_Δ φ|_Δ and P_Δ ψ|_Δ in an orthonormal loop basis) is the reference's (φ(Δ) ⊆ φ(Δ_1) + Δ°)
// unless fast is uncertain; on physical circuits (Theorem 6.6) it holds.
RC_GTEST_PROP(CircuitGraphRoute, ConditionStar, ()) {
  const Circuit<Q> c = random_circuit(true, true);
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const Truth star = fast::condition_star(fast_graph(c));
  RC_ASSERT(!tally("condition (*)", star != unknown, star.yes() == ref::condition_star(c)));
  RC_ASSERT(fast::condition_star(fast_graph(random_circuit(false, false))) != no);
}

// The two circuits where condition (*) fails (Lemma6_5_ConditionFailsPastM3): fast says no, never yes.
TEST(CircuitGraphRoute, ConditionStarFailsPastM3) {
  EXPECT_TRUE(fast::condition_star(fast_graph(remark_6_7_circuit())) == no);
  EXPECT_TRUE(fast::condition_star(fast_graph(cancelling_capacitors_circuit())) == no);
}

// CEF §6 after Theorem 6.8 by both twins: fast's Σ (the brackets of its own leaf equations, the graph's
// purely capacitive loops) has the reference's size and is nondegenerate exactly when the reference's
// block form is (all constraints second class), unless fast is uncertain.
RC_GTEST_PROP(CircuitGraphRoute, LeafSecondClass, ()) {
  const Circuit<Q> c = random_circuit(true, false);
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const fast::LeafBrackets f = fast::leaf_brackets(fast_graph(c));
  const QM sigma = ref::leaf_sigma_block_form(c);
  RC_ASSERT(f.sigma.rows() == static_cast<Eigen::Index>(sigma.rows()));
  RC_ASSERT(!tally("leaf all second class", f.second_class != unknown,
                   f.second_class.yes() == (ref::rank(sigma) == sigma.rows())));
}
