// SmallRational: an exact rational p/q held in two machine words, for running the reference's own
// algorithms without a heap allocation per number (issue 14: mpq_rational spends most of a small
// case in malloc).
//
// Why the answers are the reference's.  Every value is the exact rational, in lowest terms with
// q > 0 — the representation mpq_rational keeps.  Each operation computes the exact result with
// 128-bit intermediates (|p|, |q| < 2^63, so a product of two is below 2^126 and a sum of two such
// products below 2^127: nothing in between can overflow), reduces it, and either it fits in int64
// (|p| ≤ 2^63 − 1, 0 < q ≤ 2^63 − 1) or the operation throws `Overflow`.  So a run that finishes
// performed, number for number, the same exact arithmetic as the mpq_rational run, took the same
// branches (zero tests are exact: p == 0) and printed the same numbers; a run that throws is
// recomputed in mpq_rational by the caller (solve_reference).  Nothing is approximated.
#pragma once

#include "dcad/reference/rational.hpp"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace dcad::reference {

/// The certified backend runs the reference on SmallRational first up to this many variables (an
/// exact answer at about the cost of floating point there), and ball arithmetic first above it.
constexpr std::size_t kSmallFirstUpTo = 64;

/// A result that does not fit in SmallRational: the caller recomputes with mpq_rational.
struct Overflow : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class SmallRational {
 public:
  static constexpr const char* zero_test = "exact (p == 0 in lowest terms); Overflow when a result does not fit int64";

  SmallRational() = default;
  SmallRational(int k) : p_(k) {}  // NOLINT: exact, as the reference writes T(0), T(1)

  /// q exactly, or Overflow if its numerator or denominator does not fit.
  static SmallRational from(const Rational& q) {
    using boost::multiprecision::mpz_int;
    const mpz_int n = numerator(q), d = denominator(q);
    const mpz_int lim = std::numeric_limits<std::int64_t>::max();
    if (abs(n) > lim || d > lim) throw Overflow("input number does not fit in 64 bits");
    SmallRational r;
    r.p_ = n.convert_to<std::int64_t>();
    r.q_ = d.convert_to<std::int64_t>();
    return r;
  }
  Rational value() const { return Rational(p_) / Rational(q_); }
  std::int64_t num() const { return p_; }
  std::int64_t den() const { return q_; }
  /// mpq_rational's text: "p" or "p/q".
  std::string str() const { return q_ == 1 ? std::to_string(p_) : std::to_string(p_) + "/" + std::to_string(q_); }

  SmallRational operator-() const {
    SmallRational r;
    r.p_ = -p_;  // |p| ≤ 2^63 − 1: the negation fits
    r.q_ = q_;
    return r;
  }
  /// a/b + c/d = (a·d + c·b) / (b·d), reduced.
  friend SmallRational operator+(const SmallRational& x, const SmallRational& y) {
    if (x.p_ == 0) return y;
    if (y.p_ == 0) return x;
    return reduced(wide(x.p_) * y.q_ + wide(y.p_) * x.q_, wide(x.q_) * y.q_);
  }
  friend SmallRational operator-(const SmallRational& x, const SmallRational& y) { return x + (-y); }
  /// (a/b)·(c/d) = (a·c) / (b·d), reduced.
  friend SmallRational operator*(const SmallRational& x, const SmallRational& y) {
    if (x.p_ == 0 || y.p_ == 0) return SmallRational();
    return reduced(wide(x.p_) * y.p_, wide(x.q_) * y.q_);
  }
  /// (a/b) / (c/d) = (a·d) / (b·c); c ≠ 0 (the reference divides by pivots, which are nonzero).
  friend SmallRational operator/(const SmallRational& x, const SmallRational& y) {
    if (y.p_ == 0) throw std::domain_error("SmallRational: division by zero");
    return reduced(wide(x.p_) * y.q_, wide(x.q_) * y.p_);
  }
  SmallRational& operator+=(const SmallRational& o) { return *this = *this + o; }
  SmallRational& operator-=(const SmallRational& o) { return *this = *this - o; }
  SmallRational& operator*=(const SmallRational& o) { return *this = *this * o; }
  SmallRational& operator/=(const SmallRational& o) { return *this = *this / o; }
  /// Lowest terms with q > 0 are unique: equal values have equal (p, q).
  friend bool operator==(const SmallRational& x, const SmallRational& y) { return x.p_ == y.p_ && x.q_ == y.q_; }
  friend bool operator!=(const SmallRational& x, const SmallRational& y) { return !(x == y); }
  friend bool known_zero(const SmallRational& x) { return x.p_ == 0; }

 private:
  using Wide = __int128;
  static Wide wide(std::int64_t v) { return v; }
  static unsigned __int128 magnitude(Wide v) { return v < 0 ? -static_cast<unsigned __int128>(v) : static_cast<unsigned __int128>(v); }
  static unsigned __int128 gcd(unsigned __int128 a, unsigned __int128 b) {
    while (b != 0) {
      const unsigned __int128 t = a % b;
      a = b;
      b = t;
    }
    return a;
  }
  /// n / d in lowest terms with a positive denominator, or Overflow.  d ≠ 0.
  static SmallRational reduced(Wide n, Wide d) {
    if (n == 0) return SmallRational();
    const bool negative = (n < 0) != (d < 0);
    unsigned __int128 un = magnitude(n), ud = magnitude(d);
    const unsigned __int128 g = gcd(un, ud);
    un /= g;
    ud /= g;
    constexpr unsigned __int128 lim = static_cast<unsigned __int128>(std::numeric_limits<std::int64_t>::max());
    if (un > lim || ud > lim) throw Overflow("an exact result does not fit in 64 bits");
    SmallRational r;
    r.p_ = negative ? -static_cast<std::int64_t>(un) : static_cast<std::int64_t>(un);
    r.q_ = static_cast<std::int64_t>(ud);
    return r;
  }
  std::int64_t p_ = 0, q_ = 1;
};

}  // namespace dcad::reference
