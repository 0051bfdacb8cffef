// The pipeline on fmpq with every RREF by FLINT's own elimination (fmpq_mat_rref: fraction-free on the
// cleared integer matrix).  The RREF of a matrix is unique, so the answers are the reference's; only the
// route to each RREF differs.  Measured against the literal Gauss–Jordan on fmpq (issue 26): it lost at
// every size of the sweep, so the product does not use it; it stays here so the measurement reruns.
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/matrix.hpp"

#include <flint/fmpq_mat.h>

namespace dcad::reference {

struct FlintElimination;
/// fmpq with its RREFs by FLINT (the overload of rref below, found by argument-dependent lookup).
using FlintFmpq = BasicFmpq<FlintElimination>;

/// rref of matrix.hpp, by fmpq_mat_rref: the same unique RREF and pivot columns.
inline Rref<FlintFmpq> rref(Matrix<FlintFmpq> m) {
  fmpq_mat_t a, b;
  fmpq_mat_init(a, static_cast<slong>(m.rows()), static_cast<slong>(m.cols()));
  fmpq_mat_init(b, static_cast<slong>(m.rows()), static_cast<slong>(m.cols()));
  for (Index i = 0; i < m.rows(); ++i)
    for (Index j = 0; j < m.cols(); ++j) fmpq_swap(fmpq_mat_entry(a, i, j), m(i, j).data());
  const slong r = fmpq_mat_rref(b, a);
  Rref<FlintFmpq> out;
  out.r = Matrix<FlintFmpq>(static_cast<Index>(r), m.cols());
  for (slong i = 0; i < r; ++i) {
    bool pivot = false;
    for (Index j = 0; j < m.cols(); ++j) {
      fmpq_swap(out.r(static_cast<Index>(i), j).data(), fmpq_mat_entry(b, i, j));
      if (!pivot && !fmpq_is_zero(out.r(static_cast<Index>(i), j).data())) {
        out.pivots.push_back(j);
        pivot = true;
      }
    }
  }
  fmpq_mat_clear(a);
  fmpq_mat_clear(b);
  return out;
}

}  // namespace dcad::reference

#include "method_generic.hpp"

namespace dcad::bench {

Outcome run_flint(const families::Instance& in) {
  using F = reference::FlintFmpq;
  return run_generic<F>(
      in, [](const families::Q& q) { return F::from(q); }, [](const F& f) { return f.value().convert_to<double>(); });
}

}  // namespace dcad::bench
