// Tracked: a double with a first-order bound e of its accumulated rounding error (forward error
// analysis, Higham, Accuracy and Stability, §2–3; u = 2^-53):
//   x ± y: e = e_x + e_y + u|x ± y|        x·y: e = |x| e_y + |y| e_x + e_x e_y + u|xy|
//   x / y: e = (e_x + |x/y| e_y) / (|y| − e_y) + u|x/y|
//   f(x) for sin, cos, exp, sqrt: e = |f'(x)| e_x + 2u|f(x)|   (the C library: < 1 ulp, plus margin)
//   an input rounded to double: e = u|x|.
// Not rigorous (the bound is itself computed in rounding arithmetic: the decisions in the fast backend's
// dcad/fast/pointwise.hpp keep a factor 8 of slack), but it follows the rounding actually committed, so a zero test can
// be decided relative to each number's own error: an exact zero computed with rounding lands within e, a value far
// above e is certainly not zero.  (Neither a global scale nor Σ|terms| works: the magnitudes inside one run differ by
// many orders, and Σ|terms| grows multiplicatively through Newton's iterations on jets.)
#pragma once

#include "dcad/symbolic/jet.hpp"

#include <cmath>
#include <string>

namespace dcad::fast {

struct Tracked {
  static constexpr double u = 0x1p-53;
  double v = 0, e = 0;
  Tracked() = default;
  Tracked(int k) : v(k) {}                        // NOLINT: the algorithms write T(0), T(1): exact
  Tracked(long k) : v(static_cast<double>(k)) {}  // NOLINT (|k| < 2^53 here)
  Tracked(unsigned k) : v(k) {}                   // NOLINT
  Tracked(double value, double error) : v(value), e(error) {}
  static Tracked input(double x) { return {x, u * std::abs(x)}; }

  Tracked operator-() const { return {-v, e}; }
  friend Tracked operator+(const Tracked& a, const Tracked& b) {
    const double s = a.v + b.v;
    return {s, a.e + b.e + u * std::abs(s)};
  }
  friend Tracked operator-(const Tracked& a, const Tracked& b) { return a + (-b); }
  friend Tracked operator*(const Tracked& a, const Tracked& b) {
    const double p = a.v * b.v;
    return {p, std::abs(a.v) * b.e + std::abs(b.v) * a.e + a.e * b.e + u * std::abs(p)};
  }
  friend Tracked operator/(const Tracked& a, const Tracked& b) {
    const double q = a.v / b.v;
    const double below = std::abs(b.v) - b.e;
    return {q, below > 0 ? (a.e + std::abs(q) * b.e) / below + u * std::abs(q) : HUGE_VAL};
  }
  Tracked& operator+=(const Tracked& o) { return *this = *this + o; }
  Tracked& operator-=(const Tracked& o) { return *this = *this - o; }
  Tracked& operator*=(const Tracked& o) { return *this = *this * o; }
  Tracked& operator/=(const Tracked& o) { return *this = *this / o; }
  /// Structural comparisons only (an exactly stored integer): no decision.
  friend bool operator==(const Tracked& a, int k) { return a.v == k && a.e == 0; }
  friend bool operator!=(const Tracked& a, int k) { return !(a == k); }
  friend bool operator>(const Tracked& a, int k) { return a.v - a.e > k; }
};

}  // namespace dcad::fast

namespace dcad::symbolic {

template <>
struct JetFunctions<fast::Tracked> {
  using T = fast::Tracked;
  static constexpr bool tracks_error = true;
  /// A point's coordinate as the CAD's input: its rounding only (the history of the Newton steps
  /// that produced it does not matter: the CAD is computed at this point).
  static T as_input(const T& x) { return T::input(x.v); }
  /// x with the error bound |bound|'s value plus its own error (an a-posteriori bound).
  static T with_error(const T& x, const T& bound) { return {x.v, std::abs(bound.v) + bound.e + T::u * std::abs(x.v)}; }
  static T f(double value, double slope, const T& x) {
    return {value, std::abs(slope) * x.e + 2 * T::u * std::abs(value)};
  }
  static T sin(const T& x) { return f(std::sin(x.v), std::cos(x.v), x); }
  static T cos(const T& x) { return f(std::cos(x.v), std::sin(x.v), x); }
  static T exp(const T& x) { return f(std::exp(x.v), std::exp(x.v + x.e), x); }
  static T sqrt(const T& x) { return f(std::sqrt(x.v), 0.5 / std::sqrt(std::max(x.v - x.e, 0.0)), x); }
  static bool is_zero(const T& x) { return x.v == 0 && x.e == 0; }
  static double magnitude(const T& x) { return std::abs(x.v); }
  static std::string text(const T& x) { return std::to_string(x.v); }
};

}  // namespace dcad::symbolic
