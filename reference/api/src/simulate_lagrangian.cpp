// `dcad simulate` on the expression form: classical Runge–Kutta (RK4) on the vector field of the
// pointwise CAD in double (fast/pointwise.hpp), every evaluation at the point's projection onto
// M_c — the CAD's own Newton completion, which keeps the chart's coordinates and solves the
// constraints for the others — so the trajectory stays on M_c up to the Newton tolerance; the size
// of each projection (the drift RK4 would have made) is measured and reported.  Each output step is
// integrated with m and 2m substeps, m doubling until the two agree to 1e-9 relative (Richardson):
// the difference is the a-posteriori error estimate that is printed.
#include "simulate.hpp"
#include "projected_rk4.hpp"

#include "dcad/fast/chart.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"

#include <boost/numeric/odeint.hpp>

#include <charconv>
#include <memory>
#include <optional>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <iomanip>

namespace dcad::api {

namespace {

struct Field {
  const io::LagrangianCase& c;
  std::size_t n;
  long evaluations = 0;
  /// The solved coordinates of each step at the start of the current output step (pointwise.hpp's
  /// plan): every evaluation of the step makes the same choices, so the projection onto M_c is one
  /// fixed map — a composition of graph maps, smooth — unlike a Newton projection whose landing point
  /// depends on the path its pivot choices take.
  std::vector<std::vector<std::size_t>> plan;
  void plan_at(double t, const std::vector<double>& qv) {
    std::vector<double> start(qv);
    start.push_back(t);
    fast::ToleranceDecisions d;
    plan = fast::pointwise_cad(c.system, start, std::vector<bool>(start.size(), false), d).plan;
  }
  /// The projection of (q, v) onto M_c at time t, x = (q, v, p) there, and d/dt of (q, v).
  struct At {
    std::vector<double> x, dx;
  };
  At operator()(double t, const std::vector<double>& qv) {
    std::vector<double> start(qv);
    start.push_back(t);
    fast::ToleranceDecisions d;
    ++evaluations;
    reference::PointwiseResult<double> r;
    try {
      try {
        r = fast::pointwise_cad(c.system, start, std::vector<bool>(start.size(), false), d,
                                plan.empty() ? nullptr : &plan);
      } catch (
          const reference::PointwiseNoPoint&) {  // the plan's choices degenerate here (a rest point): choose afresh
        if (plan.empty()) throw;
        fast::ToleranceDecisions d2;
        r = fast::pointwise_cad(c.system, start, std::vector<bool>(start.size(), false), d2);
      }
    } catch (const std::range_error& e) {  // the motion left double's range: no row of NaN is ever written
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) + ": " + e.what());
    } catch (const std::domain_error& e) {  // a stage of the explicit step left the formulas' domain
      throw io::InputError(
          c.file + ": simulate: at t = " + io::float_text(t) +
          ": expected a motion inside the formulas' domain, found " + e.what() +
          " (RK4 stages left it even with the output step cut into 4096 substeps: the motion leaves the "
          "domain there, or is too stiff for dcad's explicit integrator)");
    }
    if (!r.consistent || !r.regular)
      throw io::InputError(c.file + ": simulate: expected the motion to stay on a regular M_c, found at t = " +
                           io::float_text(t) + ": " + r.why);
    return {r.point, std::vector<double>(r.velocity.begin(), r.velocity.begin() + static_cast<long>(2 * n))};
  }
};

/// E = p·v − L is conserved: no forces, L and the constraints independent of t, constraints linear in v.
bool conservative(const reference::LagrangianSystem& s) {
  for (const auto& f : s.forces)
    if (!reference::expr::is_number(f, 0)) return false;
  for (const auto& k : s.constraints)
    if (reference::expr::depends_on(k, s.t())) return false;
  const reference::LagrangianDerivatives d = reference::derivatives(s);
  for (const auto& b : d.b)
    if (!reference::expr::is_number(b, 0)) return false;
  return !reference::expr::depends_on(s.lagrangian, s.t());
}

}  // namespace

