// YM §5–§6 on formulas (reference/nonlinear/ehresmann.hpp): the Ehresmann connection, its curvature, the
// constrained Lagrangian, and YM Thm 5.6: the implicit Lagrange–d'Alembert equations (5.6) hold along
// the motion the CAD computes (CEF §5, reference/nonlinear/pointwise.hpp) — two routes to the same dynamics.
// Goldens: YM §6's rolling disk (exactly, at rational points of the circle) and L-C circuit.
#include "dcad/fast/implicit_lagrangian.hpp"
#include "dcad/reference/nonlinear/ehresmann.hpp"
#include "dcad/reference/nonlinear/pointwise.hpp"
#include "expr_gen.hpp"

#include <gtest/gtest.h>
#include <limits>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ex = reference::expr;

namespace {

/// YM §6's vertical rolling disk: q = (x, y, theta, phi).
reference::LagrangianSystem rolling_disk(const Q& m, const Q& inertia, const Q& jj, const Q& rr) {
  reference::LagrangianSystem s;
  s.n = 4;
  s.names = {"x", "y", "theta", "phi"};
  const auto v = [](Index i) { return ex::variable(4 + i); };
  s.lagrangian = ex::add(ex::add(ex::mul(ex::number(m / 2), ex::add(ex::pow(v(0), 2), ex::pow(v(1), 2))),
                                 ex::mul(ex::number(inertia / 2), ex::pow(v(2), 2))),
                         ex::mul(ex::number(jj / 2), ex::pow(v(3), 2)));
  s.constraints = {ex::sub(v(0), ex::mul(ex::mul(ex::number(rr), ex::cos(ex::variable(3))), v(2))),
                   ex::sub(v(1), ex::mul(ex::mul(ex::number(rr), ex::sin(ex::variable(3))), v(2)))};
  return s;
}

/// A formula of the disk at q, v with (cos phi, sin phi) = (c, s): exact (sin, cos as variables 9, 10).
Q at_angle(const ex::Expr& e, const std::vector<Q>& qv, const Q& c, const Q& s) {
  const ex::Expr f = reference::angles_as_variables(e, {3}, {9}, {10});
  std::vector<Q> vars(qv);
  vars.resize(9, Q(0));
  vars.push_back(s);
  vars.push_back(c);
  return reference::value_at(f, vars);
}

}  // namespace

// YM §6, the rolling disk: s = (x, y), r = (theta, phi); A¹_1 = −R cos phi, A²_1 = −R sin phi, the
// other components 0; K¹_12 = −K¹_21 = R sin phi, K²_12 = −K²_21 = −R cos phi; L_c = ½(mR² + I)v_theta²
// + ½ J v_phi²; the entry (5, 6) of B_P^♯ is −p_b K^b_12 by (5.9) (printed +p_b K^b_12: ERRATA), which is
// −m R (v_x sin phi − v_y cos phi) off the constraint space and 0 on it.  Exactly, at rational points
// of the circle and at rational velocities.
TEST(Ehresmann, RollingDiskOfYM6) {
  const Q m(2), inertia(1, 2), jj(1, 4), rr(1, 3);
  const reference::LagrangianSystem disk = rolling_disk(m, inertia, jj, rr);
  const reference::EhresmannConnection conn = reference::ehresmann_connection(disk, {Q(0), Q(0), Q(0), Q(0)});
  ASSERT_EQ(conn.s, (std::vector<std::size_t>{0, 1}));
  ASSERT_EQ(conn.r, (std::vector<std::size_t>{2, 3}));
  const auto k = reference::curvature(conn);
  const ex::Expr lc = reference::constrained_lagrangian(disk, conn);
  int checked = 0;
  for (int t = -3; t <= 3; ++t) {  // (cos, sin) = ((1 − t²)/(1 + t²), 2t/(1 + t²))
    const Q c = Q(1 - t * t, 1 + t * t), s = Q(2 * t, 1 + t * t);
    const std::vector<Q> qv{Q(1, 2), Q(-2), Q(3), Q(0), Q(5, 7), Q(-1, 3), Q(2), Q(-3, 2)};  // phi's value unused
    EXPECT_EQ(at_angle(conn.a[0][0], qv, c, s), -rr * c);
    EXPECT_EQ(at_angle(conn.a[1][0], qv, c, s), -rr * s);
    EXPECT_EQ(at_angle(conn.a[0][1], qv, c, s), 0);
    EXPECT_EQ(at_angle(conn.a[1][1], qv, c, s), 0);
    EXPECT_EQ(at_angle(k[0][0][1], qv, c, s), rr * s);
    EXPECT_EQ(at_angle(k[1][0][1], qv, c, s), -rr * c);
    for (Index b = 0; b < 2; ++b) {
      EXPECT_EQ(at_angle(k[b][1][0], qv, c, s), -at_angle(k[b][0][1], qv, c, s));
      EXPECT_EQ(at_angle(k[b][0][0], qv, c, s), 0);
    }
    EXPECT_EQ(at_angle(lc, qv, c, s), (m * rr * rr + inertia) / 2 * qv[6] * qv[6] + jj / 2 * qv[7] * qv[7]);
    // B_P^♯ (5.9): −p_b K^b_12 with p = m (v_x, v_y), at velocities off the constraint space
    const Q pk = m * qv[4] * at_angle(k[0][0][1], qv, c, s) + m * qv[5] * at_angle(k[1][0][1], qv, c, s);
    EXPECT_EQ(-pk, -m * rr * (qv[4] * s - qv[5] * c));
    EXPECT_NE(pk, 0) << "here the printed sign, +p_b K^b_12, would pass too";
    // on Δ (v_x = R cos phi v_theta, v_y = R sin phi v_theta) it vanishes: harmless in YM's example
    EXPECT_EQ(m * rr * c * qv[6] * at_angle(k[0][0][1], qv, c, s) + m * rr * s * qv[6] * at_angle(k[1][0][1], qv, c, s),
              0);
    ++checked;
  }
  EXPECT_EQ(checked, 7);
}

