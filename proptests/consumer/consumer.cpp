// A project outside dcad's tree that uses the installed package (README "dcad from C++"): the CAD on its
// own matrices, a netlist given as a string, the typed Solution read and printed, a result checked —
// all on in-memory data, no file written or read — and a property written with dcad's generators (dcad::testing).
#include "dcad/api.hpp"                 // every backend's solve, check, simulate
#include "dcad/certified/solve.hpp"     // certified::solve: a Problem in, a typed Solution out
#include "dcad/fast/cad.hpp"            // the double twin on your own matrices
#include "dcad/io/problem.hpp"          // problem(…): your data as a Problem; parse_netlist, parse_case: from text
#include "dcad/io/report.hpp"           // text and JSON as `dcad solve` prints them
#include "dcad/reference/cad.hpp"       // the exact reference on your own matrices
#include "dcad/testing/convert.hpp"     // to_double: exact matrices as Eigen doubles
#include "dcad/testing/generators.hpp"  // systems(): random exact linear Dirac systems (CEF §5), shown as case files

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <optional>
#include <sstream>
#include <variant>

namespace ref = dcad::reference;
namespace fast = dcad::fast;
using Q = ref::Rational;

// 0. Problems built in code, one per form, on every backend, with the decisions behind each answer (the trace).
TEST(MyProblems, BuiltInCodeSolvedOnEveryBackend) {
  // your own exact Dirac system (CEF §5): ω = dq∧dp on (q, p, z), E = ½ (q² + p² + z²) + z
  ref::Matrix<Q> w(3, 3), h(3, 3);
  w(0, 1) = Q(1);
  w(1, 0) = Q(-1);
  h(0, 0) = h(1, 1) = h(2, 2) = Q(1);
  const dcad::io::Problem mine =
      dcad::io::problem(ref::LinearSystem<Q>{ref::dirac_from_presymplectic(w), h, {Q(0), Q(0), Q(1)}}, {"q", "p", "z"});
  // a linear DAE E ẋ = A x (CEF (1.6)): ẋ1 = x2, 0 = x1
  dcad::io::DaeCase dae;
  dae.variables = {"x1", "x2"};
  dae.e = ref::Matrix<Q>(2, 2);
  dae.a = ref::Matrix<Q>(2, 2);
  dae.e(0, 0) = dae.a(0, 1) = dae.a(1, 0) = Q(1);
  const dcad::io::Problem index2 = dcad::io::problem(dae);
  using B = dcad::api::Backend;
  for (const B b : {B::reference, B::certified, B::fast}) {
    std::visit(
        [](const auto& s) {  // each backend's own Solution: Rational, certified::Number or double
          EXPECT_EQ(s.dims(), (std::vector<long>{3, 2}));  // ∂E/∂z = z + 1 = 0 cuts M_1; ż = 0 keeps it
          EXPECT_EQ(s.solution_rank, 0L);
          ASSERT_TRUE(s.certified.yes());
          for (const dcad::Decision& d : s.trace)  // what was decided, how, and the evidence (σ's on fast)
            EXPECT_TRUE(d.certain.yes()) << d.what << ": " << d.evidence;
          ASSERT_FALSE(s.trace.empty());
        },
        dcad::api::solve(mine, b));
    std::visit(
        [](const auto& s) {
          EXPECT_EQ(s.dims(), (std::vector<long>{2, 1, 0}));  // M_1 = {x1 = 0}, M_2 = {x1 = x2 = 0}
          EXPECT_EQ(s.index(), std::optional<long>(2));
          EXPECT_TRUE(s.certified.yes());
        },
        dcad::api::solve(index2, b));
  }
  const dcad::reference::Solution exact = std::get<dcad::reference::Solution>(dcad::api::solve(mine, B::reference));
  EXPECT_EQ(exact.trace[0].what, "dim M_1");  // the exact tiers: one exact decision per level
  EXPECT_EQ(exact.trace[0].by, dcad::DecidedBy::exact);
  const dcad::fast::Solution twin = std::get<dcad::fast::Solution>(dcad::api::solve(mine, B::fast));
  EXPECT_FALSE(twin.trace.back().singular_values.empty());  // fast: each rank with its singular values and gap
  dae.variables.pop_back();  // built in code, validated as a file is: E and A with 2 columns for 1 name are refused
  EXPECT_THROW(dcad::api::solve(dcad::io::problem(dae), B::fast), dcad::io::InputError);
}

