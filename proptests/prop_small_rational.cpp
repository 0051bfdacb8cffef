// SmallRational and WideRational (issue 14) are mpq_rational while the numbers fit in 64 / 128 bits,
// and FLINT's fmpq (issue 26: the exact tier behind them) is mpq_rational at every size: the arithmetic
// operation by operation, and the whole reference CAD on random systems (CEF §5) and on the sweep's
// perturbed family (numbers beyond 64 bits), compared exactly with the mpq_rational run.  A wrong
// reduction, sign, gcd, overflow bound or conversion fails here.
#include "support/families.hpp"
#include "support/gen.hpp"

#include "dcad/reference/cad.hpp"
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/small_rational.hpp"
#include "generators.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <limits>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;
using S = ref::SmallRational;
using W = ref::WideRational;
using F = ref::Fmpq;

namespace {

/// An integer whose magnitude has a random bit length (1 … bits − 1): small, medium and near-limit values.
rc::Gen<ref::Rational> any_integer(int bits) {
  return rc::gen::mapcat(rc::gen::inRange(1, bits), [](int length) {
    return rc::gen::map(rc::gen::pair(rc::gen::arbitrary<std::uint64_t>(), rc::gen::arbitrary<std::uint64_t>()),
                        [length](const std::pair<std::uint64_t, std::uint64_t>& words) {
                          boost::multiprecision::mpz_int z = words.first;
                          z <<= 64;
                          z += words.second;
                          z &= (boost::multiprecision::mpz_int(1) << length) - 1;  // below 2^length
                          const bool negative = words.first & 1;
                          return ref::Rational(negative ? boost::multiprecision::mpz_int(-z) : z);
                        });
  });
}

ref::Rational any_fraction(int bits) {
  const ref::Rational p = *any_integer(bits);
  const ref::Rational q = *any_integer(bits).as("denominator");
  RC_PRE(q != 0);
  return p / q;
}

bool fits(const ref::Rational& q, int bits) {
  const boost::multiprecision::mpz_int lim = (boost::multiprecision::mpz_int(1) << (bits - 1)) - 1;
  return abs(numerator(q)) <= lim && denominator(q) <= lim;
}

/// op on T gives op on mpq exactly, or throws Overflow — for 64-bit words exactly when mpq's result
/// does not fit; for 128-bit words also when an intermediate does not, but never when the operands
/// are below 2^63 (their products are below 2^126, as in the 64-bit case) and the result fits.
template <class T, class Op>
void same_as_mpq(const ref::Rational& a, const ref::Rational& b, int bits, Op op) {
  ref::Rational exact;
  try {
    exact = op(a, b);
  } catch (const std::exception&) {
    return;  // division by zero: not asked of SmallRational by the reference
  }
  try {
    const T r = op(T::from(a), T::from(b));
    RC_ASSERT(fits(exact, bits));
    RC_ASSERT(r.value() == exact);
    RC_ASSERT(r.str() == exact.str());  // the printed number is mpq's
  } catch (const ref::Overflow&) {
    RC_ASSERT(!fits(exact, bits) || (bits == 128 && !(fits(a, 64) && fits(b, 64))));
  }
}

template <class T>
void arithmetic_is_mpq_or_overflow(int bits, int operand_bits) {
  const ref::Rational a = any_fraction(operand_bits), b = any_fraction(operand_bits);
  RC_PRE(fits(a, bits) && fits(b, bits));
  same_as_mpq<T>(a, b, bits, [](const auto& x, const auto& y) { return x + y; });
  same_as_mpq<T>(a, b, bits, [](const auto& x, const auto& y) { return x - y; });
  same_as_mpq<T>(a, b, bits, [](const auto& x, const auto& y) { return x * y; });
  same_as_mpq<T>(a, b, bits, [](const auto& x, const auto& y) {
    if (y == 0) throw std::domain_error("0");
    return x / y;
  });
  RC_CLASSIFY(!fits(a * b, bits), "the product overflows");
  RC_ASSERT((T::from(a) == T::from(b)) == (a == b));
  RC_ASSERT((-T::from(a)).value() == -a);
}

template <class From, class To, class Lift>
ref::Matrix<To> lift_matrix(const ref::Matrix<From>& m, Lift lift) {
  ref::Matrix<To> out(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) out(i, j) = lift(m(i, j));
  return out;
}

template <class T>
ref::Matrix<Q> value(const ref::Matrix<T>& m) {
  return lift_matrix<T, Q>(m, [](const T& x) { return x.value(); });
}

/// The CAD of CEF §5 on T is the mpq_rational CAD: every M_k (equations, point, basis), c, consistency,
/// solution rank, and the reduced equations (5.12) — or an Overflow (then solve recomputes).  Returns
/// false on Overflow.
template <class T>
bool cad_is_the_mpq_cad(const ref::LinearSystem<Q>& s) {
  const auto lift = [](const Q& q) { return T::from(q); };
  try {
    const ref::LinearSystem<T> t{{s.d.n, ref::Subspace<T>::span(lift_matrix<Q, T>(s.d.d.basis(), lift))},
                                 lift_matrix<Q, T>(s.hessian, lift),
                                 [&] {
                                   std::vector<T> g;
                                   for (const Q& x : s.gradient) g.push_back(T::from(x));
                                   return g;
                                 }(),
                                 T::from(s.constant)};
    const ref::CadResult<T> a = ref::constraint_tower(t);
    const ref::CadResult<Q> b = ref::constraint_tower(s);
    RC_ASSERT(a.tower.size() == b.tower.size());
    RC_ASSERT(a.consistent == b.consistent);
    RC_ASSERT(a.steps == b.steps);
    for (std::size_t k = 0; k < a.tower.size(); ++k) {
      RC_ASSERT(value(a.tower[k].equations) == b.tower[k].equations);
      RC_ASSERT(a.tower[k].m.empty == b.tower[k].m.empty);
      if (b.tower[k].m.empty) continue;
      RC_ASSERT(value(a.tower[k].m.direction.basis()) == b.tower[k].m.direction.basis());
      for (std::size_t i = 0; i < b.tower[k].m.point.size(); ++i)
        RC_ASSERT(a.tower[k].m.point[i].value() == b.tower[k].m.point[i]);
    }
    if (!b.consistent) return true;
    RC_ASSERT(a.solution_rank == b.solution_rank);
    const ref::ReducedEquations<T> ra = ref::reduced_equations(t, a);
    const ref::ReducedEquations<Q> rb = ref::reduced_equations(s, b);
    RC_ASSERT(ra.coords == rb.coords);
    RC_ASSERT(value(ra.f_matrix) == rb.f_matrix);
    RC_ASSERT(value(ra.g) == rb.g);
    for (std::size_t i = 0; i < rb.f.size(); ++i) RC_ASSERT(ra.f[i].value() == rb.f[i]);
    return true;
  } catch (const ref::Overflow&) {
    return false;
  }
}

/// op on Fmpq is op on mpq, number and printed text, whatever the size (no overflow to recover from).
template <class Op>
void fmpq_same_as_mpq(const ref::Rational& a, const ref::Rational& b, Op op) {
  const ref::Rational exact = op(a, b);
  const F r = op(F::from(a), F::from(b));
  RC_ASSERT(r.value() == exact);
  RC_ASSERT(r.str() == exact.str());
}

}  // namespace

