// Properties of the exact reference: linear symplectic algebra, CEF §3.1 and Lemma 4.2.
#include "support/gen.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

// dim V + dim V^Ω = 2n  [CEF Lemma 3.1: X_i = α_i^♯ is a basis of V^Ω, r = dim V°]
RC_GTEST_PROP(Symplectic, ComplementDimension, ()) {
  const PlantedSymplectic p = planted_symplectic();
  RC_ASSERT(p.v.dim() + symplectic_complement(p.w, p.v).dim() == 2 * p.m);
}

// (V^Ω)^Ω = V
RC_GTEST_PROP(Symplectic, DoubleComplement, ()) {
  const PlantedSymplectic p = planted_symplectic();
  RC_ASSERT(symplectic_complement(p.w, symplectic_complement(p.w, p.v)) == p.v);
}

// Lemma 3.1: rank [α_i(X_j)] is even (= 2s), the X_i are a basis of V^Ω, α_i ∈ V°, and the normal
// form has the stated pattern α_i(X_j) = δ_{i,j-s} (i ≤ s), -δ_{i-s,j} (s < i ≤ 2s), 0 (i > 2s).
RC_GTEST_PROP(Symplectic, Lemma3_1_NormalForm, ()) {
  const PlantedSymplectic p = planted_symplectic();
  const NormalFormBasis<Q> nf = normal_form_basis(p.w, p.v);
  const Index r = nf.x.rows(), s = nf.s;
  RC_ASSERT(QSub::span(nf.x) == symplectic_complement(p.w, p.v));
  RC_ASSERT(QSub::span(nf.alpha) == annihilator(p.v));
  RC_ASSERT(r == annihilator(p.v).dim());
  const QM m = pairing_matrix(nf.alpha, nf.x);
  RC_ASSERT(rank(m) == 2 * s);
  for (Index i = 0; i < r; ++i)
    for (Index j = 0; j < r; ++j) {
      const Q want = (i < s && j == i + s) ? Q(1) : (i >= s && i < 2 * s && j + s == i) ? Q(-1) : Q(0);
      RC_ASSERT(m(i, j) == want);
    }
  // rank of [α_i(X_j)] is even for *any* basis of V°, not only the normal one
  const QM gamma = annihilator(p.v).basis();
  QM y(gamma.rows(), 2 * p.m);
  for (Index i = 0; i < gamma.rows(); ++i) {
    const auto yi = sharp(p.w, gamma.row(i));
    for (Index k = 0; k < yi.size(); ++k) y(i, k) = yi[k];
  }
  RC_ASSERT(rank(pairing_matrix(gamma, y)) % 2 == 0);
}

// Lemma 3.2 and Corollary 3.3: X_{2s+1..r} span V ∩ V^Ω, of dimension r − 2s; planted t recovered.
RC_GTEST_PROP(Symplectic, Lemma3_2_Corollary3_3, ()) {
  const PlantedSymplectic p = planted_symplectic();
  const NormalFormBasis<Q> nf = normal_form_basis(p.w, p.v);
  const QSub vv = intersection(p.v, symplectic_complement(p.w, p.v));
  RC_ASSERT(QSub::span(nf.x.block(2 * nf.s, nf.x.rows(), 0, nf.x.cols())) == vv);
  RC_ASSERT(vv.dim() == nf.x.rows() - 2 * nf.s);
  RC_ASSERT(vv.dim() == p.t);
  RC_ASSERT(p.v.dim() == 2 * p.a + p.t);
}

// Lemma 3.4: V^ω = V ∩ V^Ω — both sides against the kernel planted by the generator (the isotropic
// directions e_{a+1}..e_{a+t} of V in J-coordinates), which neither side computes.  Killed by:
// `intersection` returning its first argument (then both sides are V), a transposed form in
// symplectic_complement, form_kernel taking the whole domain.
RC_GTEST_PROP(Symplectic, Lemma3_4, ()) {
  const PlantedSymplectic p = planted_symplectic();
  RC_ASSERT(form_kernel(restrict_form(p.w, p.v)) == p.kernel);
  RC_ASSERT(intersection(p.v, symplectic_complement(p.w, p.v)) == p.kernel);
  RC_ASSERT(form_rank(restrict_form(p.w, p.v)) == 2 * p.a);
}

