// Exact model (reference CAD and reduced equations), then the linear flow ż = F z + f in floating
// point by the exponential of the augmented matrix A = [[F, f], [0, 0]]: one step operator
// P = exp(A h), applied repeatedly — no truncation error, only rounding.
//
// Scale invariance (component values from fF to kH): A is first balanced, Ã = D⁻¹ A D with D a
// diagonal of powers of two (Parlett–Reinsch; exact), and the state is carried in the balanced
// coordinates z̃ = D⁻¹ z.  A circuit whose values are rescaled only moves D and the time unit, so
// its balanced step matrix, and with it the relative rounding, is that of its dimensionless twin.
// Without balancing a 1 nH / 1 fF tank has A h with entries 1e-13 and 1e11 and the exponential
// loses every digit (the capacitor charge stayed 0).
//
// A-posteriori error: the same flow is run in long double (64-bit significand, its own rounding
// of F, its own exponential and products) and the largest difference, relative to the scale of each
// variable's kind over the run (the largest charge, current or flux linkage), is reported: it
// estimates the double run's error to within about 2^-11.
#include "simulate.hpp"

#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/numbers.hpp"

#include "dcad/reference/cad.hpp"
#include "dcad/reference/circuit_motion.hpp"

#include <Eigen/Core>
#include <Eigen/QR>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <map>

#include <unistd.h>

#include <chrono>
#include <charconv>
#include <cmath>
#include <limits>
#include <cstdio>
#include <sstream>

