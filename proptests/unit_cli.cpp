// The pipeline's helpers at unit level, which the CLI tests see only through whole decks:
//  * waveforms (cli/waveform.hpp): what a source is worth at t = 0, exactly, and where it is not
//    rational — these decide whether a deck's initial condition is on M_c(0) (simulate_forced.cpp);
//  * balancing (cli/simulate.hpp): the diagonal similarity that makes simulate unit-independent.
#include "simulate.hpp"
#include "waveform.hpp"

#include <gtest/gtest.h>

#include <cmath>

using dcad::io::parse_waveform;
using dcad::io::Rational;
using dcad::io::Waveform;

namespace {

Waveform wave(const std::string& spec) {
  return parse_waveform(spec, [](const std::string& s) { return dcad::reference::parse_rational(s); });
}

}  // namespace

// ngspice §4.1.2: SIN(VO VA FREQ TD THETA PHASE) is VO before TD and VO + VA sin(φ) at TD = 0.  Before
// TD every derivative is 0 exactly; with VA = 0 too.  At TD = 0 the derivatives involve ω = 2π FREQ
// (not rational) and the value is rational only at quarter turns.  Killed by: "before TD or no
// sine" read as "and" (a delayed sine's derivative at 0 then "involves π"), a phase taken in radians.
TEST(Waveform, SineAtZeroIsExactWhereItIsRational) {
  const Waveform delayed = wave("SIN(0.5 2 1000 1e-3)");
  EXPECT_EQ(delayed.exact_at_zero(0), Rational(1, 2));
  EXPECT_EQ(delayed.exact_at_zero(1), Rational(0));
  EXPECT_EQ(delayed.exact_at_zero(2), Rational(0));
  const Waveform flat = wave("SIN(3 0 1000)");  // VA = 0: a constant, every derivative exactly 0
  EXPECT_EQ(flat.exact_at_zero(0), Rational(3));
  EXPECT_EQ(flat.exact_at_zero(1), Rational(0));
  const Waveform now = wave("SIN(1 2 1000 0 0 90)");  // VO + VA sin 90° = 3; σ'(0) = VA ω cos φ: involves π
  EXPECT_EQ(now.exact_at_zero(0), Rational(3));
  EXPECT_FALSE(now.exact_at_zero(1).has_value());
  EXPECT_EQ(wave("SIN(1 2 1000 0 0 270)").exact_at_zero(0), Rational(-1));
  EXPECT_EQ(wave("SIN(1 2 1000 0 0 540)").exact_at_zero(0), Rational(1));  // 540° = 180°
  EXPECT_FALSE(wave("SIN(1 2 1000 0 0 45)").exact_at_zero(0).has_value());
  // the floating-point values agree with the exact ones
  EXPECT_DOUBLE_EQ(delayed.value(0.0, 0), 0.5);
  EXPECT_DOUBLE_EQ(now.value(0.0, 0), 3.0);
  EXPECT_NEAR(now.value(0.0, 1), 0.0, 1e-9);  // cos 90° = 0 (rounded π)
  EXPECT_NEAR(wave("SIN(0 1 1000)").value(0.0, 1), 2 * M_PI * 1000, 1e-9);
}

// A DC source is V at 0 with every derivative 0; PULSE and PWL start at their first value with their
// first slope.  Killed by: a DC derivative taken as 1.
TEST(Waveform, PiecewiseLinearAndDcAtZero) {
  const Waveform dc = wave("5");
  EXPECT_EQ(dc.exact_at_zero(0), Rational(5));
  EXPECT_EQ(dc.exact_at_zero(1), Rational(0));
  EXPECT_EQ(dc.exact_at_zero(2), Rational(0));
  const Waveform ramp = wave("PWL(0 1 2 5)");  // slope 2
  EXPECT_EQ(ramp.exact_at_zero(0), Rational(1));
  EXPECT_EQ(ramp.exact_at_zero(1), Rational(2));
  const Waveform pulse = wave("PULSE(0 1 0 1/2 1/2 1 4)");  // rises at slope 2 from 0
  EXPECT_EQ(pulse.exact_at_zero(0), Rational(0));
  EXPECT_EQ(pulse.exact_at_zero(1), Rational(2));
}

// constant(): what simulate integrates without a breakpoint — DC, and a SIN that cannot move (no
// amplitude, or frequency and phase 0).  Killed by: DC's test inverted (every SIN "constant").
TEST(Waveform, ConstantIsDcOrASineThatCannotMove) {
  EXPECT_TRUE(wave("5").constant());
  EXPECT_TRUE(wave("SIN(3 0 1000)").constant());
  EXPECT_TRUE(wave("SIN(3 2 0)").constant());  // FREQ 0, PHASE 0: VO + VA sin 0
  EXPECT_FALSE(wave("SIN(0 1 1000)").constant());
  EXPECT_FALSE(wave("PULSE(0 1 0 1 1 1 4)").constant());
  EXPECT_FALSE(wave("PWL(0 0 1 1)").constant());
}

// PWL times start at 0 or later and increase (ngspice); values may be anything.  Killed by: the
// first *value* checked for sign instead of the first time.
TEST(Waveform, PwlTimesNotValuesMustBeNonnegative) {
  EXPECT_THROW(wave("PWL(-1 0 1 1)"), std::invalid_argument);
  EXPECT_NO_THROW(wave("PWL(0 -1 1 1)"));
  EXPECT_THROW(wave("PWL(0 0 2 1 1 0)"), std::invalid_argument);  // times decrease
  EXPECT_THROW(wave("PWL(0 0 1)"), std::invalid_argument);        // not pairs
}

// Parlett–Reinsch balancing equalises each index's off-diagonal column and row sums (the diagonal is
// invariant under the similarity and takes no part), by powers of two.  Killed by: the diagonal
// counted in the column sum (a large diagonal then hides a 10^8 imbalance).
TEST(Balancing, EqualisesOffDiagonalSumsByPowersOfTwo) {
  Eigen::MatrixXd a(3, 3);
  a << 100, 1e4, 0,
       1e-4, 100, 1e3,
       0, 1e-3, -50;
  const std::vector<double> d = dcad::cli::balancing(a);
  ASSERT_EQ(d.size(), 3u);
  Eigen::MatrixXd b = a;  // D⁻¹ A D
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b(i, j) = a(i, j) * d[j] / d[i];
  for (int i = 0; i < 3; ++i) {
    int e = 0;
    EXPECT_EQ(std::frexp(d[i], &e), 0.5) << "a power of two: " << d[i];
    EXPECT_EQ(b(i, i), a(i, i));
    const double c = b.col(i).cwiseAbs().sum() - std::abs(b(i, i)), r = b.row(i).cwiseAbs().sum() - std::abs(b(i, i));
    EXPECT_LE(std::max(c / r, r / c), 4.0) << "index " << i << ": column " << c << ", row " << r;
  }
}