namespace {

/// The pointwise route (the CAD at every evaluation): where no chart of formulas could be built.
Summary simulate_pointwise(const io::LagrangianCase& c, const SimulateOptions& opt, const fast::Solution& first,
                           RowSink& out, std::ostream& log) {
  const std::size_t n = c.system.n;
  const Pointwise<double>& at = *first.pointwise;
  Field f{c, n, 0, {}};
  std::vector<double> y(2 * n);
  for (std::size_t i = 0; i < 2 * n; ++i) y[i] = at.point[i];
  double t = at.time;
  const std::vector<std::string> st = c.system.state_names();
  out.header(with_time(st));
  // rows are streamed (each one costs many evaluations of the pointwise CAD: a user watching the file,
  // or a pipe, sees them as they come — before, a redirected run showed 0 bytes for minutes), with a
  // progress line on the log every 2 s
  auto last = std::chrono::steady_clock::now();
  const auto row = [&](double time, const std::vector<double>& x) {
    projected::write_row(out, log, time, x, opt.tstop, last);
  };
  Field::At now = f(t, y);
  row(t, now.x);
  const auto energy = [&](const std::vector<double>& x) {  // E = p·v − L
    double e = 0;
    for (std::size_t i = 0; i < n; ++i) e += x[2 * n + i] * x[n + i];
    auto sp = std::make_shared<const reference::JetSpace>(0, 0);
    std::vector<reference::Jet<double>> v;
    for (std::size_t i = 0; i < 2 * n; ++i) v.emplace_back(sp, x[i]);
    v.emplace_back(sp, t);
    return e -
           reference::expr::evaluate<reference::Jet<double>>(c.system.lagrangian, v, [&](const reference::Rational& q) {
             return reference::Jet<double>(sp, q.convert_to<double>());
           }).value();
  };
  const double e0 = energy(now.x);
  double emax = 0;
  projected::Richardson rich;
  rich.log = &log;
  const double t0 = t;  // rows at t0 + k·step up to the final time --tstop
  if (opt.tstop < t0)
    throw io::InputError(c.file + ": simulate: expected --tstop at or after the initial time " + io::float_text(t0) +
                         ", found " + io::float_text(opt.tstop));
  const long steps = static_cast<long>(std::floor((opt.tstop - t0) / opt.step + 1e-9));
  for (long k = 1; k <= steps; ++k) {
    const double t1 = t0 + static_cast<double>(k) * opt.step;
    f.plan_at(t, y);
    projected::output_step(f, t, t1, y, rich);
    t = t1;
    now = f(t, y);
    row(t, now.x);
    emax = std::max(emax, std::abs(energy(now.x) - e0));
  }
  const Summary sum = projected::summary(steps + 1, rich, f.evaluations, "the pointwise CAD", log);
  log << "; energy p·v − L varied by " << io::float_text(emax) << " from " << io::float_text(e0)
      << (conservative(c.system) ? " (conserved by the exact motion)" : "") << "\n";
  return sum;
}

/// The state (q, v) at `time` is finite, or io::InputError naming the formula whose value left double's range.
void check_finite(const io::LagrangianCase& c, const std::vector<double>& q, double time) {
  for (double v : q)
    if (!std::isfinite(v)) {
      std::vector<double> at(q);
      at.push_back(time);
      const auto [path, what] = fast::nonfinite_formula(c.system, at);
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(time) + ": the motion left double's range" +
                           (path.empty() ? std::string() : " (" + path + ": " + what + ")"));
    }
}