namespace dcad::api {

namespace ref = dcad::reference;
using Q = ref::Rational;
using QM = ref::Matrix<Q>;

namespace {

/// A point of M_c meeting the prescribed values; unspecified values default to 0 where M_c allows.
template <class S>
using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;

/// Nearest S to an exact rational: through mpq's own rounding to double, then the residual, so that
/// long double gets its extra bits (an S-rounding of the exact value to within one ulp of S).
template <class S>
S nearest(const Q& x) {
  const double hi = x.convert_to<double>();
  if constexpr (sizeof(S) == sizeof(double)) {
    return hi;
  } else {
    if (!std::isfinite(hi)) return static_cast<S>(hi);
    return static_cast<S>(hi) + static_cast<S>(Q(x - Q(hi)).convert_to<double>());
  }
}

template <class S>
Mat<S> to(const QM& m) {
  Mat<S> d(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) d(i, j) = nearest<S>(m(i, j));
  return d;
}

/// What the integration needs from the exact CAD: the equations each M_k adds (levels[k], rows
/// [a | b]; levels[0] those of M_0, none), a basis of T M_c (rows) and the reduced equations.
struct ExactModel {
  std::vector<QM> levels;
  QM basis;
  ref::ReducedEquations<Q> red;
};

/// The variables the flow is integrated in: m of them whose columns of the basis of T M_c are best
/// conditioned (column-pivoted QR in double; exactness is not at stake, the choice only has to be
/// valid, and that the exact reduced_equations checks).  The "first independent" variables of the
/// report can be exponentially ill-conditioned (on an LC ladder the lift x = L z grows like the
/// Fibonacci numbers along it: 1e-9 error at 30 branches, 1e8 at 117).
std::vector<ref::Index> integration_coordinates(const QM& basis) {
  // an orthonormal basis of the same span first, so that the choice does not inherit the scaling of
  // the canonical (RREF) basis
  const Eigen::HouseholderQR<Eigen::MatrixXd> orth(to<double>(basis).transpose());
  const Eigen::MatrixXd u = orth.householderQ() * Eigen::MatrixXd::Identity(basis.cols(), basis.rows());
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(u.transpose());
  std::vector<ref::Index> coords;
  for (ref::Index i = 0; i < basis.rows(); ++i)
    coords.push_back(static_cast<ref::Index>(qr.colsPermutation().indices()(i)));
  std::sort(coords.begin(), coords.end());
  return coords;
}

/// The generic CAD on the case's `pontryagin` system.
ExactModel generic_model(const io::CaseFile& c) {
  const ref::LinearSystem<Q> s =
      ref::pontryagin_system(ref::PontryaginInput<Q>{c.pontryagin.n, c.pontryagin.k, c.pontryagin.vv, c.pontryagin.qv,
                                                     c.pontryagin.qq, c.pontryagin.q, c.pontryagin.v});
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  if (!r.consistent)
    throw io::InputError(c.file + ": simulate: expected a consistent system, found M_" + std::to_string(r.steps) +
                         " empty");
  ExactModel m;
  for (const auto& st : r.tower) m.levels.push_back(st.equations);
  m.basis = r.final_step().m.direction.basis();
  m.red = ref::reduced_equations(s, r, integration_coordinates(m.basis));
  return m;
}

/// A circuit by the structured route (reference/circuit_motion.hpp): no 3n-dimensional CAD.
ExactModel circuit_model(const io::Netlist& deck, const io::CaseFile& c) {
  const std::vector<ref::ProductStep<Q>> tower = ref::circuit_tower(deck.circuit);
  ExactModel m;
  m.levels.push_back(QM(0, 3 * deck.circuit.branches.size() + 1));
  for (const QM& rows : ref::circuit_tower_equations(deck.circuit, tower)) m.levels.push_back(rows);
  m.basis = ref::product_basis(deck.circuit, tower.back());
  m.red = ref::circuit_reduced_equations(deck.circuit, tower.back(), integration_coordinates(m.basis));
  return m;
}

std::vector<Q> initial_point(const ExactModel& r, const std::vector<std::optional<Q>>& initial, const io::CaseFile& c,
                             bool netlist) {
  const ref::InitialPoint<Q> p = ref::consistent_initial_point(r.levels, initial);
  if (!p.consistent)
    throw io::InputError(
        c.file +
        ": initial condition: expected a point of the final constraint submanifold M_c, found one that violates " +
        io::equation_text(io::printed_equation(reference::pipeline::row_equation(p.violated, 0)), c.variables) +
        " (a constraint of M_" + std::to_string(p.level) + ")" +
        (netlist && c.n / 3 > reference::pipeline::kForcedBranches
             ? "; a netlist's jump onto M_c at t = 0 is computed up to " +
                   std::to_string(reference::pipeline::kForcedBranches) + " branches only: give IC= values on M_c"
             : std::string()));
  return p.point;
}

}  // namespace

std::vector<double> balancing(const Eigen::MatrixXd& a) {
  const Eigen::Index n = a.rows();
  std::vector<double> d(n, 1.0);
  Eigen::MatrixXd b = a.cwiseAbs();
  // Parlett–Reinsch (LAPACK xGEBAL without permutations): scaling index i by f multiplies column i
  // of D⁻¹ A D by f and divides row i by f; f = 2^k nearest to √(r/c) equalises the off-diagonal
  // column and row sums c, r.  A scaling is kept only if it cuts c + r by 5%, so the sweeps end.
  for (int sweep = 0, changed = 1; changed && sweep < 200; ++sweep) {
    changed = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double c = b.col(i).sum() - b(i, i), r = b.row(i).sum() - b(i, i);
      if (!std::isfinite(c + r)) continue;
      double f = 1;
      if (c > 0 && r > 0) {
        f = std::ldexp(1.0, static_cast<int>(std::lround(std::log2(r / c) / 2)));
        if (c * f + r / f >= 0.95 * (c + r)) continue;
      } else if (c > 1 && r == 0) {
        // an index that feeds others and is fed by none (a charge whose integral is a state: a triangular
        // block) cannot be equalised; its column is shrunk to at most 1 instead — a coupling of 250 per
        // step cost the scaling and squaring six squarings and 2.5e-16 in long double (60 ulps)
        f = std::ldexp(1.0, -static_cast<int>(std::ceil(std::log2(c))));
      } else if (r > 1 && c == 0) {
        f = std::ldexp(1.0,
                       static_cast<int>(std::ceil(std::log2(r))));  // fed by others, feeding none: its row at most 1
      } else {
        continue;
      }
      d[i] *= f;
      b.col(i) *= f;
      b.row(i) /= f;
      changed = 1;
    }
  }
  return d;
}

