// Expressions and jets (reference/expression.hpp, jet.hpp), each against a route it does not use:
//  - the symbolic derivative (diff: product, quotient, power and chain rules on the formula) equals
//    the jet's coefficient (forward-mode arithmetic on truncated Taylor series), exactly, at
//    random rational points, to the second order;
//  - a jet composed with a substitution (Jet::compose) equals the formula evaluated on the
//    substituted jets;
//  - exact values of sin, cos, exp at 0 and sqrt of squares, and the NotExactHere refusal elsewhere.
#include "dcad/reference/nonlinear/expression.hpp"
#include "dcad/reference/nonlinear/jet.hpp"
#include "gen.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ex = reference::expr;
using J = reference::Jet<Q>;

namespace {

/// A random rational function of variables 0..d−1 (no sin/cos/exp/sqrt: those are exact only at 0).
ex::Expr random_expr(Index d, int depth) {
  const int kind = *rc::gen::inRange(0, depth <= 0 ? 2 : 7);
  switch (kind) {
    case 0: return ex::number(Q(*rc::gen::inRange(-3, 4), *rc::gen::inRange(1, 3)));
    case 1: return ex::variable(*rc::gen::inRange<Index>(0, d));
    case 2: return ex::add(random_expr(d, depth - 1), random_expr(d, depth - 1));
    case 3: return ex::sub(random_expr(d, depth - 1), random_expr(d, depth - 1));
    case 4: return ex::mul(random_expr(d, depth - 1), random_expr(d, depth - 1));
    case 5: return ex::pow(random_expr(d, depth - 1), *rc::gen::inRange(0, 4));
    default: {  // a divisor that is 1 + a square: never 0
      const ex::Expr den = ex::add(ex::number(1), ex::pow(random_expr(d, depth - 1), 2));
      return ex::div(random_expr(d, depth - 1), den);
    }
  }
}

J eval_jet(const ex::Expr& e, const std::vector<J>& x) {
  const auto& sp = x[0].space();
  return ex::evaluate<J>(e, x, [&](const Q& c) { return J(sp, c); });
}

std::vector<J> variables(const std::shared_ptr<const reference::JetSpace>& sp, const std::vector<Q>& point) {
  std::vector<J> x;
  for (Index i = 0; i < point.size(); ++i) x.push_back(J::variable(sp, i, point[i]));
  return x;
}

}  // namespace

// ∂e/∂x_i and ∂²e/∂x_i∂x_j by the rules of calculus = the jet's coefficients (two routes).
RC_GTEST_PROP(Expression, SymbolicDerivativesEqualJetCoefficients, ()) {
  const Index d = pick_size(1, 3);
  const ex::Expr e = random_expr(d, 4);
  std::vector<Q> point;
  for (Index i = 0; i < d; ++i) point.push_back(Q(*rc::gen::inRange(-4, 5), *rc::gen::inRange(1, 4)));
  auto sp = std::make_shared<const reference::JetSpace>(d, 2);
  const J jet = eval_jet(e, variables(sp, point));
  auto none = std::make_shared<const reference::JetSpace>(0, 0);
  std::vector<J> at;
  for (const Q& v : point) at.push_back(J(none, v));
  RC_ASSERT(eval_jet(e, at).value() == jet.value());
  for (Index i = 0; i < d; ++i) {
    const ex::Expr di = ex::diff(e, i);
    RC_ASSERT(eval_jet(di, at).value() == jet.gradient(i));
    RC_ASSERT(jet.derivative(i).value() == jet.gradient(i));
    for (Index j = 0; j < d; ++j)  // ∂²e/∂x_i∂x_j = the derivative of the derivative jet
      RC_ASSERT(eval_jet(ex::diff(di, j), at).value() == jet.derivative(i).gradient(j));
  }
}

