// Jets: truncated multivariate Taylor series  f(s0 + δ) = Σ_{|α| ≤ ord} c_α δ^α  of a function at a
// point, in d variables, over a scalar T (mpq_rational exactly, or double).  Arithmetic on jets is
// arithmetic on the functions they stand for, so a computation written once for numbers gives, run
// on jets, its result together with every derivative up to the order (forward-mode differentiation
// of all orders at once).  Each jet knows the order `ord` up to which its coefficients are right:
// a derivative knows one order less.
//
// The scalar functions at the constant term come from JetFunctions<T>: exact for rationals only
// where the value is rational (sin 0, cos 0, exp 0, the square root of a square), otherwise
// NotExactHere — never a rounded value posing as exact.
#pragma once

#include "dcad/symbolic/rational.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::symbolic {

/// A value the exact scalar cannot hold (sin 1/2, √2): the exact route cannot run at this point.
struct NotExactHere : std::domain_error {
  using std::domain_error::domain_error;
};

/// The monomials δ^α, |α| ≤ K, in d variables, in graded order (degree 0, then 1: δ_0 … δ_{d−1},
/// then 2, …), with the tables that products, derivatives and substitutions use.
class JetSpace {
 public:
  JetSpace(std::size_t d, std::size_t k) : d_(d), k_(k) {
    // the monomials, and the product table (one entry per pair of degree sum ≤ k: C(2d + k, k))
    if (binomial(d + k, k) > 200'000 || binomial(2 * d + k, k) > 20'000'000)
      throw std::length_error(
          "jets in " + std::to_string(d) + " variables to order " + std::to_string(k) + " (" +
          std::to_string(static_cast<long>(binomial(d + k, k))) + " monomials, a product table of " +
          std::to_string(static_cast<long>(binomial(2 * d + k, k))) + ") exceed what dcad computes");
    std::vector<std::uint8_t> alpha(d, 0);
    index_[alpha] = 0;
    exps_.push_back(alpha);
    start_.push_back(0);
    for (std::size_t deg = 1; deg <= k; ++deg) {
      start_.push_back(exps_.size());
      const std::size_t prev_begin = start_[deg - 1], prev_end = start_[deg];
      for (std::size_t p = prev_begin; p < prev_end; ++p) {  // α = β + e_j with j ≥ the last variable of β
        std::size_t last = 0;
        for (std::size_t j = 0; j < d; ++j)
          if (exps_[p][j]) last = j;
        for (std::size_t j = (deg == 1 ? 0 : last); j < d; ++j) {
          std::vector<std::uint8_t> a = exps_[p];
          ++a[j];
          index_[a] = static_cast<std::uint32_t>(exps_.size());
          exps_.push_back(a);
          parent_.resize(exps_.size(), {0, 0});
          parent_.back() = {static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(j)};
        }
      }
    }
    start_.push_back(exps_.size());
    parent_.resize(exps_.size(), {0, 0});
    degree_.resize(exps_.size());
    for (std::size_t deg = 0; deg <= k; ++deg)
      for (std::size_t i = start_[deg]; i < start_[deg + 1]; ++i) degree_[i] = deg;
    deriv_.resize(d);
    for (std::size_t i = 1; i < exps_.size(); ++i)
      for (std::size_t j = 0; j < d; ++j)
        if (exps_[i][j]) {
          std::vector<std::uint8_t> a = exps_[i];
          --a[j];
          deriv_[j].push_back({static_cast<std::uint32_t>(i), index_.at(a), exps_[i][j]});
        }
  }

  std::size_t vars() const { return d_; }
  std::size_t order() const { return k_; }
  std::size_t size() const { return exps_.size(); }
  std::size_t degree(std::size_t i) const { return degree_[i]; }
  /// Number of monomials of degree ≤ deg.
  std::size_t count_up_to(std::size_t deg) const { return start_[std::min(deg, k_) + 1]; }
  const std::vector<std::uint8_t>& exponents(std::size_t i) const { return exps_[i]; }
  /// α = parent(α) + e_var(α), for α ≠ 0.
  std::pair<std::uint32_t, std::uint32_t> parent(std::size_t i) const { return parent_[i]; }
  /// The index of α + β, for |α| + |β| ≤ K.
  std::uint32_t product_index(std::size_t a, std::size_t b) const {
    if (products_.empty()) build_products();
    return products_[a][b];
  }
  struct DerivativeEntry {
    std::uint32_t from, to, factor;  ///< ∂/∂δ_j δ^from = factor · δ^to
  };
  const std::vector<DerivativeEntry>& derivative_table(std::size_t j) const { return deriv_[j]; }

 private:
  static double binomial(std::size_t n, std::size_t k) {
    double r = 1;
    for (std::size_t i = 1; i <= k; ++i) r = r * static_cast<double>(n - k + i) / static_cast<double>(i);
    return r;
  }
  void build_products() const {
    products_.resize(exps_.size());
    for (std::size_t a = 0; a < exps_.size(); ++a) {
      const std::size_t lim = count_up_to(k_ - degree_[a]);
      products_[a].resize(lim);
      for (std::size_t b = 0; b < lim; ++b) {
        std::vector<std::uint8_t> s = exps_[a];
        for (std::size_t j = 0; j < d_; ++j) s[j] = static_cast<std::uint8_t>(s[j] + exps_[b][j]);
        products_[a][b] = index_.at(s);
      }
    }
  }

  std::size_t d_, k_;
  std::vector<std::vector<std::uint8_t>> exps_;
  std::map<std::vector<std::uint8_t>, std::uint32_t> index_;
  std::vector<std::size_t> start_, degree_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> parent_;
  std::vector<std::vector<DerivativeEntry>> deriv_;
  mutable std::vector<std::vector<std::uint32_t>> products_;  // built on the first product
};

/// Values of sin, cos, exp, sqrt at a scalar: double by the C library; rationals exactly or not at all.
template <class T>
struct JetFunctions {
  /// Scalars that carry a rounding-error bound (fast/tracked.hpp) say so, and how to reset it.
  static constexpr bool tracks_error = false;
  static T as_input(const T& x) { return x; }
  static T with_error(const T& x, const T&) { return x; }
  static T sin(const T& x) { return std::sin(x); }
  static T cos(const T& x) { return std::cos(x); }
  static T exp(const T& x) { return std::exp(x); }
  static T sqrt(const T& x) { return std::sqrt(x); }
  static bool is_zero(const T& x) { return x == 0; }
  static double magnitude(const T& x) { return std::abs(static_cast<double>(x)); }
  static std::string text(const T& x) { return std::to_string(x); }
};

template <>
struct JetFunctions<Rational> {
  static constexpr bool tracks_error = false;
  static Rational as_input(const Rational& x) { return x; }
  static Rational with_error(const Rational& x, const Rational&) { return x; }
  static Rational sin(const Rational& x) {
    if (x != 0) throw NotExactHere("sin(" + x.str() + ") is irrational");
    return 0;
  }
  static Rational cos(const Rational& x) {
    if (x != 0) throw NotExactHere("cos(" + x.str() + ") is irrational");
    return 1;
  }
  static Rational exp(const Rational& x) {
    if (x != 0) throw NotExactHere("exp(" + x.str() + ") is irrational");
    return 1;
  }
  static Rational sqrt(const Rational& x) {
    using boost::multiprecision::mpz_int;
    const mpz_int n = numerator(x), d = denominator(x);
    if (n >= 0) {
      const mpz_int rn = boost::multiprecision::sqrt(n), rd = boost::multiprecision::sqrt(d);
      if (rn * rn == n && rd * rd == d) return Rational(rn, rd);
    }
    throw NotExactHere("sqrt(" + x.str() + ") is irrational");
  }
  static bool is_zero(const Rational& x) { return x == 0; }
  static double magnitude(const Rational& x) { return x == 0 ? 0.0 : std::max(abs(x).convert_to<double>(), 1e-300); }
  static std::string text(const Rational& x) { return x.str(); }
};

/// A jet stores its nonzero coefficients only, as (monomial index, coefficient) pairs sorted by
/// index (graded order, so the degree never decreases along the list): most jets of a point
/// computation are polynomials of low degree or short series, and a dense vector of exact rationals
/// spent its time allocating zeros.
template <class T>
class Jet {
 public:
  using Space = std::shared_ptr<const JetSpace>;
  using Entry = std::pair<std::uint32_t, T>;
  Jet() = default;
  /// The constant function v (known to every order).
  Jet(Space sp, const T& v) : sp_(std::move(sp)), ord_(static_cast<long>(sp_->order())) {
    if (!JetFunctions<T>::is_zero(v)) c_.emplace_back(0, v);
  }
  /// The coordinate function s_i, with value v at the point.
  static Jet variable(Space sp, std::size_t i, const T& v) {
    if (i >= sp->vars()) throw std::out_of_range("Jet::variable: index out of range");
    Jet j(sp, v);
    if (sp->order() >= 1) j.c_.emplace_back(static_cast<std::uint32_t>(1 + i), T(1));
    return j;
  }