namespace {

/// ż = F z + f as the augmented flow of one output step h in balanced coordinates, in scalar S.
/// x(t_k) = x0 + L D (z̃_k − z̃_0), z̃_{k+1} = P z̃_k, P = exp(D⁻¹ A D h) (A = [[F, f], [0, 0]]).
template <class S>
struct Flow {
  Mat<S> p, lift;  ///< P; L D restricted to the first m coordinates
  Vec<S> z, z0, x0;
  Flow(const QM& a, const std::vector<double>& d, const QM& lift_q, const std::vector<Q>& x0q,
       const std::vector<Q>& z0q, double h, long stride) {
    const Eigen::Index m = a.rows() - 1;
    Mat<S> ab = to<S>(a);
    for (Eigen::Index i = 0; i <= m; ++i)
      for (Eigen::Index j = 0; j <= m; ++j) ab(i, j) *= static_cast<S>(d[j] / d[i]);  // exact: powers of two
    p = (ab * static_cast<S>(h) * static_cast<S>(stride)).exp();
    lift = to<S>(lift_q);
    for (Eigen::Index j = 0; j < m; ++j) lift.col(j) *= static_cast<S>(d[j]);
    z0.resize(m + 1);
    for (Eigen::Index i = 0; i < m; ++i) z0(i) = nearest<S>(z0q[i]) / static_cast<S>(d[i]);
    z0(m) = S(1) / static_cast<S>(d[m]);
    z = z0;
    x0.resize(x0q.size());
    for (std::size_t i = 0; i < x0q.size(); ++i) x0(i) = nearest<S>(x0q[i]);
  }
  Vec<S> x() const { return x0 + lift * (z - z0).head(lift.cols()); }
  void advance() { z = p * z; }
};

/// "\rsimulate: 42% …" on stderr, only on a terminal and only once the run has taken a second.
class Progress {
 public:
  explicit Progress(long total)
      : total_(total), start_(std::chrono::steady_clock::now()), tty_(isatty(STDERR_FILENO) == 1) {}
  void at(long k) {
    if (!tty_ || (k & 255) != 0) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    if (s < 1 || s < last_ + 0.1) return;
    last_ = s;
    const int pct = static_cast<int>(100.0 * k / std::max(1L, total_));
    std::fprintf(stderr, "\rsimulate: [%-40.*s] %3d%% (%ld/%ld rows, %.0f s)", pct * 40 / 100,
                 "########################################", pct, k, total_, s);
    shown_ = true;
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\r%80s\r", "");
  }

 private:
  long total_;
  std::chrono::steady_clock::time_point start_;
  bool tty_, shown_ = false;
  double last_ = 0;
};

}  // namespace

std::vector<std::optional<io::Rational>> netlist_initial(const io::Netlist& n) {
  const std::size_t b = n.circuit.branches.size();
  std::vector<std::optional<io::Rational>> x(3 * b);
  for (std::size_t i = 0; i < b; ++i) {
    if (!n.initial[i]) continue;
    const auto& br = n.circuit.branches[i];
    if (br.kind == ref::BranchKind::capacitor)
      x[i] = br.value * *n.initial[i];  // q = C · voltage
    else
      x[b + i] = *n.initial[i];  // v = current
  }
  return x;
}

void require_times(const SimulateOptions& opt) {
  if (!(opt.step > 0) || !(opt.tstop >= 0) || !std::isfinite(opt.tstop) || opt.tstop / opt.step > 1e9)
    throw io::InputError("simulate: expected 0 < --step and 0 <= --tstop with at most 1e9 steps, found step " +
                         io::float_text(opt.step) + ", tstop " + io::float_text(opt.tstop));
}

