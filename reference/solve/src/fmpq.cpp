// The reference pipelines on FLINT's fmpq (fmpq.hpp): when a number outgrows 128-bit words.  The same
// exact rationals as mpq_rational in lowest terms, so the same branches and the same printed numbers;
// measured 3.4–5.9× faster than mpq_rational where the words overflow (issue 26, bench/results/summary.md).
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/solve.hpp"

namespace dcad::reference::pipeline {

namespace {
Rational value(const Fmpq& q) { return q.value(); }
}  // namespace

Solution solve_linear_fmpq(const io::CaseFile& c, const Parts& parts) {
  return map_numbers<Rational>(solve_linear<Fmpq>(c, parts), value);
}

Solution solve_lc_fmpq(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts) {
  return map_numbers<Rational>(solve_lc<Fmpq>(deck, c.variables, c.coordinates, parts), value);
}

}  // namespace dcad::reference::pipeline
