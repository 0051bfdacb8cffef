// SmallRational (issue 14) is mpq_rational while the numbers fit in 64 bits: the arithmetic
// operation by operation, and the whole reference CAD on random systems (CEF §5), compared
// exactly with the mpq_rational run.  A wrong reduction, sign or overflow bound fails here.
#include "support/gen.hpp"

#include "dcad/reference/cad.hpp"
#include "dcad/reference/small_rational.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstdint>
#include <limits>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;
using S = ref::SmallRational;

namespace {

/// An int64 whose magnitude has a random bit length (1 … 63): small, medium and near-limit values.
rc::Gen<std::int64_t> any_word() {
  return rc::gen::mapcat(rc::gen::inRange(1, 64), [](int bits) {
    const std::int64_t hi = bits == 63 ? std::numeric_limits<std::int64_t>::max() : (std::int64_t{1} << bits) - 1;
    return rc::gen::inRange<std::int64_t>(-hi, hi);
  });
}

ref::Rational any_fraction() {
  const std::int64_t p = *any_word();
  const std::int64_t q = *any_word().as("denominator");
  RC_PRE(q != 0);
  return ref::Rational(p) / ref::Rational(q);
}

bool fits(const ref::Rational& q) {
  const boost::multiprecision::mpz_int lim = std::numeric_limits<std::int64_t>::max();
  return abs(numerator(q)) <= lim && denominator(q) <= lim;
}

/// op on SmallRational gives op on mpq exactly, or throws Overflow exactly when that does not fit.
template <class Op>
void same_as_mpq(const ref::Rational& a, const ref::Rational& b, Op op) {
  ref::Rational exact;
  try {
    exact = op(a, b);
  } catch (const std::exception&) {
    return;  // division by zero: not asked of SmallRational by the reference
  }
  try {
    const S r = op(S::from(a), S::from(b));
    RC_ASSERT(fits(exact));
    RC_ASSERT(r.value() == exact);
    RC_ASSERT(r.str() == exact.str());  // the printed number is mpq's
  } catch (const ref::Overflow&) {
    RC_ASSERT(!fits(exact));
  }
}

template <class From, class To, class Lift>
ref::Matrix<To> lift_matrix(const ref::Matrix<From>& m, Lift lift) {
  ref::Matrix<To> out(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) out(i, j) = lift(m(i, j));
  return out;
}

ref::Matrix<Q> value(const ref::Matrix<S>& m) { return lift_matrix<S, Q>(m, [](const S& x) { return x.value(); }); }

}  // namespace

RC_GTEST_PROP(SmallRational, ArithmeticIsMpqOrOverflow, ()) {
  const ref::Rational a = any_fraction(), b = any_fraction();
  RC_PRE(fits(a) && fits(b));
  same_as_mpq(a, b, [](const auto& x, const auto& y) { return x + y; });
  same_as_mpq(a, b, [](const auto& x, const auto& y) { return x - y; });
  same_as_mpq(a, b, [](const auto& x, const auto& y) { return x * y; });
  same_as_mpq(a, b, [](const auto& x, const auto& y) {
    if (y == 0) throw std::domain_error("0");
    return x / y;
  });
  RC_CLASSIFY(!fits(a * b), "the product overflows");
  RC_ASSERT((S::from(a) == S::from(b)) == (a == b));
  RC_ASSERT((-S::from(a)).value() == -a);
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
}

// The CAD of CEF §5 on SmallRational is the mpq_rational CAD: every M_k (equations, point, basis),
// c, consistency, solution rank, and the reduced equations (5.12) — or an Overflow (then solve
// recomputes in mpq).
RC_GTEST_PROP(SmallRational, ReferenceCadIsTheMpqCad, ()) {
  const ref::LinearSystem<Q> s = any_system();
  const auto small = [](const Q& q) { return S::from(q); };
  try {
    const ref::LinearSystem<S> t{{s.d.n, ref::Subspace<S>::span(lift_matrix<Q, S>(s.d.d.basis(), small))},
                                 lift_matrix<Q, S>(s.hessian, small),
                                 [&] {
                                   std::vector<S> g;
                                   for (const Q& x : s.gradient) g.push_back(S::from(x));
                                   return g;
                                 }(),
                                 S::from(s.constant)};
    const ref::CadResult<S> a = ref::constraint_tower(t);
    const ref::CadResult<Q> b = ref::constraint_tower(s);
    RC_ASSERT(a.tower.size() == b.tower.size());
    RC_ASSERT(a.consistent == b.consistent);
    RC_ASSERT(a.steps == b.steps);
    for (std::size_t k = 0; k < a.tower.size(); ++k) {
      RC_ASSERT(value(a.tower[k].equations) == b.tower[k].equations);
      RC_ASSERT(a.tower[k].m.empty == b.tower[k].m.empty);
      if (b.tower[k].m.empty) continue;
      RC_ASSERT(value(a.tower[k].m.direction.basis()) == b.tower[k].m.direction.basis());
      for (std::size_t i = 0; i < b.tower[k].m.point.size(); ++i) RC_ASSERT(a.tower[k].m.point[i].value() == b.tower[k].m.point[i]);
    }
    if (!b.consistent) return;
    RC_ASSERT(a.solution_rank == b.solution_rank);
    const ref::ReducedEquations<S> ra = ref::reduced_equations(t, a);
    const ref::ReducedEquations<Q> rb = ref::reduced_equations(s, b);
    RC_ASSERT(ra.coords == rb.coords);
    RC_ASSERT(value(ra.f_matrix) == rb.f_matrix);
    RC_ASSERT(value(ra.g) == rb.g);
    for (std::size_t i = 0; i < rb.f.size(); ++i) RC_ASSERT(ra.f[i].value() == rb.f[i]);
    RC_CLASSIFY(true, "fits in 64 bits");
  } catch (const ref::Overflow&) {
    RC_CLASSIFY(true, "overflow: solve recomputes in mpq");
  }
}