/// The chart's equations of motion (chart.hpp), compiled, integrated by Dormand–Prince 5(4) with step
/// control and dense output (Boost.Odeint) at two tolerances side by side: the rows are the tighter run's, the
/// estimated error is the largest difference between the two at the rows (relative to each variable's
/// scale), an upper estimate of the tighter run's error.  Each row is written projected onto M_c (Gauss–Newton
/// to 1e-14, relative: the motion written stays on the manifold it follows); both runs are projected, and
/// restarted, when their own drift exceeds 1e-10; the chart is rebuilt where a valid_where formula fell below 1e-3
/// of its value where the chart was built.
Summary simulate_on_chart(const io::LagrangianCase& c, const SimulateOptions& opt, const std::vector<double>& start,
                          fast::Chart chart, RowSink& out, std::ostream& log) {
  namespace odeint = boost::numeric::odeint;
  using State = std::vector<double>;
  const std::size_t n = c.system.n;
  auto field = std::make_unique<fast::ChartField>(chart);
  const fast::Tape lagrangian({c.system.lagrangian});
  const double tight = 1e-12, loose = 1e-10;
  auto fine = odeint::make_dense_output(tight, tight, odeint::runge_kutta_dopri5<State>());
  auto coarse = odeint::make_dense_output(loose, loose, odeint::runge_kutta_dopri5<State>());
  long evaluations = 0;
  const auto sys = [&](const State& y, State& dy, double t) { ++evaluations, field->rates(y.data(), t, dy.data()); };
  State y(start.begin(), start.end() - 1), z = y;
  double t = start.back();
  const std::vector<std::string> st = c.system.state_names();
  out.header(with_time(st));
  auto last = std::chrono::steady_clock::now();
  const auto full = [&](const State& q, double time) {  // x = (q, v, p)
    std::vector<double> x(q);
    const std::vector<double> p = field->momenta(q, time);
    x.insert(x.end(), p.begin(), p.end());
    return x;
  };
  const auto row = [&](double time, const std::vector<double>& x) {
    projected::write_row(out, log, time, x, opt.tstop, last);
  };
  const auto energy = [&](const std::vector<double>& x, double time) {  // E = p·v − L
    std::vector<double> at(x.begin(), x.begin() + static_cast<long>(2 * n));
    at.push_back(time);
    double e = 0, l = 0;
    for (std::size_t i = 0; i < n; ++i) e += x[2 * n + i] * x[n + i];
    lagrangian.evaluate(at.data(), &l);
    return e - l;
  };
  std::vector<double> x = full(y, t);
  row(t, x);
  const double e0 = energy(x, t);
  double emax = 0, estimate = 0, drift = 0, row_drift = 0;
  long steps_taken = 0, projections = 0, charts = 1;
  std::vector<double> scale(2 * n, 0);
  const double t0 = t;
  if (opt.tstop < t0)
    throw io::InputError(c.file + ": simulate: expected --tstop at or after the initial time " + io::float_text(t0) +
                         ", found " + io::float_text(opt.tstop));
  const long rows = static_cast<long>(std::floor((opt.tstop - t0) / opt.step + 1e-9));
  fine.initialize(y, t, opt.step / 16);
  coarse.initialize(z, t, opt.step / 16);
  const auto advance = [&](auto& stepper, State& s, double t1) {
    try {
      while (stepper.current_time() < t1) {
        stepper.do_step(sys);
        ++steps_taken;
        check_finite(c, stepper.current_state(), stepper.current_time());
      }
    } catch (const io::InputError&) {
      throw;
    } catch (const std::exception& e) {  // odeint's step-size control gave up
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(stepper.current_time()) +
                           ": the integrator failed (" + e.what() + "): the motion is too stiff or leaves the chart");
    }
    stepper.calc_state(t1, s);
  };
  for (long k = 1; k <= rows; ++k) {
    const double t1 = t0 + static_cast<double>(k) * opt.step;
    advance(fine, y, t1);
    advance(coarse, z, t1);
    t = t1;
    for (std::size_t i = 0; i < 2 * n; ++i) scale[i] = std::max(scale[i], std::abs(y[i]));
    double err = 0;
    for (std::size_t i = 0; i < 2 * n; ++i) err = std::max(err, std::abs(y[i] - z[i]) / std::max(scale[i], 1.0));
    estimate = std::max(estimate, err);
    bool restart = false;
    for (State* s : {&y, &z}) {
      const double d = field->drift(*s, t);
      drift = std::max(drift, d);
      if (d > 1e-10) {
        ++projections;
        restart = true;
        if (!field->project(*s, t, 1e-14))
          throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) +
                               ": the motion could not be projected back onto M_c (drift " + io::float_text(d) + ")");
      }
    }
    if (field->margin(y, t) < 1e-3) {  // a pivot or the chart's Jacobian nears zero: a new chart here
      std::vector<double> here(y);
      here.push_back(t);
      // a singular point of the tower (a rank drops: every chart's conditions vanish) is reported, never crossed
      const auto singular = [&](const std::string& otherwise) {
        fast::ToleranceDecisions d;
        const reference::PointwiseResult<double> r =
            fast::pointwise_cad(c.system, here, std::vector<bool>(here.size(), false), d);
        throw io::InputError(c.file + ": simulate: expected the motion to stay on a regular M_c, found at t = " +
                             io::float_text(t) + ": " + (!r.consistent || !r.regular ? r.why : otherwise));
      };
      try {
        std::vector<double> v;  // the pointwise CAD's velocity here: the new chart must agree with it
        try {
          fast::ToleranceDecisions d;
          const reference::PointwiseResult<double> r =
              fast::pointwise_cad(c.system, here, std::vector<bool>(here.size(), true), d);
          if (r.consistent && r.regular && r.gauge.empty())
            v.assign(r.velocity.begin(), r.velocity.begin() + static_cast<long>(2 * n));
        } catch (const std::exception&) {
        }
        chart = fast::chart_near(c.system, here, chart.dims, v.empty() ? nullptr : &v,
                                 fast::pointwise_completion(c.system));
      } catch (const fast::ChartFailure& e) {
        singular(std::string("no chart of M_c holds here (") + e.what() + ")");
      }
      field = std::make_unique<fast::ChartField>(chart);
      std::size_t weakest = 0;
      if (field->margin(y, t, &weakest) < 1e-8) {
        const fast::Chart::Condition& w = chart.valid_where[weakest];
        throw io::InputError(c.file + ": simulate: expected the motion to stay on a regular M_c, found at t = " +
                             io::float_text(t) + ": " + reference::expr::to_text(w.formula, c.system.variable_names()) +
                             " vanishes here in every chart found (" + w.what + "): a rank of the tower drops");
      }
      ++charts;
      restart = true;
      log << "simulate: new chart at t = " << io::float_text(t) << "\n";
    }
    if (restart) {
      fine.initialize(y, t, fine.current_time_step());
      coarse.initialize(z, t, coarse.current_time_step());
    }
    State on(y);  // the row: y on M_c (a copy: the run keeps its own state until its drift exceeds 1e-10)
    if (!field->project(on, t, 1e-14) && field->drift(on, t) > field->drift(y, t)) on = y;  // never a worse row
    row_drift = std::max(row_drift, field->drift(on, t));
    x = full(on, t);
    row(t, x);
    emax = std::max(emax, std::abs(energy(x, t) - e0));
  }
  Summary sum;
  sum.rows = rows + 1;
  sum.error_estimate = estimate;
  sum.worst_variable = "(two runs: tolerance 1e-12 and 1e-10)";
  log << "simulate: " << sum.rows << " rows on a chart of formulas (" << charts << (charts == 1 ? " chart" : " charts")
      << "), Dormand–Prince 5(4) with dense output at tolerances " << io::float_text(tight) << " and "
      << io::float_text(loose) << ": " << steps_taken << " steps, " << evaluations
      << " evaluations of the field; estimated error " << io::float_text(estimate)
      << " (relative, the two runs' largest difference at the rows, unprojected); largest drift from M_c "
      << io::float_text(row_drift) << " (relative, the rows', each projected; the runs' own before projection "
      << io::float_text(drift) << ", " << projections << " restarts); energy p·v − L varied by " << io::float_text(emax)
      << " from " << io::float_text(e0) << (conservative(c.system) ? " (conserved by the exact motion)" : "") << "\n";
  return sum;
}

}  // namespace

