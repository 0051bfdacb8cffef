#include "dcad/fast/dirac_field.hpp"

#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

void require_field(const AffineSkewField& f, const char* fn) {
  const Eigen::Index n = f.constant.rows();
  const auto skew = [&](const MatrixXd& m, const std::string& what) {
    if (m.rows() != n || m.cols() != n)
      throw std::invalid_argument(std::string(fn) + ": expected " + what + " " + std::to_string(n) + "x" +
                                  std::to_string(n) + ", found " + std::to_string(m.rows()) + "x" +
                                  std::to_string(m.cols()));
    require_finite(m, fn);
    if (m != -m.transpose())
      throw std::invalid_argument(std::string(fn) + ": expected " + what + " skew (M = -Mᵀ), found one that is not");
  };
  skew(f.constant, "constant");
  if (f.slopes.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(std::string(fn) + ": expected " + std::to_string(n) +
                                " slopes (one per coordinate), found " + std::to_string(f.slopes.size()));
  for (std::size_t k = 0; k < f.slopes.size(); ++k) skew(f.slopes[k], "slopes[" + std::to_string(k) + "]");
}

Integrability decide(const VectorXd& coefficients, double scale, const Options& opt) {
  Integrability out;
  if (scale == 0) {  // constant M: every coefficient is a product with an exact 0
    out.integrable = yes;
    out.evidence.rows = static_cast<int>(coefficients.size());
    out.evidence.cols = 1;
    return out;
  }
  out.evidence = decide_rank(coefficients, scale, opt);
  out.integrable = out.evidence.certain.yes() ? (out.evidence.rank == 0 ? yes : no) : unknown;
  return out;
}

double slope_norm(const AffineSkewField& f) {
  double s = 0;
  for (const MatrixXd& m : f.slopes) s += m.norm();
  return s;
}

}  // namespace

Integrability is_closed(const AffineSkewField& w, const Options& opt_in) {
  require_field(w, "is_closed");
  const int n = static_cast<int>(w.constant.rows());
  Options opt = opt_in;
  for (const MatrixXd& m : w.slopes) opt = assessed(opt, {m});
  VectorXd c(static_cast<Eigen::Index>(n) * n * n);
  for (int i = 0, r = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) c(r++) = w.slopes[i](j, k) + w.slopes[j](k, i) + w.slopes[k](i, j);
  return decide(c, slope_norm(w), opt);
}

Integrability is_jacobi(const AffineSkewField& p, const Options& opt_in) {
  require_field(p, "is_jacobi");
  const int n = static_cast<int>(p.constant.rows());
  Options opt = assessed(opt_in, {p.constant});
  for (const MatrixXd& m : p.slopes) opt = assessed(opt, {m});
  // [P, P] at x is affine in x: one block of n³ coefficients for the constant part, one per x_m
  VectorXd c(static_cast<Eigen::Index>(n + 1) * n * n * n);
  Eigen::Index r = 0;
  for (int block = -1; block < n; ++block) {
    const MatrixXd& m = block < 0 ? p.constant : p.slopes[block];
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          double s = 0;
          for (int l = 0; l < n; ++l)
            s += m(i, l) * p.slopes[l](j, k) + m(j, l) * p.slopes[l](k, i) + m(k, l) * p.slopes[l](i, j);
          c(r++) = s;
        }
  }
  return decide(c, (p.constant.norm() + slope_norm(p)) * slope_norm(p), opt);
}

}  // namespace dcad::fast
