#include "solve_circuit.hpp"

#include <cmath>
#include <stdexcept>

namespace dcad::cli {

fast::CircuitGraph circuit_graph(const io::Netlist& n, fast::Options& opt) {
  fast::CircuitGraph g;
  g.nodes = n.circuit.nodes;
  double lo = 1, hi = 1;
  for (const auto& b : n.circuit.branches) {
    const double v = b.value.convert_to<double>();
    if (b.kind != reference::BranchKind::empty) {
      if (io::Rational(v) != b.value) opt.input_exact = false;
      lo = std::min(lo, std::abs(v));
      hi = std::max(hi, std::abs(v));
    }
    g.branches.push_back({b.kind == reference::BranchKind::inductor    ? fast::BranchKind::inductor
                          : b.kind == reference::BranchKind::capacitor ? fast::BranchKind::capacitor
                                                                       : fast::BranchKind::empty,
                          b.from, b.to, v});
  }
  if (lo > 0 && hi / lo > 1 / opt.nonzero_factor) opt.input_well_scaled = false;
  return g;
}

SolveReport solve_circuit_fast(const io::Netlist& n, const io::CaseFile& c) {
  fast::Options opt;
  const fast::CircuitTower t = fast::circuit_tower(circuit_graph(n, opt), opt);
  const bool dense = c.has_pontryagin;
  SolveReport out = dense ? solve_fast(c) : SolveReport();
  const std::vector<long> generic_dims = out.dims;
  out.backend = "fast";
  out.dims = t.dims;
  out.steps = t.steps;
  out.consistent = true;  // no sources: x = 0 solves
  out.solution_rank = t.solution_rank;
  out.tower.clear();
  for (std::size_t k = 0; k < t.dims.size(); ++k) {
    SolveReport::Step step;
    step.dim = t.dims[k];
    for (const fast::SparseRow& row : t.equations[k]) {
      Equation e;
      for (const fast::Term& term : row) e.terms.emplace_back(term.var, float_text(term.coeff));
      e.rhs = "0";
      step.equations.push_back(e);
    }
    out.tower.push_back(step);
  }
  out.decisions_float += static_cast<long>(t.decisions.size());
  out.certified = (out.certified || !dense) && t.certain;
  std::string how = t.physical ? "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision)"
                               : "graph route (CEF §6 closed form in loop coordinates, signed values)";
  if (dense && generic_dims != t.dims) {  // two routes to one tower disagree: trust neither
    out.certified = false;
    how += "; the generic fast CAD found a different tower, recompute with --backend reference";
  }
  if (!dense)
    how += "; equations of motion omitted above " + std::to_string(kDenseBranches) + " branches (dense), see `dcad solve --backend reference`";
  out.note = how + (out.certified ? "" : "; some rank decision was uncertain");
  return out;
}

SolveReport solve_circuit_certified(const io::Netlist& n, const io::CaseFile& c) {
  if (c.has_pontryagin) {  // small deck: the reference pipeline in ball arithmetic (or exact), plus the graph route's loops
    fast::Options opt;
    const fast::CircuitTower t = fast::circuit_tower(circuit_graph(n, opt), opt);
    SolveReport r = solve_certified(c);
    if (t.physical && t.dims != r.dims)  // a combinatorial theorem disagrees with a certified computation: a bug
      throw std::logic_error("graph route and certified CAD disagree on " + c.file + "; please report it");
    return r;
  }
  fast::Options opt;
  const bool physical = fast::is_physical(circuit_graph(n, opt));  // the graph route decides nothing (CEF Thms 6.4, 6.6, 6.8)
  SolveReport fast = solve_circuit_fast(n, c);
  if (physical) {
    fast.backend = "certified";
    return fast;
  }
  SolveReport exact = solve_reference(io::netlist_case(n, true));
  exact.backend = "certified";
  exact.decisions_float = fast.decisions_float;
  exact.decisions_exact = 1;
  exact.note = "signed values on a large deck: no certified floating-point route, recomputed exactly from the exact input";
  return exact;
}

}  // namespace dcad::cli
