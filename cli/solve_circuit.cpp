#include "solve_circuit.hpp"
#include "convert_fast.hpp"

#include <cmath>
#include <stdexcept>

namespace dcad::cli {

fast::CircuitGraph circuit_graph(const io::Netlist& n, fast::Options& opt) {
  fast::CircuitGraph g;
  g.nodes = n.circuit.nodes;
  double lo = 1, hi = 1;
  for (const auto& b : n.circuit.branches) {
    const double v = b.kind == reference::BranchKind::empty ? 0.0 : to_double(b.value, opt);
    if (b.kind != reference::BranchKind::empty) {
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

namespace {

/// x_j = s_j x̃_j: coefficient a_j of a row in x̃ becomes a_j / s_j in x (display rows, %.17g text).
void unscale(Equation& e, const std::vector<double>& s) {
  for (auto& [var, coeff] : e.terms) coeff = float_text(std::stod(coeff) / s[var]);
}

/// S of io::Units for x = (q, v, p[, ν]): 1, 1/T, L0/T[, L0].
std::vector<double> unit_scales(const io::Units& u, std::size_t branches, bool with_nu) {
  const double t = std::pow(10.0, u.m()), l0 = std::pow(10.0, u.a);
  std::vector<double> s(3 * branches, 1.0);
  for (std::size_t i = 0; i < branches; ++i) {
    s[branches + i] = 1 / t;
    s[2 * branches + i] = l0 / t;
  }
  if (with_nu) s.resize(4 * branches, l0);
  return s;
}

/// The report of the dimensionless twin in the circuit's units: rows x̃ → x, and the equations of
/// motion dz/dt = (S F̃ S⁻¹ / T) z + S f̃ / T + S G̃ λ / T.
void to_circuit_units(SolveReport& r, const io::Units& u, std::size_t branches) {
  const std::vector<double> s = unit_scales(u, branches, false), s_nu = unit_scales(u, branches, true);
  const double t = std::pow(10.0, u.m());
  for (auto& step : r.tower)
    for (Equation& e : step.equations) unscale(e, s);
  for (Equation& e : r.adapted_chi) unscale(e, s_nu);
  for (Equation& e : r.abridged_terms) unscale(e, s_nu);
  const auto scaled = [](const std::string& text, double factor) { return float_text(std::stod(text) * factor); };
  for (std::size_t i = 0; i < r.coords.size(); ++i) {
    const double si = s[r.coords[i]];
    for (std::size_t j = 0; j < r.coords.size(); ++j) r.f_matrix[i][j] = scaled(r.f_matrix[i][j], si / (s[r.coords[j]] * t));
    r.f[i] = scaled(r.f[i], si / t);
    for (std::string& g : r.g[i]) g = scaled(g, si / t);
  }
}

}  // namespace

SolveReport solve_circuit_fast(const io::Netlist& deck, const io::CaseFile& c) {
  // the twin without units: double sees values near 1 whatever the circuit's units (fF … kH)
  io::Units units;
  const io::Netlist n = io::dimensionless(deck, units);
  fast::Options opt;
  const fast::CircuitTower t = fast::circuit_tower(circuit_graph(n, opt), opt);
  const bool dense = c.has_pontryagin;
  SolveReport out;
  if (dense) {
    io::CaseFile twin = io::netlist_case(n, true);
    twin.variables = c.variables;
    twin.coordinates = c.coordinates;
    out = solve_fast(twin);
  }
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
  to_circuit_units(out, units, n.circuit.branches.size());
  out.decisions_float += static_cast<long>(t.decisions.size());
  out.certified = (out.certified || !dense) && t.certain;
  std::string how = t.physical ? "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision)"
                               : "graph route (CEF §6 closed form in loop coordinates, signed values)";
  how += "; computed on the dimensionless twin (L / 1e" + std::to_string(units.a) + ", C / 1e" + std::to_string(units.b) +
         ", time unit 1e" + std::to_string(units.m()) + " s)";
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
  io::Units units;
  const io::Netlist twin = io::dimensionless(n, units);  // same graph, values near 1 for the cross-check
  if (c.has_pontryagin) {  // small deck: the reference pipeline in ball arithmetic (or exact), plus the graph route's loops
    fast::Options opt;
    const fast::CircuitTower t = fast::circuit_tower(circuit_graph(twin, opt), opt);
    SolveReport r = solve_certified(c);
    if (t.physical && t.dims != r.dims)  // a combinatorial theorem disagrees with a certified computation: a bug
      throw std::logic_error("graph route and certified CAD disagree on " + c.file + "; please report it");
    return r;
  }
  fast::Options opt;
  const bool physical = fast::is_physical(circuit_graph(twin, opt));  // the graph route decides nothing (CEF Thms 6.4, 6.6, 6.8)
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
