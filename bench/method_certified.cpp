#include "dcad/reference/small_rational.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

/// What `dcad solve --backend certified` does (dcad/certified/cascade.hpp): exact in machine words,
/// recomputed in FLINT's fmpq when a number outgrows 128 bits.
Outcome run_certified(const families::Instance& in) {
  try {
    Outcome o = run_small(in);  // the reference's own first tier
    o.machine_words = true;
    return o;
  } catch (const reference::Overflow&) {
  }
  Outcome o = run_fmpq(in);
  o.recomputed = true;
  return o;
}

}  // namespace dcad::bench
