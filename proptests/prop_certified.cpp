// The certified route (issue 6): the reference's algorithms in ball arithmetic.
//   * Lemma (ball.hpp): every Ball operation encloses the exact result of the exact operands, and
//     a zero test that answers, answers right.  Checked against mpq on random straight-line programs
//     mixing dyadic, non-dyadic and non-representable rationals (1 + 10^-17).
//   * Theorem (by induction over the branches, ball.hpp): a ball run that finishes has the exact
//     run's discrete output.  Checked on every family of families.hpp against the planted answer
//     (or the reference where nothing is planted); with the fallback, certified never disagrees.
//   * Not too tight: on nondegenerate data every decision is "nonzero" and balls certify all of
//     them (no needless fallback), even with non-dyadic entries.
//   * Input rounding: an input that double cannot represent decides exactly, not as rounded.
#include "convert.hpp"
#include "dcad/fast/cad.hpp"
#include "dcad/certified/ball.hpp"
#include "dcad/certified/cad.hpp"
#include "dcad/reference/cad.hpp"
#include "families.hpp"
#include "gen.hpp"
#include "tally.hpp"

#include <functional>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

namespace dcad::test {
namespace {

using certified::Ball;
using certified::Uncertain;
namespace fam = dcad::families;

bool encloses(const Ball& b, const Q& exact) { return abs(exact - Q(b.mid())) <= Q(b.rad()); }

/// A random rational of one of the kinds that matter: small integers, dyadic, p/q, 1 ± 10^-k.
Q some_rational() {
  switch (*rc::gen::inRange(0, 4)) {
    case 0: return Q(*rc::gen::inRange(-9, 10));
    case 1: return Q(*rc::gen::inRange(-99, 100)) / Q(1 << *rc::gen::inRange(0, 20));
    case 2: return Q(*rc::gen::inRange(-99, 100)) / Q(*rc::gen::inRange(1, 50));
    default: {
      Q t = 1;
      for (int i = *rc::gen::inRange(1, 25); i > 0; --i) t /= 10;
      return Q(*rc::gen::element(-1, 1)) + t * Q(*rc::gen::element(-3, 1, 7));
    }
  }
}

RC_GTEST_PROP(Ball, EnclosesTheExactValueAndZeroTestsAnswerRight, ()) {
  std::vector<Q> exact;
  std::vector<Ball> ball;
  for (int i = 0; i < 4; ++i) {
    exact.push_back(some_rational());
    ball.push_back(Ball::enclosing(exact.back()));
    RC_ASSERT(encloses(ball.back(), exact.back()));
    RC_ASSERT(ball.back().exact() == (Q(ball.back().mid()) == exact.back()));
  }
  const int steps = *rc::gen::inRange(1, 40);
  for (int s = 0; s < steps; ++s) {
    const std::size_t i = *rc::gen::inRange<std::size_t>(0, exact.size()), j = *rc::gen::inRange<std::size_t>(0, exact.size());
    const int op = *rc::gen::inRange(0, 4);
    try {
      Ball b;
      Q q;
      switch (op) {
        case 0: b = ball[i] + ball[j], q = exact[i] + exact[j]; break;
        case 1: b = ball[i] - ball[j], q = exact[i] - exact[j]; break;
        case 2: b = ball[i] * ball[j], q = exact[i] * exact[j]; break;
        default: b = ball[i] / ball[j], q = exact[i] / exact[j]; break;
      }
      RC_ASSERT(encloses(b, q));
      exact.push_back(q);
      ball.push_back(b);
    } catch (const Uncertain&) {  // division by a ball containing 0, or out of range: no claim made
    }
  }
  for (std::size_t i = 0; i < exact.size(); ++i) {
    for (std::size_t j = 0; j < exact.size(); ++j) {
      try {
        RC_ASSERT((ball[i] == ball[j]) == (exact[i] == exact[j]));
      } catch (const Uncertain&) {
        RC_ASSERT(abs(Q(ball[i].mid()) - Q(ball[j].mid())) <= Q(ball[i].rad()) + Q(ball[j].rad()));  // honest doubt
      }
    }
  }
}

struct Discrete {
  std::vector<long> dims;
  long solution_rank = 0;
  bool consistent = true;
  bool operator==(const Discrete& o) const { return dims == o.dims && solution_rank == o.solution_rank && consistent == o.consistent; }
};

template <class T>
Discrete discrete(const reference::CadResult<T>& r) {
  Discrete d;
  for (const auto& st : r.tower) d.dims.push_back(st.dim());
  d.solution_rank = static_cast<long>(r.solution_rank);
  d.consistent = r.consistent;
  return d;
}

/// The ball run, or nothing if some zero test was undecidable.
std::optional<Discrete> ball_run(const fam::Instance& in) {
  try {
    return discrete(reference::constraint_tower(fam::system_over<Ball>(in, [](const Q& q) { return Ball::enclosing(q); })));
  } catch (const Uncertain&) {
    return std::nullopt;
  }
}

Discrete exact_run(const fam::Instance& in) {
  return discrete(reference::constraint_tower(fam::system_over<Q>(in, [](const Q& q) { return q; })));
}

fam::Instance any_instance(std::mt19937_64& rng) {
  switch (*rc::gen::inRange(0, 5)) {
    case 0: return fam::graded(std::pow(10.0, *rc::gen::inRange(2, 17)), rng);
    case 1: return fam::perturbed(*rc::gen::inRange(10, 61), rng);
    case 2: return fam::tower(*rc::gen::inRange<Index>(1, 5), rng);
    case 3: return fam::lc(*rc::gen::inRange(0, 16), rng);
    default: return fam::cancel(*rc::gen::inRange(1, 17), rng);
  }
}

RC_GTEST_PROP(Certified, NeverDisagreesWithTheExactAnswerOnAnyFamily, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const fam::Instance in = any_instance(rng);
  const std::optional<Discrete> b = ball_run(in);
  Discrete truth;
  if (in.planted) {
    truth.dims = in.dims;
    truth.solution_rank = in.solution_rank;
  } else {
    truth = exact_run(in);
  }
  RC_TAG(in.family);
  RC_TAG(b ? "certified in floating point" : "recomputed exactly");
  RC_ASSERT(!tally("certified (" + in.family + ")", b.has_value(), b && *b == truth));
  if (in.planted && *rc::gen::inRange(0, 4) == 0) RC_ASSERT(exact_run(in) == truth);  // the generator's own claim
}

// The library entry point (dcad/certified/cad.hpp): whichever route it takes — 64- or 128-bit words,
// balls, mpq — its discrete answers are the exact reference's (the induction of ball.hpp, and
// SmallRational, WideRational = mpq while they fit); where every number fits in 64 bits it takes the
// first route, and any later route says why the cheaper ones gave up.  A route that
// answered with the wrong scalar's decisions (e.g. a ball answer taken although Uncertain) fails it.
RC_GTEST_PROP(Certified, LibraryTowerIsTheExactTower, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const fam::Instance in = any_instance(rng);
  const reference::LinearSystem<Q> s = fam::system_over<Q>(in, [](const Q& q) { return q; });
  const certified::CertifiedTower t = certified::constraint_tower(s);
  const Discrete truth = exact_run(in);
  RC_TAG(in.family + ": " + certified::route_name(t.route) + (t.word_bits ? " (" + std::to_string(t.word_bits) + " bits)" : ""));
  RC_ASSERT(t.dims == truth.dims);
  RC_ASSERT(static_cast<long>(t.solution_rank) == truth.solution_rank);
  RC_ASSERT(t.consistent == truth.consistent);
  RC_ASSERT(t.steps + 1 == t.dims.size());
  RC_ASSERT((t.route == certified::Route::machine_words) == (t.word_bits == 64 || t.word_bits == 128));
  RC_ASSERT((t.route == certified::Route::machine_words && t.word_bits == 64) == t.why.empty());  // else: why it gave up
}

/// A ball and its exact value side by side: every zero test is put to both.  The exact answer
/// drives the run; the ball's answer is audited against it.
struct Audited {
  static constexpr const char* zero_test = "exact, with the ball's answer audited";
  Ball b;
  Q q;
  bool lost = false;  ///< a ball operation refused (division by a ball containing 0, range)
  struct Counts {
    long certain = 0, wrong = 0, uncertain_zero = 0, uncertain_nonzero = 0;
  };
  static Counts& counts() {
    static Counts c;
    return c;
  }
  Audited() = default;
  Audited(int k) : b(k), q(k) {}  // NOLINT
  template <class F, class G>
  static Audited apply(const Audited& x, const Audited& y, F ball_op, G exact_op) {
    Audited r;
    r.q = exact_op(x.q, y.q);
    r.lost = x.lost || y.lost;
    if (!r.lost) try {
        r.b = ball_op(x.b, y.b);
      } catch (const Uncertain&) {
        r.lost = true;
      }
    return r;
  }
  Audited operator-() const {
    Audited r = *this;
    r.q = -q;
    if (!lost) r.b = -b;
    return r;
  }
  friend Audited operator+(const Audited& x, const Audited& y) { return apply(x, y, std::plus<>(), std::plus<>()); }
  friend Audited operator-(const Audited& x, const Audited& y) { return apply(x, y, std::minus<>(), std::minus<>()); }
  friend Audited operator*(const Audited& x, const Audited& y) { return apply(x, y, std::multiplies<>(), std::multiplies<>()); }
  friend Audited operator/(const Audited& x, const Audited& y) { return apply(x, y, std::divides<>(), std::divides<>()); }
  Audited& operator+=(const Audited& o) { return *this = *this + o; }
  Audited& operator-=(const Audited& o) { return *this = *this - o; }
  Audited& operator*=(const Audited& o) { return *this = *this * o; }
  Audited& operator/=(const Audited& o) { return *this = *this / o; }
  friend bool operator==(const Audited& x, const Audited& y) {
    const bool truth = x.q == y.q;
    Counts& c = counts();
    try {
      if (x.lost || y.lost) throw Uncertain("lost");
      const bool ball = x.b == y.b;
      ++c.certain;
      c.wrong += ball != truth;
    } catch (const Uncertain&) {
      ++(truth ? c.uncertain_zero : c.uncertain_nonzero);
    }
    return truth;
  }
  friend bool operator!=(const Audited& x, const Audited& y) { return !(x == y); }
  friend bool known_zero(const Audited& x) { return !x.lost && known_zero(x.b); }
  friend double pivot_weight(const Audited& x) { return x.lost ? 0.0 : pivot_weight(x.b); }
};

Audited::Counts audit(const fam::Instance& in) {
  Audited::counts() = {};
  const auto lift = [](const Q& q) {
    Audited a;
    a.q = q;
    a.b = Ball::enclosing(q);
    return a;
  };
  reference::constraint_tower(fam::system_over<Audited>(in, lift));
  return Audited::counts();
}

/// Every single zero test of the CAD, on every family: a ball that answers answers right
/// (not too loose).  Counted: the undecided tests whose exact answer is "nonzero" — the needless
/// fallbacks a tighter bound could avoid.
RC_GTEST_PROP(Certified, EveryBallAnswerIsTheExactAnswer, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const fam::Instance in = any_instance(rng);
  const Audited::Counts c = audit(in);
  RC_ASSERT(c.wrong == 0L);
  tally("zero tests, ball vs exact (" + in.family + ")", true, true);
  tally("needless: undecided but exactly nonzero (" + in.family + ")", c.uncertain_nonzero == 0, true);
}

/// Symplectic ω = Aᵀ J A with non-dyadic A (entries p/q, diagonally dominant), E = ½ xᵀ H x + g·x
/// with H tridiagonal (1, 1/3): nondegenerate, well conditioned, not representable in double.
fam::Instance nondegenerate_instance() {
  const Index m = pick_size(1, 4), n = 2 * m;
  QM a = QM::identity(n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j)
      if (i != j) a(i, j) = Q(*rc::gen::inRange(-3, 4)) / Q(*rc::gen::inRange(2, 12)) / Q(static_cast<long>(4 * n));
  fam::Instance in;
  in.family = "nondegenerate";
  in.omega = pull_back(canonical_form(n, m), a);
  in.hessian = QM::identity(n);
  for (Index i = 0; i + 1 < n; ++i) in.hessian(i, i + 1) = in.hessian(i + 1, i) = Q(1) / Q(3);
  in.gradient = integer_vector(n, 2);
  return in;
}

/// Not too tight, where it can be: on well-conditioned nondegenerate data the balls certify every
/// test whose exact answer is "nonzero" (a zero needs an exact certificate whatever the bound).
/// On the long towers they do not always: the radii of interval Gauss–Jordan grow with the depth
/// of the computation (measured in EveryBallAnswerIsTheExactAnswer's tally, see the README).
RC_GTEST_PROP(Certified, NoNeedlessFallbackOnNondegenerateData, ()) {
  const Audited::Counts c = audit(nondegenerate_instance());
  RC_ASSERT(c.wrong == 0L);
  RC_ASSERT(c.uncertain_nonzero == 0L);
}

/// The per-operation bound is tight: from exact operands, the radius is the exact rounding error
/// (error-free transformations) up to the factor 1 + 2^-45 and 2^-1000.
RC_GTEST_PROP(Ball, RadiusOfOneOperationIsTheRoundingError, ()) {
  const Ball a = Ball::enclosing(Q(*rc::gen::inRange(-999, 1000)) / Q(1 << *rc::gen::inRange(0, 30)));
  const Ball b = Ball::enclosing(Q(*rc::gen::inRange(1, 1000)) / Q(1 << *rc::gen::inRange(0, 30)));
  const Q qa(a.mid()), qb(b.mid());
  const std::vector<std::pair<Ball, Q>> ops = {{a + b, Q(qa + qb)}, {a * b, Q(qa * qb)}, {a / b, Q(qa / qb)}};
  for (const auto& [ball, exact] : ops) {
    const Q err = abs(exact - Q(ball.mid()));
    RC_ASSERT(Q(ball.rad()) >= err);
    RC_ASSERT(Q(ball.rad()) <= err * (Q(1) + Q(1) / Q(1L << 44)) + Q(std::ldexp(1.0, -999)));
  }
}

TEST(Certified, InputRoundingIsDecidedForTheExactInput) {
  // L = ½ vᵀ A v, A = [[1, 1], [1, 1 + 10^-17]] (cases/input-rounding.json): regular exactly, singular in double.
  fam::Instance in;
  in.pontryagin = true;
  in.circuit.n = 2;
  in.circuit.k = QM(0, 2);
  in.circuit.vv = QM::from_rows({{Q(1), Q(1)}, {Q(1), reference::parse_rational("1.00000000000000001")}}, 2);
  in.circuit.qq = in.circuit.qv = QM(2, 2);
  in.circuit.q = in.circuit.v = {Q(0), Q(0)};
  EXPECT_FALSE(ball_run(in).has_value());  // undecidable in floating point: the ball of A_22 has radius > 0
  EXPECT_EQ(exact_run(in).solution_rank, 0);
  in.circuit.vv(1, 1) = Q(1);  // what double sees
  EXPECT_EQ(exact_run(in).solution_rank, 1);
  ASSERT_TRUE(ball_run(in).has_value());  // exact data: the balls stay points and decide
  EXPECT_EQ(ball_run(in)->solution_rank, 1);
}

}  // namespace
}  // namespace dcad::test