  const Space& space() const { return sp_; }
  /// Coefficients are right up to this total degree (−1: nothing is known).
  long order() const { return ord_; }
  T value() const { return coefficient(0); }
  /// The coefficient of monomial i (0 if none is stored).
  T coefficient(std::size_t i) const {
    const auto it =
        std::lower_bound(c_.begin(), c_.end(), i, [](const Entry& e, std::size_t k) { return e.first < k; });
    return it != c_.end() && it->first == i ? it->second : T(0);
  }
  /// The stored (nonzero) coefficients, by increasing monomial index.
  const std::vector<Entry>& entries() const { return c_; }
  /// ∂f/∂s_i at the point.
  T gradient(std::size_t i) const { return coefficient(1 + i); }
  void set_coefficient(std::size_t i, const T& v) {
    const auto it =
        std::lower_bound(c_.begin(), c_.end(), i, [](const Entry& e, std::size_t k) { return e.first < k; });
    const bool here = it != c_.end() && it->first == i;
    if (JetFunctions<T>::is_zero(v)) {
      if (here) c_.erase(it);
    } else if (here) {
      it->second = v;
    } else {
      c_.insert(it, Entry(static_cast<std::uint32_t>(i), v));
    }
  }
  /// Every coefficient up to the order is zero (exact zero test: the scalar's ==).
  bool is_zero() const {
    for (const Entry& e : c_)
      if (!JetFunctions<T>::is_zero(e.second)) return false;
    return true;
  }