namespace {
/// io::InputError naming `what` unless every entry of q is a finite double, nonzero where q is (the
/// integration runs in floating point).
void require_double_range(const QM& q, const std::string& file, const char* what) {
  for (ref::Index i = 0; i < q.rows(); ++i)
    for (ref::Index j = 0; j < q.cols(); ++j) {
      const double x = q(i, j).convert_to<double>();
      if (!std::isfinite(x) || (x == 0 && q(i, j) != 0))
        throw io::InputError(file + ": simulate: expected " + what +
                             " within double's range (1e-308 ... 1e308), found " + q(i, j).str().substr(0, 40) +
                             (q(i, j).str().size() > 40 ? "..." : ""));
    }
}
}  // namespace

Summary simulate_linear(const io::CaseFile& c, const io::Netlist* deck,
                        const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                        RowSink& out, std::ostream& log) {
  require_times(opt);
  if (c.has_pontryagin && c.pontryagin.has_forces)
    throw std::invalid_argument("a case with `forces` is simulated by simulate_forced_case, not this function");
  if (!c.has_pontryagin && !deck)
    throw io::InputError(
        c.file + ": simulate: expected an LC netlist or a `pontryagin` case, found another form (not supported yet)");
  if (deck && deck->circuit.branches.size() > kSimulateBranches)
    throw io::InputError(
        c.file + ": simulate: expected at most " + std::to_string(kSimulateBranches) + " branches, found " +
        std::to_string(deck->circuit.branches.size()) +
        " (the flow is integrated with a dense matrix exponential; sparse integration is not supported yet)");
  const ExactModel model = deck ? circuit_model(*deck, c) : generic_model(c);
  const std::vector<Q> x0q = initial_point(model, initial, c, deck != nullptr);
  const ref::ReducedEquations<Q>& red = model.red;
  if (red.g.cols() > 0)
    log << "note: solutions are not unique (" << red.g.cols() << " free multipliers); simulating lambda = 0\n";
  // coordinates z = S x; x = x0 + Bᵀ T⁻¹ (z − S x0) with T = S Bᵀ (= I for default coordinates)
  const ref::Index m = red.coords.size(), n = c.n;
  const QM& b = model.basis;
  QM sel(m, n);
  for (ref::Index i = 0; i < m; ++i) sel(i, red.coords[i]) = Q(1);
  const QM lift = b.transpose() * ref::inverse(sel * b.transpose());  // n × m
  QM a(m + 1, m + 1);
  for (ref::Index i = 0; i < m; ++i) {
    for (ref::Index j = 0; j < m; ++j) a(i, j) = red.f_matrix(i, j);
    a(i, m) = red.f[i];
  }
  const QM z0 = sel * QM::column(x0q);
  std::vector<Q> z0v(m);
  for (ref::Index i = 0; i < m; ++i) z0v[i] = z0(i, 0);
  require_double_range(a, c.file, "equations of motion with coefficients");
  require_double_range(lift, c.file, "a parametrisation of M_c with coefficients");
  require_double_range(QM::column(x0q), c.file, "an initial state");
  const std::vector<double> d = balancing(to<double>(a));
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  // the shadow advances `stride` steps at a time (cost ~ 1/stride of the run for large systems)
  const long stride = m <= 64 ? 1 : 16;
  Flow<double> flow(a, d, lift, x0q, z0v, opt.step, 1);
  Flow<long double> shadow(a, d, lift, x0q, z0v, opt.step, stride);
  Summary sum;
  sum.rows = steps + 1;
  std::vector<long double> err(n, 0), mag(n, 0);
  out.header(with_time(c.variables));
  std::vector<double> row;
  Progress progress(steps + 1);
  for (long k = 0; k <= steps; ++k) {
    Eigen::VectorXd x = flow.x();
    if (k % stride == 0) {
      const Vec<long double> xl = shadow.x();
      for (ref::Index i = 0; i < n; ++i) {
        err[i] = std::max(err[i], std::abs(xl(i) - static_cast<long double>(x(i))));
        mag[i] = std::max(mag[i], std::abs(xl(i)));
      }
      shadow.advance();
      if (stride == 1)
        x = xl.cast<double>();  // every row has the long-double flow: print it (the double one is its estimate)
    }
    row.assign(1, static_cast<double>(k) * opt.step);
    row.insert(row.end(), x.data(), x.data() + x.size());
    out.row(row);
    flow.advance();
    progress.at(k);
  }
  Summary out_sum = summarize(
      sum.rows, err, mag, c.variables,
      deck ? io::units_of(*deck).variable_scales(deck->circuit.branches.size(), false) : std::vector<long double>());
  out_sum.error_estimate =
      std::max(out_sum.error_estimate, 4 * std::numeric_limits<double>::epsilon());  // the rows' own rounding
  return out_sum;
}

