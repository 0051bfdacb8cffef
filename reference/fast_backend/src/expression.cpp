// The expression form by the pointwise CAD in double (fast::pointwise_cad, pointwise.hpp of this backend), on the
// case's point rounded by the one exact-to-double conversion (exact.hpp).
#include "dcad/fast/chart.hpp"
#include "dcad/fast/derivative_array.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/implicit.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"

#include <cmath>
#include <set>

namespace dcad::fast {

Solution solve_expression(const io::LagrangianCase& c, const Options& options) {
  namespace pl = reference::pipeline;
  return pl::pointwise_input_errors(c, [&] {
    std::vector<bool> fixed;
    Options opt = options;
    ToleranceDecisions decide;
    reference::PointwiseResult<double> r;
    for (int seed = 0; seed < pl::kStartSeeds;
         ++seed) {  // a default point that is singular is not the generic answer: another one
      const std::vector<reference::Rational> start = pl::start_point(c, fixed, seed);
      std::vector<double> x;
      for (const reference::Rational& q : start) x.push_back(to_double(q, opt));
      decide.probe =
          opt.probe;  // one decision object over the attempts: an uncertain one before a retry stays on record
      try {
        r = pointwise_cad(c.system, x, fixed, decide);
      } catch (const reference::PointwiseNoPoint&) {
        // the pointwise CAD's Newton moves did not settle from the given values (multiplier coordinates):
        // the formulas' tower completes them (the given ones held), and the CAD runs again from there
        const std::vector<double> z = complete_on_chart(c.system, x, fixed);
        if (z.empty()) throw;
        try {
          r = pointwise_cad(c.system, z, fixed, decide);
        } catch (const reference::PointwiseNoPoint&) {  // its Newton still does not settle: every value held (z is on
                                                        // M_c to rounding)
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
    out.backend = Backend::fast;
    out.decisions.float_tests = static_cast<long>(decide.assumed);  // the zeros that rest on the hypothesis
    // a point that rounding moved (a value of large height) may sit off the locus the exact point is on
    const Truth point = opt.input_exact ? yes : unknown;
    out.certified = decide.certain & (r.regular ? yes : unknown) & point;
    if (decide.certain.unknown())
      out.note = "not certified: " + decide.evidence;
    else if (point.unknown())
      out.note = "not certified: the point was rounded to double (" + input_caveat(opt) + ")";
    return out;
  });
}

Solution solve_implicit(const io::LagrangianCase& c, const Options& options) {
  namespace pl = reference::pipeline;
  return pl::pointwise_input_errors(c, [&] {
    std::vector<bool> fixed;
    Options opt = options;
    const std::vector<reference::Rational> start = pl::start_point(c, fixed);
    std::vector<double> x;
    for (const reference::Rational& q : start) x.push_back(to_double(q, opt));
    // the derivative array decides consistency at one time: at a generic one where the case gives none
    // (at t = 0, x = t² has ẋ = 2t = 0 and looks consistent)
    if (c.system.has_time && !fixed[c.system.t()]) x[c.system.t()] = 0.3819660112501051;
    {  // the equations' numbers are rounded as the point's are: a rounding that may decide a rank voids certainty
      std::vector<const reference::expr::ExprNode*> todo;
      for (const auto& e : c.system.constraints) todo.push_back(e.get());
      std::set<const reference::expr::ExprNode*> seen;
      while (!todo.empty()) {
        const reference::expr::ExprNode* e = todo.back();
        todo.pop_back();
        if (!seen.insert(e).second) continue;
        if (e->op == reference::expr::ExprOp::Number) to_double(e->value, opt);
        if (e->a) todo.push_back(e->a.get());
        if (e->b) todo.push_back(e->b.get());
      }
    }
    const long made = opt.probe ? opt.probe->made : 0;
    const DerivativeArrayResult r = [&] {
      try {
        return derivative_array(c.system, x, fixed, opt);
      } catch (const symbolic::PointwiseNoPoint&) {
        // given values without a time may hold at the reference's default t = 0 only (x = 0 given on x = t²);
        // the attempt's decisions are not the answer's (DecisionProbe counts the retry's from where it began)
        if (!c.system.has_time || fixed[c.system.t()] || x[c.system.t()] == 0) throw;
        x[c.system.t()] = 0;
        if (opt.probe) opt.probe->made = made;
        return derivative_array(c.system, x, fixed, opt);
      }
    }();
    Solution out;
    out.file = c.file;
    out.name = c.name;
    out.variables = c.system.names;
    out.algorithm = Algorithm::implicit_equation;
    for (long d : r.dims) out.tower.push_back({d, {}});
    out.steps = r.steps;
    out.consistent = r.consistent;
    const bool ended = !r.point.empty();
    if (r.consistent && ended) out.solution_rank = r.solution_rank;
    Pointwise<double> p;
    p.route = "derivative array (Campbell) in double";
    p.regular = r.consistent ? ended : true;
    p.why = r.consistent ? (ended ? "" : r.evidence) : r.why;
    if (c.system.has_time) p.time_name = c.system.time_name;
    p.time = r.time;
    p.point = r.point;
    p.velocity = r.velocity;
    p.gauge = r.gauge;
    p.order = r.order;
    for (std::size_t k = 1; k < r.dims.size() && r.dims[k] >= 0; ++k) p.levels.push_back({r.dims[k], {}, {}});
    if (r.consistent && ended) p.checked_order = 1;
    out.pointwise = p;
    out.backend = Backend::fast;
    const Truth point = opt.input_exact ? yes : unknown;
    out.certified = r.certain & point;
    if (!r.certain.yes())
      out.note = "not certified: " + r.evidence;
    else if (point.unknown())
      out.note = "not certified: the case's numbers were rounded to double (" + input_caveat(opt) + ")";
    if (!r.certain.yes() || point.unknown()) out.certified = unknown;
    return out;
  });
}

}  // namespace dcad::fast
