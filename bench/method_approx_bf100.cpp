#include "method_generic.hpp"

#include <boost/multiprecision/cpp_bin_float.hpp>

namespace dcad::bench {

Outcome run_bf100(const families::Instance& in) {
  using F = boost::multiprecision::cpp_bin_float_100;
  return run_approx<F>(in, F("1e-85"));
}

}  // namespace dcad::bench
