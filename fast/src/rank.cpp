#include "dcad/fast/rank.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dcad::fast {

Svd full_svd(const MatrixXd& a) {
  if (a.rows() == 0 || a.cols() == 0)
    return {MatrixXd::Identity(a.rows(), a.rows()), MatrixXd::Identity(a.cols(), a.cols()), VectorXd(0)};
  // JacobiSVD, not BDCSVD: Eigen 3.4.0's BDCSVD returned U Σ Vᵀ ≠ A (error 0.19 on a 16×16
  // matrix with repeated singular values; regression case cases/regression-bdcsvd-16x16.json).
  Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return {svd.matrixU(), svd.matrixV(), svd.singularValues()};
}

double norm2(const MatrixXd& a) {
  if (a.size() == 0) return 0;
  if (std::min(a.rows(), a.cols()) <= 48) return Eigen::JacobiSVD<MatrixXd>(a).singularValues()(0);
  // power iteration on AᵀA from a fixed start with no special structure (a start of all ones is
  // orthogonal to the top singular vector of, e.g., a Laplacian)
  VectorXd x(a.cols());
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = 1.0 + 0.5 * std::sin(1.0 + 0.7 * static_cast<double>(i));
  x.normalize();
  double est = 0;
  for (int it = 0; it < 300; ++it) {
    const VectorXd y = a * x;
    const double ny = y.norm();  // ‖A x‖ with ‖x‖ = 1: a lower bound of ‖A‖₂
    if (ny == 0) break;
    const VectorXd z = a.transpose() * y;
    const double nz = z.norm();
    if (nz == 0) break;
    x = z / nz;
    const bool settled = ny - est <= 1e-7 * ny;
    est = std::max(est, ny);
    if (settled) break;
  }
  return std::max(est, a.norm() / std::sqrt(static_cast<double>(std::min(a.rows(), a.cols()))));
}

namespace {

RankDecision decide_from_sigma(const VectorXd& s, int rows, int cols, double scale, const Options& opt);

/// A with entries |a_ij| ≤ tiny set to 0, then rows and columns scaled by powers of two (exact) to
/// max-norm in [1, 2); two passes: E = D_r A D_c.  `gain` = max D_r · max D_c ≥ ‖D_r X D_c‖₂ / ‖X‖₂
/// for any X — how much A's rounding residue can grow in E.
MatrixXd equilibrated(MatrixXd a, double tiny, double& gain) {
  a = a.unaryExpr([tiny](double x) { return std::abs(x) <= tiny ? 0.0 : x; });
  VectorXd dr = VectorXd::Ones(a.rows()), dc = VectorXd::Ones(a.cols());
  for (int pass = 0; pass < 2; ++pass) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double m = a.row(i).cwiseAbs().maxCoeff();
      if (m > 0) {
        a.row(i) *= std::ldexp(1.0, -std::ilogb(m));
        dr(i) *= std::ldexp(1.0, -std::ilogb(m));
      }
    }
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      const double m = a.col(j).cwiseAbs().maxCoeff();
      if (m > 0) {
        a.col(j) *= std::ldexp(1.0, -std::ilogb(m));
        dc(j) *= std::ldexp(1.0, -std::ilogb(m));
      }
    }
  }
  gain = (dr.size() ? dr.maxCoeff() : 1.0) * (dc.size() ? dc.maxCoeff() : 1.0);
  return a;
}

}  // namespace

RankDecision decide_rank(const MatrixXd& a, double scale, const Options& opt) {
  return RankRevealing(a, scale, opt).decision();
}

double zero_threshold(int rows, int cols, double scale, const Options& opt) {
  return opt.zero_factor * std::max(rows, cols) * std::numeric_limits<double>::epsilon() * scale;
}

