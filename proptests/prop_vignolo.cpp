// V's objects at a point of 𝒜 ⊂ j₁(𝒱_{n+1}) on random data (dcad/reference/vignolo.hpp and its fast twin):
// L's first and second derivatives and affine constraints drawn freely at one point (every choice is
// realized by a polynomial L and g), L regular (Γ positive definite) or of any rank.
//  - §2.1: the contact bundle, defined as the annihilator of the distribution j₂ generates, is spanned by
//    the ω^i = dq^i − q̇^i dt; two dynamical flows differ by a vertical vector (V (2.3));
//  - (2.7b)–(2.12): 𝒜's velocities q̇ + ψ_A z^A with g ψ_A = 0 (2.8); τ(𝒜) (2.9) is affine of dimension r
//    over V(𝒜) = ψ_A ∂/∂q̇ (2.10); the Chetaev bundle (2.11) is spanned by g^σ_i ω̃^i (2.12) and is D^v on 𝒜;
//  - §2.2: Ω_l (V §3.4's expression) is the pull-back l*Ω̃_l of (2.19); Ω̃_l is symplectic iff L is regular;
//  - (3.4): for L regular, (3.3)'s unique solution is the horizontal lift of (2.13)'s, a dynamical flow on 𝒜;
//  - Prop 3.1, (3.7), Thm 3.1, (3.5)–(3.6), Prop 3.2(i): the splitting, 𝒫 of the unconstrained flow (2.20)
//    solves (3.3), ♯(ν^σ) and ♯(dφ^σ) as printed, 𝒫(X_{dφ^σ}) = 0;
//  - Prop 3.5 with (3.11): with (3.9), (3.3) on 𝓛(𝒜) and (2.13) on 𝒜 have solutions together, π_* maps the
//    first onto the second, the lift maps back, and dφ_l vanishes on every solution — for any L; Prop 3.7:
//    J̃ maps each solution into 𝒪̃_l;
//  - §3.3: z ∈ M_1 by (3.12), by (3.15)'s directions and by the solvability of (3.2), (3.9), one answer;
//  - §3.5 as printed: Ω̃_l, dφ_l, M_1 = {ẋ + t = 0}, the family (3.26) (with ERRATA's Ż^w ∂/∂ẇ; as printed it
//    fails), (3.27)'s tangency, J̃(Ẑ) = (1 − ẇ)∂/∂ẇ, 𝒪̃_l = span ∂/∂ẇ and (3.28) on S = {ẇ = 1};
//  - §3.4, (3.17), (3.21): 𝒪_l = ker Ω_l ∩ V(D^v) is (3.17b)'s; 𝒪̃_l ⌟ Ω̃_l = 0 and ⟨𝒪̃_l, dφ_l⟩ = 0;
//  - fast = reference on each (fast goes by (2.3), (2.10), (2.12), l*Ω̃_l, Ω̃_l = dφ_l ∧ dt + π*Ω_l, Thm 3.1's
//    formula and (3.17b));
//  - V's "L regular" is not enough: C = g Γ⁻¹ gᵀ must be invertible too (Γ indefinite: a line of solutions or none).
#include "support/convert.hpp"
#include "support/gen.hpp"
#include "support/tally.hpp"

#include "dcad/fast/vignolo.hpp"
#include "dcad/reference/vignolo.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