  Jet operator-() const {
    Jet r = *this;
    for (Entry& e : r.c_) e.second = -e.second;
    return r;
  }
  friend Jet operator+(const Jet& a, const Jet& b) { return merge(a, b, false); }
  friend Jet operator-(const Jet& a, const Jet& b) { return merge(a, b, true); }
  Jet& operator+=(const Jet& o) { return *this = *this + o; }
  Jet& operator-=(const Jet& o) { return *this = *this - o; }
  friend Jet operator*(const Jet& a, const Jet& b) {
    a.same_space(b);
    Jet r;
    r.sp_ = a.sp_;
    r.ord_ = std::min(a.ord_, b.ord_);
    if (r.ord_ < 0) return r;
    const std::size_t ord = static_cast<std::size_t>(r.ord_);
    Scratch& s = scratch(a.sp_->size());
    for (const Entry& x : a.c_) {
      const std::size_t dx = a.sp_->degree(x.first);
      if (dx > ord) break;
      for (const Entry& y : b.c_) {
        if (a.sp_->degree(y.first) > ord - dx) break;
        s.add(a.sp_->product_index(x.first, y.first), x.second * y.second);
      }
    }
    s.collect(r.c_);
    return r;
  }
  Jet& operator*=(const Jet& o) { return *this = *this * o; }
  /// 1/f = (1/f0) Σ_k (−(f − f0)/f0)^k; f0 = 0 is std::domain_error (not invertible at the point).
  Jet reciprocal() const {
    const T f0 = value();
    if (JetFunctions<T>::is_zero(f0)) throw std::domain_error("division by an expression that is 0 at the point");
    std::vector<T> f(static_cast<std::size_t>(std::max(ord_, 0L)) + 1);
    T p = T(1) / f0;
    for (std::size_t k = 0; k < f.size(); ++k, p = -p / f0) f[k] = p;
    return taylor(f);
  }
  friend Jet operator/(const Jet& a, const Jet& b) { return a * b.reciprocal(); }

