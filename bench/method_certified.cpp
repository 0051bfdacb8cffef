#include "dcad/certified/ball.hpp"
#include "dcad/reference/small_rational.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

/// What `dcad solve --backend certified` does (certified/cascade.hpp): exact in machine words, else
/// on Overflow the reference in ball arithmetic, exactly recomputed (fmpq) on an uncertain test.
Outcome run_certified(const families::Instance& in) {
  using certified::Ball;
  try {
    Outcome o = run_small(in);  // the reference's own first tier
    o.machine_words = true;
    return o;
  } catch (const reference::Overflow&) {
  }
  try {
    return run_generic<Ball>(in, [](const families::Q& q) { return Ball::enclosing(q); }, [](const Ball& b) { return b.mid(); });
  } catch (const certified::Uncertain&) {
    Outcome o = run_fmpq(in);
    o.recomputed = true;
    return o;
  }
}

}  // namespace dcad::bench