namespace {

using Point = ref::VignoloPoint<Q>;
using Aff = ref::AffineSubspace<Q>;

/// Γ = ∂²L/∂q̇∂q̇ positive definite (V's regular L with C = g Γ⁻¹ gᵀ invertible), invertible of any signature, or
/// of any rank.
enum class Gamma { definite, invertible, any };

/// A random point of 𝒜 with its data.
Point random_point(Gamma gamma, Index min_constraints = 0) {
  Point d;
  const Index n = pick_size(std::max<Index>(1, min_constraints), 4);
  d.n = n;
  const Index m = *rc::gen::inRange<Index>(min_constraints, n + 1);
  d.g = m ? hstack(QM::identity(m), integer_matrix(m, n - m)) * unimodular(n) : QM(0, n);
  d.qdot = integer_vector(n);
  d.g0 = (d.g * QM::column(d.qdot)).col(0);
  for (Q& c : d.g0) c = -c;
  d.lt = integer_vector(1)[0];
  d.lq = integer_vector(n);
  d.lv = integer_vector(n);
  d.ltv = integer_vector(n);
  d.lqv = integer_matrix(n, n);
  if (gamma == Gamma::definite) {
    const QM a = integer_matrix(n, n);
    d.lvv = a.transpose() * a + QM::identity(n);
  } else {
    d.lvv = symmetric_matrix(n, gamma == Gamma::invertible ? n : *rc::gen::inRange<Index>(0, n + 1));
  }
  d.phi_t = integer_vector(m);
  d.phi_q = m ? integer_matrix(m, n) : QM(0, n);
  return d;
}

fast::VignoloPoint to_fast_point(const Point& d) {
  fast::VignoloPoint f;
  f.n = d.n;
  f.qdot = to_double(d.qdot);
  f.lt = to_double(std::vector<Q>{d.lt})(0);
  f.lq = to_double(d.lq);
  f.lv = to_double(d.lv);
  f.ltv = to_double(d.ltv);
  f.lqv = to_double(d.lqv);
  f.lvv = to_double(d.lvv);
  f.g = d.g.rows() ? to_double(d.g) : Eigen::MatrixXd(0, static_cast<Eigen::Index>(d.n));
  f.g0 = to_double(d.g0);
  f.phi_t = to_double(d.phi_t);
  f.phi_q = d.g.rows() ? to_double(d.phi_q) : Eigen::MatrixXd(0, static_cast<Eigen::Index>(d.n));
  return f;
}

std::vector<Q> times(const QM& a, const std::vector<Q>& x) { return (a * QM::column(x)).col(0); }
Q dot(const std::vector<Q>& a, const std::vector<Q>& b) {
  Q s(0);
  for (Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

/// The exact and the double subspace agree (dimension, and angle at rounding level), where fast is certain.
bool near(const QSub& r, const fast::Subspace& f, const char* what) {
  const bool agree = r.dim() == static_cast<Index>(f.dim()) &&
                     (r.dim() == 0 || fast::largest_principal_angle_sin(to_fast(r), f) < 1e-8);
  return !tally(what, f.certain().yes(), agree);
}
bool near(const Aff& r, const fast::AffineSubspace& f, const char* what) {
  if (r.empty || f.empty) return !tally(what, f.certain.yes(), r.empty == f.empty);
  if (!near(r.direction, f.direction, what)) return false;
  // f's point is in r: its difference from r's point lies in the direction
  const Eigen::VectorXd diff = f.point - to_double(r.point);
  const Eigen::MatrixXd q = to_fast(r.direction).columns();
  const double off = (diff - q * (q.transpose() * diff)).norm();
  return !tally(what, f.certain.yes(), off <= 1e-8 * (1 + f.point.norm()));
}
bool near(const QM& r, const Eigen::MatrixXd& f) { return (to_double(r) - f).norm() <= 1e-9 * (1 + f.norm()); }

/// Every point of `a` (its point and its point plus each direction) satisfies `pred`.
template <class Pred>
bool all_points(const Aff& a, Pred pred) {
  if (a.empty) return true;
  if (!pred(a.point)) return false;
  for (Index k = 0; k < a.direction.dim(); ++k) {
    std::vector<Q> x = a.point;
    for (Index j = 0; j < x.size(); ++j) x[j] += a.direction.basis()(k, j);
    if (!pred(x)) return false;
  }
  return true;
}

}  // namespace

RC_GTEST_PROP(Vignolo, Section2_1_ContactFormsSpanTheAnnihilatorOfTheDynamicalFlows, ()) {
  const Point d = random_point(*rc::gen::arbitrary<bool>() ? Gamma::definite : Gamma::any);
  const Index n = d.n;
  const Aff j2 = ref::dynamical_flows(d);
  RC_ASSERT(!j2.empty);
  RC_ASSERT(j2.direction.dim() == n);  // two flows differ by a vertical vector Z^i ∂/∂q̇^i (2.3)
  for (Index k = 0; k < n; ++k)
    for (Index j = 0; j < n + 1; ++j) RC_ASSERT(j2.direction.basis()(k, j) == 0);
  RC_ASSERT(j2.point[0] == 1);  // ⟨Z, dt⟩ = 1 and the q-rates are q̇ (2.3)
  for (Index i = 0; i < n; ++i) RC_ASSERT(j2.point[1 + i] == d.qdot[i]);
  const QSub c = ref::contact_bundle(d);
  RC_ASSERT(c == QSub::span(ref::contact_forms(d)));  // spanned by ω^i = dq^i − q̇^i dt
  RC_ASSERT(c.dim() == n);
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(j2, fast::dynamical_flows(f), "V §2.1 j2"));
  RC_ASSERT(near(c, fast::contact_bundle(f), "V §2.1 contact bundle"));
}

RC_GTEST_PROP(Vignolo, Eq2_7_to_2_12_TauChetaevAndTheVelocitiesOfA, ()) {
  const Point d = random_point(*rc::gen::arbitrary<bool>() ? Gamma::definite : Gamma::any);
  const Index n = d.n, m = d.g.rows(), r = n - m;
  const Aff psi = ref::constraint_velocities(d);
  RC_ASSERT(psi.direction.dim() == r);  // rank ψ_A = r
  RC_ASSERT(psi.contains_point(d.qdot));
  if (m) RC_ASSERT((d.g * psi.direction.basis().transpose()).is_zero());  // (2.8)
  const Aff tau = ref::tau_constraint(d);
  RC_ASSERT(!tau.empty);
  RC_ASSERT(tau.direction.dim() == r);  // affine over V(𝒜)
  QM vertical_psi(r, 2 * n + 1);        // i_*(∂/∂z^A) = ψ^i_A ∂/∂q̇^i (2.10)
  for (Index a = 0; a < r; ++a)
    for (Index i = 0; i < n; ++i) vertical_psi(a, 1 + n + i) = psi.direction.basis()(a, i);
  RC_ASSERT(tau.direction == QSub::span(vertical_psi));
  RC_ASSERT(all_points(tau, [&](const std::vector<Q>& x) {  // Z = ∂/∂t + ψ^i ∂/∂q^i + … (2.10), tangent to 𝒜
    bool ok = x[0] == 1 && ref::contains(ref::constraint_tangent(d), x);
    for (Index i = 0; i < n; ++i) ok = ok && x[1 + i] == d.qdot[i];
    return ok;
  }));
  const QSub chi = ref::chetaev_bundle(d);
  RC_ASSERT(chi.dim() == m);
  RC_ASSERT(chi == QSub::span(m ? d.g * ref::contact_forms(d) : QM(0, 2 * n + 1)));  // (2.12): μ^σ = g^σ_i ω̃^i
  QM dv(m, 2 * n + 1);  // D^v: g^σ = g^σ_i dq^i + g^σ_0 dt, pulled back to j₁ (footnote 1: χ(𝒜) = D^v on 𝒜)
  for (Index s = 0; s < m; ++s) {
    dv(s, 0) = d.g0[s];
    for (Index i = 0; i < n; ++i) dv(s, 1 + i) = d.g(s, i);
  }
  RC_ASSERT(chi == QSub::span(dv));
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(psi, fast::constraint_velocities(f), "V (2.7b) velocities"));
  RC_ASSERT(near(tau, fast::tau_constraint(f), "V (2.9) tau"));
  RC_ASSERT(near(ref::constraint_tangent(d), fast::constraint_tangent(f), "V T_zA"));
  RC_ASSERT(near(chi, fast::chetaev_bundle(f), "V (2.11) Chetaev bundle"));
}

