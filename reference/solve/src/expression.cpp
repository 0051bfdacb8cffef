// The expression form by the exact pointwise CAD (the one translation unit that instantiates
// reference/nonlinear/pointwise.hpp on mpq_rational).
#include "dcad/reference/pipeline/pointwise.hpp"

namespace dcad::reference::pipeline {

dcad::Solution<Rational> solve_pointwise_exact(const io::LagrangianCase& c) {
  std::vector<bool> fixed;
  const std::vector<Rational> start = start_point(c, fixed);
  ExactDecisions<Rational> decide;
  const auto r = pointwise_cad<Rational>(c.system, start, fixed, decide, [](const Rational& q) { return q; });
  check_given<Rational>(
      r, c, [](const Rational& a, const Rational& b) { return a == b; }, [](const Rational& q) { return q.str(); });
  dcad::Solution<Rational> out = pointwise_solution(r, c, "pointwise exact");
  out.certified = r.regular ? yes : unknown;  // a singular point decides no tower
  return out;
}

}  // namespace dcad::reference::pipeline
