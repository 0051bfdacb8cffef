// Properties of the exact CAD (CEF §5) on random linear systems in both input forms.
#include "support/gen.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {

void classify(const CadResult<Q>& r) {
  RC_CLASSIFY(!r.consistent, "inconsistent");
  RC_CLASSIFY(r.consistent && !r.unique(), "non-unique");
  RC_TAG("c = " + std::to_string(r.steps));
}

}  // namespace

// §5: M_{k+1} ⊆ M_k, strictly until it stops, and c ≤ N.
RC_GTEST_PROP(Cad, TowerDecreasesAndStops, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  classify(r);
  RC_ASSERT(r.steps <= s.d.n);
  for (Index k = 1; k < r.tower.size(); ++k) {
    const AffineSubspace<Q>& big = r.tower[k - 1].m;
    const AffineSubspace<Q>& small = r.tower[k].m;
    RC_ASSERT(r.tower[k].dim() < r.tower[k - 1].dim());
    if (small.empty) continue;
    RC_ASSERT(contains(big.direction, small.direction));
    RC_ASSERT(big.contains_point(small.point));
  }
}

// Planted long towers are recovered exactly: dims N, N−1, …, 0, c = N, consistent and unique.
RC_GTEST_PROP(Cad, PlantedLongTower, ()) {
  const LinearSystem<Q> s = long_tower_system(5);
  const CadResult<Q> r = constraint_tower(s);
  RC_ASSERT(r.consistent);
  RC_ASSERT(r.steps == s.d.n);
  for (Index k = 0; k < r.tower.size(); ++k) RC_ASSERT(r.tower[k].dim() == static_cast<long>(s.d.n - k));
  RC_ASSERT(r.solution_rank == 0u);
}

// Lemma 5.1 (i)–(vii) at random points x, with W = W_k of the tower, each by its own construction:
// (i) = (v) ∃ ẋ ∈ W, (ẋ, dE(x)) ∈ D  ⇔  (ii) ∃ ẋ ∈ W, ω_D(ẋ, ·) = dE(x)|E_D  ⇔  (iii) dE(x)|E_D ∈ W^♭
// ⇔ (iv) ⟨dE(x)|E_D, W^{ω_D}⟩ = 0  ⇔  (vi) dE(x) ∈ D^♭(W)  ⇔  (vii) ⟨dE(x), W^D⟩ = 0.
RC_GTEST_PROP(Cad, Lemma5_1_Equivalences, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  const Index k = *rc::gen::inRange<Index>(0, r.tower.size());
  if (r.tower[k].m.empty) return;
  const Subspace<Q>& w = r.tower[k].w;
  // a point of M_k half the time (where (vii) holds by construction of M_{k+1}… or not), else anywhere
  const std::vector<Q> x = *rc::gen::arbitrary<bool>() ? some_point(r.tower[k].m) : integer_vector(s.d.n);
  const std::vector<Q> de = energy_differential(s, x);
  const auto kills = [&](const Subspace<Q>& u) {
    for (Index i = 0; i < u.dim(); ++i)
      if (dot(de, u.basis().row(i)) != 0) return false;
    return true;
  };
  const PresymplecticForm<Q> om = dirac_form(s.d);
  const Index n = s.d.n;
  // (i) = (v): some (ẋ, dE(x)) ∈ D with ẋ ∈ W — D ∩ (W ⊕ (Q^n)*) projected onto its covectors contains dE(x)
  const QSub w_any = QSub::span(vstack(hstack(w.basis(), QM(w.dim(), n)), hstack(QM(n, n), QM::identity(n))));
  const QM covector_part = hstack(QM(n, n), QM::identity(n));
  const bool i_v = contains(map(covector_part, intersection(s.d.d, w_any)), de);
  // (ii): ẋ = Σ c_i w_i with ω_D(ẋ, e_j) = dE(e_j) for a basis e_j of E_D — a linear system in c
  const QM& e = om.space.basis();
  std::vector<Q> rhs;
  for (Index j = 0; j < e.rows(); ++j) rhs.push_back(dot(de, e.row(j)));
  const bool ii = !solve(e * om.matrix.transpose() * w.basis().transpose(), rhs).empty;
  const bool iii = contains(flat(om, w), de);  // dE|_{E_D} ∈ W^♭ (flat: the covectors whose restriction is in it)
  const bool iv = kills(orthogonal(om, w));
  const bool vi = contains(dirac_flat(s.d, w), de);
  const bool vii = kills(dirac_orthogonal(s.d, w));
  RC_CLASSIFY(vii, "condition holds");
  RC_ASSERT(i_v == ii);
  RC_ASSERT(ii == iii);
  RC_ASSERT(iii == iv);
  RC_ASSERT(iv == vi);
  RC_ASSERT(vi == vii);
  // and M_{k+1} is exactly where it holds, on M_k
  if (k + 1 < r.tower.size() && r.tower[k].m.contains_point(x)) RC_ASSERT(vii == r.tower[k + 1].m.contains_point(x));
}