// YM §6, the L-C circuit: q = (q_L, q_C1, q_C2, q_C3), ω¹ = −dq_L + dq_C2, ω² = −dq_C1 + dq_C2 − dq_C3;
// YM's split s = (q_L, q_C1), r = (q_C2, q_C3) with A = [[−1, 0], [−1, 1]]; holonomic: K = 0; L_c =
// ½ L f_C2² − Σ q_Ci²/(2 C_i).
TEST(Ehresmann, LcCircuitOfYM6) {
  reference::LagrangianSystem lc;
  lc.n = 4;
  lc.names = {"q_L", "q_C1", "q_C2", "q_C3"};
  const auto q = [](Index i) { return ex::variable(i); };
  const auto v = [](Index i) { return ex::variable(4 + i); };
  const Q l(2), c1(3), c2(5), c3(7);
  lc.lagrangian = ex::sub(ex::sub(ex::sub(ex::mul(ex::number(l / 2), ex::pow(v(0), 2)),
                                          ex::mul(ex::number(1 / (2 * c1)), ex::pow(q(1), 2))),
                                  ex::mul(ex::number(1 / (2 * c2)), ex::pow(q(2), 2))),
                          ex::mul(ex::number(1 / (2 * c3)), ex::pow(q(3), 2)));
  lc.constraints = {ex::add(ex::neg(v(0)), v(2)), ex::sub(ex::add(ex::neg(v(1)), v(2)), v(3))};
  const reference::EhresmannConnection conn = reference::ehresmann_connection(lc, {Q(0), Q(0), Q(0), Q(0)});
  EXPECT_EQ(conn.s, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(conn.r, (std::vector<std::size_t>{2, 3}));
  const std::vector<Q> at(9, Q(1));
  const std::vector<std::vector<Q>> want{{-1, 0}, {-1, 1}};
  for (Index a = 0; a < 2; ++a)
    for (Index al = 0; al < 2; ++al) EXPECT_EQ(reference::value_at(conn.a[a][al], at), want[a][al]);
  for (const auto& kb : reference::curvature(conn))
    for (const auto& row : kb)
      for (const auto& e : row) EXPECT_TRUE(ex::is_number(e, 0)) << ex::to_text(e, lc.variable_names());
  const std::vector<Q> pt{Q(1), Q(2), Q(3), Q(4), Q(9), Q(9), Q(5), Q(-2), Q(0)};
  EXPECT_EQ(reference::value_at(reference::constrained_lagrangian(lc, conn), pt),
            l / 2 * 25 - 4 / (2 * c1) - 9 / (2 * c2) - 16 / (2 * c3));
}

// YM Thm 5.6: along the motion of the CAD (exact pointwise route) at a point of M_c, the implicit
// Lagrange–d'Alembert equations (5.6) of (L_c, Δ, X_P) hold exactly: linear Lagrangians with linear
// constraints pulled back by polynomial point transformations (so A and K depend on the point).
RC_GTEST_PROP(Ehresmann, ImplicitLagrangeDAlembertHoldAlongTheCadMotion, ()) {
  reference::PontryaginInput<Q> in = random_pontryagin(pick_size(2, 3), 1);
  in.q.assign(in.n, Q(0));
  in.v.assign(in.n, Q(0));  // homogeneous: consistent, 0 ∈ M_c
  const auto system = reference::pontryagin_system(in);
  const auto linear = reference::constraint_tower(system);
  const std::vector<Q> x0 = some_point(linear.final_step().m);
  const PointMap phi = random_map(in.n);
  const reference::LagrangianSystem s = pulled_back(in, phi);
  std::vector<Q> start = phi.inverse(std::vector<Q>(x0.begin(), x0.begin() + static_cast<long>(in.n)));
  const std::vector<Q> big_v =
      (reference::inverse(phi.jacobian(start)) *
       QM::column(std::vector<Q>(x0.begin() + static_cast<long>(in.n), x0.begin() + static_cast<long>(2 * in.n))))
          .col(0);
  start.insert(start.end(), big_v.begin(), big_v.end());
  start.push_back(0);
  reference::ExactDecisions<Q> d;
  const auto r =
      reference::pointwise_cad<Q>(s, start, std::vector<bool>(start.size(), true), d, [](const Q& c) { return c; });
  RC_LOG() << "pointwise: " << r.why << "\nL = " << ex::to_text(s.lagrangian, s.variable_names()) << "\n";
  for (const auto& c : s.constraints) RC_LOG() << "constraint " << ex::to_text(c, s.variable_names()) << "\n";
  for (const Q& v : start) RC_LOG() << v.str() << " ";
  RC_LOG() << "\nlinear dims";
  for (const auto& st : linear.tower) RC_LOG() << " " << st.dim();
  RC_LOG() << " rank " << linear.solution_rank << "\n";
  RC_ASSERT(r.consistent && r.regular);
  const reference::EhresmannConnection conn =
      reference::ehresmann_connection(s, std::vector<Q>(start.begin(), start.begin() + static_cast<long>(in.n)));
  const std::vector<Q> qv(start.begin(), start.begin() + static_cast<long>(2 * in.n));
  const std::vector<Q> qv_dot(r.velocity.begin(), r.velocity.begin() + static_cast<long>(2 * in.n));
  for (const Q& e : reference::implicit_lagrange_dalembert_residual(s, conn, qv, qv_dot)) RC_ASSERT(e == 0);
  // and for the other solutions (the gauge directions): (5.6) is linear in the motion's derivatives
  for (const auto& g : r.gauge) {
    std::vector<Q> other(qv_dot);
    for (Index i = 0; i < other.size(); ++i) other[i] += g[i];
    for (const Q& e : reference::implicit_lagrange_dalembert_residual(s, conn, qv, other)) RC_ASSERT(e == 0);
  }
}

// The same for YM §6's disk with random parameters at phi = 0 (rational there): YM's conclusion
// p~_theta' = p~_phi' = 0 holds, and a wrong motion (v_theta' ≠ 0) is caught.
RC_GTEST_PROP(Ehresmann, RollingDiskMomentaAreConserved, ()) {
  const auto pos = [] { return Q(*rc::gen::inRange(1, 20), *rc::gen::inRange(1, 20)); };
  const reference::LagrangianSystem disk = rolling_disk(pos(), pos(), pos(), pos());
  std::vector<Q> start{Q(*rc::gen::inRange(-5, 6)),
                       Q(*rc::gen::inRange(-5, 6)),
                       Q(*rc::gen::inRange(-5, 6)),
                       Q(0),
                       Q(0),
                       Q(0),
                       Q(*rc::gen::inRange(-5, 6)),
                       Q(*rc::gen::inRange(-5, 6)),
                       Q(0)};
  std::vector<bool> fixed(9, true);
  fixed[4] = fixed[5] = false;
  reference::ExactDecisions<Q> d;
  const auto r = reference::pointwise_cad<Q>(disk, start, fixed, d, [](const Q& c) { return c; });
  const auto conn = reference::ehresmann_connection(disk, {start[0], start[1], start[2], Q(0)});
  const std::vector<Q> qv(r.point.begin(), r.point.begin() + 8);
  std::vector<Q> qv_dot(r.velocity.begin(), r.velocity.begin() + 8);
  for (const Q& e : reference::implicit_lagrange_dalembert_residual(disk, conn, qv, qv_dot)) RC_ASSERT(e == 0);
  qv_dot[6] += 1;  // v_theta' = 1: the momentum p~_theta would change
  bool caught = false;
  for (const Q& e : reference::implicit_lagrange_dalembert_residual(disk, conn, qv, qv_dot)) caught = caught || e != 0;
  RC_ASSERT(caught);
}

// A nonholonomic constraint whose curvature term matters: z' = x y' − y x' (Heisenberg; fibre s = z,
// K = 2 dx∧dy up to sign), L = ½|v|² − V(q) with a random quadratic V, at random rational points.
RC_GTEST_PROP(Ehresmann, HeisenbergCurvatureTermHoldsAlongTheCadMotion, ()) {
  const Heisenberg h = heisenberg_system(1, 2, 0);  // z first: the fibre coordinate YM's rule picks
  const reference::LagrangianSystem& s = h.s;
  const std::vector<Q> x0 = heisenberg_point(h);
  RC_PRE(x0[4] != 0 || x0[5] != 0);  // a motion in the base: the curvature term p_b K^b u is then not 0
  reference::ExactDecisions<Q> d;
  const auto r = reference::pointwise_cad<Q>(s, x0, std::vector<bool>(7, true), d, [](const Q& c) { return c; });
  const auto conn = reference::ehresmann_connection(s, {x0[0], x0[1], x0[2]});
  RC_ASSERT(conn.s == std::vector<std::size_t>{0});
  const std::vector<Q> qv(x0.begin(), x0.begin() + 6), qv_dot(r.velocity.begin(), r.velocity.begin() + 6);
  for (const Q& e : reference::implicit_lagrange_dalembert_residual(s, conn, qv, qv_dot)) RC_ASSERT(e == 0);
}

namespace {

double dbl(const Q& x) { return x.convert_to<double>(); }

/// A(q), ∂A/∂q^i and K(q) of a connection at q (formulas evaluated exactly by `at`), in (r, s) order.
struct ConnectionAt {
  reference::Matrix<Q> a;
  std::vector<reference::Matrix<Q>> da, k;
};
template <class At>
ConnectionAt connection_at(const reference::EhresmannConnection& c, const At& at) {
  const std::size_t m = c.s.size(), d = c.r.size();
  ConnectionAt out{reference::Matrix<Q>(m, d), {}, {}};
  std::vector<std::size_t> order = c.r;
  order.insert(order.end(), c.s.begin(), c.s.end());
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < d; ++al) out.a(b, al) = at(c.a[b][al]);
  for (std::size_t i : order) {
    reference::Matrix<Q> di(m, d);
    for (std::size_t b = 0; b < m; ++b)
      for (std::size_t al = 0; al < d; ++al) di(b, al) = at(ex::diff(c.a[b][al], i));
    out.da.push_back(di);
  }
  const auto kf = reference::curvature(c);
  for (std::size_t b = 0; b < m; ++b) {
    reference::Matrix<Q> kb(d, d);
    for (std::size_t al = 0; al < d; ++al)
      for (std::size_t be = 0; be < d; ++be) kb(al, be) = at(kf[b][al][be]);
    out.k.push_back(kb);
  }
  return out;
}

/// fast's B_P^♯ (the canonical brackets of P's coordinate functions) less the reference's (5.9) entries: the largest
/// difference relative to the allowance (1e-12 × the largest entry × the size), > 1 where the twins differ.
double twins_difference(const ConnectionAt& c, const std::vector<Q>& p_rs) {
  const std::size_t m = c.a.rows(), d = c.a.cols();
  const std::vector<Q> p_s(p_rs.begin() + static_cast<long>(d), p_rs.end());
  const reference::Matrix<Q> exact = reference::constrained_poisson_tensor(c.a, c.k, p_s);
  Eigen::MatrixXd a(m, d);
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < d; ++al) a(b, al) = dbl(c.a(b, al));
  std::vector<Eigen::MatrixXd> da;
  for (const auto& di : c.da) {
    Eigen::MatrixXd x(m, d);
    for (std::size_t b = 0; b < m; ++b)
      for (std::size_t al = 0; al < d; ++al) x(b, al) = dbl(di(b, al));
    da.push_back(x);
  }
  Eigen::VectorXd p(p_rs.size());
  for (std::size_t i = 0; i < p_rs.size(); ++i) p(static_cast<Eigen::Index>(i)) = dbl(p_rs[i]);
  const Eigen::MatrixXd fast = fast::constrained_poisson_tensor(a, da, p);
  if (static_cast<std::size_t>(fast.rows()) != exact.rows() || static_cast<std::size_t>(fast.cols()) != exact.cols())
    return std::numeric_limits<double>::infinity();
  double scale = 1, worst = 0;
  for (std::size_t i = 0; i < exact.rows(); ++i)
    for (std::size_t j = 0; j < exact.cols(); ++j) scale = std::max(scale, std::abs(dbl(exact(i, j))));
  for (std::size_t i = 0; i < exact.rows(); ++i)
    for (std::size_t j = 0; j < exact.cols(); ++j)
      worst = std::max(worst,
                       std::abs(fast(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) - dbl(exact(i, j))));
  return worst / (1e-12 * scale * static_cast<double>(2 * d + m));
}

}  // namespace

