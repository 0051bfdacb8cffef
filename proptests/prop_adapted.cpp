// Theorem 3.28 and Theorem 7.4 (CEF §3.4, §7): with second class constraints adapted to the
// primary ones, the Dirac bracket and the abridged total energy give the equations of motion.
#include "support/gen.hpp"

#include "dcad/reference/adapted.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {

/// Ω(X, δx) = dE(x)(δx) for every δx in `tangent` (a subspace): Gotay–Nester's (3.18) / (7.7).
bool solves(const QM& w, const QM& h, const std::vector<Q>& g, const std::vector<Q>& x, const std::vector<Q>& xdot,
            const Subspace<Q>& tangent) {
  std::vector<Q> de = (h * QM::column(x)).col(0);
  for (Index i = 0; i < de.size(); ++i) de[i] += g[i];
  for (Index r = 0; r < tangent.dim(); ++r)
    if (form_value(w, xdot, tangent.basis().row(r)) != dot(de, tangent.basis().row(r))) return false;
  return true;
}

/// The λ parametrise all solutions, one direction each: the differences X(e_i) − X(0) are
/// independent and span {Y ∈ T : Ω(Y, δx) = 0 ∀ δx ∈ tangent'} — the solution directions of (3.18)
/// / (7.7) computed from the definition, not from the adapted constraints.
template <class Field>
bool parametrises_all(const Field& field, Index multipliers, const QM& w, const Subspace<Q>& t,
                      const Subspace<Q>& tangent) {
  const std::vector<Q> x0 = field(std::vector<Q>(multipliers, Q(0)));
  QM diffs(multipliers, w.rows());
  for (Index i = 0; i < multipliers; ++i) {
    std::vector<Q> e(multipliers, Q(0));
    e[i] = Q(1);
    const std::vector<Q> xi = field(e);
    for (Index j = 0; j < w.rows(); ++j) diffs(i, j) = xi[j] - x0[j];
  }
  const Subspace<Q> directions = intersection(t, Subspace<Q>::solutions(tangent.basis() * w.transpose()));
  return rank(diffs) == multipliers && Subspace<Q>::span(diffs) == directions;
}

}  // namespace

// Thm 3.28 (one leaf): for x ∈ S = M_c and every λ, X_(χ),E_AT(x) is tangent to S and solves (3.18)
// for δx ∈ T S' (S' = M primary), and the λ give every solution, each once (parametrises_all);
// a' − s' = d^(c) (Remark 3.30); first class X_ψ ∈ ker ω_c.  Killed by: an abridged field that
// drops a multiplier's term (then λ misses solutions).
RC_GTEST_PROP(Adapted, Theorem3_28, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  std::vector<bool> primary(db.constraints.rows(), false);
  for (Index i = 0; i < s.primary.rows(); ++i) primary[i] = true;  // dirac_bergmann keeps the primary rows first
  const AdaptedConstraints<Q> ad = adapted_constraints(s.omega, db.constraints, primary);
  const CadResult<Q> gn = gotay_nester(s);
  RC_TAG("a' - s' = " + std::to_string(s.primary.rows() - ad.s_prime));
  RC_ASSERT(s.primary.rows() - ad.s_prime == gn.solution_rank);
  const std::vector<Q> x = some_point(db.tower.back());
  const std::vector<Q> lambda = integer_vector(ad.abridged.size());
  const std::vector<Q> xdot = abridged_field(ad, db.constraints, s.hessian, s.gradient, x, lambda);
  const Subspace<Q>& ts = db.tower.back().direction;
  RC_ASSERT(contains(ts, xdot));
  RC_ASSERT(solves(s.omega, s.hessian, s.gradient, x, xdot, kernel(gradients(s.primary))));
  const auto field = [&](const std::vector<Q>& l) {
    return abridged_field(ad, db.constraints, s.hessian, s.gradient, x, l);
  };
  RC_ASSERT(parametrises_all(field, ad.abridged.size(), s.omega, ts, kernel(gradients(s.primary))));
  // Lemma 3.23 / Remark 3.30: the Hamiltonian fields of first class constraints span ker ω_c
  const ConstraintClasses<Q> cl = classify_constraints(s.omega, db.constraints);
  const QM fields = gradients(cl.first) * poisson_tensor(s.omega).transpose();  // rows (J a_ψ)ᵀ
  RC_ASSERT(Subspace<Q>::span(fields) == form_kernel(restrict_form(s.omega, ts)));
}