// Thm 5.4(b): the velocities solving (5.7)–(5.8) at a point of M_c form an affine space of
// dimension d^(c) = dim(ker ω_D ∩ T M_c) — and they exist at every point of M_c.
RC_GTEST_PROP(Cad, Theorem5_4_SolutionRank, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  classify(r);
  if (!r.consistent) return;
  const AffineSubspace<Q> v = velocities(s, r, some_point(r.final_step().m));
  RC_ASSERT(!v.empty);
  RC_ASSERT(v.direction.dim() == r.solution_rank);
  RC_ASSERT(contains(r.final_step().w, v.direction));
}

// Thm 5.4(a): at every x ∈ M_c some ẋ ∈ W_c solves (5.10), and (5.10) and (5.11) have the same solutions — the
// velocities (5.10) gives (`velocities`, by D's equations Γ_v ẋ = −Γ_α dE) are the affine space of ẋ ∈ W_c with
// ω_D(ẋ, ·) = dE(x)|E_D, solved here in W_c's coordinates over a basis of E_D.
RC_GTEST_PROP(Cad, Theorem5_4a_DiracSystemIsTheFormEquationOnMc, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  if (!r.consistent) return;
  const std::vector<Q> x = some_point(r.final_step().m);
  const std::vector<Q> de = energy_differential(s, x);
  const PresymplecticForm<Q> om = dirac_form(s.d);
  const QM& e = om.space.basis();
  const QM wc = r.final_step().w.basis().transpose();  // columns: a basis of W_c
  std::vector<Q> rhs;
  for (Index j = 0; j < e.rows(); ++j) rhs.push_back(dot(de, e.row(j)));
  const AffineSubspace<Q> c = solve(e * om.matrix.transpose() * wc, rhs);  // (5.11) in W_c's coordinates
  RC_ASSERT(!c.empty);                                                     // existence on all of M_c
  AffineSubspace<Q> form_side;
  form_side.empty = false;
  form_side.point = (wc * QM::column(c.point)).col(0);
  form_side.direction = map(wc, c.direction);
  const AffineSubspace<Q> dirac_side = velocities(s, r, x);  // (5.10)
  RC_ASSERT(dirac_side == form_side);
  RC_ASSERT(form_side.direction.dim() == r.solution_rank);
}

