// `dcad simulate` on the implicit form (CONTRACT "Linear and implicit DAEs"): from `initial` completed
// onto M_c (the pointwise CEF (1.6) in double, pipeline/implicit.hpp: given values held, the others
// moved by its Newton steps; every value reported as given or completed), classical Runge–Kutta (RK4)
// on ẋ of the pointwise algorithm, every evaluation at the point's projection onto M_c (the algorithm's
// own Newton completion, with the solved coordinates of the step's start: one fixed map per output
// step).  Each output step is integrated with m and 2m substeps, m doubling until the two agree to
// 1e-9 relative (Richardson): the difference is the error estimate printed; the projections' size is
// the drift RK4 made off M_c.
#include "simulate.hpp"
#include "projected_rk4.hpp"

#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"
#include "dcad/io/report.hpp"

#include <cmath>
#include <iomanip>
#include <stdexcept>

namespace dcad::api {

namespace {

struct ImplicitField {
  const io::LagrangianCase& c;
  long evaluations = 0;
  std::vector<std::vector<std::size_t>> plan;
  /// (q, v = 0, t): the pointwise algorithm's variables (the v entries are unused by the implicit form).
  std::vector<double> start(double t, const std::vector<double>& q) const {
    std::vector<double> s(q);
    s.resize(2 * c.system.n, 0.0);
    s.push_back(t);
    return s;
  }
  void plan_at(double t, const std::vector<double>& q) {
    fast::ToleranceDecisions d;
    const std::vector<double> s = start(t, q);
    try {
      plan = fast::pointwise_cad(c.system, s, std::vector<bool>(s.size(), false), d).plan;
    } catch (const std::domain_error& e) {
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) +
                           ": expected a motion inside the equations' domain, found " + e.what());
    }
  }
  struct At {
    std::vector<double> x, dx;
  };
  At operator()(double t, const std::vector<double>& q) {
    const std::vector<double> s = start(t, q);
    fast::ToleranceDecisions d;
    ++evaluations;
    reference::PointwiseResult<double> r;
    try {
      try {
        r = fast::pointwise_cad(c.system, s, std::vector<bool>(s.size(), false), d, plan.empty() ? nullptr : &plan);
      } catch (const reference::PointwiseNoPoint&) {  // the plan's choices degenerate here: choose afresh
        if (plan.empty()) throw;
        fast::ToleranceDecisions d2;
        r = fast::pointwise_cad(c.system, s, std::vector<bool>(s.size(), false), d2);
      }
    } catch (const std::range_error& e) {
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) + ": " + e.what());
    } catch (const std::domain_error& e) {  // a stage of the explicit step left the formulas' domain (Akzo's sqrt)
      throw io::InputError(
          c.file + ": simulate: at t = " + io::float_text(t) +
          ": expected a motion inside the equations' domain, found " + e.what() +
          " (RK4 stages left it even with the output step cut into 4096 substeps: the motion leaves the "
          "domain there, or is too stiff for dcad's explicit integrator)");
    } catch (const reference::PointwiseNoPoint& e) {
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) +
                           ": expected the motion to stay near M_c, found " + e.what());
    }
    if (!r.consistent || !r.regular)
      throw io::InputError(c.file + ": simulate: expected the motion to stay on a regular M_c, found at t = " +
                           io::float_text(t) + ": " + r.why);
    return {r.point, r.velocity};
  }
};

}  // namespace

Summary simulate_implicit(const io::LagrangianCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log) {
  require_times(opt);
  // the start: the pointwise algorithm in double from the given values (held) at the case's time, as
  // every evaluation of the field is (fast's own answer, the derivative array, decides at a generic time)
  namespace pl = reference::pipeline;
  std::vector<bool> fixed;
  std::vector<double> x0;
  for (const reference::Rational& q : pl::start_point(c, fixed)) x0.push_back(q.convert_to<double>());
  const reference::PointwiseResult<double> at = pl::pointwise_input_errors(c, [&] {
    fast::ToleranceDecisions d;
    return fast::pointwise_cad(c.system, x0, fixed, d);
  });
  if (!at.consistent || !at.regular)
    throw io::InputError(c.file + ": simulate: expected a regular consistent system, found: " + at.why);
  for (std::size_t i = 0; i < c.system.n; ++i)
    if (c.initial[i] && std::abs(at.point[i] - c.initial[i]->convert_to<double>()) >
                            1e-9 * (1 + std::abs(c.initial[i]->convert_to<double>())))
      throw io::InputError(c.file + ": /initial/" + c.system.names[i] + ": expected a value on M_c, found " +
                           c.initial[i]->str() + " (the constraints give " + io::float_text(at.point[i]) + ")");
  if (at.solution_rank > 0)
    log << "note: solutions are not unique (solution rank " << at.solution_rank
        << "); simulating the one of least norm in the free directions\n";
  const std::size_t n = c.system.n;
  log << "start on M_c (dims";
  for (long d : at.dims) log << " " << d;
  log << ", index " << (at.solution_rank == 0 ? std::to_string(at.steps) : std::string("none: not unique")) << "):";
  for (std::size_t i = 0; i < n; ++i)
    log << " " << c.system.names[i] << " = " << io::float_text(at.point[i])
        << (c.initial[i] ? " (given)" : " (completed)");
  log << "\n";
  ImplicitField f{c, 0, {}};
  std::vector<double> y = at.point;
  double t = at.time;
  out.header(with_time(c.system.names));
  auto last = std::chrono::steady_clock::now();
  const auto row = [&](double time, const std::vector<double>& x) {
    projected::write_row(out, log, time, x, opt.tstop, last);
  };
  row(t, y);
  const double t0 = t;
  if (opt.tstop < t0)
    throw io::InputError(c.file + ": simulate: expected --tstop at or after the initial time " + io::float_text(t0) +
                         ", found " + io::float_text(opt.tstop));
  const long steps = static_cast<long>(std::floor((opt.tstop - t0) / opt.step + 1e-9));
  projected::Richardson rich;
  rich.log = &log;
  for (long k = 1; k <= steps; ++k) {
    const double t1 = t0 + static_cast<double>(k) * opt.step;
    f.plan_at(t, y);
    projected::output_step(f, t, t1, y, rich);
    t = t1;
    row(t, y);
  }
  const Summary sum = projected::summary(steps + 1, rich, f.evaluations, "the pointwise CEF (1.6)", log);
  log << "\n";
  return sum;
}

}  // namespace dcad::api
