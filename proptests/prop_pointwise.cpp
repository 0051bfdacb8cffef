// The pointwise CAD of systems given by formulas (reference/nonlinear/pointwise.hpp; issue 13), held against
// answers it did not compute:
//  - linear Pontryagin systems written as formulas: the linear reference's tower (CEF (5.5)–(5.6),
//    Lemma 5.1 (vii): another algorithm) and its velocities (Thm 5.4);
//  - the same systems pulled back by polynomial point transformations Φ (expr_gen.hpp): the CAD is
//    intrinsic (CEF §5) and a point transformation lifts to TQ ⊕ T*Q preserving D̄_Δ and E, so the
//    tower is the linear one and the motion is the linear motion in the new coordinates;
//  - the double twin (fast/pointwise.hpp) = the exact one where it says certain;
//  - genuinely nonholonomic families with known answers: the rolling disk with random parameters
//    (YM §6) and a Heisenberg-type constraint; the time-dependent family of V §3.5.
#include "dcad/fast/chart.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/reference/cad.hpp"
#include "expr_gen.hpp"
#include "tally.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ex = reference::expr;

namespace {

using PR = reference::PointwiseResult<Q>;

PR exact_at(const reference::LagrangianSystem& s, const std::vector<Q>& qvt) {
  reference::ExactDecisions<Q> d;
  return reference::pointwise_cad<Q>(s, qvt, std::vector<bool>(qvt.size(), true), d, [](const Q& x) { return x; });
}

/// (q, v) and t of a state (q, v, p): the values the pointwise CAD starts from.
std::vector<Q> qvt_of(const std::vector<Q>& x, Index n, const Q& t = 0) {
  std::vector<Q> out(x.begin(), x.begin() + static_cast<long>(2 * n));
  out.push_back(t);
  return out;
}

/// u ∈ a + span(dirs), restricted to the coordinates [0, k).
bool in_affine(const std::vector<Q>& u, const reference::AffineSubspace<Q>& a, Index k) {
  const QM& b = a.direction.basis();
  QM m(b.rows() + 1, k);
  for (Index i = 0; i < b.rows(); ++i)
    for (Index j = 0; j < k; ++j) m(i, j) = b(i, j);
  for (Index j = 0; j < k; ++j) m(b.rows(), j) = u[j] - a.point[j];
  return reference::rank(m) == reference::rank(m.block(0, b.rows(), 0, k));
}

/// (q̇, v̇) of the linear coordinates from (Q̇, V̇) at (Q, V): first-order jets along the curve.
std::vector<Q> push_forward(const PointMap& phi, const std::vector<Q>& qv, const std::vector<Q>& qv_dot) {
  const Index n = phi.n();
  auto sp = std::make_shared<const reference::JetSpace>(1, 1);
  std::vector<reference::Jet<Q>> args;
  for (Index i = 0; i < 2 * n; ++i) {
    reference::Jet<Q> j = reference::Jet<Q>::variable(sp, 0, qv[i]);
    j.set_coefficient(1, qv_dot[i]);
    args.push_back(j);
  }
  std::vector<ex::Expr> q, v;
  phi.formulas(q, v);
  std::vector<Q> out;
  for (const auto& e : q)
    out.push_back(
        ex::evaluate<reference::Jet<Q>>(e, args, [&](const Q& c) { return reference::Jet<Q>(sp, c); }).gradient(0));
  for (const auto& e : v)
    out.push_back(
        ex::evaluate<reference::Jet<Q>>(e, args, [&](const Q& c) { return reference::Jet<Q>(sp, c); }).gradient(0));
  return out;
}

std::string to_text(const QM& m) {
  std::string s = "[";
  for (Index i = 0; i < m.rows(); ++i) {
    s += i ? "; " : "";
    for (Index j = 0; j < m.cols(); ++j) s += (j ? " " : "") + m(i, j).str();
  }
  return s + "]";
}

std::string to_text(const std::vector<long>& v) {
  std::string s;
  for (long x : v) s += " " + std::to_string(x);
  return s;
}

/// (Q, V, t = 0) of the point x = (q, v, p) in the coordinates of Φ: Q = Φ⁻¹(q), V = DΦ(Q)⁻¹ v.
std::vector<Q> pulled_back_point(const PointMap& phi, const std::vector<Q>& x) {
  const Index n = phi.n();
  std::vector<Q> out = phi.inverse(std::vector<Q>(x.begin(), x.begin() + static_cast<long>(n)));
  const std::vector<Q> v(x.begin() + static_cast<long>(n), x.begin() + static_cast<long>(2 * n));
  const std::vector<Q> big_v = (reference::inverse(phi.jacobian(out)) * QM::column(v)).col(0);
  out.insert(out.end(), big_v.begin(), big_v.end());
  out.push_back(0);
  return out;
}

/// The rolling disk (YM §6): L = ½ m (v_x² + v_y²) + ½ I v_θ² + ½ J v_φ², v_x = R cos φ v_θ, v_y = R sin φ v_θ.
reference::LagrangianSystem rolling_disk(const Q& m, const Q& inertia, const Q& jj, const Q& rr) {
  reference::LagrangianSystem s;
  s.n = 4;
  s.names = {"x", "y", "theta", "phi"};
  const auto v = [](Index i) { return ex::variable(4 + i); };
  const auto half = [](const Q& c) { return ex::number(c / 2); };
  s.lagrangian = ex::add(
      ex::add(ex::mul(half(m), ex::add(ex::pow(v(0), 2), ex::pow(v(1), 2))), ex::mul(half(inertia), ex::pow(v(2), 2))),
      ex::mul(half(jj), ex::pow(v(3), 2)));
  s.constraints = {ex::sub(v(0), ex::mul(ex::mul(ex::number(rr), ex::cos(ex::variable(3))), v(2))),
                   ex::sub(v(1), ex::mul(ex::mul(ex::number(rr), ex::sin(ex::variable(3))), v(2)))};
  return s;
}

struct Planted {
  reference::PontryaginInput<Q> in;
  reference::CadResult<Q> linear;
  reference::LinearSystem<Q> system;
  std::vector<Q> x0;  ///< a point of M_c (q, v, p)
};

Planted planted(Index max_n) {
  Planted p;
  p.in = random_pontryagin(pick_size(1, max_n));
  p.system = reference::pontryagin_system(p.in);
  p.linear = reference::constraint_tower(p.system);
  if (!p.linear
           .consistent) {  // an empty M_k is seen locally only where it is a nonzero constant: drop a, b (then 0 ∈ M_c)
    p.in.q.assign(p.in.n, Q(0));
    p.in.v.assign(p.in.n, Q(0));
    p.system = reference::pontryagin_system(p.in);
    p.linear = reference::constraint_tower(p.system);
  }
  RC_TAG("c = " + std::to_string(p.linear.steps));
  RC_LOG() << "linear system: A " << to_text(p.in.vv) << " B " << to_text(p.in.qv) << " C " << to_text(p.in.qq) << " K "
           << to_text(p.in.k) << " a " << to_text(QM::from_rows({p.in.q}, p.in.n)) << " b "
           << to_text(QM::from_rows({p.in.v}, p.in.n)) << "\n";
  p.x0 = some_point(p.linear.final_step().m);
  return p;
}

std::vector<long> linear_dims(const reference::CadResult<Q>& r) {
  std::vector<long> d;
  for (const auto& s : r.tower) d.push_back(s.dim());
  return d;
}

}  // namespace