// f(s(u)) two ways: compose the jet of f with the jets s(u), or evaluate f's formula on s(u).
RC_GTEST_PROP(Expression, CompositionEqualsEvaluationOnSubstitutedJets, ()) {
  const Index d = pick_size(1, 3), k = pick_size(1, 2);
  const ex::Expr f = random_expr(d, 3);
  std::vector<ex::Expr> s;
  for (Index i = 0; i < d; ++i) s.push_back(random_expr(k, 2));
  std::vector<Q> u0;
  for (Index i = 0; i < k; ++i) u0.push_back(Q(*rc::gen::inRange(-3, 4), *rc::gen::inRange(1, 3)));
  auto su = std::make_shared<const reference::JetSpace>(k, 3);
  std::vector<J> s_of_u;
  for (const auto& e : s) s_of_u.push_back(eval_jet(e, variables(su, u0)));
  std::vector<Q> s0;
  for (const J& x : s_of_u) s0.push_back(x.value());
  auto ss = std::make_shared<const reference::JetSpace>(d, 3);
  const J composed = eval_jet(f, variables(ss, s0)).compose(s_of_u);
  const J direct = eval_jet(f, s_of_u);
  RC_ASSERT((composed - direct).is_zero());
}

TEST(Jet, ExactFunctionsAndRefusals) {
  auto sp = std::make_shared<const reference::JetSpace>(1, 4);
  const J x0 = J::variable(sp, 0, Q(0));
  // sin, cos, exp at 0: their Taylor coefficients 0, 1, 0, −1/6; 1, 0, −1/2, 0, 1/24; 1/k!
  EXPECT_EQ(sin(x0).coefficient(3), Q(-1, 6));
  EXPECT_EQ(cos(x0).coefficient(4), Q(1, 24));
  EXPECT_EQ(exp(x0).coefficient(4), Q(1, 24));
  // √(9/4 + δ) = 3/2 + δ/3 − δ²/27 + …
  const J y = J::variable(sp, 0, Q(9, 4));
  EXPECT_EQ(sqrt(y).value(), Q(3, 2));
  EXPECT_EQ(sqrt(y).coefficient(1), Q(1, 3));
  EXPECT_EQ(sqrt(y).coefficient(2), Q(-1, 27));
  EXPECT_THROW(sin(J::variable(sp, 0, Q(1, 2))), reference::NotExactHere);
  EXPECT_THROW(sqrt(J::variable(sp, 0, Q(2))), reference::NotExactHere);
  EXPECT_THROW(J::variable(sp, 0, Q(0)).reciprocal(), std::domain_error);
  // a derivative knows one order less; a product of orders 4 and 3 knows 3
  EXPECT_EQ(x0.derivative(0).order(), 3);
  EXPECT_EQ((x0 * x0.derivative(0)).order(), 3);
}

TEST(Expression, AffineDegreeAndText) {
  const auto v = [](Index i) { return ex::variable(i); };
  const auto in_v = [](std::size_t i) { return i >= 2; };  // variables 2, 3 are velocities
  EXPECT_EQ(ex::degree_in(ex::sub(v(2), ex::mul(ex::cos(v(0)), v(3))), in_v), 1);
  EXPECT_EQ(ex::degree_in(ex::pow(v(2), 2), in_v), 2);
  EXPECT_EQ(ex::degree_in(ex::div(v(0), v(2)), in_v), -1);
  EXPECT_EQ(ex::degree_in(ex::sin(v(2)), in_v), -1);
  // folding keeps derivatives small: d/dx (1/2 x^2) = x
  const ex::Expr half_sq = ex::mul(ex::number(Q(1, 2)), ex::pow(v(0), 2));
  EXPECT_EQ(ex::to_text(ex::diff(half_sq, 0), {"x"}), "x");
  EXPECT_EQ(ex::to_text(ex::sub(v(0), ex::neg(v(1))), {"x", "y"}), "x + y");
  EXPECT_EQ(ex::to_text(ex::add(v(0), ex::mul(ex::number(-2), v(1))), {"x", "y"}), "x - 2*y");
}