// Thm 7.4 (foliated): S' = {primary = 0} foliated by leaves S'_C = S' ∩ {leaf constraints = C}, D on S'
// with presymplectic leaves (S'_C, Ω|), S = M_c of the CAD.  With χ adapted to S'_0 and E_AT for
// S_0 (leaf constraints counted as primary), X_(χ),E_AT at any x ∈ S is tangent to the leaf S_C
// through x and solves (7.7) there, for every λ.
RC_GTEST_PROP(Adapted, Theorem7_4_Foliated, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const QM leaf = any_leaf_functions(s);
  if (leaf.rows() == 0 && leaf.cols() == 0) return;  // not defined regularly
  const QM both = vstack(s.primary, leaf);
  const Index nleaf = leaf.rows();
  // the CAD of D_{(T S'_C, Ω)} on M_0 = S'
  const CadResult<Q> r = foliated_tower(FoliatedEmbedding<Q>{s.omega, s.hessian, s.gradient, s.primary, leaf});
  if (!r.consistent) return;
  RC_TAG("leaves: " + std::to_string(nleaf));
  // constraints of S_0 in the paper's order: primary, secondary, leaf (primary flags on 1 and 3)
  const AdaptedToPrimary<Q> to = adapted_to_primary(s.omega, s.primary, secondary_constraints(r), leaf);
  const QM& all = to.constraints;
  const AdaptedConstraints<Q>& ad = to.adapted;
  const std::vector<Q> x = some_point(r.final_step().m);  // any leaf: C = leaf(x)
  const std::vector<Q> lambda = integer_vector(ad.abridged.size());
  const std::vector<Q> xdot = abridged_field(ad, all, s.hessian, s.gradient, x, lambda);
  const Subspace<Q> ts_c = intersection(r.final_step().m.direction, kernel(gradients(leaf)));  // T S_C
  RC_ASSERT(contains(ts_c, xdot));
  RC_ASSERT(solves(s.omega, s.hessian, s.gradient, x, xdot, kernel(gradients(both))));  // δx ∈ T S'_C
  const auto field = [&](const std::vector<Q>& l) { return abridged_field(ad, all, s.hessian, s.gradient, x, l); };
  RC_ASSERT(parametrises_all(field, ad.abridged.size(), s.omega, ts_c, kernel(gradients(both))));
  RC_ASSERT(ad.abridged.size() == r.solution_rank);  // a' − s' = d^(c) on the leaves
}

