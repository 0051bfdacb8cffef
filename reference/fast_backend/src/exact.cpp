#include "dcad/fast/exact.hpp"

#include <boost/multiprecision/integer.hpp>

#include <algorithm>
#include <cmath>

namespace dcad::fast {

namespace {

using boost::multiprecision::mpz_int;

mpz_int odd_part(mpz_int z) {
  z = abs(z);
  return z == 0 ? mpz_int(1) : mpz_int(z >> boost::multiprecision::lsb(z));
}

}  // namespace

io::Rational height(const io::Rational& x) {
  return io::Rational(std::max(odd_part(numerator(x)), odd_part(denominator(x))));
}

double resolution(const io::Rational& x) {
  return x == 0 ? 0.0 : io::Rational(abs(x) / height(x)).convert_to<double>();
}

double to_double(const io::Rational& x, Options& opt) {
  opt.input_assessed = true;  // this conversion is the assessment (of the exact values)
  const double d = x.convert_to<double>();
  if (!std::isfinite(d) || (d == 0 && x != 0))
    throw std::invalid_argument(
        "expected numbers within double's range for the fast backend (1e-323 ... 1.8e308 in magnitude), found " +
        std::string(x > 0 ? "" : "-") + (d == 0 ? "a nonzero value below it" : "a value above it") +
        "; the exact backends (--backend reference or certified) take any rational");
  // a value of large height spans more digits than a decision can tell apart (3 + 3·2^-50, a double, beside
  // −3 cancels to 2^-50 relative), as fast::assess_input reads one entry; rounded, it also lost them
  if (height(x) * io::Rational(opt.nonzero_factor) > 1) {
    opt.input_well_scaled = false;
    if (io::Rational(d) != x) opt.input_exact = false;  // gmpq_set_d: finite d only (SIGFPE otherwise)
  }
  return d;
}

Eigen::MatrixXd to_double(const io::QMatrix& m, Options& opt) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  double lo = 1, hi = 1;  // as fast::assess_input: 1 is in the range
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t k = 0; k < m.cols(); ++k) {
      d(i, k) = to_double(m(i, k), opt);
      if (m(i, k) == 0) continue;
      lo = std::min(lo, resolution(m(i, k)));
      hi = std::max(hi, std::abs(d(i, k)));
    }
  if (lo < hi * opt.nonzero_factor) opt.input_well_scaled = false;
  return d;
}

std::vector<double> to_double_values(const std::vector<io::Rational>& values, Options& opt) {
  std::vector<double> out;
  double lo = 1, hi = 1;
  for (const io::Rational& v : values) {
    out.push_back(to_double(v, opt));
    if (v == 0) continue;
    lo = std::min(lo, std::abs(out.back()));
    hi = std::max(hi, std::abs(out.back()));
  }
  if (hi / lo > 1 / opt.nonzero_factor) opt.input_well_scaled = false;
  return out;
}

Eigen::VectorXd to_double(const std::vector<io::Rational>& v, Options& opt) {
  return to_double(io::QMatrix::from_rows({v}, v.size()), opt).transpose();
}

std::string input_caveat(const Options& opt) {
  const std::string bound = std::to_string(std::lround(1 / opt.nonzero_factor));
  std::string s;
  if (!opt.input_exact)
    s = "a value that double rounds has height above " + bound +
        " (the digits rounding drops may be what a decision turns on)";
  if (!opt.input_well_scaled)
    s += (s.empty() ? "" : "; ") + std::string("the input's magnitudes and digits span more than ") + bound +
         " (graded values, or a value of more digits, such as 1 + 2^-40)";
  return s.empty() ? s : "no rank deficiency is certain in double: " + s;
}

DiracStructure to_fast(const io::DiracInput& in, Options& opt) {
  if (in.form == "presymplectic") return dirac_from_presymplectic(to_double(in.w, opt));
  if (in.form == "distribution") {
    const Eigen::MatrixXd b = to_double(in.b, opt), w = to_double(in.w, opt);
    return dirac_from_distribution(Subspace::span(b, -1, opt), w);
  }
  if (in.form == "poisson") return dirac_from_poisson(to_double(in.p, opt));
  const Eigen::MatrixXd g = to_double(in.g, opt);  // `basis`: validated by the caller
  return {static_cast<int>(g.cols() / 2), Subspace::span(g, -1, opt)};
}

PontryaginInput to_fast(const io::PontryaginInput& p, Options& opt) {
  return {p.n,
          to_double(p.k, opt),
          to_double(p.vv, opt),
          to_double(p.qv, opt),
          to_double(p.qq, opt),
          to_double(p.q, opt),
          to_double(p.v, opt)};
}

}  // namespace dcad::fast
