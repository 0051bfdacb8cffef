#include "method_generic.hpp"

namespace dcad::bench {

Outcome run_naive(const families::Instance& in) {
  using F = double;
  return run_approx<F>(in, F(1e-9));
}

}  // namespace dcad::bench