namespace {

/// Every decision leaves through here once (DecisionProbe: testing).
RankDecision& counted(RankDecision& d, const Options& opt) {
  if (opt.probe && opt.probe->made++ == opt.probe->uncertain_at) d.certain = unknown, d.probed = true;
  return d;
}

/// ‖B‖₂ estimated by 30 steps of the power method from a fixed start with no special structure:
/// a lower bound that is close to ‖B‖₂ unless the start is nearly orthogonal to B's top right
/// singular vector; its callers take twice it (a heuristic bound, the fast backend's kind).
double power_estimate(const MatrixXd& b) {
  if (b.size() == 0) return 0;
  VectorXd x(b.cols());
  for (Eigen::Index i = 0; i < x.size(); ++i) x(i) = 1.0 + 0.5 * std::sin(2.0 + 0.9 * static_cast<double>(i));
  x.normalize();
  double est = 0;
  for (int it = 0; it < 30; ++it) {
    const VectorXd y = b * x;
    est = std::max(est, y.norm());
    const VectorXd z = b.transpose() * y;
    if (z.norm() == 0) break;
    x = z.normalized();
  }
  return est;
}

/// The QR route of a decision (no cross-check): true, with d filled, when its bounds decide.
bool decide_by_qr(const Eigen::ColPivHouseholderQR<MatrixXd>& qr, const MatrixXd& a, double scale, const Options& opt,
                  RankDecision& d) {
  const MatrixXd& f = qr.matrixQR();  // R is its upper triangle
  const Eigen::Index m = f.rows(), n = f.cols(), p = std::min(m, n);
  d = RankDecision();
  d.by_qr = true;
  d.rows = static_cast<int>(m);
  d.cols = static_cast<int>(n);
  d.scale = scale >= 0 ? scale : norm2(a);
  d.zero_threshold = zero_threshold(d.rows, d.cols, d.scale, opt);
  d.nonzero_threshold = std::max(opt.nonzero_factor * d.scale, d.zero_threshold);
  Eigen::Index k = 0;
  while (k < p && std::abs(f(k, k)) > d.zero_threshold) ++k;
  const MatrixXd r22 = f.block(k, k, p - k, n - k).triangularView<Eigen::Upper>();
  d.dropped_upper = r22.norm();
  if (d.dropped_upper > d.zero_threshold && d.dropped_upper <= d.zero_threshold * std::sqrt(static_cast<double>(p - k)))
    d.dropped_upper = 2 * power_estimate(r22);  // ‖·‖_F overstates a block of rounding residue by up to √rank
  d.kept_lower = std::numeric_limits<double>::infinity();
  if (k > 0)
    d.kept_lower = 1.0 / f.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(MatrixXd::Identity(k, k)).norm();
  if (!(d.dropped_upper <= d.zero_threshold)) return false;
  if (!(d.kept_lower > d.nonzero_threshold)) {
    // provably inside the band: τ0 < 1/‖R₁₁⁻¹‖_F ≤ σ_k ≤ ‖R[k−1:, k−1:]‖_F ≤ τ1 — uncertain, as the SVD would say
    const bool in_band = k > 0 && d.kept_lower > d.zero_threshold &&
                         MatrixXd(f.block(k - 1, k - 1, p - k + 1, n - k + 1).triangularView<Eigen::Upper>()).norm() <=
                             d.nonzero_threshold;
    if (!in_band) return false;
    d.certain = unknown;
  }
  d.rank = static_cast<int>(k);
  d.largest = p ? std::abs(f(0, 0)) : 0.0;
  for (Eigen::Index i = 0; i < p; ++i) d.singular_values.push_back(std::abs(f(i, i)));
  d.gap = d.dropped_upper > 0 ? d.kept_lower / d.dropped_upper : std::numeric_limits<double>::infinity();
  if (k < p && !deficiency_provable(opt)) d.certain = unknown;
  return true;
}

/// A decision without the cross-check: the QR route when it decides, else the SVD.
RankDecision decide_plain(const MatrixXd& a, double scale, const Options& opt) {
  if (std::min(a.rows(), a.cols()) > opt.qr_from) {
    RankDecision d;
    if (decide_by_qr(Eigen::ColPivHouseholderQR<MatrixXd>(a), a, scale, opt, d)) return d;
  }
  const VectorXd s = a.size() ? Eigen::JacobiSVD<MatrixXd>(a).singularValues() : VectorXd(0);
  return decide_from_sigma(s, static_cast<int>(a.rows()), static_cast<int>(a.cols()), scale, opt);
}

/// The cross-check of a certain deficiency: the same rank, certain, on A equilibrated (see
/// decide_rank).  On a large matrix whose equilibrated QR does not decide, the check fails at once
/// (no SVD): where pivoted QR's bounds are not conclusive, the equilibrated ranks seen differ
/// (equilibration lifts rounding residue), and an SVD would only confirm the failure at 50× the cost.
///
/// E's zero threshold is A's, times the gain of the scaling: the rounding residue A carries (below
/// τ0(A) by the decision's own hypothesis) is scaled with it, so E = D_r A D_c is decided with
/// scale gain · scale(A).  Graded data (gain 10^16) then has nothing certain in E, and the check
/// fails; a computed matrix whose rows merely differ by a few powers of two passes.
bool survives_equilibration(const MatrixXd& a, const RankDecision& d, const Options& opt) {
  double gain = 1;
  const MatrixXd e = equilibrated(a, d.zero_threshold, gain);
  const double scale = gain * d.scale;
  RankDecision de;
  if (std::min(e.rows(), e.cols()) > opt.qr_from) {
    if (!decide_by_qr(Eigen::ColPivHouseholderQR<MatrixXd>(e), e, scale, opt, de)) return false;
  } else {
    de = decide_plain(e, scale, opt);
  }
  return de.rank == d.rank && de.certain.yes();
}

}  // namespace

