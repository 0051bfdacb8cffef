// The reference pipeline on WideRational (128-bit words): the second run of solve_small, when a number
// outgrew 64 bits (one translation unit per scalar: the pipeline's templates are heavy).
#include "solve_words.hpp"

namespace dcad::cli {

SolveReport solve_wide(const io::CaseFile& c, const Parts& parts) {
  SolveReport r = solve_exact<reference::WideRational>(c, parts);
  r.word_bits = 128;
  return r;
}

SolveReport solve_circuit_wide(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  SolveReport r = solve_circuit_exact<reference::WideRational>(n, c, parts);
  r.word_bits = 128;
  return r;
}

}  // namespace dcad::cli
