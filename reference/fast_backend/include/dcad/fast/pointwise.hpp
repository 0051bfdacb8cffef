// The pointwise CAD of a Lagrangian system given by formulas, in floating point: the reference's
// own algorithm (reference/nonlinear/pointwise.hpp, written once over the scalar) on jets of Tracked doubles
// (tracked.hpp), every zero test decided relative to the magnitude the number was computed from.
// Not a route of the fast twin (it is the reference's algorithm): the fast backend uses it for the Lagrangian
// form, and simulate for its projections; it lives here, beside the reference, for that reason.
#pragma once

#include "dcad/fast/chart.hpp"
#include "dcad/fast/rank.hpp"
#include "dcad/fast/tracked.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "dcad/solution.hpp"
#include "dcad/truth.hpp"
#include "dcad/reference/nonlinear/pointwise.hpp"

#include <string>
#include <utility>
#include <vector>

namespace dcad::fast {

/// A zero test in double, relative to the number's own rounding-error bound e (tracked.hpp):
/// |v| > 64e is certainly nonzero (far above anything rounding produced); |v| ≤ 8e is taken as zero
/// (an exact zero computed with rounding lands within e; 8 covers the rounding of the bound
/// itself), and that is certain only under the separation hypothesis of rank.hpp — exact nonzeros
/// are not within 8e of 0 — for which the window 8e must be small against the step's data:
/// e ≤ 2^-26 × the largest constant term of the step's linear system (half the digits kept), and
/// the data not graded: when its nonzero constant terms span more than 1/√ε in magnitude (a
/// pulled-back mass matrix at |q| ~ 10^4 has condition ~ 10^16) no zero is certain, as in
/// rank.hpp's assess_input.
/// In between (8e, 64e]: uncertain.  An uncertain decision is recorded; the result is then not
/// certified.
struct ToleranceDecisions {
  double zero_factor = 8, nonzero_factor = 64, graded = 1 / 1.4901161193847656e-08;
  bool well_scaled = true;  ///< of the current step's data
  double scale = 0;         ///< its largest constant term
  Truth certain = yes;
  std::size_t decisions = 0;
  /// Zeros taken as certain that rest on the separation hypothesis (a value within 8 rounding bounds of 0, not one
  /// nothing was added to): 0 means every decision was proved in double — a nonzero beyond its rounding bound, or a
  /// zero no rounding touched — and the answer is certain without a hypothesis.
  std::size_t assumed = 0;
  std::string evidence;            ///< the first uncertain decision
  DecisionProbe* probe = nullptr;  ///< testing (fast/rank.hpp): each decision above counts once

  void step_data(const std::vector<Tracked>& data);
  bool zero(const Tracked& x);
  /// |v| > 2^-45 × the step's scale although taken as zero: a Newton step can still improve it
  /// (the error bound e is pessimistic; projections onto M_c should reach rounding level).
  bool polish(const Tracked& x) const { return std::abs(x.v) > 0x1p-45 * scale; }
  bool zero(const reference::Jet<Tracked>& j);
  /// The first value (in the caller's order of preference) that is certainly nonzero and at least 1/8
  /// of the largest such value (threshold pivoting); values.size() if there is none.
  std::size_t pivot(const std::vector<Tracked>& values);

 private:
  /// `answer`, after counting the decision with the probe (which may report it uncertain).
  bool probed(bool answer);
};

/// reference::pointwise_cad in double (inputs rounded to nearest), its values as doubles.  A result
/// with a value beyond double's range (inf, NaN) is never returned: std::range_error whose message names
/// the case's formula (a JSON path: /lagrangian/L, /lagrangian/constraints/k, /lagrangian/forces/i), its
/// smallest subexpression that overflowed and the point (nonfinite_formula), or says the elimination overflowed.
reference::PointwiseResult<double> pointwise_cad(const reference::LagrangianSystem& sys,
                                                 const std::vector<double>& start, const std::vector<bool>& fixed,
                                                 ToleranceDecisions& decide,
                                                 const std::vector<std::vector<std::size_t>>* plan = nullptr);

/// The first of the case's formulas (L and its first derivatives, the constraints, the forces) whose value
/// at (q, v, t) = `at` is not finite in double: its JSON path and "SUBEXPRESSION = VALUE" (the smallest
/// subexpression whose operands are finite), or two empty strings if every one is finite.
std::pair<std::string, std::string> nonfinite_formula(const reference::LagrangianSystem& sys,
                                                      const std::vector<double>& at);

/// chart_near's completion (chart.hpp) by this pointwise CAD: the point (q, v, t) of M_c its Newton moves on jets
/// reach from `start`, where the CAD there is consistent and regular; nothing otherwise.
Completion pointwise_completion(const reference::LagrangianSystem& sys);

}  // namespace dcad::fast