// 0'. The other forms built in code: a `pontryagin` case (YM §4) and a Lagrangian system by formulas (YM §5), its
// motion taken as a typed Trajectory.
TEST(MyProblems, PontryaginAndFormulasBuiltInCode) {
  // masses 2 and 1 on springs 8 and 2, tied by v1 = v2: L = ½ vᵀ A v + ½ qᵀ C q, Δ = ker K, K = [1 −1]
  dcad::io::CaseFile pair;
  pair.n = 6;
  pair.variables = {"q1", "q2", "v1", "v2", "p1", "p2"};
  pair.has_pontryagin = true;
  dcad::io::PontryaginInput& l = pair.pontryagin;
  l.n = 2;
  l.k = ref::Matrix<Q>(1, 2);
  l.k(0, 0) = Q(1);
  l.k(0, 1) = Q(-1);
  l.vv = l.qv = l.qq = ref::Matrix<Q>(2, 2);
  l.vv(0, 0) = Q(2);
  l.vv(1, 1) = Q(1);
  l.qq(0, 0) = Q(-8);
  l.qq(1, 1) = Q(-2);
  l.q = l.v = {Q(0), Q(0)};
  const dcad::certified::Solution tied = dcad::certified::solve(dcad::io::problem(pair));
  EXPECT_EQ(tied.dims(), (std::vector<long>{6, 3}));  // M_1 = {p = A v, v1 = v2}: 6 − 2 − 1, and M_2 = M_1
  EXPECT_EQ(tied.solution_rank, 0L);                  // the multiplier is fixed: 3 q̈ = −10 q

  // a particle in the plane that may not move in y: L = ½ (v_x² + v_y²), v_y = 0, from x = y = 0 at v_x = 1
  namespace ex = dcad::symbolic::expr;
  dcad::io::LagrangianCase planar;
  planar.system.n = 2;
  planar.system.names = {"x", "y"};
  const ex::Expr vx = ex::variable(planar.system.v(0)), vy = ex::variable(planar.system.v(1));
  planar.system.lagrangian = ex::div(ex::add(ex::pow(vx, 2), ex::pow(vy, 2)), ex::number(Q(2)));
  planar.system.constraints = {vy};
  planar.initial = {Q(0), Q(0), Q(1), Q(0), std::nullopt};  // x, y, v_x, v_y, t
  planar.initial_p = {std::nullopt, std::nullopt};
  planar.has_initial = true;
  const dcad::io::Problem particle = dcad::io::problem(planar);
  const dcad::reference::Solution exact = dcad::reference::solve(particle);
  EXPECT_EQ(exact.dims(), (std::vector<long>{6, 3}));  // p = ∂L/∂v and v_y = 0; v̇_y = 0 keeps it (λ = 0)
  ASSERT_TRUE(exact.pointwise.has_value());
  EXPECT_EQ(exact.pointwise->velocity[0], Q(1));  // ẋ = v_x = 1 at the point
  dcad::api::SimulateOptions opt;
  opt.tstop = 1;
  opt.step = 0.25;
  std::ostringstream log;
  const dcad::api::Trajectory t = dcad::api::simulate_trajectory(particle, opt, log);
  EXPECT_NEAR(t.column("x").back(), 1.0, 1e-12);  // x(t) = t
  EXPECT_EQ(t.column("y").back(), 0.0);
}

// 1. The CAD on your own matrices (CEF §5): (x, ẋ) ⊕ dE(x) ∈ D_ω for the presymplectic ω = dq1 ∧ dp1 on
// R^3 (x3 is a gauge direction) and E = ½ (q1² + p1²) + x3: dE(x3) = 1 can never be met, so M_1 = ∅.
TEST(MyMatrices, TheCadOnMyOwnMatrices) {
  ref::Matrix<Q> w(3, 3), h(3, 3);
  w(0, 1) = Q(1);
  w(1, 0) = Q(-1);
  h(0, 0) = h(1, 1) = Q(1);
  const std::vector<Q> g{Q(0), Q(0), Q(1)};
  const ref::LinearSystem<Q> s{ref::dirac_from_presymplectic(w), h, g};
  const ref::CadResult<Q> exact = ref::constraint_tower(s);  // exact rationals, literally CEF (5.5)-(5.6)
  EXPECT_FALSE(exact.consistent);
  EXPECT_EQ(exact.tower.back().dim(), -1);

  // the same in double: a tower with a verdict (certain, or "don't know" with its evidence)
  Eigen::MatrixXd wd = Eigen::MatrixXd::Zero(3, 3), hd = Eigen::MatrixXd::Zero(3, 3);
  wd(0, 1) = 1;
  wd(1, 0) = -1;
  hd(0, 0) = hd(1, 1) = 1;
  const fast::LinearSystem sd{fast::dirac_from_presymplectic(wd), hd, Eigen::Vector3d(0, 0, 1), 0.0};
  const fast::CadResult r = fast::constraint_tower(sd);
  ASSERT_TRUE(r.certain.yes());
  EXPECT_FALSE(r.consistent);
}

