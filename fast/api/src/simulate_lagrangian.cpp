// `dcad simulate` on the expression form: classical Runge–Kutta (RK4) on the vector field of the
// pointwise CAD in double (fast/pointwise.hpp), every evaluation at the point's projection onto
// M_c — the CAD's own Newton completion, which keeps the chart's coordinates and solves the
// constraints for the others — so the trajectory stays on M_c up to the Newton tolerance; the size
// of each projection (the drift RK4 would have made) is measured and reported.  Each output step is
// integrated with m and 2m substeps, m doubling until the two agree to 1e-9 relative (Richardson):
// the difference is the a-posteriori error estimate that is printed.
#include "simulate.hpp"

#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"

#include <charconv>
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
        r = fast::pointwise_cad(c.system, start, std::vector<bool>(start.size(), false), d, plan.empty() ? nullptr : &plan);
      } catch (const reference::PointwiseNoPoint&) {  // the plan's choices degenerate here (a rest point): choose afresh
        if (plan.empty()) throw;
        fast::ToleranceDecisions d2;
        r = fast::pointwise_cad(c.system, start, std::vector<bool>(start.size(), false), d2);
      }
    } catch (const std::range_error& e) {  // the motion left double's range: no row of NaN is ever written
      throw io::InputError(c.file + ": simulate: at t = " + io::float_text(t) + ": " + e.what());
    }
    if (!r.consistent || !r.regular)
      throw io::InputError(c.file + ": simulate: expected the motion to stay on a regular M_c, found at t = " + io::float_text(t) + ": " + r.why);
    return {r.point, std::vector<double>(r.velocity.begin(), r.velocity.begin() + static_cast<long>(2 * n))};
  }
};

std::vector<double> axpy(const std::vector<double>& y, double h, const std::vector<double>& k) {
  std::vector<double> out(y);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] += h * k[i];
  return out;
}

/// One RK4 step from (t, y) with y on M_c; returns the projection of the result onto M_c and
/// accumulates the size of that projection in `drift`.
std::vector<double> rk4(Field& f, double t, const std::vector<double>& y, double h, double& drift) {
  const auto k1 = f(t, y).dx, k2 = f(t + h / 2, axpy(y, h / 2, k1)).dx, k3 = f(t + h / 2, axpy(y, h / 2, k2)).dx,
             k4 = f(t + h, axpy(y, h, k3)).dx;
  std::vector<double> next(y);
  for (std::size_t i = 0; i < y.size(); ++i) next[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  const auto p = f(t + h, next).x;
  double scale = 1, d = 0;
  for (std::size_t i = 0; i < next.size(); ++i) {
    scale = std::max(scale, std::abs(next[i]));
    d = std::max(d, std::abs(p[i] - next[i]));
  }
  drift = std::max(drift, d / scale);
  return std::vector<double>(p.begin(), p.begin() + static_cast<long>(next.size()));
}

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

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0, s = 1;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(a[i]));
  }
  return d / s;
}

void put(std::ostream& out, double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.write(buf, r.ptr - buf);
}

}  // namespace

Summary simulate_lagrangian(const io::LagrangianCase& c, const SimulateOptions& opt, std::ostream& out, std::ostream& log) {
  require_times(opt);
  const std::size_t n = c.system.n;
  const fast::Solution first = fast::solve_expression(c);  // the initial point on M_c (given values checked)
  const Pointwise<double>& at = *first.pointwise;
  if (!first.consistent || !at.regular) throw io::InputError(c.file + ": simulate: expected a regular consistent system, found: " + at.why);
  if (first.solution_rank.value_or(0) > 0)
    log << "note: solutions are not unique (solution rank " << *first.solution_rank << "); simulating the one with the free directions set to 0\n";
  Field f{c, n, 0, {}};
  std::vector<double> y(2 * n);
  for (std::size_t i = 0; i < 2 * n; ++i) y[i] = at.point[i];
  double t = at.time;
  const std::vector<std::string> st = c.system.state_names();
  out << "t";
  for (const std::string& s : st) out << "," << s;
  out << "\n" << std::setprecision(17);
  // rows are streamed (each one costs many evaluations of the pointwise CAD: a user watching the file,
  // or a pipe, sees them as they come — before, a redirected run showed 0 bytes for minutes), with a
  // progress line on the log every 2 s
  auto last = std::chrono::steady_clock::now();
  const auto row = [&](double time, const std::vector<double>& x) {
    put(out, time);
    for (double v : x) {
      out << ",";
      put(out, v);
    }
    out << "\n";
    out.flush();
    if (std::chrono::steady_clock::now() - last > std::chrono::seconds(2)) {
      last = std::chrono::steady_clock::now();
      log << "simulate: t = " << io::float_text(time) << " of " << io::float_text(opt.tstop) << "\n";
    }
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
    return e - reference::expr::evaluate<reference::Jet<double>>(c.system.lagrangian, v, [&](const reference::Rational& q) {
                 return reference::Jet<double>(sp, q.convert_to<double>());
               }).value();
  };
  const double e0 = energy(now.x);
  double emax = 0, estimate = 0, drift = 0;
  long substeps = 0;
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  long m = 1;
  for (long k = 1; k <= steps; ++k) {
    const double t1 = static_cast<double>(k) * opt.step;
    f.plan_at(t, y);
    for (;;) {  // m and 2m substeps must agree
      std::vector<double> a = y, b = y;
      double da = 0, db = 0;
      const double h = (t1 - t) / static_cast<double>(m);
      for (long j = 0; j < m; ++j) a = rk4(f, t + static_cast<double>(j) * h, a, h, da);
      for (long j = 0; j < 2 * m; ++j) b = rk4(f, t + static_cast<double>(j) * h / 2, b, h / 2, db);
      const double err = distance(b, a);
      if (err <= 1e-9 || m >= 4096) {
        estimate = std::max(estimate, err);
        drift = std::max(drift, db);
        substeps += 2 * m;
        y = b;
        if (m > 1 && err < 1e-12) m /= 2;
        break;
      }
      m *= 2;
    }
    t = t1;
    now = f(t, y);
    row(t, now.x);
    emax = std::max(emax, std::abs(energy(now.x) - e0));
  }
  Summary sum;
  sum.rows = steps + 1;
  sum.error_estimate = estimate;
  sum.worst_variable = "(Richardson: m and 2m RK4 substeps)";
  log << "simulate: " << sum.rows << " rows, " << substeps << " RK4 substeps, " << f.evaluations
      << " evaluations of the pointwise CAD; estimated error " << io::float_text(estimate) << " per output step (relative), largest projection onto M_c "
      << io::float_text(drift) << " (relative: the drift RK4 made and the projection removed); energy p·v − L varied by " << io::float_text(emax)
      << " from " << io::float_text(e0) << (conservative(c.system) ? " (conserved by the exact motion)" : "") << "\n";
  return sum;
}

}  // namespace dcad::api
