// The certified cascade, written once (issue 26): the reference's own algorithm on ever safer scalars,
// cheapest first —
//   1. exact machine words (64-bit, then 128-bit rationals): the exact run, or reference::Overflow;
//   2. balls (ball.hpp): every zero test proved, or certified::Uncertain;
//   3. FLINT's fmpq (fmpq.hpp): the exact run, as the reference's own last tier.
// The tiers are what the sweep measured best (bench/results/summary.md, "exact tier alone", issue 26):
// words 1.9–2.6× faster than fmpq on every family (so they go first at every size: above 64 variables
// they beat the balls too), fmpq 5.7–6.1× faster than mpq_rational and 1.4–4.6× faster than FLINT's
// fraction-free fmpq_mat_rref, the hand-written balls 1.1–1.9× faster than Arb's arb_t.
// A tier that finishes took every branch the exact run takes, so its discrete answers are the exact
// ones whichever tier gave them (small_rational.hpp, ball.hpp give the proofs).  Used by
// certified::constraint_tower (cad.hpp) and certified::solve (solve.hpp).
#pragma once

#include "dcad/certified/ball.hpp"
#include "dcad/reference/small_rational.hpp"

#include <optional>
#include <string>

namespace dcad::certified {

enum class Route { machine_words, balls, exact };

inline const char* route_name(Route r) {
  return r == Route::machine_words ? "exact in machine words" : r == Route::balls ? "ball arithmetic" : "exact (fmpq)";
}

template <class R>
struct Cascaded {
  R result;
  Route route = Route::exact;
  int word_bits = 0;        ///< machine_words: 64, or 128 when a number outgrew 64 bits
  BallCounts counts;        ///< the balls' zero tests (up to the one they could not decide, if any)
  std::string overflow;     ///< why the words gave up ("" if they were not tried or did not)
  std::string uncertain;    ///< why the balls gave up
};

/// `words(bits)`: the run in 64-, then 128-bit words (sets bits; throws reference::Overflow);
/// `balls()`: the run in ball arithmetic (throws Uncertain); `exact()`: the run in fmpq.
template <class R, class Words, class Balls, class Exact>
Cascaded<R> cascade(Words words, Balls balls, Exact exact) {
  Cascaded<R> out;
  try {
    out.result = words(out.word_bits);
    out.route = Route::machine_words;
    return out;
  } catch (const reference::Overflow& e) {
    out.overflow = e.what();
  }
  try {
    Ball::Counting counting(out.counts);
    out.result = balls();
    out.route = Route::balls;
    return out;
  } catch (const Uncertain& e) {
    out.uncertain = e.what();
  }
  out.result = exact();
  out.route = Route::exact;
  return out;
}

}  // namespace dcad::certified
