#include "dcad/reference/fmpq.hpp"
#include "method_generic.hpp"

namespace dcad::bench {

/// The reference's own algorithm (Gauss–Jordan) on FLINT's fmpq: an exact tier without overflow.
Outcome run_fmpq(const families::Instance& in) {
  using F = reference::Fmpq;
  return run_generic<F>(
      in, [](const families::Q& q) { return F::from(q); }, [](const F& f) { return f.value().convert_to<double>(); });
}

}  // namespace dcad::bench
