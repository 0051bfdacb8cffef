#include "dcad/fast/rank.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
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
  return Eigen::JacobiSVD<MatrixXd>(a).singularValues()(0);
}

namespace {

RankDecision decide_from_sigma(const VectorXd& s, int rows, int cols, double scale, const Options& opt);

/// A with entries |a_ij| ≤ tiny set to 0, then rows and columns scaled by powers of two (exact) to
/// max-norm in [1, 2); two passes.
MatrixXd equilibrated(MatrixXd a, double tiny) {
  a = a.unaryExpr([tiny](double x) { return std::abs(x) <= tiny ? 0.0 : x; });
  for (int pass = 0; pass < 2; ++pass) {
    for (Eigen::Index i = 0; i < a.rows(); ++i) {
      const double m = a.row(i).cwiseAbs().maxCoeff();
      if (m > 0) a.row(i) *= std::ldexp(1.0, -std::ilogb(m));
    }
    for (Eigen::Index j = 0; j < a.cols(); ++j) {
      const double m = a.col(j).cwiseAbs().maxCoeff();
      if (m > 0) a.col(j) *= std::ldexp(1.0, -std::ilogb(m));
    }
  }
  return a;
}

}  // namespace

RankDecision decide_rank(const MatrixXd& a, double scale, const Options& opt) {
  const VectorXd s = a.size() ? Eigen::JacobiSVD<MatrixXd>(a).singularValues() : VectorXd(0);
  return decide_rank(a, s, scale, opt);
}

RankDecision decide_rank(const MatrixXd& a, const VectorXd& s, double scale, const Options& opt) {
  RankDecision d = decide_from_sigma(s, static_cast<int>(a.rows()), static_cast<int>(a.cols()), scale, opt);
  const bool deficient = d.rank < static_cast<int>(s.size());
  if (!deficient || !d.certain || d.rank == 0) return d;
  const MatrixXd e = equilibrated(a, d.zero_threshold);
  const VectorXd se = Eigen::JacobiSVD<MatrixXd>(e).singularValues();
  const RankDecision de = decide_from_sigma(se, static_cast<int>(e.rows()), static_cast<int>(e.cols()), -1, opt);
  if (de.rank != d.rank || !de.certain) d.certain = false;  // grading hides or fakes a singular value
  return d;
}

namespace {

RankDecision decide_from_sigma(const VectorXd& s, int rows, int cols, double scale, const Options& opt) {
  RankDecision d;
  d.rows = rows;
  d.cols = cols;
  d.singular_values.assign(s.data(), s.data() + s.size());
  d.scale = scale >= 0 ? scale : (s.size() ? s(0) : 0.0);
  const double eps = std::numeric_limits<double>::epsilon();
  d.zero_threshold = opt.zero_factor * std::max(rows, cols) * eps * d.scale;
  d.nonzero_threshold = std::max(opt.nonzero_factor * d.scale, d.zero_threshold);
  for (double x : d.singular_values) {
    if (x > d.zero_threshold) ++d.rank;
    if (x > d.zero_threshold && x <= d.nonzero_threshold) d.certain = false;
  }
  const bool deficient = d.rank < static_cast<int>(d.singular_values.size());
  if (deficient && !(opt.input_exact && opt.input_well_scaled)) d.certain = false;
  const double inf = std::numeric_limits<double>::infinity();
  const double above = d.rank > 0 ? d.singular_values[d.rank - 1] : inf;
  const double below = deficient ? d.singular_values[d.rank] : 0.0;
  d.gap = below > 0 ? above / below : inf;
  return d;
}

}  // namespace

std::string RankDecision::describe() const {
  std::ostringstream o;
  o.precision(3);
  o << "rank " << rank << " of " << rows << "x" << cols << (certain ? " (certain)" : " (UNCERTAIN)")
    << ": sigma around the cut [";
  const int lo = std::max(0, rank - 2), hi = std::min<int>(singular_values.size(), rank + 2);
  for (int i = lo; i < hi; ++i) o << (i > lo ? ", " : "") << (i == rank ? "| " : "") << singular_values[i];
  o << "], zero below " << zero_threshold << ", nonzero above " << nonzero_threshold << ", gap " << gap;
  return o.str();
}

void assess_input(const MatrixXd& a, Options& opt) {
  double lo = 1, hi = 1;  // 1 is in the range: D pairs vectors (unit 1 in its basis) with covectors
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double x = std::abs(a.data()[i]);
    if (x == 0) continue;
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  if (hi > 0 && lo < hi * opt.nonzero_factor) opt.input_well_scaled = false;
}

MatrixXd orthogonal_complement(const MatrixXd& q) {
  const Eigen::Index n = q.rows(), k = q.cols();
  if (k == 0) return MatrixXd::Identity(n, n);
  Eigen::HouseholderQR<MatrixXd> qr(q);
  const MatrixXd full = qr.householderQ() * MatrixXd::Identity(n, n);
  return full.rightCols(n - k);
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