// Two routes to the tower of a linear Lagrangian system: the linear CAD on subspaces (CEF (5.5)–
// (5.6)) and the pointwise CAD on its formulas; and the velocity at a point of M_c lies in the
// affine space of Thm 5.4 (velocities()), with the same solution rank.
// The jet space of order K in d variables has C(d + K, K) monomials (stars and bars), counted degree
// by degree; dcad computes jets up to 200 000 monomials and refuses beyond with a length_error, never
// an allocation that takes the machine.  Killed by: the limit written 2001 (a mutation survivor:
// no scene reached a jet of more than 2001 monomials).
TEST(JetSpace, MonomialsAreBinomialsUpToTheStatedLimit) {
  const reference::JetSpace s(3, 22);
  EXPECT_EQ(s.size(), 2300u);  // C(25, 3)
  EXPECT_EQ(s.count_up_to(0), 1u);
  EXPECT_EQ(s.count_up_to(1), 4u);
  EXPECT_EQ(s.count_up_to(2), 10u);                             // C(5, 2)
  EXPECT_EQ(s.count_up_to(21), 2024u);                          // C(24, 3)
  EXPECT_THROW(reference::JetSpace(6, 30), std::length_error);  // C(36, 6) = 1 947 792 monomials
}

RC_GTEST_PROP(Pointwise, LinearFormulasGiveTheLinearTower, ()) {
  const Planted p = planted(3);
  const PR r = exact_at(pulled_back(p.in, identity_map(p.in.n)), qvt_of(p.x0, p.in.n));
  RC_LOG() << "pointwise dims" << to_text(r.dims) << " linear" << to_text(linear_dims(p.linear)) << " why " << r.why
           << "\n";
  RC_ASSERT(r.regular);
  RC_ASSERT(r.consistent);
  RC_ASSERT(r.dims == linear_dims(p.linear));
  RC_ASSERT(r.steps == p.linear.steps);
  RC_ASSERT(r.solution_rank == p.linear.solution_rank);
  RC_ASSERT(r.moves == 0u);
  const reference::AffineSubspace<Q> vel = reference::velocities(p.system, p.linear, p.x0);
  RC_ASSERT(in_affine(r.velocity, vel, 3 * p.in.n));
  for (const auto& g : r.gauge) {
    std::vector<Q> u = vel.point;
    for (Index j = 0; j < u.size(); ++j) u[j] += g[j];
    RC_ASSERT(in_affine(u, vel, 3 * p.in.n));
  }
}