// YM (5.9) on its own example, the rolling disk of §6 (r = (theta, phi), s = (x, y)): B_P^♯ is YM's printed
// matrix except the (p~_1, p~_2) entry, printed +p_b K^b_12 — that matrix is not skew, while B_P = B|_{T*P×T*P}
// of a Poisson tensor must be; (5.9) gives −p_b K^b_12 (ERRATA).  Exactly, at rational points of the circle and
// momenta off P (where p_b K^b_12 ≠ 0; on P it vanishes for the disk).  fast reaches the same matrix from the
// canonical brackets of p~_α = p_α − A^b_α p_b, without K.  Killed by: the printed sign, a transposed A block.
TEST(Ehresmann, BpSharpOfTheRollingDiskIsYMsWithErratasSign) {
  const Q m(2), inertia(1, 2), jj(1, 4), rr(1, 3);
  const reference::EhresmannConnection conn =
      reference::ehresmann_connection(rolling_disk(m, inertia, jj, rr), {Q(0), Q(0), Q(0), Q(0)});
  for (int t = -3; t <= 3; ++t) {
    const Q c = Q(1 - t * t, 1 + t * t), s = Q(2 * t, 1 + t * t);
    const std::vector<Q> qv{Q(1, 2), Q(-2), Q(3), Q(0), Q(0), Q(0), Q(0), Q(0)};
    const ConnectionAt at = connection_at(conn, [&](const ex::Expr& e) { return at_angle(e, qv, c, s); });
    const std::vector<Q> p_rs{Q(3, 5), Q(-1, 7), Q(2), Q(-5, 3)};  // (p_theta, p_phi, p_x, p_y)
    const reference::Matrix<Q> bp = reference::constrained_poisson_tensor(at.a, at.k, {p_rs[2], p_rs[3]});
    const Q pk = p_rs[2] * rr * s - p_rs[3] * rr * c;  // p_b K^b_12 with K¹_12 = R sin phi, K²_12 = −R cos phi
    ASSERT_NE(pk, 0);
    std::vector<std::vector<Q>> printed = {{0, 0, 0, 0, 1, 0},
                                           {0, 0, 0, 0, 0, 1},
                                           {0, 0, 0, 0, rr * c, 0},
                                           {0, 0, 0, 0, rr * s, 0},
                                           {-1, 0, -rr * c, -rr * s, 0, pk},
                                           {0, -1, 0, 0, pk, 0}};
    bool printed_skew = true;
    for (std::size_t i = 0; i < 6; ++i)
      for (std::size_t j = 0; j < 6; ++j) printed_skew = printed_skew && printed[i][j] == -printed[j][i];
    EXPECT_FALSE(printed_skew) << "YM's printed (5, 6) entry";
    printed[4][5] = -pk;  // ERRATA: −p_b K^b_12
    for (std::size_t i = 0; i < 6; ++i)
      for (std::size_t j = 0; j < 6; ++j) EXPECT_EQ(bp(i, j), printed[i][j]) << i << ", " << j << " at t = " << t;
    // (5.10): {p~_1, p~_2}_P = −p_b K^b_12 and {theta, p~_1}_P = 1
    EXPECT_EQ(reference::constrained_bracket(bp, {0, 0, 0, 0, 1, 0}, {0, 0, 0, 0, 0, 1}), -pk);
    EXPECT_EQ(reference::constrained_bracket(bp, {1, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 1, 0}), 1);
    EXPECT_LE(twins_difference(at, p_rs), 1.0);
  }
}

