// The reference pipeline in exact machine words: on SmallRational (64-bit words), and on WideRational
// (128-bit words) when a number outgrows 64 bits — the same exact arithmetic as mpq_rational, number
// for number, while every number fits (small_rational.hpp); reference::Overflow when 128 bits do not
// hold one, and solve_reference then recomputes on mpq_rational.  The two instantiations of
// solve_exact live in solve_words.hpp's users: this file (64) and solve_wide.cpp (128).
#include "solve_words.hpp"

namespace dcad::cli {

SolveReport solve_small(const io::CaseFile& c, const Parts& parts) {
  try {
    SolveReport r = solve_exact<reference::SmallRational>(c, parts);
    r.word_bits = 64;
    return r;
  } catch (const reference::Overflow&) {
    return solve_wide(c, parts);
  }
}

SolveReport solve_circuit_small(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  try {
    SolveReport r = solve_circuit_exact<reference::SmallRational>(n, c, parts);
    r.word_bits = 64;
    return r;
  } catch (const reference::Overflow&) {
    return solve_circuit_wide(n, c, parts);
  }
}

}  // namespace dcad::cli