RC_GTEST_PROP(SmallRational, ArithmeticIsMpqOrOverflow, ()) { arithmetic_is_mpq_or_overflow<S>(64, 64); }

// Operands of up to 127 bits (beyond 64: Knuth's formulas with checked 128-bit intermediates and the
// 128-bit gcd), and of up to 63 bits (where WideRational must never give up on a result that fits).
RC_GTEST_PROP(WideRational, ArithmeticIsMpqOrOverflow, ()) {
  arithmetic_is_mpq_or_overflow<W>(128, *rc::gen::element(64, 128));
}

TEST(SmallRational, OverflowAtTheWordLimit) {
  const S big = S::from(ref::Rational(std::numeric_limits<std::int64_t>::max()));
  EXPECT_THROW(big + S(1), ref::Overflow);
  EXPECT_THROW(big * S(2), ref::Overflow);
  EXPECT_EQ((big - S(1) + S(1)).value(), ref::Rational(std::numeric_limits<std::int64_t>::max()));
  EXPECT_EQ((-big).value(), -ref::Rational(std::numeric_limits<std::int64_t>::max()));
  EXPECT_THROW(S::from(ref::Rational(std::numeric_limits<std::int64_t>::min())), ref::Overflow);  // |p| ≤ 2^63 − 1
  EXPECT_EQ((S(6) / S(-4)).str(), "-3/2");
  EXPECT_EQ((S(-6) / S(-3)).str(), "2");
  // … and the same numbers in 128-bit words, which hold them
  const W wide = W::from(big);
  EXPECT_EQ((wide + W(1)).value(), ref::Rational(std::numeric_limits<std::int64_t>::max()) + 1);
  EXPECT_EQ((wide * W(2)).str(), (ref::Rational(std::numeric_limits<std::int64_t>::max()) * 2).str());
  const boost::multiprecision::mpz_int top = (boost::multiprecision::mpz_int(1) << 127) - 1;  // 2^127 − 1
  const W w127 = W::from(ref::Rational(top));
  EXPECT_THROW(w127 + W(1), ref::Overflow);
  EXPECT_EQ((-w127).value(), -ref::Rational(top));
  EXPECT_EQ((W(1) / w127).str(), "1/" + top.str());
  EXPECT_THROW(W::from(ref::Rational(top + 1)), ref::Overflow);
}

