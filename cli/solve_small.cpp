// The reference pipeline on SmallRational (the one translation unit that instantiates solve_exact on
// it): the same exact arithmetic as mpq_rational while every number fits in 64-bit words, else
// reference::Overflow and solve_reference recomputes on mpq_rational (small_rational.hpp).
#include "dcad/reference/small_rational.hpp"
#include "solve_circuit_exact.hpp"

namespace dcad::cli {

using reference::SmallRational;

template <>
struct Scalar<SmallRational> {
  static SmallRational lift(const io::Rational& q) { return SmallRational::from(q); }
  static std::string text(const SmallRational& q) { return q.str(); }
  static bool printable(const SmallRational& q) { return q != 0; }
  static void keep_final(SolveReport& out, const reference::Matrix<SmallRational>& basis, const std::vector<SmallRational>& point) {
    out.has_final = true;  // exact M_c, for `dcad check`
    out.final_basis = io::QMatrix(basis.rows(), basis.cols());
    for (reference::Index i = 0; i < basis.rows(); ++i)
      for (reference::Index j = 0; j < basis.cols(); ++j) out.final_basis(i, j) = basis(i, j).value();
    out.final_point.clear();
    for (const SmallRational& x : point) out.final_point.push_back(x.value());
  }
};

SolveReport solve_small(const io::CaseFile& c, const Parts& parts) { return solve_exact<SmallRational>(c, parts); }

SolveReport solve_circuit_small(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  return solve_circuit_exact<SmallRational>(n, c, parts);
}

}  // namespace dcad::cli
