#include "convert_fast.hpp"

namespace dcad::cli {

Eigen::MatrixXd to_double(const io::QMatrix& m, fast::Options& opt) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t k = 0; k < m.cols(); ++k) {
      d(i, k) = m(i, k).convert_to<double>();
      if (io::Rational(d(i, k)) != m(i, k)) opt.input_exact = false;
    }
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
    return fast::dirac_from_distribution(fast::Subspace::span(b.transpose(), -1, opt), w);
  }
  if (in.form == "poisson") return fast::dirac_from_poisson(to_double(in.p, opt));
  const Eigen::MatrixXd g = to_double(in.g, opt);  // `basis`: validated by the caller
  return {static_cast<int>(g.cols() / 2), fast::Subspace::span(g.transpose(), -1, opt)};
}

}  // namespace dcad::cli