// CEF §2.2 (2.3): Gotay–Nester's final equation ω(ẋ, ·) = dE(x), ẋ ∈ T M_c implies ω_c(ẋ, ·) = d(E|M_c) on M_c,
// and where ω_c (ω pulled back to M_c) is symplectic the two have the same solutions; where it is degenerate they
// may not (Section2_2_DegenerateOmegaCAdmitsMoreThanGotayNester, by hand).  Presymplectic ω of planted rank, so the
// CAD is Gotay–Nester.
RC_GTEST_PROP(Cad, Section2_2_HamiltonianFormOnMc, ()) {
  const PlantedPresymplectic p = planted_presymplectic(8);
  LinearSystem<Q> s;
  s.d = dirac_from_presymplectic(p.w);
  s.hessian = symmetric_matrix(p.n, *rc::gen::inRange<Index>(0, p.n + 1));
  s.gradient = integer_vector(p.n);
  const CadResult<Q> r = constraint_tower(s);
  if (!r.consistent) return;
  const std::vector<Q> x = some_point(r.final_step().m);
  const std::vector<Q> de = energy_differential(s, x);
  const QM tmc = r.final_step().m.direction.basis().transpose();  // columns: a basis of T M_c
  const QM& tb = r.final_step().m.direction.basis();
  std::vector<Q> rhs;  // (2.3) in M_c's coordinates: ω(Σ c_i t_i, t_j) = dE(t_j)
  for (Index j = 0; j < tb.rows(); ++j) rhs.push_back(dot(de, tb.row(j)));
  const AffineSubspace<Q> c = solve(tb * p.w.transpose() * tmc, rhs);
  RC_ASSERT(!c.empty);
  AffineSubspace<Q> hamiltonian;
  hamiltonian.empty = false;
  hamiltonian.point = (tmc * QM::column(c.point)).col(0);
  hamiltonian.direction = map(tmc, c.direction);
  const AffineSubspace<Q> gotay_nester = velocities(s, r, x);  // ω(ẋ, ·) = dE(x) on all of Q^n, ẋ ∈ T M_c
  RC_ASSERT(hamiltonian.contains_point(gotay_nester.point));
  RC_ASSERT(contains(hamiltonian.direction, gotay_nester.direction));
  const bool symplectic = form_kernel(restrict_form(p.w, r.final_step().m.direction)).dim() == 0;
  RC_CLASSIFY(symplectic, "omega_c symplectic");
  if (symplectic) RC_ASSERT(hamiltonian == gotay_nester);
}

// (2.3)'s warning, by hand: on (q, p, z) with ω = dq∧dp and E = z q, Gotay–Nester gives M_1 = {q = 0} = M_c
// (dE(∂_z) = q), ω_c = 0, so (2.3) admits every ẋ ∈ T M_c = span(∂_p, ∂_z), while ω(ẋ, ·) = dE = z dq
// forces ẋ_q = 0, ẋ_p = −z: a line.
TEST(Cad, Section2_2_DegenerateOmegaCAdmitsMoreThanGotayNester) {
  LinearSystem<Q> s;
  QM w(3, 3), h(3, 3);
  w(0, 1) = Q(1);
  w(1, 0) = Q(-1);
  h(0, 2) = h(2, 0) = Q(1);
  s.d = dirac_from_presymplectic(w);
  s.hessian = h;
  s.gradient = {Q(0), Q(0), Q(0)};
  const CadResult<Q> r = constraint_tower(s);
  ASSERT_TRUE(r.consistent);
  EXPECT_EQ(r.final_step().dim(), 2);
  const std::vector<Q> x = {Q(0), Q(5), Q(2)};  // q = 0, p = 5, z = 2
  ASSERT_TRUE(r.final_step().m.contains_point(x));
  EXPECT_TRUE(form_kernel(restrict_form(w, r.final_step().m.direction)).dim() == 2u);  // ω_c = 0
  const AffineSubspace<Q> v = velocities(s, r, x);
  ASSERT_FALSE(v.empty);
  EXPECT_EQ(v.direction.dim(), 1u);                    // ẋ = (0, −z, c)
  EXPECT_TRUE(v.contains_point({Q(0), Q(-2), Q(7)}));  // any c
  EXPECT_FALSE(v.contains_point({Q(0), Q(0), Q(0)}));  // (2.3) admits it: ω_c = 0, E|M_c = 0
}

