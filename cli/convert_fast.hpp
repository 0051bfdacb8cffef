// Exact case-file data → the fast backend: rounding with bookkeeping (fast::Options records whether
// the input was exact in double and well scaled) and the fast Dirac structure of a `dirac` member.
#pragma once

#include "case_file.hpp"
#include "dcad/fast/dirac.hpp"

namespace dcad::cli {

Eigen::MatrixXd to_double(const io::QMatrix& m, fast::Options& opt);
Eigen::VectorXd to_double(const std::vector<io::Rational>& v, fast::Options& opt);
fast::DiracStructure fast_dirac(const io::DiracInput& in, fast::Options& opt);

}  // namespace dcad::cli
