// Ball: the certified cascade's tier of ball arithmetic from issue 15 to issue 26, kept here as the
// benchmark's `tier_ball` (bench/results/summary.md): measured against FLINT's fmpq and Arb's balls, it
// decided none of the instances where the machine words overflow, so the product no longer has it
// (dcad/certified/cascade.hpp says why).  The reference admits it through the generic zero-test hook
// of matrix.hpp, `T::zero_test`.
//
// Ball: a double-precision enclosure ⟨mid, rad⟩ = [mid − rad, mid + rad] of one exact rational,
// so that the reference's *own* algorithms can run in floating point with certified decisions.
//
// Why this is a proof, not a heuristic.  Every operation below returns a ball that contains the
// exact result whenever its operands contain the exact operands (derivations at each operation).
// The reference algorithms branch only on zero tests (`x == 0`, `x != 0`, `a == b`).  A Ball
// answers a zero test only when the answer holds for every number in the ball — in particular
// for the exact value — and otherwise throws `Uncertain`.  So a run that finishes took, at every
// branch, the branch the exact run takes: its discrete output (ranks, dimensions, pivots, c,
// consistency, solution rank) *is* the exact one, by induction over the branches.  Rounding can
// certify x ≠ 0 (|mid| > rad) but never x = 0, except when the ball is the single point 0
// (rad = 0): integer and dyadic data often stay exact, because operations that round nothing
// keep rad = 0 (error-free transformations below tell exactly when that is).
//
// Rounding model: IEEE-754 binary64, round to nearest, u = 2^-53.  Error-free transformations:
//   s = fl(a + b), e = (a + b) − s exactly                 (TwoSum, Knuth; Higham (4.6))
//   p = fl(a·b),   e = fma(a, b, −p) = a·b − p exactly      (Higham §4.1, no underflow)
//   q = fl(a/b),   r = fma(−q, b, a) = a − q·b exactly      (Higham §4.1, Boldo–Muller)
// The radius is then computed from nonnegative terms in ≤ 10 rounded operations, so the computed
// value z satisfies (true bound) ≤ z·(1 + 11u); `inflate` returns fl(z·(1 + 2^-45)) ≥ z(1 + 254u),
// plus 2^-1000 to cover any underflow inside the radius computation.  Magnitudes are kept in
// [2^-500, 2^500] (otherwise Uncertain("range")), so no midpoint operation underflows or overflows
// and the error-free transformations are exact.
//
// Input numbers that double cannot represent keep their exact value as a shadow (so do their
// negations).  Intervals forget correlation: ω_ij == −ω_ji would be undecidable for ω_ij = 1/3,
// since ⟨m, r⟩ − ⟨m, r⟩ = ⟨0, 2r⟩.  When the float test cannot decide and both sides carry their
// exact values, the test is settled exactly instead (an *exact verification*, counted apart).
#pragma once

#include "dcad/reference/rational.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

namespace dcad::bench {

using reference::Rational;

/// A decision the floating-point enclosure cannot make; the caller recomputes exactly.
struct Uncertain : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What a run in ball arithmetic decided: zero tests answered by the balls, and those settled by
/// comparing the exact shadows of input numbers.  Held by the run (certified::cascade) and reported
/// in its result; Ball::Counting points the zero tests of the run's extent at it.
struct BallCounts {
  long decisions = 0, verifications = 0;
};

class Ball {
 public:
  /// Declares the zero test: certified or Uncertain (see matrix.hpp, `admissible_scalar`).
  static constexpr const char* zero_test = "certified (interval), or throws Uncertain";

  Ball() = default;
  Ball(int k) : mid_(k) {}  // NOLINT: exact (|k| < 2^31), as the reference writes T(0), T(1)
  /// The exact enclosure of a rational: mid the nearest-ish double, rad ≥ |q − mid| (0 iff q is a double).
  static Ball enclosing(const Rational& q) {
    Ball b;
    b.mid_ = q.convert_to<double>();
    b.check("input");
    const Rational err = abs(q - Rational(b.mid_));
    if (err != 0) {
      b.rad_ = std::nextafter(std::nextafter(err.convert_to<double>(), HUGE_VAL), HUGE_VAL) + tiny();
      b.exact_ = std::make_shared<const Rational>(q);
    }
    return b;
  }
  static Ball from_parts(double mid, double rad) {
    Ball b;
    b.mid_ = mid;
    b.rad_ = rad;
    b.check("from_parts");
    return b;
  }

  double mid() const { return mid_; }
  double rad() const { return rad_; }
  bool exact() const { return rad_ == 0; }
  bool is_point_zero() const { return mid_ == 0 && rad_ == 0; }

