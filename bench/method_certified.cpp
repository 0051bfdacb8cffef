#include "dcad/reference/ball.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

Outcome run_certified(const families::Instance& in) {
  using reference::Ball;
  try {
    return run_generic<Ball>(in, [](const families::Q& q) { return Ball::enclosing(q); }, [](const Ball& b) { return b.mid(); });
  } catch (const reference::Uncertain&) {
    Outcome o = run_reference(in);
    o.recomputed = true;
    return o;
  }
}

}  // namespace dcad::bench
