// The certified cascade, written once (issue 26): the reference's own algorithm on the cheaper exact
// scalar first —
//   1. exact machine words (64-bit, then 128-bit rationals): the exact run, or reference::Overflow;
//   2. FLINT's fmpq (fmpq.hpp): the exact run, as the reference's own last tier.
// Both are the exact arithmetic of mpq_rational, number for number (small_rational.hpp, fmpq.hpp), so
// every discrete answer and every printed number is the reference's, whichever tier gave it.  The tiers
// are what the sweep measured best (bench/results/summary.md, "exact tier alone", issue 26): words
// 1.9–2.6× faster than fmpq on every family (first at every size); fmpq 5.7–6.1× faster than
// mpq_rational there and 3.4–5.9× where the words overflow (bench_kernels CadBeyondWords; even with
// numbers of hundreds of digits, where GMP's gcds dominate, 0.87–0.98×), and 1.4–4.6× faster than
// FLINT's fraction-free fmpq_mat_rref.  A tier of ball
// arithmetic between them (hand-written, or Arb's, 1.1–1.9× slower) lost: where the words overflow,
// the balls decided none of 10^5 adversarial instances and none of the dense cases tried — a rank
// deficiency reached through inexact numbers is never provable in intervals — and only cost a run.
// Used by certified::constraint_tower (cad.hpp) and certified::solve (solve.hpp).
#pragma once

#include "dcad/reference/small_rational.hpp"

#include <string>

namespace dcad::certified {

enum class Tier { machine_words, fmpq };

inline const char* tier_name(Tier r) { return r == Tier::machine_words ? "exact in machine words" : "exact (fmpq)"; }

template <class R>
struct Cascaded {
  R result;
  Tier tier = Tier::fmpq;
  int word_bits = 0;     ///< machine_words: 64, or 128 when a number outgrew 64 bits; 0 on the other route
  std::string overflow;  ///< why the words gave up ("" if they did not)
};

/// `words(bits)`: the run in 64-, then 128-bit words (sets bits; throws reference::Overflow);
/// `exact()`: the run in fmpq.
template <class R, class Words, class Exact>
Cascaded<R> cascade(Words words, Exact exact) {
  Cascaded<R> out;
  try {
    out.result = words(out.word_bits);
    out.tier = Tier::machine_words;
    return out;
  } catch (const reference::Overflow& e) {
    out.overflow = e.what();
    out.word_bits = 0;
  }
  out.result = exact();
  out.tier = Tier::fmpq;
  return out;
}

}  // namespace dcad::certified