// 2. A netlist given as a string, solved by the certified tier: the typed Solution, read and printed.
TEST(MyNetlist, SolveADeckGivenAsAString) {
  const dcad::io::Problem deck = dcad::io::parse_netlist(
      "two capacitors in a loop with an inductor\n"
      "L1 1 0 2u\n"
      "C1 1 0 3n\n"
      "C2 1 0 5n\n"
      ".end\n",
      "loop.cir");
  const dcad::certified::Solution s = dcad::certified::solve(deck);
  EXPECT_TRUE(s.certified.yes());
  EXPECT_EQ(s.dims(), (std::vector<long>{9, 5, 4, 3}));  // CEF Thm 6.6: a capacitive loop, so c = 3
  ASSERT_TRUE(s.circuit.has_value());
  EXPECT_EQ(s.circuit->pc_loop_branches.size(), 1u);  // the loop C1, C2 by name
  ASSERT_TRUE(s.motion.has_value());
  EXPECT_EQ(s.motion->f_matrix.size(), 3u);                              // ż = F z on the 3-dimensional M_c
  EXPECT_TRUE(s.motion->f_matrix[0][0].exact);                           // exact numbers: no rounding anywhere
  const std::string json = dcad::io::result_json(dcad::io::printed(s));  // what `dcad solve --json` prints
  EXPECT_NE(json.find("\"dims\""), std::string::npos);
  std::ostringstream report;
  report << dcad::io::report_text(dcad::io::printed(s));  // the report for people
  EXPECT_NE(report.str().find("KVL loop 1"), std::string::npos);
}

// 3. Your tool's result for a case checked against the reference, as `dcad check` does.
TEST(MyTool, ResultAgreesWithTheReference) {
  const dcad::io::Problem p = dcad::io::parse_netlist("tank\nL1 1 0 1m\nC1 1 0 1u\n.end\n", "tank.cir");
  const dcad::io::Printed mine = dcad::api::printed(dcad::api::solve(p, dcad::api::Backend::fast, dcad::Parts::none()));
  EXPECT_EQ(mine.dims(), (std::vector<long>{6, 3}));                          // CEF Thm 6.6: no capacitive loop, c = 1
  EXPECT_TRUE(dcad::api::check_text(dcad::io::result_json(mine), p).agrees);  // or your tool's JSON text
  const dcad::api::Checked wrong =
      dcad::api::check_text(R"({"dims": [6, 2], "steps": 1, "consistent": true, "solution_rank": 0})", p);
  EXPECT_FALSE(wrong.agrees);  // dim M_1 is 3, not 2: the disagreement is named
  ASSERT_FALSE(wrong.disagreements.empty());
  EXPECT_NE(wrong.disagreements[0].find("dims"), std::string::npos);
  EXPECT_THROW(dcad::io::parse_netlist("bad\nQ1 1 0 npn\n", "bad.cir"), dcad::io::InputError);
}

// 4. The motion as a typed object: simulate's rows kept as doubles (a Trajectory), a column read by name.  The LC
// tank from q_C1 = 1 uC (IC=1 V, uic) swings as cos(t / sqrt(LC)): at a quarter period the charge is 0.
TEST(MyMotion, TheTrajectoryAsDoubles) {
  const dcad::io::Problem p =
      dcad::io::parse_netlist("tank\nL1 1 0 1m\nC1 1 0 1u IC=1\n.tran 1u 1m uic\n.end\n", "tank.cir");
  dcad::api::SimulateOptions opt;
  opt.tstop = 2e-4;
  opt.step = 1e-6;
  std::ostringstream log;
  const dcad::api::Trajectory t = dcad::api::simulate_trajectory(p, opt, log);
  ASSERT_EQ(t.rows.size(), 201u);
  EXPECT_EQ(t.names.front(), "t");
  const std::vector<double> q = t.column("q_C1");
  EXPECT_NEAR(q.front(), 1e-6, 1e-18);
  const double quarter = 3.141592653589793 / 2 * std::sqrt(1e-3 * 1e-6);  // 49.67 us
  const std::size_t k = static_cast<std::size_t>(quarter / opt.step);
  EXPECT_NEAR(q[k], 1e-6 * std::cos(t.rows[k][0] / std::sqrt(1e-9)), 1e-15);
  EXPECT_LT(t.summary.error_estimate, 1e-9);
}

// 5. A property of *your* CAD against the reference, on dcad's random Dirac systems with planted structure.
RC_GTEST_PROP(MyCad, AgreesWithTheReferenceWhereItIsCertain, ()) {
  using namespace dcad::test;
  const ref::LinearSystem<Q> s = *systems();  // a failing case prints as "dcad case: {…}"
  const ref::CadResult<Q> exact = ref::constraint_tower(s);
  fast::Options opt;  // the conversion records what the input's heights leave certain
  const fast::LinearSystem mine{fast::dirac_from_basis(to_double(s.d.d.basis(), &opt), opt), to_double(s.hessian, &opt),
                                to_double(QM::column(s.gradient), &opt).col(0), 0.0};
  const fast::CadResult r = fast::constraint_tower(mine, opt);  // put your implementation here
  RC_CLASSIFY(r.certain.unknown(), "uncertain");
  if (r.certain.unknown()) return;  // an honest "don't know" is allowed; a wrong certain answer is not
  RC_ASSERT(r.tower.size() == exact.tower.size());
  for (std::size_t k = 0; k < exact.tower.size(); ++k) RC_ASSERT(r.tower[k].dim() == exact.tower[k].dim());
  RC_ASSERT(r.consistent == exact.consistent);
}