RC_GTEST_PROP(Vignolo, Section2_2_PoincareCartanIsThePullBackOfTheBundleForm, ()) {
  const bool regular = *rc::gen::arbitrary<bool>();
  const Point d = random_point(regular ? Gamma::definite : Gamma::any);
  const QM w = ref::lagrangian_bundle_form(d), s = ref::section_tangent(d), pc = ref::poincare_cartan(d);
  RC_ASSERT(ref::is_skew(w));
  RC_ASSERT(s.transpose() * w * s == pc);  // Ω_l = l*(Ω̃_l)
  // regular section ⇔ Ω̃_l symplectic (rank 2n + 2)
  RC_ASSERT((ref::rank(w) == 2 * d.n + 2) == (ref::rank(d.lvv) == d.n));
  if (regular) RC_ASSERT(ref::is_symplectic(w));
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(w, fast::lagrangian_bundle_form(f)));
  RC_ASSERT(near(pc, fast::poincare_cartan(f)));
  RC_ASSERT(near(s, fast::section_tangent(f)));
  RC_ASSERT(near(QM::column(ref::trivialization_differential(d)), fast::trivialization_differential(f)));
  RC_ASSERT(near(QM::column(ref::lagrangian_differential(d)), fast::lagrangian_differential(f)));
  RC_ASSERT(near(ref::chetaev_forms(d), fast::chetaev_forms(f)));
  RC_ASSERT(near(ref::bundle_constraint_differentials(d), fast::bundle_constraint_differentials(f)));
  const std::vector<Q> x = integer_vector(2 * d.n + 1);  // (2.17) and (2.18) on a random vector
  RC_ASSERT(near(QM::column(ref::bundle_horizontal_lift(d, x)), fast::bundle_horizontal_lift(f, to_double(x))));
  const std::vector<Q> y = integer_vector(2 * d.n + 2);
  RC_ASSERT(near(QM::column(ref::vertical_endomorphism(d, y)), fast::vertical_endomorphism(f, to_double(y))));
}

RC_GTEST_PROP(Vignolo, Eq3_4_RegularSolutionIsTheHorizontalLiftOfTheLagrangeChetaevFlow, ()) {
  const Point d = random_point(Gamma::definite);
  const Aff z = ref::lagrange_chetaev_fields(d, false), zhat = ref::nonholonomic_fields(d, true);
  RC_ASSERT(!z.empty);  // L regular, g of full rank: one dynamical flow (2.13)–(2.14)
  RC_ASSERT(z.direction.dim() == 0);
  RC_ASSERT(ref::tau_constraint(d).contains_point(z.point));  // a dynamical flow tangent to 𝒜
  // (2.14): d/dt ∂L/∂q̇ − ∂L/∂q = Γ q̈ + ∂²L/∂t∂q̇ + ∂²L/∂q∂q̇ q̇ − ∂L/∂q ∈ span{g^σ} (the reaction λ_σ g^σ)
  const std::vector<Q> acc(z.point.begin() + 1 + static_cast<long>(d.n), z.point.end());
  std::vector<Q> reaction = times(d.lvv, acc);
  const std::vector<Q> bq = times(d.lqv, d.qdot);
  for (Index i = 0; i < d.n; ++i) reaction[i] += d.ltv[i] + bq[i] - d.lq[i];
  RC_ASSERT(ref::contains(QSub::span(d.g.rows() ? d.g : QM(0, d.n)), reaction));
  RC_ASSERT(!zhat.empty);
  RC_ASSERT(zhat.direction.dim() == 0);
  RC_ASSERT(zhat.point == ref::bundle_horizontal_lift(d, z.point));  // (3.4): Ẑ = Z + Z(L) ∂/∂u̇
  // (3.3) without (3.9), as §3.1 states it: the same unique solution (3.9) is then a consequence
  const Aff loose = ref::nonholonomic_fields(d, false);
  RC_ASSERT(!loose.empty && loose.direction.dim() == 0);
  RC_ASSERT(loose.point == zhat.point);
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(z, fast::lagrange_chetaev_fields(f, false), "V (2.13) regular"));
  RC_ASSERT(near(zhat, fast::nonholonomic_fields(f, true), "V (3.3)+(3.9) regular"));
  RC_ASSERT(near(loose, fast::nonholonomic_fields(f, false), "V (3.3) as printed, regular"));
}

