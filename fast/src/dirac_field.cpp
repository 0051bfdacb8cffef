#include "dcad/fast/dirac_field.hpp"

#include <cmath>
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

bool all_zero(const std::vector<MatrixXd>& ms) {
  for (const MatrixXd& m : ms)
    if ((m.array() != 0).any()) return false;
  return true;
}

double slope_norm(const AffineSkewField& f) {
  double s = 0;
  for (const MatrixXd& m : f.slopes) s += m.norm();
  return s;
}

/// Options with every matrix of the field assessed (assessed() stops after its first call).
Options assessed_field(const AffineSkewField& f, const Options& opt_in) {
  if (opt_in.input_assessed) return opt_in;
  Options opt = opt_in;
  assess_input(f.constant, opt);
  for (const MatrixXd& m : f.slopes) assess_input(m, opt);
  opt.input_assessed = true;
  return opt;
}

/// Folds one block of coefficients, decided at its own scale (what its terms may have lost to rounding), into
/// `out`: a certainly nonzero block makes the answer no; an uncertain one, unknown unless another is certainly
/// nonzero.  `exact_zero`: every coefficient is a sum of products with an exact 0 (nothing to decide); a scale
/// that under- or overflowed is no scale, and the block is then uncertain.
void decide_block(const VectorXd& coefficients, bool exact_zero, double scale, const Options& opt, Integrability& out) {
  if (exact_zero || out.integrable.no()) return;
  if (!(scale > 0) || !std::isfinite(scale)) {
    out.integrable = unknown;
    return;
  }
  const RankDecision d = decide_rank(coefficients, scale, opt);
  if (!d.certain.yes()) {
    out.integrable = unknown;
    out.evidence = d;
  } else if (d.rank > 0) {
    out.integrable = no;
    out.evidence = d;
  } else if (out.integrable.yes()) {
    out.evidence = d;
  }
}

}  // namespace

Integrability is_closed(const AffineSkewField& w, const Options& opt_in) {
  require_field(w, "is_closed");
  const int n = static_cast<int>(w.constant.rows());
  const Options opt = assessed_field(w, opt_in);
  VectorXd c(static_cast<Eigen::Index>(n) * n * n);
  for (int i = 0, r = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) c(r++) = w.slopes[i](j, k) + w.slopes[j](k, i) + w.slopes[k](i, j);
  Integrability out{yes, {}};
  decide_block(c, all_zero(w.slopes), slope_norm(w), opt, out);  // dω is constant: one block
  return out;
}

Integrability is_jacobi(const AffineSkewField& p, const Options& opt_in) {
  require_field(p, "is_jacobi");
  const int n = static_cast<int>(p.constant.rows());
  const Options opt = assessed_field(p, opt_in);
  // [P, P] at x is affine in x: one block of n³ coefficients for the constant part, one per x_m, each decided at
  // the scale of its own terms (‖M‖ Σ_l ‖∂_l P‖, M the constant or the slope of x_m)
  Integrability out{yes, {}};
  for (int block = -1; block < n; ++block) {
    const MatrixXd& m = block < 0 ? p.constant : p.slopes[block];
    VectorXd c(static_cast<Eigen::Index>(n) * n * n);
    Eigen::Index r = 0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          double s = 0;
          for (int l = 0; l < n; ++l)
            s += m(i, l) * p.slopes[l](j, k) + m(j, l) * p.slopes[l](k, i) + m(k, l) * p.slopes[l](i, j);
          c(r++) = s;
        }
    decide_block(c, all_zero({m}) || all_zero(p.slopes), m.norm() * slope_norm(p), opt, out);
  }
  return out;
}

}  // namespace dcad::fast
