// CEF (1.6) for the implicit form φ(t, x, ẋ) = a(t, x)·ẋ + b(t, x) = 0 on formulas, exactly at a point:
//     M_0 = R^N,   M_{k+1} = {x ∈ M_k : some v ∈ T_x M_k (with ∂_t of a moving M_k) has a(t, x) v + b(t, x) = 0}.
// With M_k = {c(t, x) = 0} (the constraints found so far, their differentials independent at the point),
// "some v tangent to M_k" is "the linear system in v
//     a(t, x) v = −b(t, x)            (the equations)
//     ∂c/∂x (t, x) v = −∂c/∂t (t, x)    (v tangent to M_k(t))
// is solvable".  Gaussian elimination of this system *on the formulas*, with pivots whose values at the
// point are nonzero (so nonzero near it), leaves rows whose coefficients must vanish identically and whose
// right-hand sides ψ (Fredholm) must vanish: the ψ are the candidates for M_{k+1}.  A candidate whose
// differential at the point is independent of the constraints' is a new constraint (M_{k+1} is cut out by
// it near the point); one that is dependent must vanish identically on M_{k+1}; when no candidate is new,
// M_c = M_k.  Each step adds only the new constraints' rows to the system eliminated so far (the old rows
// and their candidates are unchanged, and were settled at their step).
//
// Every decision is exact: a pivot is a nonzero rational value at the point; "vanishes identically" is an
// identity of the formulas (in lowest terms as rational functions over Q, on FLINT's multivariate
// polynomials, the numerator is 0 — a proof, never a test to some order); a condition on the time alone is
// nonzero if a Taylor coefficient at the point is.
// Where a decision would need more than that (a coefficient that vanishes at the point but not as a
// formula: a singular point, or a formula that vanishes on M_k without vanishing identically) the route
// says so (IdeUndecided) and decides nothing: the jet route (pointwise.hpp) then takes the case, as before.
// This route never expands a chart, so its cost grows with the formulas, not with C(N + K, K) monomials:
// the jet route stops at about 25 variables, this one runs pendulum chains of 100 in milliseconds.
//
// The point: given values are held; the others move by exact Newton steps (the coordinates every
// nonzero candidate is affine in first, each constraint moving its pivot coordinate) and the pass starts
// again, as in the jet route.  A row's pivot is a number where it has one (its multiples keep the other
// rows polynomial), else any entry nonzero at the point, which divides.
#pragma once

#include "dcad/reference/nonlinear/lagrangian_system.hpp"
#include "dcad/reference/nonlinear/pointwise/result.hpp"

#include <string>
#include <variant>
#include <vector>

namespace dcad::reference {

/// The tower of CEF (1.6) decided on formulas, with the formulas themselves.
struct IdeFormulas {
  /// dims, steps, consistency, the point, the velocity and its gauge, each step's constraints as tangent
  /// equations at the point (solved for a coordinate), as the jet route reports them (checked_order −1:
  /// every zero test was an identity of the formulas).
  PointwiseResult<Rational> result;
  /// levels[k]: the constraints (formula = 0) that cut M_{k+1} out of M_k; with `solved[k][i]` the
  /// coordinate (variable index) each is solved for at the point.
  std::vector<std::vector<expr::Expr>> levels;
  std::vector<std::vector<std::size_t>> solved;
  /// d/dt x_i on M_c as formulas in (x, t) (consistent results only), the free velocities set to 0.
  std::vector<expr::Expr> rates;
  std::vector<std::size_t> free;  ///< coordinates whose velocity is a free unknown on M_c (solution_rank many)
  struct Condition {
    std::string what;
    expr::Expr formula;  ///< must not vanish for the elimination (and so the formulas) to hold
  };
  std::vector<Condition> valid_where;
};

/// A decision the formulas alone cannot make exactly, and which one.
struct IdeUndecided {
  std::string why;
  bool no_point = false;  ///< what was open: a point of M_c (exact Newton steps did not land), not a decision
};

/// CEF (1.6) of the implicit system `s` (LagrangianSystem::implicit) at `start` (values of x, and of the
/// time at index s.t(); `fixed[i]`: the user gave variable i, never move it), exactly.  NotExactHere where
/// a formula's value is irrational at the point.
std::variant<IdeFormulas, IdeUndecided> ide_on_formulas(const LagrangianSystem& s, std::vector<Rational> start,
                                                        const std::vector<bool>& fixed, std::size_t max_moves = 12);

}  // namespace dcad::reference
