// The linear DAE form E ẋ = A x + f(t) (CONTRACT "Linear and implicit DAEs (CEF (1.6))") by the
// reference: CEF (1.6) literally, in exact rationals (dcad/reference/linear_ide.hpp), with the sources'
// conditions decided against the case's formulas for f.
#pragma once

#include "dcad/io/dae_case.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/solution.hpp"

namespace dcad::reference::pipeline {

/// The tower (each step's constraints, in the variables and the sources' jets f_i^(d)(t)), steps,
/// consistency (a condition 0 = Σ c f_i^(d)(t) that fails for generic t empties its M_k), the
/// solution rank, the velocities on M_c and, for square E and A, whether det(sE − A) ≢ 0.
dcad::Solution<Rational> solve_dae(const io::DaeCase& c);

/// A result for the case with nothing decided yet: its file, name, variables and the algorithm's name
/// (CEF (1.6)), exact, from `backend`.
dcad::Solution<Rational> dae_result(const io::DaeCase& c, Backend backend);

/// Whether g(t) = 0 for all t, for g a formula in the time (variable 0): yes when g is a polynomial
/// in t (degree d) that vanishes at t = 0, 1, …, d, or the number 0; no when some exact value is not
/// 0; else unknown (a transcendental g that vanishes at t = 0).  `evidence` says which.
Truth vanishes_identically(const reference::expr::Expr& g, std::string& evidence);

}  // namespace dcad::reference::pipeline