// Lemma 5.5 (A): uniqueness (d^(c) = 0) ⇔ (i) ker ω_D ∩ T M_c = 0 ⇔ (ii) W_c ∩ E_D^{ω_D} = 0;
// (B) ω_D|W_c symplectic ⇔ W_c ∩ W_c^{ω_D} = 0, and then solutions are unique.  Each side by its own
// route: uniqueness from the velocities (ẋ ∈ T M_c, (ẋ, dE(x)) ∈ D: D itself, not ω_D), (i) and (ii)
// from ω_D's kernel, "symplectic" from the determinant of ω_D's Gram matrix on W_c, the other side
// of (B) from W_c^{ω_D}.  Killed by: the solution rank or W_c computed from the wrong step, a
// determinant or form kernel that ignores a row.
RC_GTEST_PROP(Cad, Lemma5_5, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  if (!r.consistent) return;
  const PresymplecticForm<Q> om = dirac_form(s.d);
  const Subspace<Q>& w = r.final_step().w;
  const bool unique = velocities(s, r, some_point(r.final_step().m)).direction.dim() == 0;
  const bool a_i = intersection(form_kernel(om), r.final_step().m.direction).dim() == 0;
  const bool a_ii = intersection(w, orthogonal(om, om.space)).dim() == 0;
  RC_ASSERT(unique == r.unique());
  RC_ASSERT(unique == a_i);
  RC_ASSERT(a_i == a_ii);
  const bool symplectic = w.dim() == 0 || determinant(gram(restrict_form(om, w))) != 0;
  RC_ASSERT(symplectic == (form_kernel(restrict_form(om, w)).dim() == 0));
  RC_ASSERT(symplectic == (intersection(w, orthogonal(om, w)).dim() == 0));
  if (symplectic) RC_ASSERT(unique);
  RC_CLASSIFY(symplectic, "omega_D|W_c symplectic");
  RC_CLASSIFY(unique && !symplectic, "unique, W_c not symplectic");
}

// Solutions of the reduced equations (5.12) satisfy the original implicit system (1.1): for random
// z ∈ M_c (in its coordinates) and λ, the ẋ built from ż is tangent to M_c and (ẋ, dE(x)) ∈ D.
RC_GTEST_PROP(Cad, ReducedEquationsSolveTheImplicitSystem, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  if (!r.consistent) return;
  const ReducedEquations<Q> red = reduced_equations(s, r);
  const Index n = s.d.n, m = red.coords.size();
  const std::vector<Q> x = some_point(r.final_step().m);
  std::vector<Q> z(m);
  for (Index i = 0; i < m; ++i) z[i] = x[red.coords[i]];
  const std::vector<Q> lambda = integer_vector(red.g.cols());
  std::vector<Q> zdot = (red.f_matrix * QM::column(z)).col(0);
  for (Index i = 0; i < m; ++i) {
    zdot[i] += red.f[i];
    for (Index j = 0; j < lambda.size(); ++j) zdot[i] += red.g(i, j) * lambda[j];
  }
  // ẋ is the tangent vector of M_c with coordinates ż: ẋ = Bᵀ (S Bᵀ)^{-1} ż
  const QM& b = r.final_step().m.direction.basis();
  QM sel(m, n);
  for (Index i = 0; i < m; ++i) sel(i, red.coords[i]) = Q(1);
  const std::vector<Q> xdot = (b.transpose() * inverse(sel * b.transpose()) * QM::column(zdot)).col(0);
  std::vector<Q> pair = xdot;
  const std::vector<Q> de = energy_differential(s, x);
  pair.insert(pair.end(), de.begin(), de.end());
  RC_ASSERT(contains(s.d.d, pair));
}

// Discrete outputs are invariant under linear changes of coordinates x = A y (A unimodular):
// D pulls back to {(A^{-1} v, Aᵀ α)}, H to Aᵀ H A, g to Aᵀ g.
RC_GTEST_PROP(Cad, InvariantUnderLinearCoordinateChanges, ()) {
  const LinearSystem<Q> s = *systems();
  const Index n = s.d.n;
  const LinearSystem<Q> moved = change_coordinates(s, unimodular(n));
  const CadResult<Q> r1 = constraint_tower(s), r2 = constraint_tower(moved);
  RC_ASSERT(r1.steps == r2.steps);
  RC_ASSERT(r1.consistent == r2.consistent);
  for (Index k = 0; k < r1.tower.size(); ++k) RC_ASSERT(r1.tower[k].dim() == r2.tower[k].dim());
  RC_ASSERT(r1.solution_rank == r2.solution_rank);
}