// YM's L-C circuit (§6): the connection dcad derives from KCL, s = (q_L, q_C1), r = (q_C2, q_C3), A = [[−1, 0],
// [−1, 1]], is holonomic (K = 0), and B_P^♯ is YM's last matrix of §6, [[0, 0, δ], [0, 0, −A], [−δ, Aᵀ, 0]], entry for
// entry.  Killed by: a connection solved for the wrong coordinates or sign, a transposed A block.
TEST(Ehresmann, BpSharpOfTheLcCircuitIsYMs) {
  reference::LagrangianSystem lc;
  lc.n = 4;
  lc.names = {"q_L", "q_C1", "q_C2", "q_C3"};
  const auto v = [](Index i) { return ex::variable(4 + i); };
  lc.lagrangian = ex::mul(ex::number(Q(1, 2)), ex::pow(v(0), 2));
  lc.constraints = {ex::add(ex::neg(v(0)), v(2)), ex::sub(ex::add(ex::neg(v(1)), v(2)), v(3))};
  const reference::EhresmannConnection conn = reference::ehresmann_connection(lc, {Q(0), Q(0), Q(0), Q(0)});
  ASSERT_EQ(conn.s, (std::vector<std::size_t>{0, 1}));
  const ConnectionAt at =
      connection_at(conn, [](const ex::Expr& e) { return reference::value_at(e, std::vector<Q>(8)); });
  const reference::Matrix<Q> bp = reference::constrained_poisson_tensor(at.a, at.k, {Q(7), Q(-3)});
  const std::vector<std::vector<Q>> ym = {{0, 0, 0, 0, 1, 0},  {0, 0, 0, 0, 0, 1},    {0, 0, 0, 0, 1, 0},
                                          {0, 0, 0, 0, 1, -1}, {-1, 0, -1, -1, 0, 0}, {0, -1, 0, 1, 0, 0}};
  for (std::size_t i = 0; i < 6; ++i)
    for (std::size_t j = 0; j < 6; ++j) EXPECT_EQ(bp(i, j), ym[i][j]) << i << ", " << j;
  EXPECT_LE(twins_difference(at, {Q(1), Q(2), Q(7), Q(-3)}), 1.0);
}

