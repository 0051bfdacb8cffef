// Exact case-file data → the fast backend: rounding with bookkeeping (fast::Options records whether
// the input was exact in double and well scaled) and the fast Dirac structure of a `dirac` member.
#pragma once

#include "case_file.hpp"
#include "dcad/fast/cad.hpp"

namespace dcad::cli {

/// x rounded to double; clears opt.input_exact if that changed it.  Throws std::invalid_argument for
/// a value beyond double's range (|x| > 1.8e308, or a nonzero |x| < 4.9e-324 that would read as 0):
/// the fast backend cannot represent it, the exact ones can.
double to_double(const io::Rational& x, fast::Options& opt);
Eigen::MatrixXd to_double(const io::QMatrix& m, fast::Options& opt);
Eigen::VectorXd to_double(const std::vector<io::Rational>& v, fast::Options& opt);
/// A case's `pontryagin` data in double (forces are not part of it).
fast::PontryaginInput fast_pontryagin(const io::PontryaginInput& p, fast::Options& opt);
fast::DiracStructure fast_dirac(const io::DiracInput& in, fast::Options& opt);

}  // namespace dcad::cli