// The CAD is intrinsic: pulled back by a polynomial point transformation, the tower is the linear
// one, and the motion pushed forward by Φ is the linear motion (modulo the gauge).
RC_GTEST_PROP(Pointwise, PointTransformationsKeepTheTowerAndTheMotion, ()) {
  const Planted p = planted(3);
  const Index n = p.in.n;
  const PointMap phi = random_map(n);
  const std::vector<Q> start = pulled_back_point(phi, p.x0);
  const PR r = exact_at(pulled_back(p.in, phi), start);
  RC_ASSERT(r.regular);
  RC_ASSERT(r.dims == linear_dims(p.linear));
  RC_ASSERT(r.steps == p.linear.steps);
  RC_ASSERT(r.solution_rank == p.linear.solution_rank);
  const reference::AffineSubspace<Q> vel = reference::velocities(p.system, p.linear, p.x0);
  const std::vector<Q> qv(start.begin(), start.begin() + static_cast<long>(2 * n));
  RC_ASSERT(in_affine(
      push_forward(phi, qv, std::vector<Q>(r.velocity.begin(), r.velocity.begin() + static_cast<long>(2 * n))), vel,
      2 * n));
  // P = DΦᵀ p: the momenta are the linear ones pulled back
  const QM jac = phi.jacobian(std::vector<Q>(start.begin(), start.begin() + static_cast<long>(n)));
  const std::vector<Q> big_p =
      (jac.transpose() * QM::column(std::vector<Q>(p.x0.begin() + static_cast<long>(2 * n), p.x0.end()))).col(0);
  for (Index i = 0; i < n; ++i) RC_ASSERT(r.point[2 * n + i] == big_p[i]);
}

