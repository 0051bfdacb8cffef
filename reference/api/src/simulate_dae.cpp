// `dcad simulate` on the linear DAE form (issue 30): the exact reference's velocities on M_c,
// ẋ = X x + W u(t) (reference/linear_ide.hpp; the free directions, solution rank many, set to 0),
// from `initial` completed onto M_c(t0) = {C x = G u(t0)} — the given values held, the others solved
// for (least squares of least norm where M_c leaves them free), every completed value reported on the
// log — integrated by Boost.Odeint's Dormand–Prince 5(4) with dense output (rtol 1e-10, atol 1e-12
// of the state's scale).  u(t) = (f, f', …) is evaluated from the case's formulas.  The drift off
// M_c(t) is measured at every row and its largest value reported.
#include "simulate.hpp"

#include "dcad/fast/chart.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/dae.hpp"
#include "dcad/reference/nonlinear/expression.hpp"

#include <Eigen/Dense>
#include <boost/numeric/odeint.hpp>

#include <charconv>
#include <cmath>

namespace dcad::api {

namespace {

namespace ex = reference::expr;

/// The jet columns' formulas: "f_3''(t)" is f_3 differentiated twice.
std::vector<ex::Expr> jet_formulas(const io::DaeCase& c, const std::vector<std::string>& names) {
  std::vector<ex::Expr> out;
  for (const std::string& name : names) {
    const std::size_t open = name.find('(');
    std::size_t k = 2, i = 0;
    while (k < open && std::isdigit(static_cast<unsigned char>(name[k])))
      i = 10 * i + static_cast<std::size_t>(name[k++] - '0');
    ex::Expr e = c.f.at(i - 1);
    for (; k < open && name[k] == '\''; ++k) e = ex::diff(e, 0);
    out.push_back(e);
  }
  return out;
}

/// The start of a DAE's motion on M_c(t0) = {C x = rhs0}: the given values held, the others the least-norm
/// least-squares completion (logged); a given value that leaves the constraints violated is bad /initial,
/// naming the constraint.
Eigen::VectorXd dae_start(const io::DaeCase& c, const dcad::Solution<reference::Rational>& s, const Eigen::MatrixXd& cm,
                          const Eigen::VectorXd& rhs0, double t0, std::ostream& log) {
  using Eigen::MatrixXd;
  using Eigen::VectorXd;
  const std::size_t n = c.variables.size();
  std::vector<Eigen::Index> given, other;
  VectorXd x0 = VectorXd::Zero(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (c.initial[i]) {
      given.push_back(static_cast<Eigen::Index>(i));
      x0(static_cast<Eigen::Index>(i)) = c.initial[i]->convert_to<double>();
    } else {
      other.push_back(static_cast<Eigen::Index>(i));
    }
  }
  if (cm.rows() > 0) {
    MatrixXd co(cm.rows(), static_cast<Eigen::Index>(other.size()));
    for (std::size_t j = 0; j < other.size(); ++j) co.col(static_cast<Eigen::Index>(j)) = cm.col(other[j]);
    VectorXd b = rhs0;
    for (Eigen::Index g : given) b -= cm.col(g) * x0(g);
    if (!other.empty()) {  // least squares of least norm (a COD of a matrix without columns is not asked for)
      const Eigen::CompleteOrthogonalDecomposition<MatrixXd> cod(co);
      const VectorXd y = cod.solve(b);
      for (std::size_t j = 0; j < other.size(); ++j) x0(other[j]) = y(static_cast<Eigen::Index>(j));
    }
    const VectorXd res = cm * x0 - rhs0;
    const double scale = 1 + x0.cwiseAbs().maxCoeff() + rhs0.cwiseAbs().maxCoeff();
    for (Eigen::Index i = 0; i < res.size(); ++i)
      if (std::abs(res(i)) > 1e-9 * scale * (1 + cm.row(i).cwiseAbs().maxCoeff())) {
        const std::vector<std::string> names = s.columns();
        std::string eq;
        for (const auto& [col, q] : (*s.final_constraints)[static_cast<std::size_t>(i)].terms) {
          const std::string mag = abs(q) == 1 ? "" : reference::Rational(abs(q)).str() + "*";
          eq += (eq.empty() ? (q < 0 ? "-" : "") : (q < 0 ? " - " : " + ")) + mag + names[col];
        }
        for (const std::string& f : s.source_names) eq += "; " + f;
        throw io::InputError(c.file + ": /initial: expected values on M_c at t = " + io::float_text(t0) +
                             ", found the constraint " + eq + " = 0 violated by " + io::float_text(res(i)) +
                             " (the given values fix it)");
      }
  }
  log << "simulate: the start on M_c at t = " << io::float_text(t0) << ":";
  for (std::size_t i = 0; i < n; ++i)
    log << " " << c.variables[i] << " = " << io::float_text(x0(static_cast<Eigen::Index>(i)))
        << (c.initial[i] ? " (given)" : " (completed)");
  log << "\n";
  return x0;
}

}  // namespace

Summary simulate_dae(const io::DaeCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log) {
  using Eigen::MatrixXd;
  using Eigen::VectorXd;
  const dcad::Solution<reference::Rational> s = reference::pipeline::solve_dae(c);
  if (!s.consistent)
    throw io::InputError(c.file + ": simulate: expected a consistent DAE, found M_" + std::to_string(s.steps) +
                         " empty (dcad solve says why)");
  if (s.certified.unknown())
    log << "warning: a condition on the sources was not decided (dcad solve lists it); the motion assumes it holds\n";
  const std::size_t n = c.variables.size(), nj = s.jets.size();
  const std::vector<ex::Expr> jets = jet_formulas(c, s.jets);
  const fast::Tape tape(jets);  // the jets compiled once (fast/chart.hpp), evaluated in double
  const auto u_at = [&](double t) {
    VectorXd u(static_cast<Eigen::Index>(nj));
    if (nj > 0) tape.evaluate(&t, u.data());
    return u;
  };
  // M_c = {C x = G u}: rows of final_constraints over (x, jets)
  const auto& fin = *s.final_constraints;
  MatrixXd cm = MatrixXd::Zero(static_cast<Eigen::Index>(fin.size()), static_cast<Eigen::Index>(n));
  MatrixXd gm = MatrixXd::Zero(static_cast<Eigen::Index>(fin.size()), static_cast<Eigen::Index>(nj));
  for (std::size_t i = 0; i < fin.size(); ++i)
    for (const auto& [col, q] : fin[i].terms) {
      if (col < n)
        cm(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(col)) = q.convert_to<double>();
      else
        gm(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(col - n)) =
            -q.convert_to<double>();  // C x − G u = 0
    }
  const Motion<reference::Rational>& mo = *s.motion;
  MatrixXd xr(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n)),
      wr = MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(nj));
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j)
      xr(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = mo.f_matrix[i][j].convert_to<double>();
    for (std::size_t j = 0; j < nj; ++j)
      wr(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = mo.s[i][j].convert_to<double>();
  }
  // the start: given values held, the others solved for on M_c(t0)
  const double t0 = c.initial_time ? c.initial_time->convert_to<double>() : 0.0;
  const VectorXd x0 = dae_start(c, s, cm, gm * u_at(t0), t0, log);
  if (s.solution_rank && *s.solution_rank > 0)
    log << "simulate: the solution is not unique (solution rank " << *s.solution_rank
        << "): the free directions are set to 0\n";
  out.header(with_time(c.variables));
  using State = std::vector<double>;
  const auto field = [&](const State& x, State& dx, double t) {
    const Eigen::Map<const VectorXd> xv(x.data(), static_cast<Eigen::Index>(n));
    const VectorXd d = xr * xv + wr * u_at(t);
    dx.assign(d.data(), d.data() + d.size());
  };
  namespace odeint = boost::numeric::odeint;
  auto stepper = odeint::make_dense_output(1e-12, 1e-10, odeint::runge_kutta_dopri5<State>());
  State x(x0.data(), x0.data() + x0.size());
  long rows = 0;
  double drift = 0;
  std::vector<double> values;
  const auto row = [&](const State& xs, double t) {
    values.assign(1, t);
    values.insert(values.end(), xs.begin(), xs.end());
    out.row(values);
    out.flush();
    ++rows;
    if (cm.rows() > 0) {
      const Eigen::Map<const VectorXd> xv(xs.data(), static_cast<Eigen::Index>(n));
      const VectorXd r = cm * xv - gm * u_at(t);
      drift = std::max(drift, r.cwiseAbs().maxCoeff() / (1 + xv.cwiseAbs().maxCoeff()));
    }
  };
  odeint::integrate_const(stepper, field, x, t0, t0 + opt.tstop, opt.step, row);
  log << "simulate: " << rows << " rows; largest drift off M_c " << io::float_text(drift)
      << " (relative to the state)\n";
  Summary sum;
  sum.rows = rows;
  sum.error_estimate = drift;
  sum.estimate_kind = "largest drift off M_c(t), relative";
  return sum;
}

}  // namespace dcad::api
