#include "convert_fast.hpp"

#include <cmath>

namespace dcad::cli {

double to_double(const io::Rational& x, fast::Options& opt) {
  const double d = x.convert_to<double>();
  if (!std::isfinite(d) || (d == 0 && x != 0))
    throw std::invalid_argument("expected numbers within double's range for the fast backend (1e-323 ... 1.8e308 in magnitude), found " +
                                std::string(x > 0 ? "" : "-") + (d == 0 ? "a nonzero value below it" : "a value above it") +
                                "; the exact backends (--backend reference or certified) take any rational");
  if (io::Rational(d) != x) opt.input_exact = false;  // gmpq_set_d: finite d only (SIGFPE otherwise)
  return d;
}

Eigen::MatrixXd to_double(const io::QMatrix& m, fast::Options& opt) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t k = 0; k < m.cols(); ++k) d(i, k) = to_double(m(i, k), opt);
  fast::assess_input(d, opt);
  return d;
}

Eigen::VectorXd to_double(const std::vector<io::Rational>& v, fast::Options& opt) {
  return to_double(io::QMatrix::from_rows({v}, v.size()), opt).transpose();
}

fast::DiracStructure fast_dirac(const io::DiracInput& in, fast::Options& opt) {
  if (in.form == "presymplectic") return fast::dirac_from_presymplectic(to_double(in.w, opt));
  if (in.form == "distribution") {
    const Eigen::MatrixXd b = to_double(in.b, opt), w = to_double(in.w, opt);
    return fast::dirac_from_distribution(fast::Subspace::span(b, -1, opt), w);
  }
  if (in.form == "poisson") return fast::dirac_from_poisson(to_double(in.p, opt));
  const Eigen::MatrixXd g = to_double(in.g, opt);  // `basis`: validated by the caller
  return {static_cast<int>(g.cols() / 2), fast::Subspace::span(g, -1, opt)};
}

fast::PontryaginInput fast_pontryagin(const io::PontryaginInput& p, fast::Options& opt) {
  return {p.n, to_double(p.k, opt), to_double(p.vv, opt), to_double(p.qv, opt), to_double(p.qq, opt), to_double(p.q, opt), to_double(p.v, opt)};
}

}  // namespace dcad::cli
