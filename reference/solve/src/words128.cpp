// The reference pipelines on WideRational (128-bit words): the second run of the machine-word tier,
// when a number outgrew 64 bits (words64.cpp).
#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/solve.hpp"

namespace dcad::reference::pipeline {

namespace {
Rational value(const WideRational& q) { return q.value(); }
}  // namespace

Solution solve_linear_wide(const io::CaseFile& c, const Parts& parts) {
  return map_numbers<Rational>(solve_linear<WideRational>(c, parts), value);
}

Solution solve_lc_wide(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts) {
  return map_numbers<Rational>(solve_lc<WideRational>(deck, c.variables, c.coordinates, parts), value);
}

}  // namespace dcad::reference::pipeline