// CEF §7 after (7.7), (7.8), Remark 7.3 and the extended Poisson manifold, on random foliated systems: at
// x ∈ S (any leaf, C = φ_leaf(x)) Λ_x is nonempty; for λ ∈ Λ_x the field (7.8) J (dE + λ^i dφ_i) is tangent
// to S_C and solves (7.7) on the leaf (Ω(X, δx) = dE(δx) for δx ∈ T S'_C); every solution X of (7.7) (the
// CAD's velocities) is J (dE + λ^i dφ_i) for exactly one λ, which lies in Λ_x (Remark 7.3); and the
// Hamiltonian field of E_{λ̃,T} on the extended Poisson manifold at (x, C) on the graph of C is (X, 0) for
// any derivative of the section, tangent to that graph (the motion preserves it).
RC_GTEST_PROP(Adapted, Section7_FoliatedMultipliersAndExtendedField, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const QM leaf = any_leaf_functions(s);
  if (leaf.rows() == 0 && leaf.cols() == 0) return;
  const FoliatedEmbedding<Q> f{s.omega, s.hessian, s.gradient, s.primary, leaf};
  const CadResult<Q> r = foliated_tower(f);
  if (!r.consistent) return;
  const Index n = s.omega.rows();
  const QM secondary = secondary_constraints(r);
  const std::vector<Q> x = some_point(r.final_step().m);
  const AffineSubspace<Q> lambda = foliated_multipliers(f, secondary, x);
  RC_ASSERT(!lambda.empty);
  RC_TAG("leaves: " + std::to_string(leaf.rows()) + ", dim Lambda: " + std::to_string(lambda.direction.dim()));
  const QM both = vstack(s.primary, leaf);
  const Subspace<Q> ts_c = intersection(r.final_step().m.direction, kernel(gradients(leaf)));
  const std::vector<Q> l = some_point(lambda);
  const std::vector<Q> field = foliated_field(f, x, l);
  RC_ASSERT(contains(ts_c, field));                                                      // (7.8): S_C preserved
  RC_ASSERT(solves(s.omega, s.hessian, s.gradient, x, field, kernel(gradients(both))));  // (7.7)
  const AffineSubspace<Q> xdots = velocities(foliated_system(f), r, x);
  const std::vector<Q> xdot = some_point(xdots);
  const QM jmult = poisson_tensor(s.omega) * gradients(both).transpose();
  std::vector<Q> rest = xdot, de = foliated_field(f, x, std::vector<Q>(both.rows(), Q(0)));
  for (Index i = 0; i < n; ++i) rest[i] -= de[i];
  const AffineSubspace<Q> unique = solve(jmult, rest);  // Remark 7.3
  RC_ASSERT(!unique.empty && unique.direction.dim() == 0u);
  RC_ASSERT(lambda.contains_point(unique.point));
  std::vector<Q> c(leaf.rows());
  for (Index k = 0; k < leaf.rows(); ++k) c[k] = dot(gradients(leaf).row(k), x) - leaf(k, n);
  const std::vector<Q> ext = extended_hamiltonian_field(f, x, c, l, integer_matrix(both.rows(), n));
  std::vector<Q> expected = field;
  expected.resize(n + leaf.rows(), Q(0));
  RC_ASSERT(ext == expected);
  RC_ASSERT((hstack(gradients(leaf), -QM::identity(leaf.rows())) * QM::column(ext)).is_zero());  // d(φ − C)(X) = 0
}

// CEF Remark 7.5: Dirac's equation ġ ≈ {g, H_T}* with the total Hamiltonian of the primary constraints alone
// is not the motion of a foliated system.  P = R², Ω = dq ∧ dp, E = (q² + p²)/2, no primary constraint, leaves
// p = C: (7.7) on each leaf gives the secondary q = 0, S_C = {(0, C)}, and Λ_x = {λ = −p}, so the motion is
// rest, X = (p + λ, −q) = 0.  Dirac's algorithm on (P, Ω, E, P) finds no constraint and H_T = E: its field
// (p, −q) = (C, 0) at (0, C) leaves S_C for every C ≠ 0.
TEST(Adapted, Remark7_5_DiracsEquationIsWrongWhenFoliated) {
  const QM w = QM::from_rows({{Q(0), Q(1)}, {Q(-1), Q(0)}}, 2);
  const QM h = QM::identity(2);
  const FoliatedEmbedding<Q> f{w, h, {Q(0), Q(0)}, QM(0, 3), QM::from_rows({{Q(0), Q(1), Q(0)}}, 3)};
  const CadResult<Q> r = foliated_tower(f);
  ASSERT_TRUE(r.consistent);
  ASSERT_EQ(r.final_step().m.direction.dim(), 1u);  // S = {q = 0}, foliated by the points (0, C)
  const std::vector<Q> x{Q(0), Q(3)};
  const AffineSubspace<Q> lambda = foliated_multipliers(f, secondary_constraints(r), x);
  ASSERT_FALSE(lambda.empty);
  EXPECT_EQ(lambda.point, std::vector<Q>{Q(-3)});
  EXPECT_EQ(foliated_field(f, x, lambda.point), (std::vector<Q>{Q(0), Q(0)}));
  const ConstrainedSystem<Q> unfoliated{w, h, {Q(0), Q(0)}, QM(0, 3)};
  const DiracBergmannResult<Q> db = dirac_bergmann(unfoliated);
  EXPECT_EQ(db.tower.back().direction.dim(), 2u);  // Dirac: no constraint at all
  const std::vector<Q> dirac = total_energy_field(unfoliated, x, {});
  EXPECT_EQ(dirac, (std::vector<Q>{Q(3), Q(0)}));  // not tangent to S_C = {(0, 3)}
}
