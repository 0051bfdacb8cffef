// SmallRational and WideRational: an exact rational p/q held in two machine words (64-bit, 128-bit),
// for running the reference's own algorithms without a heap allocation per number (issue 14:
// mpq_rational spends most of a small case in malloc).  The reference runs on SmallRational first,
// on WideRational when a number outgrows 64 bits, and on FLINT's fmpq when it outgrows 128.
//
// Why the answers are the reference's.  Every value is the exact rational, in lowest terms with
// q > 0 — the representation mpq_rational keeps.  Each operation computes its exact result already in
// lowest terms by Knuth's formulas (TAOCP vol. 2, §4.5.1: the gcds are taken of the operands, never of
// a double-width result) in 128-bit intermediates whose every product and sum is checked, and either
// the result fits in the word (|p| ≤ 2^(w−1) − 1, 0 < q ≤ 2^(w−1) − 1) or the operation throws
// `Overflow`.  So a run that finishes performed, number for number, the same exact arithmetic as the
// mpq_rational run, took the same branches (zero tests are exact: p == 0) and printed the same
// numbers; a run that throws is recomputed on the next type by the caller (reference::solve, certified::solve).
// Nothing is approximated.
//   * 64-bit words: operands below 2^63 make products below 2^126 and sums of two below 2^127, so no
//     intermediate overflows and Overflow is thrown exactly when the exact result does not fit.
//   * 128-bit words: an intermediate may overflow although the reduced result would fit; that too
//     throws Overflow (the caller then recomputes — never a wrong number).
// (prop_small_rational holds every operation of both to mpq's.)
#pragma once

#include "dcad/reference/rational.hpp"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace dcad::reference {

/// A result that does not fit in the word: the caller recomputes on a wider type.
struct Overflow : std::runtime_error {
  using std::runtime_error::runtime_error;
};

namespace words {

using I = __int128;  ///< every intermediate
using U = unsigned __int128;

inline U magnitude(I v) { return v < 0 ? U(0) - static_cast<U>(v) : static_cast<U>(v); }

inline int ctz(std::uint64_t v) { return __builtin_ctzll(v); }
inline int ctz(U v) {
  const auto lo = static_cast<std::uint64_t>(v);
  return lo ? __builtin_ctzll(lo) : 64 + __builtin_ctzll(static_cast<std::uint64_t>(v >> 64));
}

/// gcd by Stein's binary algorithm (Knuth, §4.5.2, Algorithm B); gcd(0, b) = b.
template <class T>
T binary_gcd(T a, T b) {
  if (a == 0) return b;
  if (b == 0) return a;
  const int shift = ctz(T(a | b));
  a >>= ctz(a);
  do {
    b >>= ctz(b);
    if (a > b) std::swap(a, b);
    b -= a;
  } while (b != 0);
  return a << shift;
}

inline std::uint64_t gcd(std::uint64_t a, std::uint64_t b) {
  if (a == 1 || b == 1) return 1;  // integers: the common case of circuit and integer data
  return binary_gcd(a, b);
}

/// The same on 128-bit words, by 64-bit words while both fit.
inline U gcd(U a, U b) {
  constexpr U low = std::numeric_limits<std::uint64_t>::max();
  if (a <= low && b <= low) return gcd(static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b));
  return binary_gcd(a, b);
}

inline I mul(I a, I b) {
  I r;
  if (__builtin_mul_overflow(a, b, &r)) throw Overflow("an exact intermediate does not fit in 128 bits");
  return r;
}

inline I add(I a, I b) {
  I r;
  if (__builtin_add_overflow(a, b, &r)) throw Overflow("an exact intermediate does not fit in 128 bits");
  return r;
}

/// Boost's integer from a 128-bit one, by 64-bit halves (mpz_int has no 128-bit constructor).
inline boost::multiprecision::mpz_int to_mpz(I v) {
  const U m = magnitude(v);
  boost::multiprecision::mpz_int z = static_cast<std::uint64_t>(m >> 64);
  z <<= 64;
  z += static_cast<std::uint64_t>(m);
  return v < 0 ? boost::multiprecision::mpz_int(-z) : z;
}

}  // namespace words

