// The reference pipelines in exact machine words: SmallRational (64-bit), then WideRational (words128.cpp)
// when a number outgrows 64 bits — the same exact arithmetic as mpq_rational, number for number, while
// every number fits (small_rational.hpp); reference::Overflow when 128 bits do not hold one.  One heavy
// instantiation per translation unit.
#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/solve.hpp"

namespace dcad::reference::pipeline {

Solution solve_linear_wide(const io::CaseFile& c, const Parts& parts);
Solution solve_lc_wide(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts);

namespace {
Rational value(const SmallRational& q) { return q.value(); }
}  // namespace

Solution solve_linear_words(const io::CaseFile& c, const Parts& parts, int& bits) {
  try {
    const dcad::Solution<SmallRational> s = solve_linear<SmallRational>(c, parts);
    bits = 64;
    return map_numbers<Rational>(s, value);
  } catch (const Overflow&) {
    bits = 128;
    return solve_linear_wide(c, parts);
  }
}

Solution solve_lc_words(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts, int& bits) {
  try {
    const dcad::Solution<SmallRational> s = solve_lc<SmallRational>(deck, c.variables, c.coordinates, parts);
    bits = 64;
    return map_numbers<Rational>(s, value);
  } catch (const Overflow&) {
    bits = 128;
    return solve_lc_wide(deck, c, parts);
  }
}

}  // namespace dcad::reference::pipeline