Summary simulate_lagrangian(const io::LagrangianCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log) {
  require_times(opt);
  const fast::Solution first = fast::solve_expression(c);  // the initial point on M_c (given values checked)
  const Pointwise<double>& at = *first.pointwise;
  if (!first.consistent || !at.regular)
    throw io::InputError(c.file + ": simulate: expected a regular consistent system, found: " + at.why);
  if (first.solution_rank.value_or(0) > 0)
    log << "note: solutions are not unique (solution rank " << *first.solution_rank
        << "); simulating the one with the free directions set to 0\n";
  std::vector<double> start(at.point.begin(), at.point.begin() + static_cast<long>(2 * c.system.n));
  start.push_back(at.time);
  std::optional<fast::Chart> chart;
  try {
    const std::vector<double> v(at.velocity.begin(), at.velocity.begin() + static_cast<long>(2 * c.system.n));
    chart = fast::chart_near(c.system, start, first.dims(), at.gauge.empty() ? &v : nullptr,
                             fast::pointwise_completion(c.system));
  } catch (const fast::ChartFailure& e) {
    log << "note: no chart of formulas (" << e.what() << "): the pointwise CAD at every evaluation (slow)\n";
    return simulate_pointwise(c, opt, first, out, log);
  }
  return simulate_on_chart(c, opt, start, *chart, out, log);
}

}  // namespace dcad::api
