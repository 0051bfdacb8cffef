// The reference pipelines in ball arithmetic (the one translation unit that instantiates them on
// certified::Ball): every zero test proved, or certified::Uncertain.
#include "dcad/certified/numbers.hpp"
#include "dcad/reference/pipeline/circuit.hpp"

namespace dcad::certified {

dcad::Solution<Ball> solve_linear_balls(const io::CaseFile& c, const Parts& parts) {
  return reference::pipeline::solve_linear<Ball>(c, parts);
}

dcad::Solution<Ball> solve_lc_balls(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts) {
  return reference::pipeline::solve_lc<Ball>(deck, c.variables, c.coordinates, parts);
}

}  // namespace dcad::certified
