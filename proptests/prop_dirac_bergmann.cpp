// Dirac–Bergmann against Gotay–Nester, and first/second class constraints with the Dirac bracket,
// on random linear constrained Hamiltonian systems (N, Ω, E, M).  [CEF §2, Lemma 3.23]
#include "support/gen.hpp"

#include "dcad/reference/dirac_bergmann.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {}  // namespace

// §2: the Dirac–Bergmann and the Gotay–Nester algorithms produce the same M_k.
RC_GTEST_PROP(DiracBergmann, SameTowerAsGotayNester, ()) {
  const ConstrainedSystem<Q> s = any_constrained_system();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  const CadResult<Q> gn = gotay_nester(s);
  RC_CLASSIFY(!db.consistent, "inconsistent");
  RC_TAG("c = " + std::to_string(db.tower.size() - 1));
  RC_ASSERT(db.consistent == gn.consistent);
  RC_ASSERT(db.tower.size() == gn.tower.size());
  for (Index k = 0; k < db.tower.size(); ++k) RC_ASSERT(db.tower[k] == gn.tower[k].m);
}

// §2.2: Λ^(c) ≅ S^(c) by λ ↦ X_{E_T} — the image of the multipliers at x ∈ M_c is exactly the
// Gotay–Nester solution set S^(c)_x, of the same dimension; and X_{E_T} is tangent to M_c.
RC_GTEST_PROP(DiracBergmann, MultipliersMatchSolutions, ()) {
  const ConstrainedSystem<Q> s = any_constrained_system();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const CadResult<Q> gn = gotay_nester(s);
  const std::vector<Q> x = some_point(db.tower.back());
  const AffineSubspace<Q> lambda = multipliers(s, db, x);
  RC_ASSERT(!lambda.empty);
  const AffineSubspace<Q> sx = velocities(gotay_nester_system(s), gn, x);
  RC_ASSERT(lambda.direction.dim() == sx.direction.dim());
  RC_ASSERT(lambda.direction.dim() == gn.solution_rank);
  const std::vector<Q> l = some_point(lambda);
  const std::vector<Q> field = total_energy_field(s, x, l);
  RC_ASSERT(sx.contains_point(field));
  RC_ASSERT(contains(db.tower.back().direction, field));
}

// Lemma 3.23 / Cor. 3.3 with V = T M_c: 2s = r − dim ker ω_c; ψ are first class ({ψ, φ_j} = 0),
// det Σ ≠ 0; the Dirac tensor J* is skew, kills every χ ({F, χ_j}* = 0 for all F), and
// {ψ_i, ψ_j}* = 0.
RC_GTEST_PROP(DiracBergmann, Lemma3_23_Classes, ()) {
  const ConstrainedSystem<Q> s = any_constrained_system();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const ConstraintClasses<Q> cl = classify_constraints(s.omega, db.constraints);
  const QM j = poisson_tensor(s.omega), a = gradients(db.constraints);
  const Index r = a.rows();
  const Subspace<Q> tmc = db.tower.back().direction;
  RC_TAG("2s = " + std::to_string(2 * cl.s) + " of r = " + std::to_string(r));
  RC_ASSERT(2 * cl.s == r - form_kernel(restrict_form(s.omega, tmc)).dim());
  RC_ASSERT(cl.first.rows() == r - 2 * cl.s);
  RC_ASSERT((gradients(cl.first) * j * a.transpose()).is_zero());
  RC_ASSERT(rank(cl.sigma) == 2 * cl.s);
  RC_ASSERT(is_skew(cl.dirac_tensor));
  QM g(cl.second.size(), a.cols());
  for (Index p = 0; p < cl.second.size(); ++p)
    for (Index k = 0; k < a.cols(); ++k) g(p, k) = a(cl.second[p], k);
  RC_ASSERT((g * cl.dirac_tensor).is_zero());
  RC_ASSERT((gradients(cl.first) * cl.dirac_tensor * gradients(cl.first).transpose()).is_zero());
  // (3.9)–(3.11) with V^χ = span{X_χ} = J·(span dχ):  V^χ ∩ T S = 0,  V^χ ⊕ ker ω = (T S)^Ω,
  // (V^χ)^Ω ∩ (ker ω)^Ω = T S
  QM gchi(cl.second.size(), a.cols());
  for (Index p = 0; p < cl.second.size(); ++p)
    for (Index k = 0; k < a.cols(); ++k) gchi(p, k) = a(cl.second[p], k);
  const Subspace<Q> vchi = Subspace<Q>::span(gchi * j.transpose());
  const Subspace<Q> kerw = form_kernel(restrict_form(s.omega, tmc));
  RC_ASSERT(intersection(vchi, tmc).dim() == 0u);
  RC_ASSERT(vchi.dim() + kerw.dim() == symplectic_complement(s.omega, tmc).dim());
  RC_ASSERT(sum(vchi, kerw) == symplectic_complement(s.omega, tmc));
  RC_ASSERT(intersection(symplectic_complement(s.omega, vchi), symplectic_complement(s.omega, kerw)) == tmc);
  // Thm 3.24: the second class subbundle V^Ω contains T M_c, has dim M_c + dim ker ω_c, and is symplectic
  const Subspace<Q>& vo = cl.second_class_subbundle;
  RC_ASSERT(contains(vo, tmc));
  RC_ASSERT(vo.dim() == tmc.dim() + form_kernel(restrict_form(s.omega, tmc)).dim());
  RC_ASSERT(form_kernel(restrict_form(s.omega, vo)).dim() == 0u);
}

