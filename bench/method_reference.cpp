#include "method_generic.hpp"

namespace dcad::bench {

Outcome run_reference(const families::Instance& in) {
  using Q = families::Q;
  return run_generic<Q>(in, [](const Q& q) { return q; }, [](const Q& q) { return q.convert_to<double>(); });
}

}  // namespace dcad::bench