// Over random connections affine in q (n ≤ 5, m ≤ 2): the reference's (5.9) with the curvature formula equals
// fast's canonical brackets of P's coordinate functions — two routes to B_P = B|_{T*P×T*P} [YM §5].  Killed by: a
// sign or index of K's four terms, of the A blocks, or of the bracket.
namespace {

Q small_rational() { return Q(*rc::gen::inRange(-4, 5), *rc::gen::inRange(1, 4)); }

/// A random connection on q = (r, s), r the first d coordinates: A^b_α(q) = c + Σ g_i q^i + h q^i q^j, affine
/// and one product (so A, ∂A and K all depend on the point).
reference::EhresmannConnection random_connection(std::size_t d, std::size_t m) {
  const std::size_t n = d + m;
  reference::EhresmannConnection conn;
  for (std::size_t i = 0; i < d; ++i) conn.r.push_back(i);
  for (std::size_t i = 0; i < m; ++i) conn.s.push_back(d + i);
  conn.a.assign(m, std::vector<ex::Expr>(d));
  for (auto& row : conn.a)
    for (auto& e : row) {
      e = ex::number(small_rational());
      for (std::size_t i = 0; i < n; ++i) e = ex::add(e, ex::mul(ex::number(small_rational()), ex::variable(i)));
      const std::size_t i = *rc::gen::inRange<std::size_t>(0, n), j = *rc::gen::inRange<std::size_t>(0, n);
      e = ex::add(e, ex::mul(ex::number(small_rational()), ex::mul(ex::variable(i), ex::variable(j))));
    }
  return conn;
}

}  // namespace

