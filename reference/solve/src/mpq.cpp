// The reference pipelines on mpq_rational: when a number outgrows 128-bit words.
#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/solve.hpp"

namespace dcad::reference::pipeline {

Solution solve_linear_mpq(const io::CaseFile& c, const Parts& parts) { return solve_linear<Rational>(c, parts); }

Solution solve_lc_mpq(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts) {
  return solve_lc<Rational>(deck, c.variables, c.coordinates, parts);
}

}  // namespace dcad::reference::pipeline
