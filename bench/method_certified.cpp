#include "dcad/certified/ball.hpp"
#include "dcad/reference/small_rational.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

/// What `dcad solve --backend certified` does: exact in machine words (N ≤ kSmallFirstUpTo), else
/// or on Overflow the reference in ball arithmetic, exactly recomputed (mpq) on an uncertain test.
Outcome run_certified(const families::Instance& in) {
  using certified::Ball;
  if (in.n() <= reference::kSmallFirstUpTo) {
    try {
      Outcome o = run_small(in);  // the reference's own first tier
      o.machine_words = true;
      return o;
    } catch (const reference::Overflow&) {
    }
  }
  try {
    return run_generic<Ball>(in, [](const families::Q& q) { return Ball::enclosing(q); }, [](const Ball& b) { return b.mid(); });
  } catch (const certified::Uncertain&) {
    Outcome o = run_mpq(in);
    o.recomputed = true;
    return o;
  }
}

}  // namespace dcad::bench