RC_GTEST_PROP(Vignolo, Prop3_1_Thm3_1_TheConstrainedFlowIsTheProjectionOfTheFreeOne, ()) {
  const Point d = random_point(Gamma::definite);
  const Index n = d.n, m = d.g.rows(), dim = 2 * n + 2;
  const QM w = ref::lagrangian_bundle_form(d);
  const ref::ConstrainedSplitting<Q> s = ref::constrained_splitting(d);
  const QSub other = ref::sum(s.chetaev_complement, s.tangent_complement);
  RC_ASSERT(s.chetaev_complement.dim() == m);
  RC_ASSERT(ref::intersection(s.chetaev_complement, s.tangent_complement).dim() == 0);
  RC_ASSERT(ref::form_rank(ref::restrict_form(w, other)) == other.dim());  // Prop 3.1: a symplectic subspace
  RC_ASSERT(ref::intersection(other, s.constrained).dim() == 0);           // (3.7)
  RC_ASSERT(other.dim() + s.constrained.dim() == dim);
  const Aff free = ref::unconstrained_fields(d), zhat = ref::nonholonomic_fields(d, false);
  RC_ASSERT(!free.empty && free.direction.dim() == 0);
  RC_ASSERT(zhat.contains_point(ref::constrained_projection(d, free.point)));                        // Thm 3.1
  RC_ASSERT(ref::nonholonomic_fields(d, true).point == ref::constrained_projection(d, free.point));  // and (3.9)
  const QM nu = ref::chetaev_forms(d), dphi = ref::bundle_constraint_differentials(d);
  const QM gamma_inv = ref::inverse(d.lvv);
  for (Index sg = 0; sg < m; ++sg) {
    const std::vector<Q> x_nu = ref::sharp(w, nu.row(sg)), x_dphi = ref::sharp(w, dphi.row(sg));
    const std::vector<Q> gi = times(gamma_inv, d.g.row(sg));
    for (Index i = 0; i < n; ++i) {
      RC_ASSERT(x_dphi[1 + i] == -gi[i]);  // (3.5): X_{dφ^σ} = −Γ^{ij} g^σ_j ∂/∂q^i + vertical
      RC_ASSERT(x_nu[1 + i] == 0);  // (3.6): X_{ν^σ} = −Γ^{ij} g^σ_j (∂/∂q̇^i + ∂L/∂q̇^i ∂/∂u̇)
      RC_ASSERT(x_nu[1 + n + i] == -gi[i]);
    }
    RC_ASSERT(x_nu[0] == 0);
    RC_ASSERT(x_dphi[0] == 0);  // (3.5): no ∂/∂t
    RC_ASSERT(x_nu[dim - 1] == -dot(gi, d.lv));
    RC_ASSERT(ref::constrained_projection(d, x_dphi) == std::vector<Q>(dim));  // Prop 3.2(i): φ^σ are Casimirs
  }
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(free, fast::unconstrained_fields(f), "V (2.20)"));
  const Eigen::VectorXd pf = fast::constrained_projection(f, to_double(free.point));
  RC_ASSERT((pf - to_double(zhat.point)).norm() <= 1e-8 * (1 + pf.norm()));
  const fast::ConstrainedSplitting fs = fast::constrained_splitting(f);
  RC_ASSERT(near(s.chetaev_complement, fs.chetaev_complement, "V Prop 3.1 (chi0)^perp"));
  RC_ASSERT(near(s.tangent_complement, fs.tangent_complement, "V Prop 3.1 TL(A)^perp"));
  RC_ASSERT(near(s.constrained, fs.constrained, "V (3.7) chi0 ∩ TL(A)"));
}