// fast = reference: the double twin on the same pulled-back system at the same point.
RC_GTEST_PROP(Pointwise, FastEqualsReferenceOnPulledBackSystems, ()) {
  const Planted p = planted(3);
  const Index n = p.in.n;
  const PointMap phi = random_map(n);
  const std::vector<Q> start = pulled_back_point(phi, p.x0);
  const reference::LagrangianSystem s = pulled_back(p.in, phi);
  QM cm(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) cm(i, j) = phi.c[i][j];
  RC_LOG() << "L1 " << to_text(phi.l1) << " L2 " << to_text(phi.l2) << " c " << to_text(cm) << " L "
           << ex::to_text(s.lagrangian, s.variable_names()) << "\n";
  const PR r = exact_at(s, start);
  std::vector<double> xd;
  for (const Q& x : start) xd.push_back(x.convert_to<double>());
  fast::ToleranceDecisions d;
  reference::PointwiseResult<double> f;
  try {
    f = fast::pointwise_cad(s, xd, std::vector<bool>(xd.size(), false), d);
  } catch (const reference::PointwiseNoPoint& e) {
    // no answer is not a wrong answer: the double route's Newton projection can fail to settle (it did at
    // the start x0 = (3/2, -3, 21/2, -33/2, -12, 21/2) of a pulled-back system with linear A = [-1 -4 0;
    // -4 -15 0; 0 0 0], C = [-2 0 -4; 0 1 0; -4 0 -8], a point of M_c where the exact route moves 0)
    RC_TAG("fast: no point reached");
    tally("pointwise dims", false, true);
    return;
  }
  // The double route's own verdict is certain under the separation hypothesis only (fast/pointwise.hpp), which
  // pulled-back kinetic matrices can break: at q ~ 10^3 their entries reach 10^6 with determinant 2, and the
  // last pivot (1.7e-10) is below rounding (seed 918873982, cases/regression-pointwise-pulled-back.json).
  // Such a miss is tagged, not failed; what must hold is the backend's answer: `--backend fast` (fast::solve) confirms
  // a certain answer by the reference before it says certified, and a certified answer is the reference's.
  const bool hypothesis = d.certain.yes() && f.regular;
  RC_LOG() << "exact dims" << to_text(r.dims) << " rank " << r.solution_rank << "; double dims" << to_text(f.dims)
           << " rank " << f.solution_rank << " moves " << f.moves << " certain " << d.certain.text() << "\n";
  for (Index i = 0; i < r.velocity.size() && i < f.velocity.size(); ++i)
    RC_LOG() << "  x " << (i < start.size() ? start[i].str() : "") << " exact " << r.velocity[i].convert_to<double>()
             << " double " << f.velocity[i] << "\n";
  // with no zero assumed (ToleranceDecisions::assumed), every decision was proved in double: no hypothesis to fail
  RC_ASSERT(!tally("pointwise, proved in double", hypothesis && d.assumed == 0,
                   f.dims == r.dims && f.solution_rank == r.solution_rank));
  if (hypothesis && (f.dims != r.dims || f.solution_rank != r.solution_rank))
    RC_TAG("double: the separation hypothesis missed (the exact confirmation must catch it)");
  io::LagrangianCase c;
  c.system = s;
  c.has_initial = true;
  c.initial.assign(2 * n + 1, std::nullopt);
  c.initial_p.assign(n, std::nullopt);
  for (Index i = 0; i < 2 * n; ++i) c.initial[i] = start[i];
  io::Problem pr;
  pr.input = io::ExpressionCase{c};
  const fast::Solution b = fast::solve(pr);
  const bool certain = b.certified.yes();
  // certified: confirmed by the certified tier, or proved in double (no zero assumed: decisions.float_tests = 0)
  RC_ASSERT(!certain || b.decisions.exact_verifications == 1 || b.decisions.float_tests == 0);
  RC_ASSERT(!tally("pointwise dims", certain, b.dims() == r.dims && f.dims == r.dims));
  RC_ASSERT(!tally("pointwise solution rank", certain,
                   b.solution_rank == std::optional<long>(static_cast<long>(r.solution_rank)) &&
                       f.solution_rank == r.solution_rank));
  if (certain && f.dims == r.dims && f.moves == 0) {  // same point: same velocity (modulo the gauge)
    double scale = 1, worst = 0;
    for (Index i = 0; i < 3 * n; ++i) scale = std::max(scale, std::abs(r.velocity[i].convert_to<double>()));
    if (r.gauge.empty())
      for (Index i = 0; i < 3 * n; ++i)
        worst = std::max(worst, std::abs(f.velocity[i] - r.velocity[i].convert_to<double>()));
    // 1e-5 of the scale, not 1e-6: double's forward error is ε times the condition number, and pulled-back
    // points reach |q| ~ 2e4 (kinetic entries ~ 1e8). Counterexample under clang's ASan build (seed 662236186,
    // q = (-12, 147, 21744), v = (0, 0, 1)): certain, same dims, v-rates 0.99984 against 1 at scale 193785.
    RC_ASSERT(worst <= 1e-5 * scale);
  }
}