  /// Σ_k f[k] (g − g0)^k: a function of one variable, given by its Taylor coefficients at g0,
  /// applied to this jet g (Horner).
  Jet taylor(const std::vector<T>& f) const {
    Jet delta = *this;
    delta.drop_constant();
    const std::size_t top = std::min<std::size_t>(f.size() - 1, static_cast<std::size_t>(std::max(ord_, 0L)));
    Jet r(sp_, f[top]);
    for (std::size_t k = top; k-- > 0;) r = r * delta + Jet(sp_, f[k]);
    r.set_order(ord_);
    return r;
  }

  /// ∂f/∂s_i (known to one order less).
  Jet derivative(std::size_t i) const {
    Jet r;
    r.sp_ = sp_;
    r.ord_ = ord_ - 1;
    Scratch& s = scratch(sp_->size());
    for (const auto& e : sp_->derivative_table(i)) {
      if (static_cast<long>(sp_->degree(e.to)) > r.ord_) continue;
      const T c = coefficient(e.from);
      if (!JetFunctions<T>::is_zero(c)) s.add(e.to, T(e.factor) * c);
    }
    s.collect(r.c_);
    return r;
  }

  /// Σ c_α δ^α at a displacement δ from the point (the Taylor polynomial; exact for polynomials of
  /// degree ≤ order).
  T at(const std::vector<T>& delta) const {
    T s(0);
    for (const Entry& e : c_) {
      T mono(1);
      const auto& a = sp_->exponents(e.first);
      for (std::size_t v = 0; v < a.size(); ++v)
        for (unsigned k = 0; k < a[v]; ++k) mono *= delta[v];
      s += e.second * mono;
    }
    return s;
  }

  /// f(s(u)): this jet (in variables s) with s_i = subs[i], jets in other variables u whose values
  /// are the point of this jet's space.
  Jet compose(const std::vector<Jet>& subs) const {
    if (subs.size() != sp_->vars()) throw std::invalid_argument("Jet::compose: one substitution per variable");
    const Space& to = subs.empty() ? sp_ : subs[0].sp_;
    long ord = ord_;
    std::vector<Jet> delta;
    for (const Jet& s : subs) {
      ord = std::min(ord, s.ord_);
      Jet d = s;
      d.drop_constant();
      delta.push_back(d);
    }
    Jet r(to, T(0));
    r.ord_ = ord;
    if (ord < 0) return r;
    const std::size_t n = sp_->count_up_to(static_cast<std::size_t>(ord));
    std::vector<char> needed(n, 0);  // δ^α is needed if a coefficient at α or a descendant is nonzero
    for (const Entry& e : c_)
      if (e.first < n) needed[e.first] = 1;
    for (std::size_t i = n; i-- > 1;)
      if (needed[i]) needed[sp_->parent(i).first] = 1;
    std::vector<Jet> mon(n);
    std::size_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!needed[i]) continue;
      if (i > 0) {
        const auto [p, v] = sp_->parent(i);
        mon[i] = p == 0 ? delta[v] : mon[p] * delta[v];
      }
      while (next < c_.size() && c_[next].first < i) ++next;
      if (next < c_.size() && c_[next].first == i)
        r = r + (i == 0 ? Jet(to, c_[next].second) : mon[i] * Jet(to, c_[next].second));
    }
    r.set_order(ord);
    return r;
  }

  /// Coefficients above `ord` are unknown: forget them.
  void set_order(long ord) {
    ord_ = std::min(ord_, ord);
    const std::size_t known = ord_ < 0 ? 0 : sp_->count_up_to(static_cast<std::size_t>(ord_));
    while (!c_.empty() && c_.back().first >= known) c_.pop_back();
  }

 private:
  /// A reusable dense accumulator (per thread and scalar): products and derivatives add into it,
  /// then collect the touched entries in index order and reset them.
  struct Scratch {
    std::vector<T> acc;
    std::vector<char> used;
    std::vector<std::uint32_t> touched;
    void add(std::uint32_t i, const T& v) {
      if (!used[i]) {
        used[i] = 1;
        touched.push_back(i);
        acc[i] = v;
      } else {
        acc[i] += v;
      }
    }
    void collect(std::vector<Entry>& out) {
      std::sort(touched.begin(), touched.end());
      out.clear();
      out.reserve(touched.size());
      for (std::uint32_t i : touched) {
        if (!JetFunctions<T>::is_zero(acc[i])) out.emplace_back(i, acc[i]);
        used[i] = 0;
      }
      touched.clear();
    }
  };
  static Scratch& scratch(std::size_t size) {
    thread_local Scratch s;
    if (s.acc.size() < size) {
      s.acc.resize(size, T(0));
      s.used.resize(size, 0);
    }
    return s;
  }
  static Jet merge(const Jet& a, const Jet& b, bool minus) {
    a.same_space(b);
    Jet r;
    r.sp_ = a.sp_;
    r.ord_ = std::min(a.ord_, b.ord_);
    const std::size_t known = r.ord_ < 0 ? 0 : a.sp_->count_up_to(static_cast<std::size_t>(r.ord_));
    std::size_t i = 0, j = 0;
    while (i < a.c_.size() || j < b.c_.size()) {
      const std::uint32_t ia = i < a.c_.size() ? a.c_[i].first : UINT32_MAX,
                          ib = j < b.c_.size() ? b.c_[j].first : UINT32_MAX;
      const std::uint32_t k = std::min(ia, ib);
      if (k >= known) break;
      T v = ia == k ? a.c_[i].second : T(0);
      if (ib == k) {
        if (minus)
          v -= b.c_[j].second;
        else
          v += b.c_[j].second;
      }
      if (ia == k) ++i;
      if (ib == k) ++j;
      if (!JetFunctions<T>::is_zero(v)) r.c_.emplace_back(k, v);
    }
    return r;
  }
  void same_space(const Jet& o) const {
    if (sp_ != o.sp_) throw std::logic_error("Jet: operands live in different spaces");
  }
  void drop_constant() {
    if (!c_.empty() && c_[0].first == 0) c_.erase(c_.begin());
  }

  Space sp_;
  std::vector<Entry> c_;
  long ord_ = -1;
};

