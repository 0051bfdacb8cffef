// `dcad solve` on an LC netlist by the reference's structured route (reference/circuit_motion.hpp):
// the closed-form tower of CEF §6 as products {q ∈ S_j, v ∈ V_j, p = φ v} of subspaces of Q^n and
// the equations of motion from D̄_Δ on M_c — no 3n-dimensional CAD.  Written once over the scalar
// and instantiated like solve_exact: Rational (solve_reference.cpp) and Ball (solve_ball.cpp).
// The §7 constraints adapted to the primary ones (Thm 7.4, on T*TQ: 4n variables) are added by the
// generic pipeline up to kAdaptedBranches branches.
#pragma once

#include "dcad/reference/circuit_motion.hpp"
#include "dcad/io/netlist.hpp"
#include "solve_circuit.hpp"
#include "solve_exact.hpp"

namespace dcad::cli {

template <class T>
SolveReport solve_circuit_exact(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts = {}) {
  namespace ref = dcad::reference;
  ref::Circuit<T> circ;
  circ.nodes = deck.circuit.nodes;
  for (const auto& b : deck.circuit.branches) circ.branches.push_back({b.name, b.kind, b.from, b.to, Scalar<T>::lift(b.value)});
  const ref::Index n = circ.branches.size();
  const std::vector<ref::ProductStep<T>> tower = ref::circuit_tower(circ);
  const std::vector<ref::Matrix<T>> added = ref::circuit_tower_equations(circ, tower);
  SolveReport out;
  out.consistent = true;  // no sources: x = 0 solves
  out.steps = static_cast<long>(tower.size());
  out.dims.push_back(static_cast<long>(3 * n));
  out.tower.push_back({static_cast<long>(3 * n), {}});
  for (std::size_t j = 0; j < tower.size(); ++j) {
    SolveReport::Step step;
    step.dim = static_cast<long>(tower[j].dim());
    for (ref::Index i = 0; i < added[j].rows(); ++i) step.equations.push_back(row_equation(added[j], i));
    out.dims.push_back(step.dim);
    out.tower.push_back(step);
    if (parts.final_constraints)
      for (const Equation& e : step.equations) out.final_constraints.push_back(e);  // all of them: M_c
  }
  const ref::ProductStep<T>& mc = tower.back();
  if (parts.final_constraints) {
    out.has_final_constraints = true;
    Scalar<T>::keep_final(out, ref::product_basis(circ, mc), std::vector<T>(3 * n, T(0)));
  }
  const ref::ReducedEquations<T> red = ref::circuit_reduced_equations(circ, mc, c.coordinates);
  out.solution_rank = static_cast<long>(red.g.cols());  // dim ker A = dim(ker ω_D ∩ T M_c)  [Thm 5.4(b)]
  if (parts.reduced) keep_reduced(out, red);
  if (c.has_pontryagin && n <= kAdaptedBranches && parts.adapted) exact_foliated<T>(out, c);
  return out;
}

}  // namespace dcad::cli
