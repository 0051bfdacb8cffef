// reference::solve — the exact reference on any problem (issue 26: a typed solve in each twin).  Every
// route is the literal reference in exact rational arithmetic: numbers are held in 64-bit, then
// 128-bit words while they fit (SmallRational, WideRational: the same exact arithmetic, see
// small_rational.hpp) and in FLINT's fmpq once a number outgrows them (fmpq.hpp; the forced and
// expression routes in mpq_rational).
//   linear cases        CEF §5 tower, Lemma 3.23 classes, Thm 3.28 / 7.4, (5.12)   pipeline/linear.hpp
//   LC netlists         CEF §6 closed form, D̄_Δ on M_c                            pipeline/circuit.hpp
//   forces and sources  YM §4, moving M_k(t) as in V §3                            pipeline/forced.hpp
//   the expression form the pointwise CAD at the case's point                     pipeline/pointwise.hpp
#pragma once

#include "dcad/inspection.hpp"
#include "dcad/io/input_error.hpp"
#include "dcad/io/problem.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/solution.hpp"

#include <string>
#include <utility>

namespace dcad::reference {

using Solution = dcad::Solution<Rational>;

/// io::InputError for bad input (naming the file and the JSON path or line), e.g. a form that is not
/// a Dirac structure or an expression-form point where a formula is irrational.
Solution solve(const io::Problem& p, const Parts& parts = {});

/// The bad input reference::solve reports where its exact route cannot run at the case's point (the expression
/// and implicit forms: a value of the formulas there is irrational): an io::InputError (exit 1) whose `cause`
/// says which value ("sqrt(123/100000) is irrational").  dcad check takes it as "no claim could be judged".
struct NoExactPoint : io::InputError {
  NoExactPoint(const std::string& message, std::string why) : io::InputError(message), cause(std::move(why)) {}
  std::string cause;
};

/// What a `dirac` case's structure is (CEF Lemma 4.1, Prop. 4.3): valid, dim E_D, rank and kernel of ω_D,
/// presymplectic or Poisson.
Inspection inspect(const io::CaseFile& c);

namespace pipeline {

/// The linear pipeline in 64-bit, then 128-bit words (`bits` says which); reference::Overflow when a
/// number outgrows 128 bits.
Solution solve_linear_words(const io::CaseFile& c, const Parts& parts, int& bits);
/// The linear pipeline in FLINT's fmpq (exact, no overflow).
Solution solve_linear_fmpq(const io::CaseFile& c, const Parts& parts);
/// The LC structured route, likewise.  `c`: the netlist's variables and coordinates.
Solution solve_lc_words(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts, int& bits);
Solution solve_lc_fmpq(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts);

}  // namespace pipeline

}  // namespace dcad::reference
