// Expressions (expression.hpp) as reduced rational functions N/D over Q, on FLINT's multivariate
// polynomials (fmpq_mpoly, LGPL): the expression's variables, and one more variable per distinct sin, cos,
// exp or sqrt of a (reduced) argument.  N/D is kept in lowest terms (fmpq_mpoly_gcd) with D monic, so it is
// unique for the function's rational part: e is identically zero where N = 0 (a proof — expansion,
// collection and cancellation of common factors are identities).  The converse fails only through the
// transcendental atoms (sin² + cos² is not 1 here), never wrongly.  CEF (1.6) on formulas (ide_formulas.cpp)
// decides its zero tests here: the eliminated system's entries are quotients by pivots, and
// (2 x + 1)/(66 x + 33) must cancel to 1/33.
#pragma once

#include "dcad/reference/nonlinear/expression.hpp"

#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace dcad::reference {

class RationalFunctions {
 public:
  /// Expressions in variables 0 … variables−1.
  explicit RationalFunctions(std::size_t variables);
  ~RationalFunctions();
  RationalFunctions(const RationalFunctions&) = delete;
  RationalFunctions& operator=(const RationalFunctions&) = delete;

  /// e is identically zero (true: proved; false: not proved — e may still vanish, through its atoms).
  /// Expressions too large to reduce (more than 20,000 terms in N or D, more than 64 atoms) prove nothing.
  bool zero(const expr::Expr& e);
  /// e in lowest terms as an expression (N/D), or nothing if too large; `involves[i]`: the reduced form
  /// (its atoms' arguments included) has variable i; `atoms`: it has a sin, cos, exp or sqrt (without one, a
  /// reduced form other than 0 is a nonzero function: the zero test is then complete).
  std::optional<expr::Expr> reduced(const expr::Expr& e, std::vector<bool>* involves = nullptr, bool* atoms = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> p_;
};

}  // namespace dcad::reference