/// A variable's kind: its name up to the first '_' for circuits (q_, v_, p_: charges, currents, flux
/// linkages), else every variable is of one kind.
std::string kind_of(const std::string& name) {
  const std::size_t u = name.find('_');
  return u == 1 && (name[0] == 'q' || name[0] == 'v' || name[0] == 'p') ? name.substr(0, 1) : std::string();
}

Summary summarize(long rows, const std::vector<long double>& err, const std::vector<long double>& mag,
                  const std::vector<std::string>& names, const std::vector<long double>& natural) {
  Summary sum;
  sum.rows = rows;
  // the scale of a variable: the largest magnitude over the run among the variables of its kind (a
  // current that is 1e-30 at the far end of a ladder is measured against the currents, not against
  // itself: relative to itself its rounding reads as an error of 100 %)
  std::map<std::string, long double> scale;
  for (std::size_t i = 0; i < mag.size(); ++i) scale[kind_of(names[i])] = std::max(scale[kind_of(names[i])], mag[i]);
  long double state = 0;  // the whole state's size in natural units
  for (std::size_t i = 0; i < natural.size(); ++i) state = std::max(state, mag[i] / natural[i]);
  for (std::size_t i = 0; i < err.size(); ++i) {
    const long double s = std::max(scale[kind_of(names[i])], natural.empty() ? 0.0L : state * natural[i]);
    if (s == 0) continue;
    const double e = static_cast<double>(err[i] / s);
    if (e >= sum.error_estimate) {
      sum.error_estimate = e;
      sum.worst_variable = names[i];
    }
  }
  return sum;
}

void CsvRows::header(const std::vector<std::string>& names) {
  line_.clear();
  for (const std::string& n : names) line_ += (line_.empty() ? "" : ",") + n;
  out_ << line_ << "\n";
}

void CsvRows::row(const std::vector<double>& values) {
  line_.clear();
  char buf[32];
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) line_ += ',';
    line_.append(buf, std::to_chars(buf, buf + sizeof buf, values[i]).ptr);
  }
  line_ += '\n';
  out_ << line_;
}

std::vector<std::string> with_time(const std::vector<std::string>& names) {
  std::vector<std::string> out = {"t"};
  out.insert(out.end(), names.begin(), names.end());
  return out;
}

EnergyCsv::EnergyCsv(std::ostream* out) : out_(out) {
  if (out_) *out_ << "t,E,P_forces,P_sources,P_constraints,W_forces,W_sources,W_constraints\n";
}

void EnergyCsv::row(double t, double e, double p_forces, double p_sources, double p_constraints, double w_forces,
                    double w_sources, double w_constraints) {
  if (!out_) return;
  line_.clear();
  char buf[32];
  for (double v : {t, e, p_forces, p_sources, p_constraints, w_forces, w_sources, w_constraints}) {
    if (!line_.empty()) line_ += ',';
    line_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  }
  *out_ << line_ << "\n";
}

}  // namespace dcad::api