  Ball operator-() const {
    Ball b = from_parts(-mid_, rad_);
    if (exact_) b.exact_ = std::make_shared<const Rational>(-*exact_);
    return b;
  }
  /// |x + y − s| ≤ α + β + |e|, with e the exact rounding error of s = fl(a + b).
  friend Ball operator+(const Ball& a, const Ball& b) {
    if (a.is_point_zero()) return b;  // 0 + y = y exactly: structural zeros add no radius
    if (b.is_point_zero()) return a;
    Ball c;
    c.mid_ = a.mid_ + b.mid_;
    const double bb = c.mid_ - a.mid_;
    const double e = (a.mid_ - (c.mid_ - bb)) + (b.mid_ - bb);  // TwoSum
    c.rad_ = radius(a.rad_ == 0 && b.rad_ == 0 && e == 0, a.rad_ + b.rad_ + std::abs(e));
    c.check("+");
    return c;
  }
  friend Ball operator-(const Ball& a, const Ball& b) { return a + (-b); }
  /// x = a + ξ, y = b + η (|ξ| ≤ α, |η| ≤ β): |x y − a b| ≤ |a|β + |b|α + αβ; plus |ab − p| = |e|.
  friend Ball operator*(const Ball& a, const Ball& b) {
    if (a.is_point_zero() || b.is_point_zero()) return Ball(0);  // 0 · y = 0 exactly, whatever y's radius
    Ball c;
    c.mid_ = a.mid_ * b.mid_;
    const double e = std::fma(a.mid_, b.mid_, -c.mid_);
    const double z = std::abs(a.mid_) * b.rad_ + std::abs(b.mid_) * a.rad_ + a.rad_ * b.rad_ + std::abs(e);
    c.rad_ = radius(a.rad_ == 0 && b.rad_ == 0 && e == 0, z);
    c.check("*");
    return c;
  }
  /// Needs 0 ∉ b (else Uncertain).  x/y − a/b = ((x − a) b − a (y − b)) / (y b), |y| ≥ |b| − β:
  ///   |x/y − a/b| ≤ (α + |a/b| β) / (|b| − β),  |a/b| ≤ |q| + d,  d = |a/b − q| = |r| / |b|.
  friend Ball operator/(const Ball& a, const Ball& b) {
    if (!(std::abs(b.mid_) > b.rad_)) throw Uncertain("division by a ball that contains 0");
    if (a.is_point_zero()) return Ball(0);
    Ball c;
    c.mid_ = a.mid_ / b.mid_;
    const double r = std::fma(-c.mid_, b.mid_, a.mid_);
    const double d = std::abs(r) / std::abs(b.mid_);
    const double below = (std::abs(b.mid_) - b.rad_) * (1 - 0x1p-45);  // ≤ |b| − β despite rounding
    const double z = (a.rad_ + (std::abs(c.mid_) + d) * b.rad_) / below + d;
    c.rad_ = radius(a.rad_ == 0 && b.rad_ == 0 && r == 0, z);
    c.check("/");
    return c;
  }
  Ball& operator+=(const Ball& o) { return *this = *this + o; }
  Ball& operator-=(const Ball& o) { return *this = *this - o; }
  Ball& operator*=(const Ball& o) { return *this = *this * o; }
  Ball& operator/=(const Ball& o) { return *this = *this / o; }

  /// The zero test of the reference, certified: true iff the ball is {0}; false iff 0 ∉ ball;
  /// otherwise Uncertain (with the evidence).  Each answer counts as one decision.
  friend bool operator==(const Ball& a, const Ball& b) {
    const Ball d = a - b;
    if (d.is_point_zero()) return ++counts().decisions, true;
    if (std::abs(d.mid_) > d.rad_) return ++counts().decisions, false;
    if ((a.exact_ || a.rad_ == 0) && (b.exact_ || b.rad_ == 0)) return ++counts().verifications, a.value() == b.value();
    char evidence[96];
    std::snprintf(evidence, sizeof evidence, "|mid| = %.3g <= radius %.3g", std::abs(d.mid_), d.rad_);
    throw Uncertain(std::string("the ball of a difference contains 0: ") + evidence);
  }
  friend bool operator!=(const Ball& a, const Ball& b) { return !(a == b); }
  /// No decision: true only if the ball is {0} (used where skipping a zero is an optimization).
  friend bool known_zero(const Ball& a) { return a.is_point_zero(); }
  /// Pivot preference (no decision): larger is better; 0 means "not certainly nonzero".
  friend double pivot_weight(const Ball& a) { return std::abs(a.mid_) > a.rad_ ? std::abs(a.mid_) : 0.0; }

  /// While alive, the zero tests of this thread count into `counts` (nested runs restore the outer).
  class Counting {
   public:
    explicit Counting(BallCounts& counts) : outer_(current()) { current() = &counts; }
    ~Counting() { current() = outer_; }
    Counting(const Counting&) = delete;
    Counting& operator=(const Counting&) = delete;

   private:
    BallCounts* outer_;
  };

 private:
  /// The counts of the run in progress on this thread: a pointer to the run's own (none outside a run).
  static BallCounts*& current() {
    thread_local BallCounts* run = nullptr;
    return run;
  }
  static BallCounts& counts() {
    thread_local BallCounts outside;  // tests outside a counted run: not reported anywhere
    return current() ? *current() : outside;
  }
  static constexpr double tiny() { return 0x1p-1000; }
  static double radius(bool exact, double z) { return exact ? 0.0 : z * (1 + 0x1p-45) + tiny(); }
  void check(const char* op) const {
    const double m = std::abs(mid_);
    if (!std::isfinite(mid_) || !std::isfinite(rad_) || (m != 0 && (m < 0x1p-500 || m > 0x1p500)) || rad_ > 0x1p500)
      throw Uncertain(std::string("Ball ") + op + ": magnitude outside the certified range [2^-500, 2^500]");
  }
  Rational value() const { return exact_ ? *exact_ : Rational(mid_); }  // only when exact_ or rad_ == 0
  double mid_ = 0, rad_ = 0;
  std::shared_ptr<const Rational> exact_;  ///< the exact value, for input numbers and their negations
};

}  // namespace dcad::bench
