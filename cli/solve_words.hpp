// How the reference pipeline reads and prints numbers in machine words (SmallRational, WideRational):
// lifted exactly from the case's rationals, printed as mpq_rational prints them.
#pragma once

#include "dcad/reference/small_rational.hpp"
#include "solve_circuit_exact.hpp"

namespace dcad::cli {

template <class W>
struct Scalar<reference::BasicSmallRational<W>> {
  using S = reference::BasicSmallRational<W>;
  static S lift(const io::Rational& q) { return S::from(q); }
  static std::string text(const S& q) { return q.str(); }
  static bool printable(const S& q) { return q != 0; }
  static void keep_final(SolveReport& out, const reference::Matrix<S>& basis, const std::vector<S>& point) {
    out.has_final = true;  // exact M_c, for `dcad check`
    out.final_basis = io::QMatrix(basis.rows(), basis.cols());
    for (reference::Index i = 0; i < basis.rows(); ++i)
      for (reference::Index j = 0; j < basis.cols(); ++j) out.final_basis(i, j) = basis(i, j).value();
    out.final_point.clear();
    for (const S& x : point) out.final_point.push_back(x.value());
  }
};

/// The pipeline on WideRational alone; throws reference::Overflow (solve_wide.cpp).
SolveReport solve_wide(const io::CaseFile& c, const Parts& parts);
SolveReport solve_circuit_wide(const io::Netlist& n, const io::CaseFile& c, const Parts& parts);

}  // namespace dcad::cli