namespace {

/// decide_rank with the singular values, not counted (RankRevealing counts its own decision once).
RankDecision decide_with_sigma(const MatrixXd& a, const VectorXd& s, double scale, const Options& opt) {
  RankDecision d = decide_from_sigma(s, static_cast<int>(a.rows()), static_cast<int>(a.cols()), scale, opt);
  const bool deficient = d.rank < static_cast<int>(s.size());
  if (!deficient || d.certain.unknown() || d.rank == 0) return d;
  if (!survives_equilibration(a, d, opt)) d.certain = unknown;  // grading hides or fakes a singular value
  return d;
}

}  // namespace

RankDecision decide_rank(const MatrixXd& a, const VectorXd& s, double scale, const Options& opt) {
  RankDecision d = decide_with_sigma(a, s, scale, assessed(opt, {a}));  // a caller's matrix: assessed first
  return counted(d, opt);
}

RankDecision decide_rank_either(const MatrixXd& a, int offset, double scale_a, const MatrixXd& b,
                                const VectorXd& sigma_b, double scale_b, const Options& opt_in) {
  const Options opt = assessed(opt_in, {a, b});
  RankDecision d = RankRevealing(a, scale_a, opt, false).decision();
  d.rank -= offset;
  const RankDecision db = decide_with_sigma(b, sigma_b, scale_b, opt);
  if (db.rank == d.rank) {
    const Truth either = d.certain | db.certain;  // either route proves the same rank
    if (either.yes()) d = db;
    d.certain = either;
  } else {
    d.certain = unknown;
  }
  d.by_two_routes = true;
  return counted(d, opt);
}

RankRevealing::RankRevealing(const MatrixXd& a, double scale, const Options& opt, bool count) {
  decide(a, scale, assessed(opt, {a}));  // a caller's matrix (unassessed options): assessed first
  if (count) counted(d_, opt);
}

void RankRevealing::decide(const MatrixXd& a, double scale, const Options& opt) {
  const Eigen::Index m = a.rows(), p = std::min(m, a.cols());
  if (p > opt.qr_from && scale >= 0) {  // σ₁ ≤ ‖A‖_F ≤ τ0: rank 0 with nothing to factor
    const double frobenius = a.norm(),
                 tau0 = zero_threshold(static_cast<int>(m), static_cast<int>(a.cols()), scale, opt);
    if (frobenius <= tau0) {
      d_.rows = static_cast<int>(m);
      d_.cols = static_cast<int>(a.cols());
      d_.scale = scale;
      d_.zero_threshold = tau0;
      d_.nonzero_threshold = std::max(opt.nonzero_factor * scale, tau0);
      d_.by_qr = d_.by_norm = true;  // Q = I: no reflectors
      d_.largest = d_.dropped_upper = frobenius;
      d_.kept_lower = d_.gap = std::numeric_limits<double>::infinity();
      d_.certain = deficiency_provable(opt) ? yes : unknown;
      m_ = m;
      n_ = a.cols();
      qr_ = MatrixXd::Zero(m, a.cols());
      tau_ = VectorXd(0);
      p_.setIdentity(a.cols());
      return;
    }
  }
  if (p > opt.qr_from) {
    Eigen::ColPivHouseholderQR<MatrixXd> qr(a);
    if (decide_by_qr(qr, a, scale, opt, d_)) {
      if (d_.rank < p && d_.certain.yes() && d_.rank > 0 && !survives_equilibration(a, d_, opt)) d_.certain = unknown;
      m_ = m;
      n_ = a.cols();
      qr_ = qr.matrixQR();
      tau_ = qr.hCoeffs();
      p_ = qr.colsPermutation();
      return;
    }
  }
  const Svd s = full_svd(a);
  d_ = decide_with_sigma(a, s.sigma, scale, opt);
  m_ = m;
  n_ = a.cols();
  u_ = s.u;
  v_ = s.v.leftCols(d_.rank);
  sigma_ = s.sigma.head(d_.rank);
}

