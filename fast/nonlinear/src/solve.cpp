// The expression form by the pointwise CAD in double (fast::pointwise_cad).
#include "dcad/fast/pointwise.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"

#include <cmath>

namespace dcad::fast {

dcad::Solution<double> solve_expression(const io::LagrangianCase& c) {
  namespace pl = reference::pipeline;
  return pl::pointwise_input_errors(c, [&] {
    std::vector<bool> fixed;
    const std::vector<reference::Rational> start = pl::start_point(c, fixed);
    std::vector<double> x;
    for (const reference::Rational& q : start) x.push_back(q.convert_to<double>());
    ToleranceDecisions decide;
    const reference::PointwiseResult<double> r = pointwise_cad(c.system, x, fixed, decide);
    pl::check_given<double>(
        r, c,
        [](const double& a, const reference::Rational& b) {
          const double bb = b.convert_to<double>();
          return std::abs(a - bb) <= 1e-9 * (1 + std::abs(bb));
        },
        [](const double& v) { return io::float_text(v); });
    dcad::Solution<double> out = pl::pointwise_solution(r, c, "pointwise double");
    out.backend = "fast";
    out.certified = decide.certain & (r.regular ? yes : unknown);
    if (decide.certain.unknown()) out.note = "not certified: " + decide.evidence;
    return out;
  });
}

}  // namespace dcad::fast
