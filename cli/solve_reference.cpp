// The CAD by the exact reference (the one translation unit that instantiates solve_exact on mpq_rational).
#include "dcad/reference/small_rational.hpp"
#include "solve_circuit_exact.hpp"

namespace dcad::cli {

template <>
struct Scalar<io::Rational> {
  static io::Rational lift(const io::Rational& q) { return q; }
  static std::string text(const io::Rational& q) { return q.str(); }
  static bool printable(const io::Rational& q) { return q != 0; }
  static void keep_final(SolveReport& out, const io::QMatrix& basis, const std::vector<io::Rational>& point) {
    out.has_final = true;  // exact M_c, for `dcad check`
    out.final_basis = basis;
    out.final_point = point;
  }
};

SolveReport solve_reference(const io::CaseFile& c, const Parts& parts) {
  SolveReport out;
  try {
    out = solve_small(c, parts);
  } catch (const reference::Overflow&) {
    out = solve_rational(c, parts);
  }
  out.backend = "reference";
  return out;
}

SolveReport solve_rational(const io::CaseFile& c, const Parts& parts) {
  SolveReport out = solve_exact<io::Rational>(c, parts);
  out.backend = "reference";
  return out;
}

SolveReport solve_circuit_rational(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  return solve_circuit_exact<io::Rational>(n, c, parts);
}

SolveReport solve_circuit_reference(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  SolveReport out;
  try {
    out = solve_circuit_small(n, c, parts);
  } catch (const reference::Overflow&) {
    out = solve_circuit_rational(n, c, parts);
  }
  out.backend = "reference";
  out.note = "structured route for circuits (CEF §6 closed form and D̄_Δ on M_c, exact)" +
             std::string(c.has_pontryagin && n.circuit.branches.size() <= kAdaptedBranches
                             ? ""
                             : "; the §7 adapted constraints (T*TQ, 4n variables) are given up to " + std::to_string(kAdaptedBranches) +
                                   " branches");
  return out;
}

}  // namespace dcad::cli
