// Fmpq: FLINT's exact rational (fmpq_t, LGPL) as a scalar of the reference's own algorithms.  The value
// is the exact rational p/q in lowest terms, as mpq_rational keeps it, so a run on BasicFmpq performs the
// same exact arithmetic, takes the same branches (zero tests are exact: p == 0) and prints the same
// numbers as on mpq_rational; FLINT keeps p and q of up to 62 bits in the word itself (no heap
// allocation) and moves them to GMP only when they grow, so there is no overflow to recover from.
// (prop_small_rational holds Fmpq's arithmetic to mpq_rational's.)
#pragma once

#include "dcad/reference/rational.hpp"

#include <flint/fmpq.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace dcad::reference {

/// `Tag` only makes another type of the same number, so that an overload of rref may go by FLINT's own
/// elimination (bench/method_flint.cpp measures that; it lost to Gauss–Jordan); the reference's is Fmpq.
template <class Tag = void>
class BasicFmpq {
 public:
  static constexpr const char* zero_test = "exact (FLINT fmpq in lowest terms: p == 0)";

  BasicFmpq() { fmpq_init(v_); }
  BasicFmpq(int k) {  // NOLINT: the algorithms write T(0), T(1), T(-1)
    fmpq_init(v_);
    fmpq_set_si(v_, k, 1);
  }
  BasicFmpq(const BasicFmpq& o) {
    fmpq_init(v_);
    fmpq_set(v_, o.v_);
  }
  BasicFmpq(BasicFmpq&& o) noexcept {
    fmpq_init(v_);
    fmpq_swap(v_, o.v_);
  }
  BasicFmpq& operator=(const BasicFmpq& o) {
    fmpq_set(v_, o.v_);
    return *this;
  }
  BasicFmpq& operator=(BasicFmpq&& o) noexcept {
    fmpq_swap(v_, o.v_);
    return *this;
  }
  ~BasicFmpq() { fmpq_clear(v_); }

  static BasicFmpq from(const Rational& q) {
    BasicFmpq r;
    fmpq_set_mpq(r.v_, q.backend().data());
    return r;
  }
  Rational value() const {
    Rational q;
    fmpq_get_mpq(q.backend().data(), v_);
    return q;
  }
  std::string str() const { return value().str(); }

  BasicFmpq operator-() const {
    BasicFmpq r;
    fmpq_neg(r.v_, v_);
    return r;
  }
  friend BasicFmpq operator+(const BasicFmpq& a, const BasicFmpq& b) {
    BasicFmpq r;
    fmpq_add(r.v_, a.v_, b.v_);
    return r;
  }
  friend BasicFmpq operator-(const BasicFmpq& a, const BasicFmpq& b) {
    BasicFmpq r;
    fmpq_sub(r.v_, a.v_, b.v_);
    return r;
  }
  friend BasicFmpq operator*(const BasicFmpq& a, const BasicFmpq& b) {
    BasicFmpq r;
    fmpq_mul(r.v_, a.v_, b.v_);
    return r;
  }
  friend BasicFmpq operator/(const BasicFmpq& a, const BasicFmpq& b) {
    BasicFmpq r;
    fmpq_div(r.v_, a.v_, nonzero(b).v_);  // the algorithms divide by pivots only
    return r;
  }
  BasicFmpq& operator+=(const BasicFmpq& o) {
    fmpq_add(v_, v_, o.v_);
    return *this;
  }
  BasicFmpq& operator-=(const BasicFmpq& o) {
    fmpq_sub(v_, v_, o.v_);
    return *this;
  }
  BasicFmpq& operator*=(const BasicFmpq& o) {
    fmpq_mul(v_, v_, o.v_);
    return *this;
  }
  BasicFmpq& operator/=(const BasicFmpq& o) {
    fmpq_div(v_, v_, nonzero(o).v_);
    return *this;
  }
  friend bool operator==(const BasicFmpq& a, const BasicFmpq& b) { return fmpq_equal(a.v_, b.v_); }
  friend bool operator!=(const BasicFmpq& a, const BasicFmpq& b) { return !fmpq_equal(a.v_, b.v_); }
  friend bool operator==(const BasicFmpq& a, int k) { return fmpq_equal_si(const_cast<fmpq*>(a.v_), k); }
  friend bool operator!=(const BasicFmpq& a, int k) { return !(a == k); }
  friend bool known_zero(const BasicFmpq& a) { return fmpq_is_zero(a.v_); }

  fmpq* data() { return v_; }
  const fmpq* data() const { return v_; }

 private:
  /// FLINT aborts the process on a division by zero; this throws, as SmallRational and mpq_rational do.
  static const BasicFmpq& nonzero(const BasicFmpq& b) {
    if (fmpq_is_zero(b.v_)) throw std::domain_error("Fmpq: division by zero");
    return b;
  }
  fmpq_t v_;
};

using Fmpq = BasicFmpq<>;

}  // namespace dcad::reference
