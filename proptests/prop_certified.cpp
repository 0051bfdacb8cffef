// The certified tier (issues 6, 14, 26): the reference's own algorithm in exact machine words, then in
// FLINT's fmpq (dcad/certified/cascade.hpp).
//   * Theorem (small_rational.hpp, fmpq.hpp): both are mpq_rational's exact arithmetic, so whichever
//     route the cascade takes, its discrete answers are the exact reference's.  Checked on every family
//     of families.hpp (planted answers, and the reference where nothing is planted), including the
//     perturbed family beyond 128 bits, where the cascade must reach fmpq and say why.
//   * Input rounding: an input that double cannot represent is decided exactly, not as rounded.
//   * Krawczyk's test (zero_enclosure.hpp): a proved box holds the zero.  Checked on planted rational
//     zeros of random quadratic systems (the exact zero inside the ball, compared in rationals), and on
//     sin against the C library's long double; a double zero (F' singular there) is never "proved".
// (The cascade's former tier of ball arithmetic lost the measurement of issue 26 and left the product;
// it is bench/ball.hpp now.)
#include "dcad/certified/cad.hpp"
#include "dcad/certified/zero_enclosure.hpp"
#include "dcad/reference/cad.hpp"
#include "families.hpp"
#include "gen.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>

namespace dcad::test {
namespace {

namespace fam = dcad::families;

struct Discrete {
  std::vector<long> dims;
  long solution_rank = 0;
  bool consistent = true;
  bool operator==(const Discrete& o) const {
    return dims == o.dims && solution_rank == o.solution_rank && consistent == o.consistent;
  }
};

Discrete exact_run(const fam::Instance& in) {
  const reference::CadResult<Q> r = reference::constraint_tower(fam::system_over<Q>(in, [](const Q& q) { return q; }));
  Discrete d;
  for (const auto& st : r.tower) d.dims.push_back(st.dim());
  d.solution_rank = static_cast<long>(r.solution_rank);
  d.consistent = r.consistent;
  return d;
}

Discrete certified_run(const fam::Instance& in) {
  const certified::CertifiedTower t =
      certified::constraint_tower(fam::system_over<Q>(in, [](const Q& q) { return q; }));
  return {t.dims, static_cast<long>(t.solution_rank), t.consistent};
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

// The library entry point (dcad/certified/cad.hpp): whichever route it takes — 64- or 128-bit words,
// fmpq — its discrete answers are the exact reference's (and the planted ones); where every number
// fits in 64 bits it takes the first route, and a later route says why the cheaper ones gave up.
RC_GTEST_PROP(Certified, LibraryTowerIsTheExactTower, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  const fam::Instance in = any_instance(rng);
  const reference::LinearSystem<Q> s = fam::system_over<Q>(in, [](const Q& q) { return q; });
  const certified::CertifiedTower t = certified::constraint_tower(s);
  const Discrete truth = exact_run(in);
  RC_TAG(in.family + ": " + certified::tier_name(t.tier) +
         (t.word_bits ? " (" + std::to_string(t.word_bits) + " bits)" : ""));
  RC_ASSERT(t.dims == truth.dims);
  RC_ASSERT(static_cast<long>(t.solution_rank) == truth.solution_rank);
  RC_ASSERT(t.consistent == truth.consistent);
  if (in.planted) RC_ASSERT(t.dims == in.dims && static_cast<long>(t.solution_rank) == in.solution_rank);
  RC_ASSERT(t.steps + 1 == t.dims.size());
  RC_ASSERT((t.tier == certified::Tier::machine_words) == (t.word_bits == 64 || t.word_bits == 128));
  RC_ASSERT((t.tier == certified::Tier::machine_words && t.word_bits == 64) == t.why.empty());  // else: why it gave up
}

// Beyond 128 bits, the cascade reaches fmpq, says why, and still answers exactly: the perturbed family
// (ω = Sᵀ (J ⊕ 2^-k e_a∧e_b ⊕ 0) S, E = 0) with ω scaled by 3^90 / 7^d — a nonzero scalar changes
// neither ker ω nor the tower, so the planted answer stands, and every entry now outgrows 128 bits.
RC_GTEST_PROP(Certified, BeyondTheWordsTheCascadeIsExactInFmpq, ()) {
  std::mt19937_64 rng(*rc::gen::arbitrary<std::uint64_t>());
  fam::Instance in = fam::perturbed(*rc::gen::inRange(10, 61), rng, *rc::gen::inRange<Index>(6, 13));
  const Q scale = Q(boost::multiprecision::pow(boost::multiprecision::mpz_int(3), 90)) /
                  Q(boost::multiprecision::pow(boost::multiprecision::mpz_int(7), *rc::gen::inRange(0, 4)));
  for (Index i = 0; i < in.omega.rows(); ++i)
    for (Index j = 0; j < in.omega.cols(); ++j) in.omega(i, j) *= scale;
  const certified::CertifiedTower t =
      certified::constraint_tower(fam::system_over<Q>(in, [](const Q& q) { return q; }));
  RC_ASSERT(t.tier == certified::Tier::fmpq);
  RC_ASSERT(t.dims == in.dims);
  RC_ASSERT(static_cast<long>(t.solution_rank) == in.solution_rank);
  if (t.tier == certified::Tier::fmpq) {
    RC_ASSERT(t.word_bits == 0);
    RC_ASSERT(t.why.find("128-bit words") != std::string::npos);
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
  EXPECT_EQ(exact_run(in).solution_rank, 0);
  EXPECT_EQ(certified_run(in), exact_run(in));
  in.circuit.vv(1, 1) = Q(1);  // what double sees
  EXPECT_EQ(exact_run(in).solution_rank, 1);
  EXPECT_EQ(certified_run(in), exact_run(in));
}

namespace ex = reference::expr;

/// The exact rational q lies in the ball [mid − rad, mid + rad] (compared exactly).
bool in_ball(const Q& q, const certified::Enclosure& e) {
  if (!std::isfinite(e.mid) || !std::isfinite(e.rad)) return false;
  return Q(e.mid) - Q(e.rad) <= q && q <= Q(e.mid) + Q(e.rad);
}

/// ∂/∂x_j of every equation over m variables.
std::vector<std::vector<ex::Expr>> gradients_of(const std::vector<ex::Expr>& f, std::size_t m) {
  std::vector<std::vector<ex::Expr>> g;
  for (const ex::Expr& e : f) {
    g.emplace_back();
    for (std::size_t j = 0; j < m; ++j) g.back().push_back(ex::diff(e, j));
  }
  return g;
}

RC_GTEST_PROP(Certified, KrawczykBallHoldsThePlantedZero, ()) {
  // F_k(x) = Σ_j a_kj (x_j − z_j) + b_k (x_i − z_i)(x_l − z_l): zero at the planted rational z; some
  // coordinates given at z exactly, the start z + 1e-9 noise.  Proved ⇒ every ball holds z exactly.
  const std::size_t m = static_cast<std::size_t>(*rc::gen::inRange(2, 6)),
                    k = static_cast<std::size_t>(*rc::gen::inRange<int>(1, static_cast<int>(m)));
  std::vector<Q> z(m);
  for (Q& q : z) q = Q(*rc::gen::inRange(-50, 51), *rc::gen::inRange(1, 30));
  std::vector<ex::Expr> f;
  for (std::size_t r = 0; r < k; ++r) {
    ex::Expr e = ex::number(0);
    for (std::size_t j = 0; j < m; ++j)
      e = ex::add(e, ex::mul(ex::number(Q(*rc::gen::inRange(-9, 10), *rc::gen::inRange(1, 5))),
                             ex::sub(ex::variable(j), ex::number(z[j]))));
    const std::size_t i = *rc::gen::inRange<std::size_t>(0, m), l = *rc::gen::inRange<std::size_t>(0, m);
    e = ex::add(e, ex::mul(ex::number(*rc::gen::inRange(-3, 4)), ex::mul(ex::sub(ex::variable(i), ex::number(z[i])),
                                                                         ex::sub(ex::variable(l), ex::number(z[l])))));
    f.push_back(e);
  }
  certified::ZeroProblem p;
  p.equations = f;
  p.gradients = gradients_of(f, m);
  p.given.resize(m);  // k unknowns at random places, the rest given at z: z is the zero near the start
  std::vector<std::size_t> order(m);
  for (std::size_t j = 0; j < m; ++j) order[j] = j;
  for (std::size_t j = m - 1; j > 0; --j) std::swap(order[j], order[*rc::gen::inRange<std::size_t>(0, j + 1)]);
  for (std::size_t j = k; j < m; ++j) p.given[order[j]] = z[order[j]];
  for (std::size_t j = 0; j < m; ++j)
    p.approx.push_back(z[j].convert_to<double>() * (1 + 1e-9 * *rc::gen::inRange(-5, 6)));
  p.outputs = f;
  const certified::ZeroEnclosure e = certified::enclose_zero(p);
  RC_TAG(e.proved ? "proved" : "not proved");
  if (!e.proved) return;  // a random a may be singular: no claim, nothing to check
  RC_ASSERT(e.solved.size() == k);
  for (const certified::Enclosure& o : e.outputs) RC_ASSERT(in_ball(Q(0), o));
  RC_TAG(e.given_moved ? "given values moved" : "given values held");
  if (e.given_moved) return;  // the unknowns' Jacobian was singular: another zero, with given values solved for
  for (std::size_t j = 0; j < m; ++j) RC_ASSERT(in_ball(z[j], e.values[j]));
}

TEST(Certified, KrawczykBallsOfSinAndADoubleZero) {
  // y = sin x at x = 7/10 given: the ball holds sin(0.7) (long double libm, independent of Arb).
  certified::ZeroProblem p;
  p.equations = {ex::sub(ex::variable(1), ex::sin(ex::variable(0)))};
  p.gradients = gradients_of(p.equations, 2);
  p.given = {Q(7, 10), std::nullopt};
  p.approx = {0.7, 0.64};
  p.nonzero = {ex::cos(ex::variable(0))};
  p.outputs = {ex::mul(ex::variable(1), ex::variable(1))};
  certified::ZeroEnclosure e = certified::enclose_zero(p);
  ASSERT_TRUE(e.proved) << e.why;
  const long double s = std::sin(0.7L);
  EXPECT_LE(std::fabs(static_cast<long double>(e.values[1].mid) - s),
            static_cast<long double>(e.values[1].rad) + 1e-18L);
  EXPECT_LE(e.values[1].rad, 1e-16);
  EXPECT_LE(std::fabs(static_cast<long double>(e.outputs[0].mid) - s * s),
            static_cast<long double>(e.outputs[0].rad) + 1e-18L);
  // a condition that vanishes at the zero is not proved nonzero: not proved
  p.nonzero = {ex::sub(ex::variable(0), ex::number(Q(7, 10)))};
  EXPECT_FALSE(certified::enclose_zero(p).proved);
  // y² = 0: F' = 2y vanishes at the zero; no box passes Krawczyk's test
  certified::ZeroProblem d;
  d.equations = {ex::mul(ex::variable(0), ex::variable(0))};
  d.gradients = gradients_of(d.equations, 1);
  d.given = {std::nullopt};
  d.approx = {1e-9};
  EXPECT_FALSE(certified::enclose_zero(d).proved);
}

}  // namespace
}  // namespace dcad::test