template <class W>
class BasicSmallRational {
  static_assert(std::is_same<W, std::int64_t>::value || std::is_same<W, __int128>::value, "64- or 128-bit words");
  using I = words::I;
  using U = words::U;
  static constexpr int kBits = std::is_same<W, std::int64_t>::value ? 64 : 128;
  static constexpr U kMax = (U(1) << (kBits - 1)) - 1;  ///< 2^(w−1) − 1: |p| and q, so −p always fits

 public:
  static constexpr const char* zero_test =
      "exact (p == 0 in lowest terms); Overflow when a result does not fit the word";

  BasicSmallRational() = default;
  BasicSmallRational(int k) : p_(k) {}  // NOLINT: exact, as the reference writes T(0), T(1)

  /// q exactly, or Overflow if its numerator or denominator does not fit.
  static BasicSmallRational from(const Rational& q) {
    using boost::multiprecision::mpz_int;
    const mpz_int n = numerator(q), d = denominator(q);
    if constexpr (kBits == 64) {
      const mpz_int lim = std::numeric_limits<std::int64_t>::max();
      if (abs(n) > lim || d > lim) throw Overflow("input number does not fit in 64 bits");
      return make(n.convert_to<std::int64_t>(), d.convert_to<std::int64_t>());
    }
    const mpz_int lim = words::to_mpz(static_cast<I>(kMax));
    if (abs(n) > lim || d > lim) throw Overflow("input number does not fit in " + std::to_string(kBits) + " bits");
    const mpz_int an = abs(n);
    const auto half = [](const mpz_int& z, unsigned shift) {
      return static_cast<U>(
          static_cast<std::uint64_t>(mpz_int(z >> shift) & mpz_int(std::numeric_limits<std::uint64_t>::max())));
    };
    const U un = (half(an, 64) << 64) | half(an, 0), ud = (half(d, 64) << 64) | half(d, 0);
    return make(n < 0 ? -static_cast<I>(un) : static_cast<I>(un), static_cast<I>(ud));
  }
  template <class V>
  static BasicSmallRational from(const BasicSmallRational<V>& x) {  // a narrower word always fits
    return make(x.num(), x.den());
  }
  Rational value() const {
    if constexpr (kBits == 64) return Rational(static_cast<std::int64_t>(p_)) / Rational(static_cast<std::int64_t>(q_));
    return Rational(words::to_mpz(p_)) / Rational(words::to_mpz(q_));
  }
  W num() const { return p_; }
  W den() const { return q_; }
  /// mpq_rational's text: "p" or "p/q".
  std::string str() const {
    if constexpr (kBits == 64) return q_ == 1 ? std::to_string(p_) : std::to_string(p_) + "/" + std::to_string(q_);
    return value().str();
  }

