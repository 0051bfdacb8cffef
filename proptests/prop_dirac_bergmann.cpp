// Dirac–Bergmann against Gotay–Nester, and first/second class constraints with the Dirac bracket,
// on random linear constrained Hamiltonian systems (N, Ω, E, M).  [CEF §2, Lemma 3.23]
#include "support/gen.hpp"

#include "dcad/reference/dirac_bergmann.hpp"
#include "dcad/reference/quotient.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad::reference;
using namespace dcad::test;

namespace {

/// dE_T(x) = H x + g + λ^i a_i: the total energy's differential with multipliers λ.
std::vector<Q> total_energy_differential(const ConstrainedSystem<Q>& s, const std::vector<Q>& x,
                                         const std::vector<Q>& l) {
  std::vector<Q> d = (s.hessian * QM::column(x)).col(0);
  const QM prim = gradients(s.primary);
  for (Index i = 0; i < d.size(); ++i) {
    d[i] += s.gradient[i];
    for (Index k = 0; k < l.size(); ++k) d[i] += l[k] * prim(k, i);
  }
  return d;
}

/// CEF Thm 3.19, Lemma 3.20 (3.6) and Remark 3.21 on M̃_c at x ∈ M_c with two multipliers l, m: "" or what fails.
std::string tilde_quotient_fails(const ConstrainedSystem<Q>& s, const GaugeQuotient<Q>& q, const std::vector<Q>& x,
                                 const std::vector<Q>& l, const std::vector<Q>& m) {
  const QM d = q.tangent.basis();
  if (rank(q.tilde_coordinates * d.transpose()) != q.tangent.dim() - q.physical_gauge.dim() ||
      q.tilde_coordinates.rows() != q.tangent.dim() - q.physical_gauge.dim())
    return "C~ is not onto M~_c";
  if (!(q.tilde_coordinates * q.physical_gauge.basis().transpose()).is_zero()) return "C~ does not kill K~_c";
  if (!(q.coordinates * d.transpose() == q.fibration * q.tilde_coordinates * d.transpose())) return "P C~ != C on TM_c";
  const std::vector<Q> a = total_energy_field(s, x, l), b = total_energy_field(s, x, m);
  std::vector<Q> diff(a.size());
  for (Index i = 0; i < a.size(); ++i) diff[i] = a[i] - b[i];
  if (!contains(q.physical_gauge, diff)) return "two solutions differ off K~_c (Remark 3.21)";
  if (!(q.tilde_coordinates * QM::column(a) == q.tilde_coordinates * QM::column(b))) return "two X~ ((3.6))";
  if (!(q.fibration * q.tilde_coordinates * QM::column(a) == q.coordinates * QM::column(a))) return "P X~ != Xbar";
  return "";
}

}  // namespace