// The rolling disk (YM §6) with random positive parameters, at phi = 0 where every value is
// rational: dims [12, 6], unique, and the motion of YM's equations: x' = R v_theta, y' = 0,
// v_theta' = v_phi' = 0, v_y' = R v_phi v_theta (the rolling constraint differentiated).
RC_GTEST_PROP(Pointwise, RollingDiskWithRandomParameters, ()) {
  const auto pos = [] { return Q(*rc::gen::inRange(1, 20), *rc::gen::inRange(1, 20)); };
  const Q m = pos(), inertia = pos(), jj = pos(), rr = pos();
  const reference::LagrangianSystem s = rolling_disk(m, inertia, jj, rr);
  const Q x = *rc::gen::inRange(-5, 6), y = *rc::gen::inRange(-5, 6), th = *rc::gen::inRange(-5, 6),
          vth = *rc::gen::inRange(-5, 6), vph = *rc::gen::inRange(-5, 6);
  reference::ExactDecisions<Q> d;
  std::vector<bool> fixed(9, false);
  for (Index i : {0, 1, 2, 3, 6, 7}) fixed[i] = true;
  const PR r = reference::pointwise_cad<Q>(s, {x, y, th, Q(0), Q(0), Q(0), vth, vph, Q(0)}, fixed, d,
                                           [](const Q& c) { return c; });
  RC_ASSERT(r.dims == (std::vector<long>{12, 6}));
  RC_ASSERT(r.solution_rank == 0u);
  RC_ASSERT(r.point[4] == rr * vth);  // v_x = R cos 0 v_theta
  RC_ASSERT(r.velocity[0] == rr * vth);
  RC_ASSERT(r.velocity[1] == 0);
  RC_ASSERT(r.velocity[6] == 0);
  RC_ASSERT(r.velocity[7] == 0);
  RC_ASSERT(r.velocity[5] == rr * vph * vth);
  RC_ASSERT(r.velocity[2 * 4 + 2] == 0);  // p_theta' = (m R² + I) v_theta' − m R (…) = 0 at phi = 0 with v_x' = 0
}

// A Heisenberg-type (nonholonomic, polynomial) constraint z' = x y' − y x' with a quadratic potential:
// M_1 = {p = v, constraint} (dim 9 − 3 − 1 = 5) and L regular on Δ: dims [9, 5], unique, exactly at
// random rational points; the reaction keeps the constraint: d/dt (v_z − x v_y + y v_x) = 0.
RC_GTEST_PROP(Pointwise, HeisenbergConstraint, ()) {
  const Heisenberg h = heisenberg_system(0, 1, 2);
  const reference::LagrangianSystem& s = h.s;
  const std::vector<Q> x0 = heisenberg_point(h);
  const PR r = exact_at(s, x0);
  RC_ASSERT(r.dims == (std::vector<long>{9, 5}));
  RC_ASSERT(r.solution_rank == 0u);
  const std::vector<Q>& u = r.velocity;  // d/dt(v_z − x v_y + y v_x) = v̇_z − ẋ v_y − x v̇_y + ẏ v_x + y v̇_x
  RC_ASSERT(u[5] - u[0] * x0[4] - x0[0] * u[4] + u[1] * x0[3] + x0[1] * u[3] == 0);
}

