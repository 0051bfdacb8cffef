// The expression form by the pointwise CAD in double (fast::pointwise_cad, dcad::fast_nonlinear), on the
// case's point rounded by the one exact-to-double conversion (exact.hpp).
#include "dcad/fast/chart.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"

#include <cmath>

namespace dcad::fast {

Solution solve_expression(const io::LagrangianCase& c, const Options& options) {
  namespace pl = reference::pipeline;
  return pl::pointwise_input_errors(c, [&] {
    std::vector<bool> fixed;
    Options opt = options;
    ToleranceDecisions decide;
    reference::PointwiseResult<double> r;
    for (int seed = 0; seed < pl::kStartSeeds; ++seed) {  // a default point that is singular is not the generic answer: another one
      const std::vector<reference::Rational> start = pl::start_point(c, fixed, seed);
      std::vector<double> x;
      for (const reference::Rational& q : start) x.push_back(to_double(q, opt));
      decide.probe = opt.probe;  // one decision object over the attempts: an uncertain one before a retry stays on record
      try {
        r = pointwise_cad(c.system, x, fixed, decide);
      } catch (const reference::PointwiseNoPoint&) {
        // the pointwise CAD's Newton moves did not settle from the given values (multiplier coordinates):
        // the formulas' tower completes them (the given ones held), and the CAD runs again from there
        const std::vector<double> z = complete_on_chart(c.system, x, fixed);
        if (z.empty()) throw;
        try {
          r = pointwise_cad(c.system, z, fixed, decide);
        } catch (const reference::PointwiseNoPoint&) {  // its Newton still does not settle: every value held (z is on M_c to rounding)
          r = pointwise_cad(c.system, z, std::vector<bool>(z.size(), true), decide);
        }
      }
      if (r.regular || c.has_initial) break;
    }
    pl::check_given<double>(
        r, c,
        [](const double& a, const reference::Rational& b) {  // a tolerance for given values, not a decision
          const double bb = b.convert_to<double>();
          return std::abs(a - bb) <= 1e-9 * (1 + std::abs(bb));
        },
        [](const double& v) { return io::float_text(v); });
    Solution out = pl::pointwise_solution(r, c, "pointwise double");
    out.backend = "fast";
    // a point that rounding moved (a value of large height) may sit off the locus the exact point is on
    const Truth point = opt.input_exact ? yes : unknown;
    out.certified = decide.certain & (r.regular ? yes : unknown) & point;
    if (decide.certain.unknown()) out.note = "not certified: " + decide.evidence;
    else if (point.unknown()) out.note = "not certified: the point was rounded to double (" + input_caveat(opt) + ")";
    return out;
  });
}

}  // namespace dcad::fast