// Lemma 5.5 (A)(iii) and (B)(ii) with the ambient Ω, for D = D_{(T M, Ω)} (E_D = T M):
// uniqueness ⇔ W_c ∩ E_D^Ω = 0; ω_D|W_c symplectic ⇔ W_c ∩ W_c^Ω = 0.
RC_GTEST_PROP(DiracBergmann, Lemma5_5_AmbientOmega, ()) {
  const ConstrainedSystem<Q> s = any_constrained_system();
  const Subspace<Q> tm = kernel(gradients(s.primary));
  const LinearSystem<Q> ls{dirac_from_distribution(tm, s.omega), s.hessian, s.gradient, Q(0)};
  const CadResult<Q> r = constraint_tower(ls, s.primary);
  if (!r.consistent) return;
  const Subspace<Q>& w = r.final_step().w;
  RC_ASSERT(r.unique() == (intersection(w, symplectic_complement(s.omega, tm)).dim() == 0));
  const bool symplectic = form_kernel(restrict_form(dirac_form(ls.d), w)).dim() == 0;
  RC_ASSERT(symplectic == (intersection(w, symplectic_complement(s.omega, w)).dim() == 0));
}

// §2.1: the equations of motion by the Dirac bracket equal those by the canonical bracket on M_c:
// J* (dE + λ^i dφ_i) = J (dE + λ^i dφ_i) at x ∈ M_c, λ ∈ Λ_x (E_T is first class).
RC_GTEST_PROP(DiracBergmann, DiracBracketGivesTheSameMotion, ()) {
  const ConstrainedSystem<Q> s = any_constrained_system();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const ConstraintClasses<Q> cl = classify_constraints(s.omega, db.constraints);
  const std::vector<Q> x = some_point(db.tower.back());
  const AffineSubspace<Q> lambda = multipliers(s, db, x);
  const std::vector<Q> l = some_point(lambda);
  std::vector<Q> d = (s.hessian * QM::column(x)).col(0);
  const QM prim = gradients(s.primary);
  for (Index i = 0; i < d.size(); ++i) {
    d[i] += s.gradient[i];
    for (Index k = 0; k < l.size(); ++k) d[i] += l[k] * prim(k, i);
  }
  RC_ASSERT((cl.dirac_tensor * QM::column(d)).col(0) == total_energy_field(s, x, l));
}
