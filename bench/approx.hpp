// Approx<F>: a floating scalar whose zero test is |x| ≤ tolerance — how the reference's
// elimination behaves when run "naively" in double or in cpp_bin_float_50/_100.  An unsound
// comparison method for the benchmark only (the product's floating route is Ball, ball.hpp).
#pragma once

#include <cmath>

namespace dcad::bench {

template <class F>
struct Approx {
  static constexpr const char* zero_test = "|x| <= tolerance (unsound; benchmark comparison only)";
  F v = 0;
  Approx() = default;
  Approx(int k) : v(k) {}  // NOLINT
  explicit Approx(const F& x) : v(x) {}
  /// The absolute tolerance of the zero test (set per instance: relative × largest input entry).
  static F& tolerance() {
    thread_local F t = 0;
    return t;
  }
  Approx operator-() const { return Approx(-v); }
  friend Approx operator+(const Approx& a, const Approx& b) { return Approx(a.v + b.v); }
  friend Approx operator-(const Approx& a, const Approx& b) { return Approx(a.v - b.v); }
  friend Approx operator*(const Approx& a, const Approx& b) { return Approx(a.v * b.v); }
  friend Approx operator/(const Approx& a, const Approx& b) { return Approx(a.v / b.v); }
  Approx& operator+=(const Approx& o) { return *this = *this + o; }
  Approx& operator-=(const Approx& o) { return *this = *this - o; }
  Approx& operator*=(const Approx& o) { return *this = *this * o; }
  Approx& operator/=(const Approx& o) { return *this = *this / o; }
  friend bool operator==(const Approx& a, const Approx& b) {
    using std::abs;
    return abs(a.v - b.v) <= tolerance();
  }
  friend bool operator!=(const Approx& a, const Approx& b) { return !(a == b); }
};

}  // namespace dcad::bench