MatrixXd RankRevealing::q_columns(Eigen::Index from, Eigen::Index count) const {
  if (!d_.by_qr) return u_.middleCols(from, count);
  MatrixXd e = MatrixXd::Zero(m_, count);
  e.middleRows(from, count).setIdentity();
  const Eigen::Index reflectors = tau_.size();
  e.applyOnTheLeft(Eigen::householderSequence(qr_.leftCols(reflectors), tau_));
  return e;
}

MatrixXd RankRevealing::range() const { return q_columns(0, d_.rank); }

MatrixXd RankRevealing::corange() const { return q_columns(d_.rank, m_ - d_.rank); }

MatrixXd RankRevealing::min_norm_transposed(const MatrixXd& b) const {
  const int r = d_.rank;
  if (d_.by_qr) {  // Aᵀ = P Rᵀ Qᵀ:  R₁₁ᵀ Y = (Pᵀ B)[0:r],  X = Q_r Y
    const MatrixXd pb = p_.transpose() * b;
    MatrixXd x = MatrixXd::Zero(m_, b.cols());
    x.topRows(r) = qr_.topLeftCorner(r, r).triangularView<Eigen::Upper>().transpose().solve(pb.topRows(r));
    x.applyOnTheLeft(Eigen::householderSequence(qr_.leftCols(tau_.size()), tau_));
    return x;
  }
  // Aᵀ = V Σ Uᵀ:  X = U_r Σ_r⁻¹ V_rᵀ B
  return u_.leftCols(r) * (sigma_.cwiseInverse().asDiagonal() * (v_.transpose() * b));
}

MatrixXd RankRevealing::solve_range(const MatrixXd& y) const {
  const int r = d_.rank;
  if (d_.by_qr) {  // A P = Q R:  R₁₁ (Pᵀ X)_top = (Qᵀ Y)_top, (Pᵀ X)_rest = 0
    MatrixXd qty = y;
    qty.applyOnTheLeft(Eigen::householderSequence(qr_.leftCols(tau_.size()), tau_).transpose());
    MatrixXd px = MatrixXd::Zero(n_, y.cols());
    px.topRows(r) = qr_.topLeftCorner(r, r).triangularView<Eigen::Upper>().solve(qty.topRows(r));
    return p_ * px;
  }
  // A = U Σ Vᵀ:  X = V_r Σ_r⁻¹ U_rᵀ Y
  return v_ * (sigma_.cwiseInverse().asDiagonal() * (u_.leftCols(r).transpose() * y));
}

namespace {

RankDecision decide_from_sigma(const VectorXd& s, int rows, int cols, double scale, const Options& opt) {
  RankDecision d;
  d.rows = rows;
  d.cols = cols;
  d.singular_values.assign(s.data(), s.data() + s.size());
  d.scale = scale >= 0 ? scale : (s.size() ? s(0) : 0.0);
  d.zero_threshold = zero_threshold(rows, cols, d.scale, opt);
  d.nonzero_threshold = std::max(opt.nonzero_factor * d.scale, d.zero_threshold);
  for (double x : d.singular_values) {
    if (x > d.zero_threshold) ++d.rank;
    if (x > d.zero_threshold && x <= d.nonzero_threshold) d.certain = unknown;
  }
  const bool deficient = d.rank < static_cast<int>(d.singular_values.size());
  if (deficient && !deficiency_provable(opt)) d.certain = unknown;
  const double inf = std::numeric_limits<double>::infinity();
  const double above = d.rank > 0 ? d.singular_values[d.rank - 1] : inf;
  const double below = deficient ? d.singular_values[d.rank] : 0.0;
  d.gap = below > 0 ? above / below : inf;
  d.largest = s.size() ? s(0) : 0.0;
  d.kept_lower = above;
  d.dropped_upper = below;
  return d;
}

}  // namespace

Decision traced(const RankDecision& d, const std::string& what) {
  Decision t;
  t.what = what;
  t.rows = d.rows;
  t.cols = d.cols;
  t.rank = d.rank;
  t.by = d.by_two_routes ? DecidedBy::two_routes
         : d.by_norm     ? DecidedBy::norm
         : d.by_qr       ? DecidedBy::pivoted_qr
                         : DecidedBy::singular_values;
  t.certain = d.certain;
  t.singular_values = d.singular_values;
  t.zero_threshold = d.zero_threshold;
  t.nonzero_threshold = d.nonzero_threshold;
  t.gap = d.gap;
  t.evidence = d.describe();
  return t;
}

