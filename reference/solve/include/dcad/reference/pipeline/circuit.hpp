// The reference pipeline on an LC netlist by the structured route (reference/circuit_motion.hpp): the
// closed-form tower of CEF §6 as products {q ∈ S_j, v ∈ V_j, p = φ v} of subspaces of Q^n and the
// equations of motion from D̄_Δ on M_c — no 3n-dimensional CAD.  Written once over the scalar, as
// pipeline/linear.hpp.  The §7 constraints adapted to the primary ones (Thm 7.4, on T*TQ: 4n
// variables) are added by the generic pipeline up to kAdaptedBranches branches.
#pragma once

#include "dcad/io/netlist.hpp"
#include "dcad/lc_graph.hpp"
#include "dcad/reference/circuit_motion.hpp"
#include "dcad/reference/pipeline/linear.hpp"

namespace dcad::reference::pipeline {

/// The §7 constraints adapted to the primary ones (T*TQ: 4n variables) are computed up to this many branches.
constexpr std::size_t kAdaptedBranches = 24;

/// The structured route (dense in n: O(n³) exact elimination) takes LC circuits up to this many
/// branches; physical ones beyond it take the graph route (tower and its equations, no motion).
constexpr std::size_t kStructuredBranches = 400;

/// The LC deck as the graph route's branches, exactly.
inline std::vector<lc::Branch<Rational>> lc_graph_of(const io::Netlist& deck) {
  std::vector<lc::Branch<Rational>> out;
  for (const auto& b : deck.circuit.branches) out.push_back({b.kind, b.from, b.to, b.value});
  return out;
}

/// A physical LC circuit by the graph route, exactly (CEF Thms 6.4, 6.6, 6.8 decide every step):
/// the tower with its equations, each coefficient through `number`; no equations of motion.
template <class N, class Convert>
dcad::Solution<N> lc_graph_solution(const io::Netlist& deck, const std::vector<std::string>& variables,
                                    Convert number) {
  const lc::Tower<Rational> t = lc::physical_tower(deck.circuit.nodes, lc_graph_of(deck));
  dcad::Solution<N> s;
  s.certified = yes;  // the graph's theorems decide every step: no rank is decided
  s.variables = variables;
  for (std::size_t k = 0; k < t.dims.size(); ++k) {
    Level<N> level{t.dims[k], {}};
    for (const lc::Row<Rational>& row : t.equations[k]) {
      Equation<N> e;
      for (const lc::Term<Rational>& term : row) e.terms.emplace_back(term.var, number(term.coeff));
      e.rhs = number(Rational(0));
      level.constraints.push_back(e);
    }
    s.tower.push_back(level);
  }
  s.steps = t.steps;
  s.consistent = true;  // no sources: x = 0 solves
  s.solution_rank = t.solution_rank;
  s.exact = true;
  s.trace = exact_trace(s.dims(), DecidedBy::graph, "CEF Thms 6.4, 6.6, 6.8 on the circuit's graph: no rank decided");
  return s;
}

template <class T>
Circuit<T> circuit_of(const io::Netlist& deck) {
  Circuit<T> circ;
  circ.nodes = deck.circuit.nodes;
  for (const auto& b : deck.circuit.branches)
    circ.branches.push_back({b.name, b.kind, b.from, b.to, Numbers<T>::lift(b.value)});
  return circ;
}

/// `variables`: the circuit's (q_*, v_*, p_*); `coordinates`: the variables to write the motion in (empty: default).
template <class T>
dcad::Solution<T> solve_lc(const io::Netlist& deck, const std::vector<std::string>& variables,
                           const std::vector<std::size_t>& coordinates, const Parts& parts) {
  const Circuit<T> circ = circuit_of<T>(deck);
  const Index n = circ.branches.size();
  const std::vector<ProductStep<T>> tower = circuit_tower(circ);
  const std::vector<Matrix<T>> added = circuit_tower_equations(circ, tower);
  dcad::Solution<T> out;
  out.certified = Numbers<T>::exact ? yes : unknown;  // every rank an exact zero test in exact T
  out.file = deck.file;
  out.name = deck.title;
  out.variables = variables;
  out.consistent = true;  // no sources: x = 0 solves
  out.steps = static_cast<long>(tower.size());
  out.tower.push_back({static_cast<long>(3 * n), {}});
  std::vector<Equation<T>> all;
  for (std::size_t j = 0; j < tower.size(); ++j) {
    out.tower.push_back({static_cast<long>(tower[j].dim()), equations(added[j])});
    for (const Equation<T>& e : out.tower.back().constraints) all.push_back(e);  // all of them: M_c
  }
  const ProductStep<T>& mc = tower.back();
  if (parts.final_constraints) {
    out.final_constraints = all;
    if constexpr (Numbers<T>::exact)
      out.final_exact = ExactSubspace<T>{dense(product_basis(circ, mc)), std::vector<T>(3 * n, T(0))};
  }
  const ReducedEquations<T> red = circuit_reduced_equations(circ, mc, coordinates);
  out.solution_rank = static_cast<long>(red.g.cols());  // dim ker A = dim(ker ω_D ∩ T M_c)  [Thm 5.4(b)]
  if (parts.reduced) out.motion = motion_of(red);
  if (n <= kAdaptedBranches && parts.adapted) {
    const io::CaseFile dense_case = io::netlist_case(deck, true);
    out.adapted = foliated_adapted<T>(dense_case.pontryagin, variables);
  }
  return out;
}

}  // namespace dcad::reference::pipeline
