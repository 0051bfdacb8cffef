// Integrability of Dirac structures that depend on the point, in double; the twin of
// dcad/reference/dirac_field.hpp.  A different route: the reference evaluates CEF §4's definition (the Lie
// derivative expression on sections) as a polynomial; fast computes the classical tensors Courant's theorem
// reduces it to — dω for the graph of a 2-form, the Schouten bracket [P, P] for the graph of a bivector — and
// decides them zero with its one decision point (the coefficients as one column, rank 0 or 1).
#pragma once

#include "dcad/affine_skew_field.hpp"
#include "dcad/fast/rank.hpp"

namespace dcad::fast {

/// M(x) = constant + Σ_k x_k slopes[k] (dcad/affine_skew_field.hpp).
using AffineSkewField = AffineSkewData<MatrixXd>;

struct Integrability {
  Truth integrable = unknown;  ///< yes, no, or unknown when the decision below is uncertain
  RankDecision evidence;       ///< on the coefficients of dω or [P, P] (rank 0: integrable)
};

/// The graph of ω(x) is integrable iff dω = 0  [CEF §4 before Thm 4.7; Courant 1990].
Integrability is_closed(const AffineSkewField& w, const Options& opt = {});
/// The graph of P(x) is integrable iff [P, P] = 0 (Jacobi).
Integrability is_jacobi(const AffineSkewField& p, const Options& opt = {});

}  // namespace dcad::fast
