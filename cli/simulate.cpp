// Exact model (reference CAD and reduced equations, or the fast ones with --backend fast), then the
// linear flow ż = F z + f in double by the exponential of the augmented matrix [[F, f], [0, 0]]: one
// exact step operator P = exp(A h), applied repeatedly — no truncation error, only rounding.
#include "simulate.hpp"
#include "solve.hpp"

#include "dcad/reference/cad.hpp"

#include <Eigen/Core>
#include <unsupported/Eigen/MatrixFunctions>

#include <charconv>
#include <cmath>
#include <iomanip>

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;
using QM = ref::Matrix<Q>;

namespace {

/// A point of M_c meeting the prescribed values; unspecified values default to 0 where M_c allows.
std::vector<Q> initial_point(const ref::CadResult<Q>& r, const std::vector<std::optional<Q>>& initial, const io::CaseFile& c) {
  const ref::Index n = c.n;
  QM given(0, n + 1), defaults(0, n + 1);
  for (ref::Index i = 0; i < n; ++i) {
    QM row(1, n + 1);
    row(0, i) = Q(1);
    row(0, n) = initial[i] ? *initial[i] : Q(0);
    if (initial[i]) given = ref::vstack(given, row);
    else defaults = ref::vstack(defaults, row);
  }
  QM constraints(0, n + 1);
  for (const auto& st : r.tower) constraints = ref::vstack(constraints, st.equations);
  // the first constraint of the tower that the prescribed values cannot meet is the violated one
  QM acc = given;
  for (ref::Index i = 0; i < constraints.rows(); ++i) {
    acc = ref::vstack(acc, constraints.block(i, i + 1, 0, n + 1));
    if (ref::affine_from_augmented(acc).empty) {
      std::string level;
      for (ref::Index k = 0, seen = 0; k < r.tower.size(); seen += r.tower[k].equations.rows(), ++k)
        if (i < seen + r.tower[k].equations.rows()) {
          level = "M_" + std::to_string(k);
          break;
        }
      throw io::InputError(c.file + ": initial condition: expected a point of the final constraint submanifold M_c, found one that violates " +
                           equation_text(row_equation(constraints, i), c.variables) + " (a constraint of " + level + ")");
    }
  }
  ref::AffineSubspace<Q> with_defaults = ref::affine_from_augmented(ref::vstack(acc, defaults));
  const ref::AffineSubspace<Q> chosen = with_defaults.empty ? ref::affine_from_augmented(acc) : with_defaults;
  return chosen.point;
}

Eigen::MatrixXd dbl(const QM& m) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) d(i, j) = m(i, j).convert_to<double>();
  return d;
}

}  // namespace

std::vector<std::optional<io::Rational>> netlist_initial(const io::Netlist& n) {
  const std::size_t b = n.circuit.branches.size();
  std::vector<std::optional<io::Rational>> x(3 * b);
  for (std::size_t i = 0; i < b; ++i) {
    if (!n.initial[i]) continue;
    const auto& br = n.circuit.branches[i];
    if (br.kind == ref::BranchKind::capacitor) x[i] = br.value * *n.initial[i];  // q = C · voltage
    else x[b + i] = *n.initial[i];                                              // v = current
  }
  return x;
}

void simulate(const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
              std::ostream& out, std::ostream& log) {
  if (!(opt.step > 0) || !(opt.tstop >= 0) || !std::isfinite(opt.tstop) || opt.tstop / opt.step > 1e8)
    throw io::InputError("simulate: expected 0 < --step and 0 <= --tstop with at most 1e8 steps, found step " +
                         std::to_string(opt.step) + ", tstop " + std::to_string(opt.tstop));
  if (!c.has_pontryagin)
    throw io::InputError(c.file + ": simulate: expected an LC netlist or a `pontryagin` case, found another form (not supported yet)");
  const ref::LinearSystem<Q> s = ref::pontryagin_system(ref::PontryaginInput<Q>{
      c.pontryagin.n, c.pontryagin.k, c.pontryagin.vv, c.pontryagin.qv, c.pontryagin.qq, c.pontryagin.q, c.pontryagin.v});
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  if (!r.consistent) throw io::InputError(c.file + ": simulate: expected a consistent system, found M_" + std::to_string(r.steps) + " empty");
  const std::vector<Q> x0q = initial_point(r, initial, c);
  const ref::ReducedEquations<Q> red = ref::reduced_equations(s, r);
  if (red.g.cols() > 0) log << "note: solutions are not unique (" << red.g.cols() << " free multipliers); simulating lambda = 0\n";
  // coordinates z = S x; x = x0 + Bᵀ T⁻¹ (z − S x0) with T = S Bᵀ (= I for default coordinates)
  const ref::Index m = red.coords.size(), n = c.n;
  const QM& b = r.final_step().m.direction.basis();
  QM sel(m, n);
  for (ref::Index i = 0; i < m; ++i) sel(i, red.coords[i]) = Q(1);
  const QM lift = b.transpose() * ref::inverse(sel * b.transpose());  // n × m
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m + 1, m + 1);
  a.topLeftCorner(m, m) = dbl(red.f_matrix);
  a.topRightCorner(m, 1) = dbl(QM::column(red.f));
  const Eigen::MatrixXd p = (a * opt.step).exp();
  const Eigen::MatrixXd liftd = dbl(lift);
  const Eigen::VectorXd x0 = dbl(QM::column(x0q)), z0 = dbl(sel * QM::column(x0q));
  Eigen::VectorXd za(m + 1);
  za << z0, 1.0;
  out << "t";
  for (const std::string& v : c.variables) out << "," << v;
  out << "\n";
  // Shortest round-trip text (std::to_chars): the same doubles as %.17g, several times faster to
  // write — at 10^4 rows formatting was most of the run time.
  std::string line;
  char buf[32];
  const auto put = [&](double v) { line.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr); };
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  for (long k = 0; k <= steps; ++k) {
    const Eigen::VectorXd x = x0 + liftd * (za.head(m) - z0);
    line.clear();
    put(k * opt.step);
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      line += ',';
      put(x(i));
    }
    line += '\n';
    out << line;
    za = p * za;
  }
}

}  // namespace dcad::cli
