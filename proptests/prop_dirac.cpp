// Properties of the exact reference: linear Dirac structures, CEF §4.
#include "support/gen.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

// Planted answers: dim E_D = k, rank ω_D = 2h, dim ker ω_D = k − 2h; presymplectic iff k = n.
RC_GTEST_PROP(Dirac, PlantedDistribution, ()) {
  const PlantedDirac p = planted_dirac_from_distribution();
  RC_ASSERT(dirac_defect(p.d).empty());
  const PresymplecticForm<Q> om = dirac_form(p.d);
  RC_ASSERT(om.space == p.e);
  RC_ASSERT(form_rank(om) == 2 * p.h);
  RC_ASSERT(form_kernel(om).dim() == p.k - 2 * p.h);
  RC_ASSERT(is_presymplectic(p.d) == (p.k == p.n));
}

// Planted answers for Poisson graphs: E_D = im P, ω_D symplectic of rank 2h, P recovered.
RC_GTEST_PROP(Dirac, PlantedPoisson, ()) {
  const PlantedDirac p = planted_dirac_from_poisson();
  RC_ASSERT(dirac_defect(p.d).empty());
  RC_ASSERT(is_poisson(p.d));
  RC_ASSERT(poisson_bivector(p.d) == p.w);
  RC_ASSERT(dirac_distribution(p.d) == image(p.w));
  RC_ASSERT(form_rank(dirac_form(p.d)) == 2 * p.h);
  RC_ASSERT(form_kernel(dirac_form(p.d)).dim() == 0);
}

// Lemma 4.1: dim D = n and isotropic  ⇔  D = D^⊥; on Dirac structures and on random subspaces.
RC_GTEST_PROP(Dirac, Lemma4_1, ()) {
  DiracStructure<Q> d;
  if (*rc::gen::arbitrary<bool>()) {
    d = any_dirac();
  } else {
    const Index n = pick_size(1, 8);
    d = {n, QSub::span(integer_matrix(pick_size(0, 2 * n), 2 * n, 1))};
  }
  RC_ASSERT(dirac_defect(d).empty() == is_dirac_by_definition(d));
}

// Prop. 4.3: D ↦ (E_D, ω_D) ↦ D_{ω} is the identity; ω_D is skew and independent of the α chosen.
RC_GTEST_PROP(Dirac, Proposition4_3_RoundTrip, ()) {
  const DiracStructure<Q> d = any_dirac();
  const PresymplecticForm<Q> om = dirac_form(d);
  RC_ASSERT(is_skew(om.matrix));
  RC_ASSERT(dirac_from_distribution(om.space, om.matrix).d == d.d);
  // independence of α: α + γ with (0, γ) ∈ D (γ ∈ E_D°) gives the same ω_D(v, w) for w ∈ E_D
  const QSub e = dirac_distribution(d);
  if (e.dim() == 0) return;
  const std::vector<Q> v = e.basis().row(0);
  const AffineSubspace<Q> alphas = dirac_flat(d, v);
  RC_ASSERT(!alphas.empty);
  RC_ASSERT(alphas.direction == annihilator(e));
  std::vector<Q> other = alphas.point;
  for (Index i = 0; i < alphas.direction.dim(); ++i)
    for (Index k = 0; k < d.n; ++k) other[k] += Q(3) * alphas.direction.basis()(i, k);
  for (Index j = 0; j < e.dim(); ++j) {
    RC_ASSERT(dot(alphas.point, e.basis().row(j)) == dot(other, e.basis().row(j)));
    RC_ASSERT(dot(other, e.basis().row(j)) == form_value(om.matrix, v, e.basis().row(j)));
  }
}

// Prop. 4.4: D^♭(W) = (W^D)° for W ⊆ E_D.  Both sides also against the planted data of
// D = D_{E,ω} (Prop. 4.3: (v, α) ∈ D ⇔ v ∈ E and α|_E = ω(v, ·)|_E), which never goes through D's
// basis: D^♭(W) = ω^♭(W) + E° and W^D = E ∩ {X : ω(w, X) = 0 ∀ w ∈ W}.  Killed by: `intersection`
// returning its first argument; dirac_from_distribution with ω transposed; dirac_orthogonal
// reading the vector part instead of the covector part.
RC_GTEST_PROP(Dirac, Proposition4_4, ()) {
  const PlantedDirac p = planted_dirac_from_distribution();
  const QSub w = random_subspace_of(p.e);
  const QM flats = w.basis() * p.w;  // rows: ω(w_i, ·)
  RC_ASSERT(dirac_flat(p.d, w) == sum(QSub::span(flats), annihilator(p.e)));
  RC_ASSERT(dirac_orthogonal(p.d, w) == intersection(p.e, QSub::solutions(flats)));
  RC_ASSERT(dirac_flat(p.d, w) == annihilator(dirac_orthogonal(p.d, w)));
  const DiracStructure<Q> d = any_dirac();  // and on every kind of Dirac structure
  const QSub v = random_subspace_of(dirac_distribution(d));
  RC_ASSERT(dirac_flat(d, v) == annihilator(dirac_orthogonal(d, v)));
}

// §4: W^D ∩ E_D = W^{ω_D} — the Dirac route against the presymplectic route.
RC_GTEST_PROP(Dirac, OrthogonalMeetsDistribution, ()) {
  const DiracStructure<Q> d = any_dirac();
  const PresymplecticForm<Q> om = dirac_form(d);
  const QSub w = random_subspace_of(om.space);
  RC_ASSERT(intersection(dirac_orthogonal(d, w), om.space) == orthogonal(om, w));
}

// Prop. 4.6: W^{♭ω_D} = (W^{ω_D})^{°E_D} and W^♭ = (W^D)°; the first, restricted to E_D, is the
// second restricted to E_D (D^♭(W)|_{E_D} = ω_D^♭(W)).
RC_GTEST_PROP(Dirac, Proposition4_6, ()) {
  const DiracStructure<Q> d = any_dirac();
  const PresymplecticForm<Q> om = dirac_form(d);
  const QSub w = random_subspace_of(om.space);
  RC_ASSERT(flat(om, w) == annihilator(orthogonal(om, w)));
  RC_ASSERT(dirac_flat(d, w) == annihilator(dirac_orthogonal(d, w)));
  RC_ASSERT(sum(dirac_flat(d, w), annihilator(om.space)) == flat(om, w));
}

// The constructors agree where they overlap: D_ω equals the `distribution` form with E = Q^n, and
// D_ω is the graph of a bivector iff ω is nondegenerate, with P = (Wᵀ)^{-1} (α = Wᵀ v ⇔ v = P α).
RC_GTEST_PROP(Dirac, ConstructorsAgree, ()) {
  const PlantedPresymplectic p = planted_presymplectic();
  const DiracStructure<Q> d = dirac_from_presymplectic(p.w);
  RC_ASSERT(d.d == dirac_from_distribution(QSub::whole(p.n), p.w).d);
  RC_ASSERT(is_presymplectic(d));
  RC_ASSERT(is_poisson(d) == (2 * p.h == p.n));
  if (!is_poisson(d)) return;
  RC_ASSERT(poisson_bivector(d) * p.w.transpose() == QM::identity(p.n));
}
