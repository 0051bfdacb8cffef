#include "method_generic.hpp"

#include <boost/multiprecision/cpp_bin_float.hpp>

namespace dcad::bench {

Outcome run_bf50(const families::Instance& in) {
  using F = boost::multiprecision::cpp_bin_float_50;
  return run_approx<F>(in, F("1e-40"));
}

}  // namespace dcad::bench