// §2: the Dirac–Bergmann and the Gotay–Nester algorithms produce the same M_k.
RC_GTEST_PROP(DiracBergmann, SameTowerAsGotayNester, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
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
  const ConstrainedSystem<Q> s = *constrained_systems();
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
// {ψ_i, ψ_j}* = 0; (3.9)–(3.11); (c) S^χ = {χ = 0}, symplectic, of dimension 2n − 2s, with S first class in it;
// (e) the Dirac bracket is the bracket of the restrictions to S^χ, and F_χ's; (f) shifted χ^C give the same.
RC_GTEST_PROP(DiracBergmann, Lemma3_23_Classes, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
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
  // (c): S^χ = {χ = 0} has T S^χ = (V^χ)^Ω and T S^χ ⊕ V^χ = T P; it contains S, is symplectic, of dimension
  // dim S + dim ker ω = 2n − 2s, and S is first class in it: (T S)^Ω ∩ T S^χ ⊆ T S
  const Subspace<Q> schi = kernel(gchi);
  RC_ASSERT(schi == symplectic_complement(s.omega, vchi));
  RC_ASSERT(intersection(schi, vchi).dim() == 0u);
  RC_ASSERT(schi.dim() + vchi.dim() == a.cols());
  RC_ASSERT(contains(schi, tmc));
  RC_ASSERT(form_kernel(restrict_form(s.omega, schi)).dim() == 0u);
  RC_ASSERT(schi.dim() == tmc.dim() + kerw.dim());
  RC_ASSERT(schi.dim() == a.cols() - 2 * cl.s);
  RC_ASSERT(contains(tmc, intersection(symplectic_complement(s.omega, tmc), schi)));
  // (e): {F, G}_(χ) = {F|S^χ, G|S^χ}_χ and X_(χ),F = X_{F|S^χ} — the Dirac tensor J* is the Poisson tensor of
  // ω^χ = Ω|S^χ in S^χ's coordinates (basis rows B), pushed forward: J* = Bᵀ poisson_tensor(B Ω Bᵀ) B; and for
  // linear F, F_χ = F − χ_i c^{ij} {χ_j, F} Poisson-commutes with every χ_k and {F_χ, G_χ} = {F, G}_(χ)
  const QM& bs = schi.basis();
  RC_ASSERT(cl.dirac_tensor == bs.transpose() * poisson_tensor(bs * s.omega * bs.transpose()) * bs);
  if (!cl.second.empty()) {
    const QM alpha = integer_matrix(1, a.cols()), beta = integer_matrix(1, a.cols());
    const QM cinv = inverse(gchi * j * gchi.transpose());
    // dF_χ = α − Σ_i (Σ_j c^{ij} {χ_j, F}) dχ_i, {χ_j, F} = a_j J αᵀ, c^{ij} the inverse of c_ij = {χ_i, χ_j}
    const auto chi_corrected = [&](const QM& f) { return f - (cinv * gchi * j * f.transpose()).transpose() * gchi; };
    const QM fa = chi_corrected(alpha), fb = chi_corrected(beta);
    RC_ASSERT((fa * j * gchi.transpose()).is_zero());
    RC_ASSERT(fa * j * fb.transpose() == alpha * cl.dirac_tensor * beta.transpose());
    // (f): χ^C = χ − C, C random: S^{χ^C} is nonempty (dχ independent) with the same tangent space, (3.14)
    // c^{χ^C} = c^χ and (3.15) the same Dirac bracket
    QM shifted = db.constraints;
    for (Index p = 0; p < cl.second.size(); ++p)
      shifted(cl.second[p], shifted.cols() - 1) += Q(*rc::gen::inRange(-3, 4));
    const ConstraintClasses<Q> clc = classify_constraints(s.omega, shifted);
    RC_ASSERT(rank(gchi) == 2 * cl.s);
    RC_ASSERT(clc.sigma == cl.sigma);
    RC_ASSERT(clc.dirac_tensor == cl.dirac_tensor);
  }
  // Thm 3.24: the second class subbundle V^Ω contains T M_c, has dim M_c + dim ker ω_c, and is symplectic
  const Subspace<Q>& vo = cl.second_class_subbundle;
  RC_ASSERT(contains(vo, tmc));
  RC_ASSERT(vo.dim() == tmc.dim() + form_kernel(restrict_form(s.omega, tmc)).dim());
  RC_ASSERT(form_kernel(restrict_form(s.omega, vo)).dim() == 0u);
}

// Lemma 5.5 (A)(iii) and (B)(ii) with the ambient Ω, for D = D_{(T M, Ω)} (E_D = T M):
// uniqueness ⇔ W_c ∩ E_D^Ω = 0; ω_D|W_c symplectic ⇔ W_c ∩ W_c^Ω = 0.
RC_GTEST_PROP(DiracBergmann, Lemma5_5_AmbientOmega, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
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
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const ConstraintClasses<Q> cl = classify_constraints(s.omega, db.constraints);
  const std::vector<Q> x = some_point(db.tower.back());
  const AffineSubspace<Q> lambda = multipliers(s, db, x);
  const std::vector<Q> l = some_point(lambda);
  const std::vector<Q> d = total_energy_differential(s, x, l);
  RC_ASSERT((cl.dirac_tensor * QM::column(d)).col(0) == total_energy_field(s, x, l));
}

// CEF §3.2 on M̄_c = M_c / K_c: (3.5) K̃_c = ker ω ∩ TM_c ⊆ K_c = ker ω_c, with dim K̃_c = d^(c), the
// dimension of the Gotay–Nester solution set (Thm 3.19); Lemma 3.9 (a): C kills exactly K_c on TM_c and
// ω̄_c is symplectic and pulls back to ω_c; Lemma 3.20 (d): dE(x) vanishes on K_c at every x ∈ M_c;
// (3.8) and Remark 3.21: every solution X of (3.4) at x ∈ M_c (any λ ∈ Λ^(c)_x) projects to the one
// solution of (3.8), C X = X̄(C x); the section x(z) lies on M_c over z.
RC_GTEST_PROP(DiracBergmann, Lemma3_9_GaugeQuotient, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const GaugeQuotient<Q> q = gauge_quotient(s, db);
  const CadResult<Q> gn = gotay_nester(s);
  const Index n = s.omega.rows(), m = q.form.rows();
  RC_TAG("dim K_c = " + std::to_string(q.gauge.dim()) + ", d^(c) = " + std::to_string(q.physical_gauge.dim()));
  RC_ASSERT(contains(q.gauge, q.physical_gauge));                                               // (3.5)
  RC_ASSERT(static_cast<long>(q.physical_gauge.dim()) == static_cast<long>(gn.solution_rank));  // Thm 3.19
  RC_ASSERT(q.gauge == form_kernel(restrict_form(s.omega, db.tower.back().direction)));
  RC_ASSERT(m == q.tangent.dim() - q.gauge.dim());
  RC_ASSERT(is_skew(q.form) && rank(q.form) == m);
  RC_ASSERT((q.coordinates * q.gauge.basis().transpose()).is_zero());
  RC_ASSERT(rank(q.coordinates * q.tangent.basis().transpose()) == m);
  if (q.tangent.dim() > 0) {
    const QM y = integer_matrix(2, q.tangent.dim()) * q.tangent.basis();  // two vectors of TM_c, as rows
    const QM cy = q.coordinates * y.transpose();                          // C y, C y' as columns
    RC_ASSERT(y.block(0, 1, 0, n) * s.omega * y.block(1, 2, 0, n).transpose() ==
              cy.block(0, m, 0, 1).transpose() * q.form * cy.block(0, m, 1, 2));
  }
  const std::vector<Q> x = some_point(db.tower.back());
  std::vector<Q> de = (s.hessian * QM::column(x)).col(0);
  for (Index i = 0; i < n; ++i) de[i] += s.gradient[i];
  RC_ASSERT((QM::from_rows({de}, n) * q.gauge.basis().transpose()).is_zero());  // Lemma 3.20 (d)
  const std::vector<Q> field = total_energy_field(s, x, some_point(multipliers(s, db, x)));
  const std::vector<Q> z = (q.coordinates * QM::column(x)).col(0);
  RC_ASSERT((q.coordinates * QM::column(field)).col(0) == quotient_field(q, z));  // (3.8)
  std::vector<Q> xz = q.point;
  const std::vector<Q> cx0 = (q.coordinates * QM::column(q.point)).col(0);
  std::vector<Q> dz(m);
  for (Index i = 0; i < m; ++i) dz[i] = z[i] - cx0[i];
  const std::vector<Q> sdz = (q.section * QM::column(dz)).col(0);
  for (Index i = 0; i < n; ++i) xz[i] += sdz[i];
  RC_ASSERT(db.tower.back().contains_point(xz));
  RC_ASSERT((q.coordinates * QM::column(xz)).col(0) == z);
}

// Lemma 3.23 (d)–(e) for every choice, not only the χ picked from the constraints: V any complement of
// ker ω in (T M_c)^Ω ((3.12); a random one: classify's complement plus random multiples of ker ω) —
// dim V = 2s; (3.13) V^♭ ⊕ (ker ω)^♭ = (T M_c)°; T M_c ⊆ V^Ω = T S^V, symplectic, of dim M_c + dim ker ω;
// dχ′, dψ independent and det Σ′ ≠ 0; and the motion by χ′'s Dirac bracket is the canonical one,
// J*′ dE_T = J dE_T on M_c (E_T is first class), whichever V.
RC_GTEST_PROP(DiracBergmann, Lemma3_23d_AnySecondClassChoice, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const ConstraintClasses<Q> cl = classify_constraints(s.omega, db.constraints);
  const Subspace<Q> tmc = db.tower.back().direction;
  const Subspace<Q> kerw = form_kernel(restrict_form(s.omega, tmc));
  const QM e = extending_rows(kerw.basis(), symplectic_complement(s.omega, tmc).basis());
  const Subspace<Q> v = Subspace<Q>::span(e + integer_matrix(e.rows(), kerw.dim()) * kerw.basis());
  const SecondClassChoice<Q> ch = second_class_choice(s.omega, db.tower.back(), v);
  RC_TAG("2s = " + std::to_string(v.dim()) + ", dim ker w = " + std::to_string(kerw.dim()));
  RC_ASSERT(v.dim() == 2 * cl.s);
  const Subspace<Q> vflat = Subspace<Q>::span(v.basis() * s.omega), kflat = Subspace<Q>::span(kerw.basis() * s.omega);
  RC_ASSERT(intersection(vflat, kflat).dim() == 0u);
  RC_ASSERT(sum(vflat, kflat) == annihilator(tmc));  // (3.13)
  RC_ASSERT(contains(ch.tangent, tmc));
  RC_ASSERT(form_kernel(restrict_form(s.omega, ch.tangent)).dim() == 0u);
  RC_ASSERT(ch.tangent.dim() == tmc.dim() + kerw.dim());
  RC_ASSERT(rank(vstack(gradients(ch.chi), gradients(cl.first))) == ch.chi.rows() + cl.first.rows());
  RC_ASSERT(rank(ch.sigma) == ch.sigma.rows());
  const std::vector<Q> x = some_point(db.tower.back());
  const std::vector<Q> l = some_point(multipliers(s, db, x));
  const std::vector<Q> d = total_energy_differential(s, x, l);
  RC_ASSERT((ch.dirac_tensor * QM::column(d)).col(0) == total_energy_field(s, x, l));
}

// Lemma 3.23 (d)–(e) in §3.3's abstract setting, planted: in canonical coordinates S fixes (q_i, p_i) for
// i in A (second class pairs) and p_j for j in B (first class), then a unimodular change and a shift —
// so 2s = 2|A| and dim ker ω = |B| are known, and both are often nonzero together (the case where the
// choice of V matters).  For a random V with (3.12): dim V = 2s, (3.13), T S ⊆ V^Ω symplectic of dim
// S + dim ker ω, det Σ′ ≠ 0, and (e): the Dirac bracket's field of any F is the Hamiltonian field of F on
// S^V, J*′ dF = X_{F|S^V} (the unique X ∈ V^Ω with Ω(X, y) = dF(y) for all y ∈ V^Ω).
RC_GTEST_PROP(DiracBergmann, Lemma3_23d_PlantedSecondClass, ()) {
  const Index m = pick_size(1, 4), n = 2 * m;
  const QM change = unimodular(n);
  const QM w = pull_back(canonical_form(n, m), change);
  const Index pairs = *rc::gen::inRange<Index>(0, m + 1), firsts = *rc::gen::inRange<Index>(0, m - pairs + 1);
  QM rows(2 * pairs + firsts, n);
  for (Index i = 0; i < pairs; ++i) rows(2 * i, i) = rows(2 * i + 1, m + i) = Q(1);  // q_i, p_i
  for (Index j = 0; j < firsts; ++j) rows(2 * pairs + j, m + pairs + j) = Q(1);      // p_j
  AffineSubspace<Q> sub;
  sub.empty = false;
  sub.direction = kernel(rows * change);
  sub.point = integer_vector(n, 2);
  RC_TAG("2s = " + std::to_string(2 * pairs) + ", dim ker w = " + std::to_string(firsts));
  const Subspace<Q> kerw = form_kernel(restrict_form(w, sub.direction));
  RC_ASSERT(kerw.dim() == firsts);
  const QM e = extending_rows(kerw.basis(), symplectic_complement(w, sub.direction).basis());
  const Subspace<Q> v = Subspace<Q>::span(e + integer_matrix(e.rows(), kerw.dim()) * kerw.basis());
  const SecondClassChoice<Q> ch = second_class_choice(w, sub, v);
  RC_ASSERT(v.dim() == 2 * pairs);
  const Subspace<Q> vflat = Subspace<Q>::span(v.basis() * w), kflat = Subspace<Q>::span(kerw.basis() * w);
  RC_ASSERT(intersection(vflat, kflat).dim() == 0u);
  RC_ASSERT(sum(vflat, kflat) == annihilator(sub.direction));  // (3.13)
  RC_ASSERT(contains(ch.tangent, sub.direction));
  RC_ASSERT(ch.tangent.dim() == sub.direction.dim() + firsts);
  RC_ASSERT(form_kernel(restrict_form(w, ch.tangent)).dim() == 0u);
  RC_ASSERT(rank(ch.sigma) == 2 * pairs);
  const std::vector<Q> df = integer_vector(n);
  const AffineSubspace<Q> x = solve_on_subspace(restrict_form(w, ch.tangent), df);
  RC_ASSERT(!x.empty && x.direction.dim() == 0u);
  RC_ASSERT((ch.dirac_tensor * QM::column(df)).col(0) == x.point);  // (e)
  // Def 3.22: S is first class in P exactly when it has no second class pair; (c): in S^V it always is
  RC_ASSERT(is_first_class_submanifold(w, sub.direction) == (pairs == 0));
  RC_ASSERT(contains(sub.direction, intersection(symplectic_complement(w, sub.direction), ch.tangent)));
}

// Def 3.22 on M_c: first class (every function vanishing on it first class) ⇔ no second class constraint
// (2s = 0) ⇔ coisotropic, (T M_c)^Ω ⊆ T M_c.
RC_GTEST_PROP(DiracBergmann, Def3_22_FirstClassSubmanifold, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const Subspace<Q>& tmc = db.tower.back().direction;
  const bool first = is_first_class_submanifold(s.omega, tmc);
  RC_CLASSIFY(first, "first class");
  RC_ASSERT(first == (classify_constraints(s.omega, db.constraints).s == 0));
  RC_ASSERT(first == contains(tmc, symplectic_complement(s.omega, tmc)));
}

// CEF Def 3.10 and Lemmas 3.12–3.17 on the linear first class functions f = α·x of M_c (X_f = J α):
// 3.12 (b) {X_f : f ∈ R^(c)} = TM_c; 3.13 (a) f ∈ R^(c) is constant along K_c; 3.16 for f ∈ R^(c):
// f|_{M_c} constant ⇔ X_f ∈ K_c = ker ω_c ⇔ {f, h} = 0 on M_c for every h ∈ R^(c) (for a random f and for a
// random first class constraint, f ∈ I^(c)); 3.17: (p_{K_c})_* is onto M̄_c's linear functions, its kernel
// is I^(c), and it is a Poisson map, {f, h} = {f̄, h̄} in ω̄_c's bracket.
RC_GTEST_PROP(DiracBergmann, Lemmas3_12_3_17_FirstClassFunctions, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const GaugeQuotient<Q> q = gauge_quotient(s, db);
  const QM j = poisson_tensor(s.omega);
  const Index m = q.form.rows();
  const Subspace<Q> r = first_class_covectors(s.omega, q.tangent);
  const Subspace<Q> ideal = intersection(r, annihilator(q.tangent));  // I^(c)
  RC_TAG("dim R = " + std::to_string(r.dim()) + ", dim I = " + std::to_string(ideal.dim()));
  RC_ASSERT(map(j, r) == q.tangent);                               // 3.12 (b)
  RC_ASSERT((r.basis() * q.gauge.basis().transpose()).is_zero());  // 3.13 (a)
  QM bars(0, m);
  for (Index i = 0; i < r.dim(); ++i) bars = vstack(bars, QM::from_rows({push_forward(q, r.basis().row(i))}, m));
  RC_ASSERT(rank(bars) == m);             // 3.17: onto
  RC_ASSERT(r.dim() - m == ideal.dim());  // 3.17: its kernel is I^(c)
  const QM alpha = integer_matrix(1, r.dim()) * r.basis(), beta = integer_matrix(1, r.dim()) * r.basis();
  const QM abar = QM::from_rows({push_forward(q, alpha.row(0))}, m),
           bbar = QM::from_rows({push_forward(q, beta.row(0))}, m);
  RC_ASSERT(alpha * j * beta.transpose() == abar * poisson_tensor(q.form) * bbar.transpose());  // 3.17: Poisson
  const QM gamma = integer_matrix(1, ideal.dim()) * ideal.basis();
  for (const QM& c : {alpha, gamma}) {  // 3.16 (i) ⇔ (ii) ⇔ (iii)
    const bool constant = (c * q.tangent.basis().transpose()).is_zero();
    const bool in_gauge = contains(q.gauge, (j * c.transpose()).col(0));
    const bool commutes = (c * j * r.basis().transpose()).is_zero();
    RC_ASSERT(constant == in_gauge);
    RC_ASSERT(in_gauge == commutes);
  }
}

// CEF Thm 3.19, Lemma 3.20 (3.6)–(3.7) and Remark 3.21 on M̃_c = M_c / K̃_c: C̃ kills exactly K̃_c on TM_c; two
// solutions X, X′ of (3.4) at x ∈ M_c (any two multipliers) differ by K̃_c and project to the one X̃ = C̃ X —
// uniqueness recovered on M̃_c; and the fibration p_{K_c K̃_c} (P) carries C̃ to C on TM_c, so X̃ to X̄.
RC_GTEST_PROP(DiracBergmann, Lemma3_20_TildeQuotient, ()) {
  const ConstrainedSystem<Q> s = *constrained_systems();
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  if (!db.consistent) return;
  const GaugeQuotient<Q> q = gauge_quotient(s, db);
  RC_TAG("dim M~_c = " + std::to_string(q.tilde_coordinates.rows()) +
         ", dim Mbar_c = " + std::to_string(q.form.rows()));
  const std::vector<Q> x = some_point(db.tower.back());
  const AffineSubspace<Q> lambda = multipliers(s, db, x);
  RC_ASSERT(tilde_quotient_fails(s, q, x, some_point(lambda), some_point(lambda)) == "");
}

// The same where M̃_c ≠ M̄_c (rare among random systems): L = ½ (q̇₁ − q₂)², so p₂ = 0 is primary and
// E = ½ p₁² + p₁ q₂ gives the secondary p₁ = 0, both first class: K_c = TM_c (dim 2, M̄_c a point) but
// K̃_c = span ∂/∂q₂ (dim 1): M̃_c is the line of q₁ — Remark 3.21's physical state is finer than M̄_c's.
TEST(DiracBergmann, Lemma3_20_TildeQuotientFinerThanBar) {
  ConstrainedSystem<Q> s;
  s.omega = QM(4, 4);  // (q₁, q₂, p₁, p₂), Ω = dq ∧ dp
  for (Index i = 0; i < 2; ++i) s.omega(i, 2 + i) = Q(1), s.omega(2 + i, i) = Q(-1);
  s.hessian = QM(4, 4);
  s.hessian(2, 2) = s.hessian(1, 2) = s.hessian(2, 1) = Q(1);
  s.gradient.assign(4, Q(0));
  s.primary = QM::from_rows({{Q(0), Q(0), Q(0), Q(1), Q(0)}}, 5);
  const DiracBergmannResult<Q> db = dirac_bergmann(s);
  ASSERT_TRUE(db.consistent);
  const GaugeQuotient<Q> q = gauge_quotient(s, db);
  EXPECT_EQ(q.gauge.dim(), 2u);
  EXPECT_EQ(q.physical_gauge.dim(), 1u);
  EXPECT_EQ(q.tilde_coordinates.rows(), 1u);
  EXPECT_EQ(q.form.rows(), 0u);
  const std::vector<Q> x{Q(2), Q(-1), Q(0), Q(0)};
  const AffineSubspace<Q> lambda = multipliers(s, db, x);
  ASSERT_FALSE(lambda.empty);
  std::vector<Q> other = lambda.point;
  for (Index i = 0; i < other.size(); ++i) other[i] += lambda.direction.dim() ? lambda.direction.basis()(0, i) : Q(0);
  EXPECT_EQ(tilde_quotient_fails(s, q, x, lambda.point, other), "");
}