RC_GTEST_PROP(Ehresmann, BpSharpIsTheCanonicalBracketOfPsCoordinates, ()) {
  const std::size_t d = *rc::gen::inRange<std::size_t>(1, 4), m = *rc::gen::inRange<std::size_t>(1, 3), n = d + m;
  const auto small = [] { return small_rational(); };
  const reference::EhresmannConnection conn = random_connection(d, m);
  std::vector<Q> q(2 * n);
  for (std::size_t i = 0; i < n; ++i) q[i] = small();
  const ConnectionAt at = connection_at(conn, [&](const ex::Expr& e) { return reference::value_at(e, q); });
  std::vector<Q> p(n);
  for (auto& x : p) x = small();
  RC_ASSERT(twins_difference(at, p) <= 1.0);
}

// YM Prop 5.1 and the constrained energy after it, on random connections (random_connection) and random Lagrangians
// L = Σ c_i v_i²/2 + Σ g_i q^{j_i} v_i + Σ h_i (q^i)² (c_i > 0), at random (q, v ∈ Δ), q̇, v̇:
//  - the proof's identity dω^b(v, ·) = K^b_{αβ} u^β dr^α on Δ: dω^b(hor u, hor w) by the definition of d
//    (connection_form_differential) is Σ K^b_{αβ} u^β w^α with YM's coordinate K — so with the Remark's
//    K^b(Y, Z) = K^b_{αβ} Y^α Z^β, dω^b(hor Y, hor Z) = K^b(Z, Y) = −K^b(Y, Z);
//  - (5.7) ⇔ (5.6): with p̃ = ∂L_c/∂u and its rate along (q̇, v̇), the coefficients of the variation (5.7) less its
//    right side (ldap_variation, dω literal) are the residuals of (5.6) (implicit_lagrange_dalembert_residual, with
//    K): δr^α's is −(d/dt p̃_α − rhs_α), δu's is 0, δp̃_α's is ṙ^α − u^α — for every q̇, v̇, not only on solutions;
//  - E_c(q, u, ∂L_c/∂u) = Σ p_i v_i − L(q, v) with p = ∂L/∂v: the constrained energy is the energy on Δ;
//  - fast's dω^b(hor u, hor w) by the Lie bracket of horizontal lifts equals the reference's (1e-12).
// d ≥ 2 base directions (with one, K and dω(v, hor e) vanish identically and nothing above is tested).
// Killed by: a sign of dω or of K, the s-part of the lift, the transposed K in (5.6).
RC_GTEST_PROP(Ehresmann, Prop5_1_LdapPrincipleIsTheImplicitLagrangeDAlembertEquations, ()) {
  const std::size_t d = *rc::gen::inRange<std::size_t>(2, 4), m = *rc::gen::inRange<std::size_t>(1, 3), n = d + m;
  const reference::EhresmannConnection conn = random_connection(d, m);
  reference::LagrangianSystem sys;
  sys.n = n;
  for (std::size_t i = 0; i < n; ++i) sys.names.push_back("q" + std::to_string(i));
  sys.lagrangian = ex::number(0);
  for (std::size_t i = 0; i < n; ++i) {
    const ex::Expr v = ex::variable(sys.v(i)), q = ex::variable(*rc::gen::inRange<std::size_t>(0, n));
    sys.lagrangian = ex::add(sys.lagrangian, ex::mul(ex::number(Q(*rc::gen::inRange(1, 5), 2)), ex::pow(v, 2)));
    sys.lagrangian = ex::add(sys.lagrangian, ex::mul(ex::number(small_rational()), ex::mul(q, v)));
    sys.lagrangian = ex::add(sys.lagrangian, ex::mul(ex::number(small_rational()), ex::pow(ex::variable(i), 2)));
  }
  std::vector<Q> q(n), u(d), w(d), q_dot(n), v_dot(n);
  for (auto* vec : {&q, &u, &w, &q_dot, &v_dot})
    for (Q& x : *vec) x = small_rational();
  const std::vector<Q> v = reference::horizontal_lift(conn, q, u), hw = reference::horizontal_lift(conn, q, w);
  // the proof's identity, and fast's route to dω
  const std::vector<Q> dw = reference::connection_form_differential(conn, q, v, hw);
  const auto kf = reference::curvature(conn);
  const ConnectionAt at = connection_at(conn, [&](const ex::Expr& e) { return reference::value_at(e, q); });
  Eigen::MatrixXd a(m, d);
  std::vector<Eigen::MatrixXd> da;
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < d; ++al) a(b, al) = dbl(at.a(b, al));
  for (const auto& di : at.da) {
    Eigen::MatrixXd x(m, d);
    for (std::size_t b = 0; b < m; ++b)
      for (std::size_t al = 0; al < d; ++al) x(b, al) = dbl(di(b, al));
    da.push_back(x);
  }
  Eigen::VectorXd ud(d), wd(d);
  for (std::size_t al = 0; al < d; ++al) ud(al) = dbl(u[al]), wd(al) = dbl(w[al]);
  const Eigen::VectorXd fast_dw = fast::horizontal_form_differential(a, da, ud, wd);
  for (std::size_t b = 0; b < m; ++b) {
    Q k_uw = 0;
    for (std::size_t al = 0; al < d; ++al)
      for (std::size_t be = 0; be < d; ++be) k_uw += reference::value_at(kf[b][al][be], q) * u[be] * w[al];
    RC_ASSERT(dw[b] == k_uw);
    RC_ASSERT(std::abs(fast_dw(static_cast<Eigen::Index>(b)) - dbl(dw[b])) <= 1e-12 * (1 + std::abs(dbl(dw[b]))));
  }
  // (5.7) ⇔ (5.6): p̃ = ∂L_c/∂u and d/dt p̃ along (q̇, v̇), by first-order jets
  std::vector<Q> qv(q);
  qv.insert(qv.end(), v.begin(), v.end());
  std::vector<Q> qv_dot(q_dot);
  qv_dot.insert(qv_dot.end(), v_dot.begin(), v_dot.end());
  auto sp = std::make_shared<const reference::JetSpace>(1, 1);
  std::vector<reference::Jet<Q>> x;
  for (std::size_t i = 0; i < 2 * n; ++i) {
    reference::Jet<Q> j = reference::Jet<Q>::variable(sp, 0, qv[i]);
    j.set_coefficient(1, qv_dot[i]);
    x.push_back(j);
  }
  x.emplace_back(sp, Q(0));
  const ex::Expr lc = reference::constrained_lagrangian(sys, conn);
  std::vector<Q> pt, pt_dot;
  for (std::size_t al = 0; al < d; ++al) {
    const auto j = ex::evaluate<reference::Jet<Q>>(ex::diff(lc, sys.v(conn.r[al])), x,
                                                   [&](const Q& c) { return reference::Jet<Q>(sp, c); });
    pt.push_back(j.value());
    pt_dot.push_back(j.gradient(0));
  }
  const reference::LdapVariation var = reference::ldap_variation(sys, conn, qv, q_dot, pt, pt_dot);
  const std::vector<Q> res = reference::implicit_lagrange_dalembert_residual(sys, conn, qv, qv_dot);
  for (std::size_t al = 0; al < d; ++al) {
    RC_ASSERT(var.dr[al] == -res[m + d + al]);
    RC_ASSERT(var.du[al] == 0);
    RC_ASSERT(var.dp[al] == res[m + al]);
  }
  // E_c on P is the energy on Δ
  std::vector<Q> at_t(qv);
  at_t.push_back(Q(0));
  Q energy = -reference::value_at(sys.lagrangian, at_t);
  for (std::size_t i = 0; i < n; ++i) energy += reference::value_at(ex::diff(sys.lagrangian, sys.v(i)), at_t) * v[i];
  RC_ASSERT(reference::constrained_energy(sys, conn, qv, pt) == energy);
}