template <class T>
Jet<T> pow_int(const Jet<T>& a, long k) {
  if (k < 0) return pow_int(a.reciprocal(), -k);
  Jet<T> r(a.space(), T(1)), base = a;
  r.set_order(a.order());
  for (; k > 0; k >>= 1) {
    if (k & 1) r = r * base;
    if (k > 1) base = base * base;
  }
  return r;
}

template <class T>
Jet<T> exp(const Jet<T>& a) {
  std::vector<T> f(static_cast<std::size_t>(std::max(a.order(), 0L)) + 1);
  T e = JetFunctions<T>::exp(a.value());
  for (std::size_t k = 0; k < f.size(); ++k) {
    f[k] = e;
    e /= T(static_cast<long>(k + 1));
  }
  return a.taylor(f);
}

/// sin (is_sin) or cos at a + δ from the cycle of their derivatives, divided by k!.
template <class T>
Jet<T> sin_or_cos(const Jet<T>& a, bool is_sin) {
  const T s = JetFunctions<T>::sin(a.value()), c = JetFunctions<T>::cos(a.value());
  const T cycle[4] = {is_sin ? s : c, is_sin ? c : -s, is_sin ? -s : -c, is_sin ? -c : s};
  std::vector<T> f(static_cast<std::size_t>(std::max(a.order(), 0L)) + 1);
  T fact(1);
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (k > 0) fact *= T(static_cast<long>(k));
    f[k] = cycle[k % 4] / fact;
  }
  return a.taylor(f);
}
template <class T>
Jet<T> sin(const Jet<T>& a) {
  return sin_or_cos(a, true);
}
template <class T>
Jet<T> cos(const Jet<T>& a) {
  return sin_or_cos(a, false);
}

/// √(a0 + δ) = √a0 Σ_k binom(1/2, k) (δ/a0)^k; a0 ≤ 0 is std::domain_error.
template <class T>
Jet<T> sqrt(const Jet<T>& a) {
  if (!(a.value() > 0)) throw std::domain_error("sqrt of a value that is not positive at the point");
  const T r0 = JetFunctions<T>::sqrt(a.value());
  std::vector<T> f(static_cast<std::size_t>(std::max(a.order(), 0L)) + 1);
  T binom(1), p = r0;
  for (std::size_t k = 0; k < f.size(); ++k) {
    f[k] = binom * p;
    binom = binom * (T(1) / T(2) - T(static_cast<long>(k))) / T(static_cast<long>(k + 1));
    p /= a.value();
  }
  return a.taylor(f);
}

}  // namespace dcad::symbolic
