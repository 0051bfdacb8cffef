// The implicit form φ(t, x, ẋ) = 0 in double by Campbell's derivative array (Campbell 1987; Campbell–
// Gear 1995, "The index of general nonlinear DAEs"), a route of its own beside the reference's CEF (1.6)
// on jets (pipeline/implicit.hpp):
//     F_k(t, x, x', …, x^(k+1)) = (φ, dφ/dt, …, d^kφ/dt^k) = 0,   d/dt = ∂_t + Σ_j x^(j+1)·∂_{x^(j)}.
// Its zero set projects onto M_{k+1} of CEF (1.6) (a curve through x solving φ has all its derivatives
// solving F_k, and conversely locally, at constant ranks).  At a point of {F_k = 0} (Gauss–Newton with
// minimum-norm steps, the given values held), with J_d = ∂F_k/∂(x', …, x^(k+1)), J_r its columns after
// x', and Z the left null space of J_d:
//     dim M_{k+1} = N − rank(Zᵀ ∂F_k/∂x),   the ẋ with F_k = 0 form an affine space of dimension
//     N − rank J_d + rank J_r  (the solution rank; 0: F_k is "1-full", ẋ is unique).
// The tower ends at the first k with dim M_{k+1} = dim M_k: steps = k, and where ẋ is unique that is the
// index.  Every rank is a fast::RankDecision with its evidence; consistency is the Gauss–Newton residual,
// certain only far from the threshold either way.
#pragma once

#include "dcad/fast/rank.hpp"
#include "dcad/symbolic/lagrangian_system.hpp"
#include "dcad/truth.hpp"

#include <string>
#include <vector>

namespace dcad::fast {

struct DerivativeArrayResult {
  std::vector<long> dims;  ///< dim M_k, k = 0…c (−1: empty)
  long steps = 0;
  bool consistent = true;
  long solution_rank = 0;
  double time = 0;
  std::vector<double> point, velocity;     ///< x and one ẋ (the minimum-norm one where not unique)
  std::vector<std::vector<double>> gauge;  ///< an orthonormal basis of the other solutions' ẋ differences
  long order = 0;                          ///< the derivative array's last k
  Truth certain = yes;
  std::string evidence;  ///< the first uncertain decision
  std::string why;       ///< inconsistent: which F_k has no zero near the point
};

/// The derivative array route at `start` (values of x, v (ignored) and t, LagrangianSystem's indices;
/// fixed[i]: a given value, held).  symbolic::PointwiseNoPoint when the given values cannot be held
/// on {F_k = 0} but the others can (given values off M_c).
DerivativeArrayResult derivative_array(const symbolic::LagrangianSystem& sys, const std::vector<double>& start,
                                       const std::vector<bool>& fixed, const Options& opt = {});

}  // namespace dcad::fast
