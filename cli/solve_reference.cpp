// The CAD by the exact reference (the one translation unit that instantiates solve_exact on mpq_rational).
#include "solve_exact.hpp"

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

SolveReport solve_reference(const io::CaseFile& c) {
  SolveReport out = solve_exact<io::Rational>(c);
  out.backend = "reference";
  return out;
}

}  // namespace dcad::cli
