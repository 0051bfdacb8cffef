// The CAD of a Lagrangian system given by formulas, at a point (CEF §5–§6 for D̄_Δ, YM §4 forces,
// V §3 time dependence), by local reduction in the sense of Rabier–Rheinboldt.  Written once over
// the scalar T and a decision object: ExactDecisions<Rational> (zero means == 0), a tolerance with
// evidence in the fast backend (dcad::fast_exact, reference/fast_backend: dcad/fast/pointwise.hpp).  The steps, each in
// its own file:
//   pointwise/result.hpp     the result (tower, point, velocity, gauge) and the exact zero tests
//   pointwise/system.hpp     the linear system for (ṡ, λ) on M_k, as jets in its chart
//   pointwise/eliminate.hpp  elimination at the point, its Fredholm candidates
//   pointwise/run.hpp        one pass: M_1, then M_k → M_{k+1} (graph or move the point)
//
// M_1 = {p = ∂L/∂v, a(t,q)·v + b(t,q) = 0} (CEF (6.20), YM (5.2)–(5.3)), a graph over the chart
// (t, q, v_free).  On M_k, in a chart s (a subset of the variables t, q, v, the others being functions
// of s), the definition of the CAD,
//     M_{k+1} = {x ∈ M_k : some ẋ ∈ T_x M_k has (ẋ, dE(x) − F) ∈ D̄_Δ(x)}       [CEF Lemma 5.1, Remark 5.2]
// reads: the linear system for (ṡ, λ) (system.hpp) is solvable.  Near the point its rank is its rank
// at the point if, after eliminating with pivots that are nonzero at the point, the rest of the matrix
// vanishes on M_k; then the system is solvable iff the eliminated right-hand sides ψ (Fredholm)
// vanish: they are the new constraints.  Everything is computed on jets (jet.hpp): the rest of the
// matrix and the ψ are series on M_k, so "vanishes on M_k" is a zero test of a series, known to the
// jet's order.  A point where a pivot or a constraint's differential vanishes although the series does
// not is singular (the rank drops there): it is reported, never used.  M_{k+1} is then the graph of
// the solved coordinates over the rest, found as series by Newton's method on jets.
//
// The point: values given by the user are kept; the others start at the given defaults and move
// by Newton steps onto each M_k in turn (exactly: the exact route stops if no rational point is
// reached, which happens only for constraints that are not affine in the coordinates it moves).
#pragma once

#include "dcad/reference/nonlinear/pointwise/run.hpp"

namespace dcad::reference {

/// The pointwise CAD of `sys` near `start` (values of q, v and t, indices as in LagrangianSystem;
/// `fixed[i]`: the user gave variable i, never move it).  `constant` turns exact input numbers into
/// T.  Jets are computed to order `order` and more if the tower needs it.  `plan`: another result's
/// plan, to make the same choice of solved coordinates where it works (simulate's projections).
template <class T, class Decide>
PointwiseResult<T> pointwise_cad(const LagrangianSystem& sys, std::vector<T> start, const std::vector<bool>& fixed,
                                 Decide& decide, const std::function<T(const Rational&)>& constant, long order = 3,
                                 std::size_t max_moves = 12,
                                 const std::vector<std::vector<std::size_t>>* plan = nullptr) {
  const LagrangianDerivatives der = derivatives(sys);
  PointwiseResult<T> out;
  std::size_t moves = 0, polished = 0, constant_nudges = 0;
  for (long K = order;;) {
    pointwise_detail::Run<T, Decide> run(sys, der, fixed, decide, constant, plan, polished, &constant_nudges);
    const auto o = run.pass(start, K, out);
    if (o == pointwise_detail::Run<T, Decide>::Outcome::Done) {
      out.moves = moves;
      return out;
    }
    if (o == pointwise_detail::Run<T, Decide>::Outcome::MoreOrder) {
      K += 2;
      if (K > static_cast<long>(2 * sys.n + 6))
        throw std::logic_error("pointwise_cad: the tower needs jets beyond order 2n+6");
      continue;
    }
    if (++moves > max_moves)
      throw PointwiseNoPoint(
          "no point of M_c was reached from the given values in " + std::to_string(max_moves) +
          " Newton steps (the exact route needs a point with rational coordinates: give values on M_c)");
  }
}

}  // namespace dcad::reference