// The time-dependent family of V §3.5: L = ½(v_x² + v_y²) + w (v_x + a t) + b z, constraint v_z = w:
// M_2 = {v_x + a t = 0}, M_3 = {v_w = a}, dims [12, 7, 6, 5], unique, for every a, b (V (3.27)).
RC_GTEST_PROP(Pointwise, VignoloFamily, ()) {
  const Q a(*rc::gen::inRange(-5, 6), *rc::gen::inRange(1, 4)), b = *rc::gen::inRange(-5, 6),
                                                                t0(*rc::gen::inRange(-5, 6), 2);
  reference::LagrangianSystem s;
  s.n = 4;
  s.has_time = true;
  s.names = {"x", "y", "z", "w"};
  const auto q = [](Index i) { return ex::variable(i); };
  const auto v = [](Index i) { return ex::variable(4 + i); };
  const ex::Expr t = ex::variable(8);
  s.lagrangian = ex::add(ex::add(ex::mul(ex::number(Q(1, 2)), ex::add(ex::pow(v(0), 2), ex::pow(v(1), 2))),
                                 ex::mul(q(3), ex::add(v(0), ex::mul(ex::number(a), t)))),
                         ex::mul(ex::number(b), q(2)));
  s.constraints = {ex::sub(v(2), q(3))};
  std::vector<Q> start(9, 0);
  for (Index i = 0; i < 8; ++i) start[i] = *rc::gen::inRange(-3, 4);
  start[8] = t0;
  std::vector<bool> fixed(9, false);
  fixed[8] = true;
  reference::ExactDecisions<Q> d;
  const PR r = reference::pointwise_cad<Q>(s, start, fixed, d, [](const Q& c) { return c; });
  RC_ASSERT(r.dims == (std::vector<long>{12, 7, 6, 5}));
  RC_ASSERT(r.solution_rank == 0u);
  RC_ASSERT(r.point[4] == -a * t0);  // v_x = −a t
  RC_ASSERT(r.point[7] == a);        // v_w = a
  RC_ASSERT(r.velocity[4] == -a);    // x'' = −a
  RC_ASSERT(r.velocity[6] == a);     // z'' = w' = a
}

// ---- The CAD as formulas on a chart (fast/chart.hpp; issue 29) -------------------------------

namespace {

/// e at the point (q, v, t) exactly (jets of order 0 over no variable: the reference's own arithmetic).
Q exact_value(const ex::Expr& e, const std::vector<Q>& qvt) {
  auto sp = std::make_shared<const reference::JetSpace>(0, 0);
  std::vector<reference::Jet<Q>> args;
  for (const Q& x : qvt) args.emplace_back(sp, x);
  return ex::evaluate<reference::Jet<Q>>(e, args, [&](const Q& c) { return reference::Jet<Q>(sp, c); }).value();
}

std::vector<double> doubles(const std::vector<Q>& x) {
  std::vector<double> out;
  for (const Q& v : x) out.push_back(v.convert_to<double>());
  return out;
}

}  // namespace