RC_GTEST_PROP(Vignolo, Prop3_5_SolutionsOnTheBundleAndOnAAreOneByProjection, ()) {
  const Point d = random_point(Gamma::any);  // any rank of Γ
  const Index dim = 2 * d.n + 1;
  const Aff z = ref::lagrange_chetaev_fields(d, true), zhat = ref::nonholonomic_fields(d, true);
  RC_ASSERT(z.empty == zhat.empty);  // Prop 3.5: algebraic solutions together
  if (!z.empty) {
    QM pi(dim, dim + 1);  // π_*
    for (Index i = 0; i < dim; ++i) pi(i, i) = Q(1);
    RC_ASSERT(ref::map(pi, zhat.direction) == z.direction);
    RC_ASSERT(z.contains_point(times(pi, zhat.point)));
    RC_ASSERT(zhat.contains_point(ref::bundle_horizontal_lift(d, z.point)));  // the lift solves (3.2), (3.9)
    const std::vector<Q> dphil = ref::trivialization_differential(d);
    RC_ASSERT(dot(dphil, zhat.point) == 0);  // (3.11)
    for (Index k = 0; k < zhat.direction.dim(); ++k) RC_ASSERT(dot(dphil, zhat.direction.basis().row(k)) == 0);
    const QSub ot = ref::lifted_sode_obstruction(d);  // Prop 3.7: J̃(X) ∈ 𝒪̃_l, here at the point, for every solution
    RC_ASSERT(
        all_points(zhat, [&](const std::vector<Q>& x) { return ref::contains(ot, ref::vertical_endomorphism(d, x)); }));
  }
  // §3.3: z ∈ M_1 by (3.12) ⇔ dφ_l vanishes on (3.15)'s directions ⇔ (3.2), (3.9) have a solution at z
  const bool m1 = ref::in_first_constraint_manifold(d);
  RC_ASSERT(m1 == !zhat.empty);
  const QSub a = ref::first_constraint_directions(d);
  RC_ASSERT(m1 == (times(a.basis(), ref::trivialization_differential(d)) == std::vector<Q>(a.dim())));
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(!tally("V (3.12) z in M_1", !fast::in_first_constraint_manifold(f).unknown(),
                   fast::in_first_constraint_manifold(f).yes() == m1));
  RC_ASSERT(near(a, fast::first_constraint_directions(f), "V (3.15) directions"));
  RC_ASSERT(near(ref::first_level_directions(d), fast::first_level_directions(f), "V TM_0 ∩ chi0"));
  RC_ASSERT(near(z, fast::lagrange_chetaev_fields(f, true), "V (2.13)+(3.9)"));
  RC_ASSERT(near(zhat, fast::nonholonomic_fields(f, true), "V (3.3)+(3.9) by Prop 3.5"));
}

RC_GTEST_PROP(Vignolo, Section3_4_TheObstructionDistributionIsInTheKernel, ()) {
  const Point d = random_point(Gamma::any);
  const Index n = d.n;
  const QSub o = ref::sode_obstruction(d), ot = ref::lifted_sode_obstruction(d);
  QM vg = ref::vstack(d.lvv, d.g.rows() ? d.g : QM(0, n));  // (3.17b): Γ V = 0, g V = 0
  RC_ASSERT(o.dim() == n - ref::rank(vg));
  for (Index k = 0; k < o.dim(); ++k) {
    const std::vector<Q> v = o.basis().row(k);
    for (Index j = 0; j < n + 1; ++j) RC_ASSERT(v[j] == 0);  // (3.17a): vertical, V^i ∂/∂q̇^i
    RC_ASSERT(times(vg, std::vector<Q>(v.begin() + 1 + n, v.end())) == std::vector<Q>(vg.rows()));
  }
  const QM w = ref::lagrangian_bundle_form(d);
  const std::vector<Q> dphil = ref::trivialization_differential(d);
  for (Index k = 0; k < ot.dim(); ++k) {
    const std::vector<Q> v = ot.basis().row(k);
    RC_ASSERT(ref::flat(w, v) == std::vector<Q>(2 * n + 2));                               // 𝒪̃_l ⌟ Ω̃_l = 0
    RC_ASSERT(dot(dphil, v) == 0);                                                         // ⟨𝒪̃_l, dφ_l⟩ = 0
    RC_ASSERT(v[2 * n + 1] == dot(d.lv, std::vector<Q>(v.begin() + 1 + n, v.end() - 1)));  // (3.21)
  }
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(o, fast::sode_obstruction(f), "V (3.17) O_l"));
  RC_ASSERT(near(ot, fast::lifted_sode_obstruction(f), "V (3.21) lifted O_l"));
}