void append_traced(std::vector<Decision>& trace, const std::vector<RankDecision>& ds, const std::string& what) {
  for (std::size_t i = 0; i < ds.size(); ++i) trace.push_back(traced(ds[i], what + " #" + std::to_string(i + 1)));
}

RankDecision proved_by_structure(RankDecision d, int structural) {
  d.structural = structural;
  if (!d.certain.yes() && !d.probed && d.rank == structural && d.kept_lower > d.nonzero_threshold) d.certain = yes;
  return d;
}

std::string RankDecision::describe() const {
  std::ostringstream o;
  o.precision(3);
  if (by_norm) {
    o << "rank 0 of " << rows << "x" << cols << (certain.yes() ? " (certain)" : " (UNCERTAIN)") << ": Frobenius norm "
      << dropped_upper << " <= zero threshold " << zero_threshold;
    return o.str();
  }
  o << "rank " << rank << " of " << rows << "x" << cols << (certain.yes() ? " (certain)" : " (UNCERTAIN)")
    << (by_qr ? ": pivoted QR, |r_ii| around the cut [" : ": sigma around the cut [");
  const int lo = std::max(0, rank - 2), hi = std::min<int>(singular_values.size(), rank + 2);
  for (int i = lo; i < hi; ++i) o << (i > lo ? ", " : "") << (i == rank ? "| " : "") << singular_values[i];
  o << "]";
  if (by_qr) o << ", sigma_rank >= " << kept_lower << ", sigma_rank+1 <= " << dropped_upper;
  o << ", zero below " << zero_threshold << ", nonzero above " << nonzero_threshold << ", gap " << gap;
  if (structural >= 0)
    o << "; structural rank " << structural
      << (structural == rank ? " (the pattern of entries not identically 0 allows no more)" : "");
  return o.str();
}

namespace {
/// The value of x's lowest nonzero binary digit (x ≠ 0, finite): 1 + 2^-40 → 2^-40.
double lowest_digit(double x) {
  int e = 0;
  const double m = std::frexp(std::abs(x), &e);                         // x = m · 2^e, m ∈ [1/2, 1)
  const auto mantissa = static_cast<std::uint64_t>(std::ldexp(m, 53));  // exact: 53 bits
  return std::ldexp(1.0, e - 53 + __builtin_ctzll(mantissa));
}
}  // namespace

Options assessed(const Options& opt, std::initializer_list<Eigen::Ref<const MatrixXd>> data) {
  if (opt.input_assessed) return opt;
  Options out = opt;
  for (const auto& a : data) assess_input(a, out);
  out.input_assessed = true;
  return out;
}

void assess_input(const Eigen::Ref<const MatrixXd>& a, Options& opt) {
  // the magnitudes present in the data: each entry's largest and smallest binary digit (an entry
  // 1 + 2^-40 carries 2^-40 as much as an entry 2^-40 does, and can cancel down to it)
  double lo = 1, hi = 1;  // 1 is in the range: D pairs vectors (unit 1 in its basis) with covectors
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double x = std::abs(a(i, j));
      if (x == 0 || !std::isfinite(x)) continue;
      lo = std::min(lo, lowest_digit(x));
      hi = std::max(hi, x);
    }
  if (hi > 0 && lo < hi * opt.nonzero_factor) opt.input_well_scaled = false;
}

MatrixXd orthogonal_complement(const MatrixXd& q) {
  const Eigen::Index n = q.rows(), k = q.cols();
  if (k == 0) return MatrixXd::Identity(n, n);
  Eigen::HouseholderQR<MatrixXd> qr(q);
  MatrixXd rest = MatrixXd::Zero(n, n - k);  // Q · [0; I]: only the columns asked for
  rest.bottomRows(n - k).setIdentity();
  rest.applyOnTheLeft(qr.householderQ());
  return rest;
}

void require_finite(const MatrixXd& a, const std::string& fn) {
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j)
      if (!std::isfinite(a(i, j))) {
        std::ostringstream o;
        o << fn << ": expected finite entries, found " << a(i, j) << " at (" << i << ", " << j << ")";
        throw std::invalid_argument(o.str());
      }
}

}  // namespace dcad::fast