// Two routes to the equations of motion of a nonlinear system: the exact pointwise CAD (jets at the
// point, the reference) and the formulas of the chart (Gaussian elimination on the expression DAG, its
// pivots decided in double at another, generic point of M_c).  On pulled-back linear systems (the tower
// is the linear one, CEF §5 is intrinsic), at the exact point x0 of M_c: the chart's tower is the
// reference's, every constraint formula vanishes exactly at x0, and where the chart's conditions hold
// there, its rates (free ones 0) are a solution — equal to the reference's velocity when unique, in
// velocity + span(gauge) otherwise (Thm 5.4) — exactly, in rationals.
// Killed by: the back substitution skipping a pivoted column's term (v̇ off by that product), and by
// the candidate test without the rounding bound (tracked values): identically zero rows then read as
// new constraints (cases/regression-pointwise-skipped-column's system got dims [9, 5, 3, 1]).
RC_GTEST_PROP(Chart, FormulasEqualTheExactPointwiseCad, ()) {
  const Planted p = planted(3);
  const Index n = p.in.n;
  const PointMap phi = random_map(n);
  const std::vector<Q> start = pulled_back_point(phi, p.x0);
  const reference::LagrangianSystem s = pulled_back(p.in, phi);
  const PR r = exact_at(s, start);
  RC_PRE(r.consistent && r.regular);
  std::vector<Q> at(r.point.begin(), r.point.begin() + static_cast<long>(2 * n));
  at.push_back(r.time);
  // the product's validation: the chart's rates at x0 must equal the pointwise CAD's in double (another route)
  std::vector<double> v;
  try {
    fast::ToleranceDecisions dd;
    const reference::PointwiseResult<double> f =
        fast::pointwise_cad(s, doubles(at), std::vector<bool>(at.size(), true), dd);
    if (f.regular && f.consistent && f.gauge.empty())
      v.assign(f.velocity.begin(), f.velocity.begin() + static_cast<long>(2 * n));
  } catch (const std::exception&) {
  }
  if (v.empty() && r.gauge.empty()) {  // formulas() refuses an unchecked chart for a unique motion (api/formulas.cpp)
    RC_TAG("no double velocity at x0");
    return;
  }
  fast::Chart ch;
  try {
    ch = fast::chart_near(s, doubles(at), r.dims, v.empty() ? nullptr : &v, fast::pointwise_completion(s));
  } catch (const fast::ChartFailure&
               e) {  // no formulas is not wrong formulas (the result says why); the tag shows how often
    RC_TAG("no chart");
    RC_LOG() << e.what() << "\n";
    return;
  }
  RC_ASSERT(ch.dims == r.dims);
  for (const ex::Expr& c : ch.constraints) RC_ASSERT(exact_value(c, at) == 0);
  for (const auto& v : ch.valid_where)
    if (exact_value(v.formula, at) == 0) {
      RC_TAG("x0 outside the chart");
      return;
    }
  // what the elimination took as 0 (in double, at a generic point) must vanish at x0 for the chart to be M_c's
  // there: chart_near checks it to the drift tolerance (1e-8 of the terms), which an entry of -4/5625 beside
  // terms of 10^5 meets (seed 733862999); exactly, it does not, and the product's balls at the given values
  // refuse such a chart (api/formulas.cpp at_given)
  for (const ex::Expr& z : ch.vanishing)
    if (exact_value(z, at) != 0) {
      RC_TAG("a zero decision of the chart fails at x0");
      return;
    }
  std::vector<Q> u(2 * n);
  for (Index i = 0; i < 2 * n; ++i) u[i] = exact_value(ch.rates[i], at);
  RC_TAG(r.solution_rank ? "not unique" : "unique");
  RC_LOG() << "L " << ex::to_text(s.lagrangian, s.variable_names()) << "\ndims" << to_text(r.dims) << " chart dims"
           << to_text(ch.dims) << " rank " << r.solution_rank << "\n";
  for (Index i = 0; i < 2 * n; ++i)
    RC_LOG() << "  " << s.variable_names()[i] << " = " << at[i].str() << ": chart " << u[i].str() << " reference "
             << r.velocity[i].str() << "\n";
  for (const auto& g : r.gauge) {
    RC_LOG() << "  gauge";
    for (const Q& x : g) RC_LOG() << " " << x.str();
    RC_LOG() << "\n";
  }
  for (const auto& z : ch.vanishing) RC_LOG() << "  taken as 0 on M_c: " << exact_value(z, at).str() << "\n";
  for (const auto& c : ch.valid_where) RC_LOG() << "  valid where: " << exact_value(c.formula, at).str() << " != 0\n";
  if (r.gauge.empty()) {
    for (Index i = 0; i < 2 * n; ++i) RC_ASSERT(u[i] == r.velocity[i]);
  } else {  // u − velocity ∈ span(gauge) on the (q, v) coordinates
    reference::AffineSubspace<Q> a;
    a.point = r.velocity;
    QM g(r.gauge.size(), 3 * n);
    for (Index i = 0; i < r.gauge.size(); ++i)
      for (Index j = 0; j < 3 * n; ++j) g(i, j) = r.gauge[i][j];
    a.direction = reference::Subspace<Q>::span(g);
    RC_ASSERT(in_affine(u, a, 2 * n));
  }
}