  BasicSmallRational operator-() const { return make(-static_cast<I>(p_), q_); }  // |p| ≤ 2^(w−1) − 1
  /// a/b + c/d in lowest terms without reducing a double-width fraction (Knuth, TAOCP vol. 2, §4.5.1):
  /// with g = gcd(b, d), t = a·(d/g) + c·(b/g) and g' = gcd(t, g), the sum is (t/g') / ((b/g)·(d/g')),
  /// and that is in lowest terms (a prime dividing both would divide g, hence t/g', or one of b, d and
  /// not the other — see Knuth).
  friend BasicSmallRational operator+(const BasicSmallRational& x, const BasicSmallRational& y) {
    if (x.p_ == 0) return y;
    if (y.p_ == 0) return x;
    if constexpr (kBits == 64) {  // the same formulas in 64-bit divisions (a 128-bit one costs several)
      const auto b = static_cast<std::uint64_t>(x.q_), d = static_cast<std::uint64_t>(y.q_);
      const std::uint64_t g = words::gcd(b, d);
      const I t = I(x.p_) * static_cast<std::int64_t>(d / g) + I(y.p_) * static_cast<std::int64_t>(b / g);  // < 2^127
      if (t == 0) return BasicSmallRational();
      const std::uint64_t g2 = g == 1 ? 1 : words::gcd(static_cast<std::uint64_t>(words::magnitude(t) % g), g);
      return fitted(g2 == 1 ? t : t / static_cast<std::int64_t>(g2), I(b / g) * static_cast<std::int64_t>(d / g2));
    }
    const I b = x.q_, d = y.q_;
    const I g = static_cast<I>(words::gcd(static_cast<U>(b), static_cast<U>(d)));
    const I t = words::add(words::mul(x.p_, d / g), words::mul(y.p_, b / g));
    if (t == 0) return BasicSmallRational();
    const I g2 = g == 1 ? 1 : static_cast<I>(words::gcd(words::magnitude(t) % static_cast<U>(g), static_cast<U>(g)));
    return fitted(t / g2, words::mul(b / g, d / g2));
  }
  friend BasicSmallRational operator-(const BasicSmallRational& x, const BasicSmallRational& y) { return x + (-y); }
  /// (a/b)·(c/d) in lowest terms (Knuth, §4.5.1): with g1 = gcd(a, d) and g2 = gcd(c, b) it is
  /// ((a/g1)·(c/g2)) / ((b/g2)·(d/g1)), already reduced since a/b and c/d are.
  friend BasicSmallRational operator*(const BasicSmallRational& x, const BasicSmallRational& y) {
    if (x.p_ == 0 || y.p_ == 0) return BasicSmallRational();
    if constexpr (kBits == 64) {
      const auto g1 = static_cast<std::int64_t>(words::gcd(abs64(x.p_), static_cast<std::uint64_t>(y.q_)));
      const auto g2 = static_cast<std::int64_t>(words::gcd(abs64(y.p_), static_cast<std::uint64_t>(x.q_)));
      return fitted(I(x.p_ / g1) * (y.p_ / g2), I(x.q_ / g2) * (y.q_ / g1));  // < 2^126
    }
    const I g1 = static_cast<I>(words::gcd(words::magnitude(x.p_), static_cast<U>(y.q_)));
    const I g2 = static_cast<I>(words::gcd(words::magnitude(y.p_), static_cast<U>(x.q_)));
    return fitted(words::mul(x.p_ / g1, y.p_ / g2), words::mul(x.q_ / g2, y.q_ / g1));
  }
  /// (a/b) / (c/d) = (a/b)·(d/c) with the sign of c moved to the numerator; c ≠ 0 (the reference
  /// divides by pivots, which are nonzero).
  friend BasicSmallRational operator/(const BasicSmallRational& x, const BasicSmallRational& y) {
    if (y.p_ == 0) throw std::domain_error("SmallRational: division by zero");
    const I c = y.p_, d = y.q_;
    return x * make(c < 0 ? -d : d, c < 0 ? -c : c);  // 1/y in lowest terms: |c| ≤ 2^(w−1) − 1 fits
  }
  BasicSmallRational& operator+=(const BasicSmallRational& o) { return *this = *this + o; }
  BasicSmallRational& operator-=(const BasicSmallRational& o) { return *this = *this - o; }
  BasicSmallRational& operator*=(const BasicSmallRational& o) { return *this = *this * o; }
  BasicSmallRational& operator/=(const BasicSmallRational& o) { return *this = *this / o; }
  /// Lowest terms with q > 0 are unique: equal values have equal (p, q).
  friend bool operator==(const BasicSmallRational& x, const BasicSmallRational& y) {
    return x.p_ == y.p_ && x.q_ == y.q_;
  }
  friend bool operator!=(const BasicSmallRational& x, const BasicSmallRational& y) { return !(x == y); }
  friend bool known_zero(const BasicSmallRational& x) { return x.p_ == 0; }

 private:
  static std::uint64_t abs64(std::int64_t v) {
    return v < 0 ? 0 - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
  }
  /// p / q as given (lowest terms, q > 0, both within the word: the callers' guarantee).
  static BasicSmallRational make(I p, I q) {
    BasicSmallRational r;
    r.p_ = static_cast<W>(p);
    r.q_ = static_cast<W>(q);
    return r;
  }
  /// n / d, already in lowest terms with d > 0, or Overflow if either does not fit the word.
  static BasicSmallRational fitted(I n, I d) {
    if (words::magnitude(n) > kMax || static_cast<U>(d) > kMax)  // n, d: never beyond 2^127 here
      throw Overflow("an exact result does not fit in " + std::to_string(kBits) + " bits");
    return make(n, d);
  }
  W p_ = 0, q_ = 1;
};

/// Exact rationals in 64-bit words (the reference's first run).
using SmallRational = BasicSmallRational<std::int64_t>;
/// Exact rationals in 128-bit words (the reference's second run, when a number outgrows 64 bits).
using WideRational = BasicSmallRational<__int128>;

}  // namespace dcad::reference
