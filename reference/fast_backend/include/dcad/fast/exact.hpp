// dcad::fast_exact — the one exact → double conversion (issue 26): exact data (dcad::io's problems,
// the reference's rationals) rounded for the fast twin, with the bookkeeping its certainty rests on
// (Options records whether the input was exact in double and well scaled).  The CLI, the tests
// and the installed testing helpers (dcad/testing/convert.hpp) all convert here.  A library of its
// own beside dcad::fast, so that dcad::fast itself names no exact arithmetic.
#pragma once

#include "dcad/fast/cad.hpp"
#include "dcad/io/case_file.hpp"

namespace dcad::fast {

/// The height of x = 2^e p/q (p, q odd and coprime): max(|p|, q); 1 for x = 0.  For a double x it is
/// its odd mantissa: 1 + 2^-40 has height 2^40 + 1, 3/8 has 3; and 1/3 has 3, 1.00000000000000001 has
/// 100000000000000001.
io::Rational height(const io::Rational& x);
/// |x| / height(x): the smallest magnitude that x carries (for a double, its lowest binary digit, as
/// assess_input reads it; for 1/10 = 2^-1 · 1/5, 1/50), down to which it can cancel.
double resolution(const io::Rational& x);

/// x rounded to double.  Throws std::invalid_argument for a value beyond double's range (|x| > 1.8e308,
/// or a nonzero |x| < 4.9e-324 that would read as 0): the fast backend cannot represent it, the exact
/// ones can.  If x's height exceeds 1/nonzero_factor (2^26), clears opt.input_well_scaled (x's own
/// digits span more than a decision tells apart: 3 + 3·2^-50 beside −3 cancels to 2^-50 relative, as
/// assess_input reads one entry) and, if rounding changed x, opt.input_exact (what rounding
/// drops may be the very difference a rank decision is about: 1.00000000000000001 reads as 1).  A rounded value of
/// small height (1/3, 0.1, 1/47) moves by at most 2^-53 relative, as the first step of any computation on it would: the
/// separation hypothesis of Options (nonzero singular values of the exact data above τ1, the small-height data dcad is
/// built for) covers it as it covers the rounding inside every decision.
double to_double(const io::Rational& x, Options& opt);
/// Each entry as above; clears opt.input_well_scaled if the entries' magnitudes and resolutions (and
/// 1) span more than 1/nonzero_factor — assess_input on the exact entries (the same answer on
/// entries exact in double; a rounded 1/3, whose double has a full mantissa, has resolution 1/9).
Eigen::MatrixXd to_double(const io::QMatrix& m, Options& opt);
Eigen::VectorXd to_double(const std::vector<io::Rational>& v, Options& opt);
/// A circuit's element values (L, C, R, M) each as above; clears opt.input_well_scaled if their
/// magnitudes (and 1) span more than 1/nonzero_factor (graded values: no deficiency is then certain).
std::vector<double> to_double_values(const std::vector<io::Rational>& values, Options& opt);
/// Why no rank deficiency can be certain in double on this input, in words ("" if the converters
/// above left both flags of opt set): the note of a fast result that is not certified for this reason.
std::string input_caveat(const Options& opt);
/// A case's `pontryagin` data in double (forces are not part of it).
PontryaginInput to_fast(const io::PontryaginInput& p, Options& opt);
/// A case's `dirac` member as fast's Dirac structure (a `basis` is not validated here).
DiracStructure to_fast(const io::DiracInput& in, Options& opt);

}  // namespace dcad::fast