// The rolling disk (YM §6) at generic angles — never φ = 0, where sin φ = 0 hides a wrong sign of a
// sin φ term: its motion is known in closed form (the constraints differentiated, the reactions
// eliminated by hand): v̇_θ = v̇_φ = 0, v̇_x = −R sin φ v_φ v_θ, v̇_y = R cos φ v_φ v_θ.  The chart's
// rates at random points of M_c (random φ ∈ (−3, 3), random velocities, R, masses) are these values.
RC_GTEST_PROP(Chart, RollingDiskAtGenericAnglesIsTheClosedForm, ()) {
  const auto pos = [] { return Q(*rc::gen::inRange(1, 20), *rc::gen::inRange(1, 20)); };
  const Q m = pos(), inertia = pos(), jj = pos(), rr = pos();
  const reference::LagrangianSystem s = rolling_disk(m, inertia, jj, rr);
  const double R = rr.convert_to<double>(), ph = *rc::gen::inRange(-300, 301) / 100.0,
               vth = *rc::gen::inRange(-50, 51) / 10.0, vph = *rc::gen::inRange(-50, 51) / 10.0;
  const std::vector<double> x0{0.5, -1.25, 0.75, ph, R * std::cos(ph) * vth, R * std::sin(ph) * vth, vth, vph, 0};
  const fast::Chart ch = fast::chart_near(s, x0, {12, 6});
  const fast::ChartField f(ch);
  std::vector<double> u(8);
  f.rates(x0.data(), 0, u.data());
  RC_LOG() << "phi " << ph << " v_theta " << vth << " v_phi " << vph << " rates " << u[4] << " " << u[5] << " " << u[6]
           << " " << u[7] << "\n";
  const double scale = std::max(1.0, R * std::abs(vph * vth));
  RC_ASSERT(std::abs(u[4] + R * std::sin(ph) * vph * vth) <= 1e-12 * scale);
  RC_ASSERT(std::abs(u[5] - R * std::cos(ph) * vph * vth) <= 1e-12 * scale);
  RC_ASSERT(std::abs(u[6]) <= 1e-12 * scale);
  RC_ASSERT(std::abs(u[7]) <= 1e-12 * scale);
}

// The Cartesian pendulum (Hairer–Wanner VII.1; cases/cartesian-pendulum.json) with the multiplier as a
// coordinate, at random rational points of M_c: x = (3/5, −4/5) l, v = s (4/5, 3/5) l (tangent), and by
// hand μ = m(|v|² − g y)/l² (M_4), μ̇ = m(2 v·a − g v_y)/l² with a = (−μx, −g m − μy)/m (M_5),
// μ̈ = m(2|a|² + 2 v·ȧ − g a_y)/l² with ȧ = −(μ̇ x + μ v)/m: the chart's five-level tower and rates,
// exactly.  (The index-3 reduction every DAE tool performs; derived here without the CAD.)
RC_GTEST_PROP(Chart, CartesianPendulumIsTheHandReduction, ()) {
  const Q m(*rc::gen::inRange(1, 10), *rc::gen::inRange(1, 4)), g(*rc::gen::inRange(1, 1000), 100),
      l(*rc::gen::inRange(1, 5), *rc::gen::inRange(1, 3)), sp(*rc::gen::inRange(-20, 21), 4);
  reference::LagrangianSystem s;
  s.n = 3;
  s.names = {"x", "y", "mu"};
  const ex::Expr x = ex::variable(0), y = ex::variable(1), mu = ex::variable(2), vx = ex::variable(3),
                 vy = ex::variable(4);
  s.lagrangian = ex::sub(
      ex::sub(ex::mul(ex::number(m / 2), ex::add(ex::pow(vx, 2), ex::pow(vy, 2))), ex::mul(ex::number(m * g), y)),
      ex::mul(ex::mul(ex::number(Q(1, 2)), mu), ex::sub(ex::add(ex::pow(x, 2), ex::pow(y, 2)), ex::number(l * l))));
  const Q px = Q(3, 5) * l, py = Q(-4, 5) * l, vxx = sp * Q(4, 5) * l, vyy = sp * Q(3, 5) * l;
  const Q muv = m * (vxx * vxx + vyy * vyy - g * py) / (l * l);
  const Q ax = -muv * px / m, ay = -g - muv * py / m;
  const Q mud = m * (2 * (vxx * ax + vyy * ay) - g * vyy) / (l * l);
  const Q adx = -(mud * px + muv * vxx) / m, ady = -(mud * py + muv * vyy) / m;
  const Q mudd = m * (2 * (ax * ax + ay * ay) + 2 * (vxx * adx + vyy * ady) - g * ay) / (l * l);
  const std::vector<Q> at{px, py, muv, vxx, vyy, mud, 0};
  const fast::Chart ch = fast::chart_near(s, doubles(at), {9, 6, 5, 4, 3, 2});
  for (const ex::Expr& c : ch.constraints) RC_ASSERT(exact_value(c, at) == 0);
  const std::vector<Q> want{vxx, vyy, mud, ax, ay, mudd};
  for (Index i = 0; i < 6; ++i) RC_ASSERT(exact_value(ch.rates[i], at) == want[i]);
}