// Lemmas 3.5–3.6 and Corollary 3.7: (3.1) is solvable iff β(V^ω) = 0; then every returned X
// satisfies i_X ω = β|_V, the set has dimension r − 2s = dim ker ω, and equals the solution set
// computed straight from the definition; where ω is symplectic and β^♯ ∈ V (β = v^♭, v ∈ V), λ = 0 and X = β^♯.
RC_GTEST_PROP(Symplectic, Lemma3_5_3_6_Corollary3_7, ()) {
  const PlantedSymplectic p = planted_symplectic();
  const Index n = 2 * p.m;
  std::vector<Q> beta = integer_vector(n), in_v;
  const int kind = *rc::gen::inRange(0, 3);
  if (kind == 1) {  // a third of the time, make β vanish on V^ω so a solution exists
    const QM k = intersection(p.v, symplectic_complement(p.w, p.v)).basis();
    const QM ann = annihilator(QSub::span(k)).basis();
    beta = ann.rows() ? (integer_matrix(1, ann.rows()) * ann).row(0) : std::vector<Q>(n, Q(0));
  } else if (kind == 2 && p.v.dim() > 0) {  // and a third, β = v^♭ for some v ∈ V: β^♯ = v ∈ V
    in_v = (integer_matrix(1, p.v.dim()) * p.v.basis()).row(0);
    beta = flat(p.w, in_v);
  }
  const PresymplecticForm<Q> om = restrict_form(p.w, p.v);
  const QSub ker = form_kernel(om);
  bool kills_kernel = true;
  for (Index i = 0; i < ker.dim(); ++i) kills_kernel = kills_kernel && dot(beta, ker.basis().row(i)) == 0;
  const RestrictedSolution<Q> sol = solve_restricted(p.w, p.v, beta);
  RC_ASSERT(sol.lambda.empty == !kills_kernel);
  RC_ASSERT(sol.x == solve_on_subspace(om, beta));
  if (sol.x.empty) return;
  RC_ASSERT(sol.x.direction.dim() == annihilator(p.v).dim() - 2 * normal_form_basis(p.w, p.v).s);
  RC_ASSERT(sol.x.direction.dim() == ker.dim());
  RC_ASSERT(sol.lambda.direction.dim() == ker.dim());
  // Lemma 3.6's last sentence: ω symplectic ⇒ (3.1) and (3.3) solve uniquely, and β^♯ ∈ V ⇒ λ = 0, X = β^♯
  RC_CLASSIFY(ker.dim() == 0 && !in_v.empty(), "symplectic, beta^sharp in V");
  if (ker.dim() == 0 && !in_v.empty()) {
    RC_ASSERT(sol.lambda.point == std::vector<Q>(sol.lambda.point.size(), Q(0)));
    RC_ASSERT(sol.x.point == in_v);
  }
  // verify X = point + direction combination: X ∈ V and ω(X, b) = β(b) for every basis vector b of V
  std::vector<Q> x = sol.x.point;
  for (Index i = 0; i < sol.x.direction.dim(); ++i)
    for (Index k = 0; k < n; ++k) x[k] += Q(static_cast<int>(i) + 1) * sol.x.direction.basis()(i, k);
  RC_ASSERT(contains(p.v, x));
  for (Index j = 0; j < p.v.dim(); ++j)
    RC_ASSERT(form_value(p.w, x, p.v.basis().row(j)) == dot(beta, p.v.basis().row(j)));
}

// Lemma 4.2: ω^♭(W) = (W^ω)° for a presymplectic ω on V (as subspaces of (Q^n)* containing V°),
// on presymplectic forms of planted rank, restricted to random subspaces.
RC_GTEST_PROP(Presymplectic, Lemma4_2, ()) {
  const PlantedPresymplectic p = planted_presymplectic();
  const PresymplecticForm<Q> whole = restrict_form(p.w, QSub::whole(p.n));
  RC_ASSERT(form_rank(whole) == 2 * p.h);
  RC_ASSERT(form_kernel(whole).dim() == p.n - 2 * p.h);
  const PresymplecticForm<Q> om = restrict_form(whole, random_subspace_of(QSub::whole(p.n)));
  const QSub w = random_subspace_of(om.space);
  RC_ASSERT(flat(om, w) == annihilator(orthogonal(om, w)));
  RC_ASSERT(form_rank(om) % 2 == 0);
}
