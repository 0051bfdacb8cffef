// The linear DAE form E ẋ = A x + f(t) at circuit size, certified (issue 30): the tower of CEF (1.6) on the
// constraints' rows, as fast's sparse route computes it (reference/fast_backend/src/dae_sparse.cpp), but every
// decision proved:
//   M_k(t) = {C_k x = g_k(u(t))}, u the sources' jets; x ∈ M_{k+1} ⇔ x ∈ M_k and some v has E v = A x + f,
//   C_k v = ġ_k ⇔ y_Eᵀ (A x + f) + y_Cᵀ ġ_k = 0 for every (y_E, y_C) in the left null space of S_k = [E; C_k],
// so C_{k+1} = [C_k; y_Eᵀ A] with right sides −y_Eᵀ f − y_Cᵀ ġ_k (CEF (1.6), linear; the reference's
// reference/linear_ide.hpp on dense matrices).  A new row dependent on the others (z) is a condition on the
// sources, z·(right sides) = 0, decided against f as the reference decides it (pipeline/dae.hpp).
//
// How each rank is proved: the left null space of S_k (and of [C_k; new rows]) is computed modulo a prime
// p ~ 2^62 by sparse elimination (rows in order, each reduced by the pivots so far; a row that reduces to
// zero is dependent, its combination a null vector with 1 at itself), then lifted to Q by rational
// reconstruction (CRT over more primes until it verifies) and *verified exactly*: yᵀ S_k = 0 in rationals.
// A minor nonzero mod p is nonzero over Q, so rank_Q S_k ≥ rank_p S_k: the verified null vectors —
// independent, each with its own dependent row — are then all of them, and rank_Q = rank_p exactly.
// No tolerance, no threshold: graded data (pF beside mF) are only rationals here.  Where the lifting does
// not verify within its primes, or the elimination outgrows its budget, it says so (NotExactHere) and
// api falls back to fast's sparse route, not certified.
#pragma once

#include "dcad/io/dae_case.hpp"
#include "dcad/solution.hpp"

namespace dcad::certified {

/// The tower (each step's constraints over the variables and the sources' jets), steps, consistency,
/// the solution rank and, for square E and A, whether det(sE − A) ≢ 0 — all exact; no equations of
/// motion (dense N × N at this size).  reference::NotExactHere where a proof was not reached.
dcad::Solution<reference::Rational> solve_dae_sparse(const io::DaeCase& c);

}  // namespace dcad::certified