// Remark 5.3 (and §5, constant D): the CAD equals Gotay–Nester run on each presymplectic leaf
// x0 + E_D — M_k ∩ (x0 + E_D) is the k-th Gotay–Nester constraint set of (E_D, ω_D, E|leaf), as sets; and
// (5.2) ⇔ (5.4): at x0 ∈ M_c the CAD's velocities are those of Gotay–Nester on the leaf at y = 0.
RC_GTEST_PROP(Cad, Remark5_3_GotayNesterOnLeaves, ()) {
  const LinearSystem<Q> s = *systems();
  const CadResult<Q> r = constraint_tower(s);
  const Subspace<Q> e = dirac_distribution(s.d);
  const std::vector<Q> x0 =
      *rc::gen::arbitrary<bool>() && r.consistent ? some_point(r.final_step().m) : integer_vector(s.d.n);
  // leaf coordinates y: x = x0 + Bᵀ y; ω_D and E pulled back; GN = CAD of the presymplectic D_ω.
  const QM& b = e.basis();
  const PresymplecticForm<Q> om = dirac_form(s.d);
  LinearSystem<Q> leaf;
  leaf.d = dirac_from_presymplectic(b * om.matrix * b.transpose());
  leaf.hessian = b * s.hessian * b.transpose();
  leaf.gradient = (b * QM::column(energy_differential(s, x0))).col(0);
  const CadResult<Q> gn = constraint_tower(leaf);
  // compare dim(M_k ∩ leaf) with the GN dims, up to the first empty set
  const Subspace<Q> leaf_dir = e;
  for (Index k = 0; k < std::max(r.tower.size(), gn.tower.size()); ++k) {
    const CadStep<Q>& ck = r.tower[std::min(k, r.tower.size() - 1)];
    const CadStep<Q>& gk = gn.tower[std::min(k, gn.tower.size() - 1)];
    long cad_dim = -1;
    if (!ck.m.empty) {  // M_k ∩ (x0 + E_D): solve x0 + Bᵀ y ∈ M_k
      const QM eq = annihilator(ck.m.direction).basis();
      std::vector<Q> rhs(eq.rows());
      for (Index i = 0; i < eq.rows(); ++i) rhs[i] = dot(eq.row(i), ck.m.point) - dot(eq.row(i), x0);
      const AffineSubspace<Q> meet = solve(eq * b.transpose(), rhs);
      cad_dim = meet.empty ? -1 : static_cast<long>(meet.direction.dim());
      RC_ASSERT(meet == gk.m);  // as sets, in the leaf's coordinates y: S_k = M_k ∩ S (5.9) = (5.6)
    }
    RC_ASSERT(cad_dim == gk.dim());
    if (cad_dim < 0) break;
  }
  // (5.2) ⇔ (5.4) with y(0) = 0: at x0 ∈ M_c the CAD's velocities are Bᵀ of Gotay–Nester's on the leaf at y = 0
  if (!r.consistent || !r.final_step().m.contains_point(x0)) return;
  RC_ASSERT(gn.consistent);
  const AffineSubspace<Q> on_leaf = velocities(leaf, gn, std::vector<Q>(e.dim(), Q(0)));
  RC_ASSERT(!on_leaf.empty);
  AffineSubspace<Q> pushed;
  pushed.empty = false;
  pushed.point = (b.transpose() * QM::column(on_leaf.point)).col(0);
  pushed.direction = map(b.transpose(), on_leaf.direction);
  RC_TAG("velocities compared on the leaf");
  RC_ASSERT(velocities(s, r, x0) == pushed);
}
