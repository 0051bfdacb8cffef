// Theorem 3.28 and Theorem 7.4 (CEF §3.4, §7): with second class constraints adapted to the
// primary ones, the Dirac bracket and the abridged total energy give the equations of motion.
#include "support/gen.hpp"

#include "dcad/reference/adapted.hpp"

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
  const ConstrainedSystem<Q> s = any_constrained_system();
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
  const ConstrainedSystem<Q> s = any_constrained_system();
  const Index n = s.omega.rows();
  const Index nleaf = *rc::gen::inRange<Index>(0, 3);
  QM leaf = hstack(integer_matrix(nleaf, n, 2), QM(nleaf, 1));  // φ_leaf(x) = c·x, level sets C
  QM both = vstack(s.primary, leaf);
  if (rank(gradients(both)) != both.rows()) return;  // defined regularly
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