TEST(Vignolo, BadDataIsRefusedNamingTheField) {
  // qdot off 𝒜 (g q̇ + g0 = 1), an asymmetric Γ, a missing entry: each twin names the field, expected and found
  Point d;
  d.n = 2;
  d.qdot = {Q(1), Q(0)};
  d.lq = d.lv = d.ltv = {Q(0), Q(0)};
  d.lqv = QM(2, 2);
  d.lvv = QM::identity(2);
  d.g = QM::from_rows({{Q(1), Q(1)}}, 2);
  d.g0 = {Q(0)};
  d.phi_t = {Q(0)};
  d.phi_q = QM(1, 2);
  const auto message = [](auto&& call) {
    try {
      call();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const auto both = [&](const Point& p, const std::string& part) {
    EXPECT_NE(message([&] { ref::poincare_cartan(p); }).find(part), std::string::npos) << part;
    EXPECT_NE(message([&] { fast::poincare_cartan(to_fast_point(p)); }).find(part), std::string::npos) << part;
  };
  both(d, "z on the constraint submanifold");
  d.g0 = {Q(-1)};
  EXPECT_NO_THROW(ref::poincare_cartan(d));
  Point asym = d;
  asym.lvv(0, 1) = Q(1);
  both(asym, "symmetric lvv");
  Point shortv = d;
  shortv.lq = {Q(0)};
  both(shortv, "lq of length 2, found length 1");
  EXPECT_NE(message([&] { ref::vertical_endomorphism(shortv, std::vector<Q>(6)); }).find("lq of length 2"),
            std::string::npos);
  EXPECT_NE(message([&] {
              fast::vertical_endomorphism(to_fast_point(shortv), Eigen::VectorXd::Zero(6));
            }).find("lq of length 2"),
            std::string::npos);
  EXPECT_NE(
      message([&] { ref::constrained_projection(d, std::vector<Q>(3)); }).find("X of length 2n + 2, found length 3"),
      std::string::npos);
  Point unconstrained = d;  // no constraint: g may be 0x0 (a default matrix) as well as 0xn
  unconstrained.g = QM();
  unconstrained.g0 = unconstrained.phi_t = {};
  unconstrained.phi_q = QM();
  EXPECT_EQ(ref::sode_obstruction(unconstrained).dim(), 0u);
  EXPECT_EQ(fast::sode_obstruction(to_fast_point(unconstrained)).dim(), 0);
  Point dependent = d;
  dependent.g = QM::from_rows({{Q(1), Q(1)}, {Q(2), Q(2)}}, 2);
  dependent.g0 = {Q(-1), Q(-2)};
  dependent.phi_t = {Q(0), Q(0)};
  dependent.phi_q = QM(2, 2);
  both(dependent, "independent constraints");
}

namespace {

/// V §3.5 at (t; x, y, z, w; ẋ, ẏ, ż = w, ẇ): L = ½(ẋ² + ẏ²) + w(ẋ + t) + z with the constraint ż − w = 0,
/// its derivatives taken by hand.
Point vignolo_3_5(const std::vector<Q>& v) {
  const Q &t = v[0], &w = v[4], &xd = v[5], &yd = v[6], &wd = v[7];
  Point d;
  d.n = 4;
  d.qdot = {xd, yd, w, wd};
  d.lt = w;
  d.lq = {Q(0), Q(0), Q(1), xd + t};
  d.lv = {xd + w, yd, Q(0), Q(0)};
  d.ltv = std::vector<Q>(4);
  d.lqv = QM(4, 4);
  d.lqv(0, 3) = Q(1);  // ∂²L/∂w∂ẋ
  d.lvv = QM(4, 4);
  d.lvv(0, 0) = d.lvv(1, 1) = Q(1);
  d.g = QM::from_rows({{Q(0), Q(0), Q(1), Q(0)}}, 4);
  d.g0 = {-w};
  d.phi_t = {Q(0)};
  d.phi_q = QM::from_rows({{Q(0), Q(0), Q(0), Q(-1)}}, 4);
  return d;
}

/// A vector of 𝓛 (t, x, y, z, w, ẋ, ẏ, ż, ẇ, u̇) from its nonzero components.
std::vector<Q> bundle_vector(std::initializer_list<std::pair<Index, Q>> entries) {
  std::vector<Q> x(10);
  for (const auto& [i, c] : entries) x[i] = c;
  return x;
}

}  // namespace

RC_GTEST_PROP(Vignolo, Section3_5_ExampleAsPrinted, ()) {
  std::vector<Q> v = integer_vector(8, 4);
  if (*rc::gen::arbitrary<bool>()) v[5] = -v[0];  // M_1 = {ẋ + t = 0}
  if (*rc::gen::arbitrary<bool>()) v[7] = Q(1);   // S = {ẇ = 1}
  const bool on_m1 = v[5] + v[0] == 0;
  const Point d = vignolo_3_5(v);
  const Q &t = v[0], &w = v[4], &xd = v[5], &yd = v[6], &wd = v[7];
  enum { T, X, Y, Z, W, XD, YD, ZD, WD, U };
  // Ω̃_l and dφ_l as printed
  QM printed(10, 10);
  const auto add = [&](const std::vector<Q>& a, const std::vector<Q>& b, const Q& c) {
    for (Index i = 0; i < 10; ++i)
      for (Index j = 0; j < 10; ++j) printed(i, j) += c * (a[i] * b[j] - b[i] * a[j]);
  };
  const auto e = [](Index i) { return bundle_vector({{i, Q(1)}}); };
  const std::vector<Q> omx = bundle_vector({{X, Q(1)}, {T, -xd}}), omy = bundle_vector({{Y, Q(1)}, {T, -yd}});
  add(e(U), e(T), Q(1));
  add(e(XD), omx, Q(1));
  add(e(W), omx, Q(1));
  add(e(YD), omy, Q(1));
  add(e(XD), e(T), -(xd + w));
  add(e(YD), e(T), -yd);
  RC_ASSERT(ref::lagrangian_bundle_form(d) == printed);
  RC_ASSERT(ref::trivialization_differential(d) ==
            bundle_vector({{U, Q(1)}, {XD, -xd - w}, {YD, -yd}, {W, -(xd + t)}, {T, -w}, {Z, Q(-1)}}));
  // (3.25) — (3.3) with (3.9) — has solutions exactly on M_1, the family (3.26) (ERRATA: Ż^w ∂/∂ẇ)
  const Aff sol = ref::nonholonomic_fields(d, true);
  RC_ASSERT(sol.empty == !on_m1);
  RC_ASSERT(ref::in_first_constraint_manifold(d) == on_m1);  // (3.12)
  if (!on_m1) return;
  const std::vector<Q> z0 = {Q(1), xd, yd, w, Q(0), Q(0), Q(0), Q(0), Q(0)};          // Z^w = Ż^w = 0
  const std::vector<Q> zw = {Q(0), Q(0), Q(0), Q(0), Q(1), Q(-1), Q(0), Q(1), Q(0)};  // ∂w − ∂ẋ + ∂ż
  const std::vector<Q> zwd = {Q(0), Q(0), Q(0), Q(0), Q(0), Q(0), Q(0), Q(0), Q(1)};  // ∂ẇ
  RC_ASSERT(sol.direction ==
            QSub::span(QM::from_rows({ref::bundle_horizontal_lift(d, zw), ref::bundle_horizontal_lift(d, zwd)}, 10)));
  RC_ASSERT(sol.contains_point(ref::bundle_horizontal_lift(d, z0)));  // (3.26a): Ẑ = Z + Z(L) ∂/∂u̇
  RC_ASSERT(!ref::contains(sol.direction, e(U)));  // as printed, Ż^w ∂/∂u̇: not a direction of (3.25)'s solutions
  // (3.27): tangent to M_1 iff Ẑ(ẋ + t) = Ẋ + Ż^0 = 0, i.e. Z^w = 1; J̃(Ẑ) = (1 − ẇ) ∂/∂ẇ and 𝒪̃_l = span ∂/∂ẇ
  std::vector<Q> z27 = z0;
  for (Index i = 0; i < 9; ++i) z27[i] += zw[i] + Q(*rc::gen::inRange(-3, 4)) * zwd[i];
  const std::vector<Q> zhat = ref::bundle_horizontal_lift(d, z27);
  RC_ASSERT(sol.contains_point(zhat));
  RC_ASSERT(zhat[XD] + zhat[T] == 0);
  RC_ASSERT(ref::bundle_horizontal_lift(d, z0)[XD] + 1 != 0);  // Z^w = 0: not tangent to M_1
  RC_ASSERT(ref::vertical_endomorphism(d, zhat) == bundle_vector({{WD, 1 - wd}}));
  RC_ASSERT(ref::lifted_sode_obstruction(d) == QSub::span(QM::from_rows({e(WD)}, 10)));
  // (3.28) on S = {ẇ = 1}: Z̄ = ∂t + ẋ∂x + ẏ∂y + ż∂z + ∂w − ∂ẋ + ∂ż + (ż + t) ∂/∂u̇, a dynamical flow there
  const std::vector<Q> zbar =
      bundle_vector({{T, Q(1)}, {X, xd}, {Y, yd}, {Z, w}, {W, Q(1)}, {XD, Q(-1)}, {ZD, Q(1)}, {U, w + t}});
  RC_ASSERT(sol.contains_point(zbar));
  RC_ASSERT((ref::vertical_endomorphism(d, zbar) == std::vector<Q>(10)) == (wd == 1));
  if (wd == 1) {  // Ẑ|_S = Z̄|_S + V|_S with V = Ż^w ∂/∂ẇ ∈ 𝒪̃_l
    std::vector<Q> rest = zhat;
    for (Index i = 0; i < 10; ++i) rest[i] -= zbar[i];
    RC_ASSERT(ref::contains(ref::lifted_sode_obstruction(d), rest));
  }
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(sol, fast::nonholonomic_fields(f, true), "V §3.5 (3.26)"));
}

// V's "L regular" (det Γ ≠ 0 and rank g maximal) makes C = g Γ⁻¹ gᵀ invertible only where Γ is definite (V's proof of
// Prop 3.1 says "in view of the regularity assumptions … the matrix C is non-singular").  For Γ invertible of any
// signature: (2.13) and (3.3) have one solution exactly where C is invertible, and (3.7) is a direct sum exactly there.
RC_GTEST_PROP(Vignolo, IndefiniteGammaSolvesUniquelyExactlyWhereCIsInvertible, ()) {
  const Point d = random_point(Gamma::invertible, 1);
  const Index m = d.g.rows();
  const QM c = d.g * ref::inverse(d.lvv) * d.g.transpose();
  const bool invertible = ref::rank(c) == m;
  const Aff z = ref::lagrange_chetaev_fields(d, false), zhat = ref::nonholonomic_fields(d, false);
  RC_TAG(invertible ? "C invertible" : "C singular");
  if (invertible) {
    RC_ASSERT(!z.empty && z.direction.dim() == 0);
    RC_ASSERT(!zhat.empty && zhat.direction.dim() == 0);
    RC_ASSERT(zhat.point == ref::bundle_horizontal_lift(d, z.point));  // (3.4)
    const Aff free = ref::unconstrained_fields(d);
    RC_ASSERT(ref::constrained_projection(d, free.point) == zhat.point);  // Thm 3.1
  } else {
    RC_ASSERT(z.empty || z.direction.dim() > 0);  // none, or a family: not "the unique solution"
    RC_ASSERT(zhat.empty == z.empty);
    bool refused = false;
    try {
      ref::constrained_projection(d, std::vector<Q>(2 * d.n + 2));
    } catch (const std::invalid_argument&) {
      refused = true;
    }
    RC_ASSERT(refused);  // (3.7) is not a direct sum
  }
  const fast::VignoloPoint f = to_fast_point(d);
  RC_ASSERT(near(z, fast::lagrange_chetaev_fields(f, false), "V (2.13) indefinite"));
  RC_ASSERT(near(zhat, fast::nonholonomic_fields(f, false), "V (3.3) indefinite"));
}

namespace {

/// L = ½(ẋ² − ẏ²) + a x with the constraint ẋ + ẏ = 0 at (t, x, y, ẋ, ẏ) = (0, 0, 0, 1, −1): Γ = diag(1, −1) is
/// invertible, C = g Γ⁻¹ gᵀ = 1 − 1 = 0.
Point hyperbolic(const Q& a) {
  Point d;
  d.n = 2;
  d.qdot = {Q(1), Q(-1)};
  d.lq = {a, Q(0)};
  d.lv = {Q(1), Q(1)};  // (ẋ, −ẏ)
  d.ltv = std::vector<Q>(2);
  d.lqv = QM(2, 2);
  d.lvv = QM::from_rows({{Q(1), Q(0)}, {Q(0), Q(-1)}}, 2);
  d.g = QM::from_rows({{Q(1), Q(1)}}, 2);
  d.g0 = {Q(0)};
  d.phi_t = {Q(0)};
  d.phi_q = QM(1, 2);
  return d;
}

}  // namespace

// The two ways V's uniqueness fails with Γ invertible and indefinite (candidate erratum to V Prop 3.1 and §3.1):
// ẍ = a + λ, ÿ = −λ (2.14) with ẍ + ÿ = 0 — every λ when a = 0 (a line of solutions), none when a = 1.
TEST(Vignolo, IndefiniteGammaLineOrNothing) {
  const Aff line = ref::lagrange_chetaev_fields(hyperbolic(Q(0)), false);
  ASSERT_FALSE(line.empty);
  EXPECT_EQ(line.direction.dim(), 1u);
  EXPECT_EQ(ref::nonholonomic_fields(hyperbolic(Q(0)), false).direction.dim(), 1u);
  EXPECT_TRUE(ref::lagrange_chetaev_fields(hyperbolic(Q(1)), false).empty);
  EXPECT_TRUE(ref::nonholonomic_fields(hyperbolic(Q(1)), false).empty);
  EXPECT_TRUE(ref::is_symplectic(ref::lagrangian_bundle_form(hyperbolic(Q(1)))));  // L is regular all the same
  EXPECT_THROW(fast::constrained_projection(to_fast_point(hyperbolic(Q(1))), Eigen::VectorXd::Zero(6)),
               std::invalid_argument);
}

// fast's certainty covers every input value: ∂L/∂t = 1e20 beside derivatives of 1 changes no answer exactly but
// swamps the scale of the decisions it enters (dφ_l's dt part), so fast must not call z ∈ M_1 certain where, exactly,
// z ∉ M_1 (n = 1, no constraint, Γ = 0, ∂L/∂q = ∂L/∂q̇ = 1: dφ_l(∂/∂q) = −1 on (3.15)'s direction ∂/∂q).
TEST(Vignolo, HugeTimeDerivativeLeavesFastUncertainNotWrong) {
  Point d;
  d.n = 1;
  d.qdot = {Q(0)};
  d.lq = d.lv = {Q(1)};
  d.ltv = {Q(0)};
  d.lqv = d.lvv = QM(1, 1);
  d.g = QM(0, 1);
  d.phi_q = QM(0, 1);
  EXPECT_FALSE(ref::in_first_constraint_manifold(d));
  fast::VignoloPoint f = to_fast_point(d);
  EXPECT_TRUE(fast::in_first_constraint_manifold(f).no());
  f.lt = 1e20;
  EXPECT_FALSE(fast::in_first_constraint_manifold(f).yes());
}