// The CAD of CEF §5 on SmallRational is the mpq_rational CAD (or an Overflow: then solve recomputes).
RC_GTEST_PROP(SmallRational, ReferenceCadIsTheMpqCad, ()) {
  RC_CLASSIFY(cad_is_the_mpq_cad<S>(*systems()), "fits in 64 bits");
}

// The same on WideRational, on random systems and on the sweep's perturbed family (ω moved by a shear
// and perturbed by 2^-k, k up to 60: numbers that outgrow 64 bits, the reason WideRational exists).
RC_GTEST_PROP(WideRational, ReferenceCadIsTheMpqCad, ()) {
  if (*rc::gen::arbitrary<bool>()) {
    RC_CLASSIFY(cad_is_the_mpq_cad<W>(*systems()), "random system, fits in 128 bits");
    return;
  }
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const families::Instance in = families::perturbed(*rc::gen::inRange(30, 61), rng);
  const ref::LinearSystem<Q> s = families::system_over<Q>(in, [](const Q& q) { return q; });
  RC_CLASSIFY(!cad_is_the_mpq_cad<S>(s), "perturbed beyond 64 bits");
  RC_CLASSIFY(cad_is_the_mpq_cad<W>(s), "perturbed, fits in 128 bits");
}

// FLINT aborts on a division by zero; Fmpq throws instead, as SmallRational and mpq_rational do (a
// process that aborts is a crash, not a clear error).
TEST(Fmpq, DivisionByZeroThrows) {
  EXPECT_THROW(F(1) / F(0), std::domain_error);
  F x(3);
  EXPECT_THROW(x /= F(0), std::domain_error);
  EXPECT_EQ((F(6) / F(-4)).str(), "-3/2");
}

// Fmpq on operands of up to 200 bits (FLINT keeps up to 62 bits in the word, beyond in GMP: both sides
// of that line and the moves between them).
RC_GTEST_PROP(Fmpq, ArithmeticIsMpq, ()) {
  const ref::Rational a = any_fraction(*rc::gen::element(8, 62, 64, 200)),
                      b = any_fraction(*rc::gen::element(8, 62, 64, 200));
  fmpq_same_as_mpq(a, b, [](const auto& x, const auto& y) { return x + y; });
  fmpq_same_as_mpq(a, b, [](const auto& x, const auto& y) { return x - y; });
  fmpq_same_as_mpq(a, b, [](const auto& x, const auto& y) { return x * y; });
  if (b != 0) fmpq_same_as_mpq(a, b, [](const auto& x, const auto& y) { return x / y; });
  RC_ASSERT((F::from(a) == F::from(b)) == (a == b));
  RC_ASSERT((-F::from(a)).value() == -a);
  RC_ASSERT(known_zero(F::from(a)) == (a == 0));
  F acc = F::from(a);
  acc += F::from(b), acc *= F::from(b), acc -= F::from(a);
  RC_ASSERT(acc.value() == (a + b) * b - a);
  RC_CLASSIFY(!fits(a, 64) || !fits(b, 64), "an operand beyond 64 bits (in GMP)");
}

// The CAD of CEF §5 on Fmpq is the mpq_rational CAD, on random systems and on the perturbed family
// beyond 128 bits (where the reference and the certified cascade reach it).
RC_GTEST_PROP(Fmpq, ReferenceCadIsTheMpqCad, ()) {
  if (*rc::gen::arbitrary<bool>()) {
    RC_ASSERT(cad_is_the_mpq_cad<F>(*systems()));
    return;
  }
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const families::Instance in = families::perturbed(*rc::gen::inRange(30, 61), rng);
  const ref::LinearSystem<Q> s = families::system_over<Q>(in, [](const Q& q) { return q; });
  RC_CLASSIFY(!cad_is_the_mpq_cad<W>(s), "perturbed beyond 128 bits");
  RC_ASSERT(cad_is_the_mpq_cad<F>(s));
}
