#include "dcad/reference/small_rational.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

/// What `dcad solve --backend reference` does: the CAD on SmallRational, on WideRational if a number
/// outgrows 64 bits, on FLINT's fmpq if it outgrows 128 (small_rational.hpp, fmpq.hpp: the same
/// exact arithmetic either way).
Outcome run_reference(const families::Instance& in) {
  try {
    return run_small(in);
  } catch (const reference::Overflow&) {
    return run_fmpq(in);
  }
}

Outcome run_small(const families::Instance& in) {
  using Q = families::Q;
  using S = reference::SmallRational;
  using W = reference::WideRational;
  try {
    return run_generic<S>(
        in, [](const Q& q) { return S::from(q); }, [](const S& s) { return s.value().convert_to<double>(); });
  } catch (const reference::Overflow&) {
    return run_generic<W>(
        in, [](const Q& q) { return W::from(q); }, [](const W& s) { return s.value().convert_to<double>(); });
  }
}

Outcome run_mpq(const families::Instance& in) {
  using Q = families::Q;
  return run_generic<Q>(
      in, [](const Q& q) { return q; }, [](const Q& q) { return q.convert_to<double>(); });
}

}  // namespace dcad::bench
