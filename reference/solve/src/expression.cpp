// The expression form by the exact pointwise CAD (the one translation unit that instantiates
// reference/nonlinear/pointwise.hpp on mpq_rational).
#include "dcad/reference/pipeline/pointwise.hpp"

namespace dcad::reference::pipeline {

dcad::Solution<Rational> solve_pointwise_exact(const io::LagrangianCase& c) {
  std::vector<bool> fixed;
  ExactDecisions<Rational> decide;
  PointwiseResult<Rational> r;
  for (int seed = 0; seed < kStartSeeds; ++seed) {  // a default point that is singular is not the generic answer: another one
    const std::vector<Rational> start = start_point(c, fixed, seed);
    r = pointwise_cad<Rational>(c.system, start, fixed, decide, [](const Rational& q) { return q; });
    if (r.regular || c.has_initial) break;
  }
  check_given<Rational>(
      r, c, [](const Rational& a, const Rational& b) { return a == b; }, [](const Rational& q) { return q.str(); });
  dcad::Solution<Rational> out = pointwise_solution(r, c, "pointwise exact");
  out.certified = r.regular ? yes : unknown;  // a singular point decides no tower
  return out;
}

}  // namespace dcad::reference::pipeline
