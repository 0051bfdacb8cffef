#include "solve_circuit.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/fast/circuit_motion.hpp"
#include "dcad/reference/small_rational.hpp"

#include <cmath>
#include <stdexcept>

namespace dcad::cli {

fast::CircuitGraph circuit_graph(const io::Netlist& n, fast::Options& opt) {
  std::vector<io::Rational> values;  // of the elements (an empty branch has none)
  for (const auto& b : n.circuit.branches)
    if (b.kind != reference::BranchKind::empty) values.push_back(b.value);
  const std::vector<double> v = fast::to_double_values(values, opt);
  fast::CircuitGraph g;
  g.nodes = n.circuit.nodes;
  std::size_t next = 0;
  for (const auto& b : n.circuit.branches)  // one BranchKind for both twins (dcad/types.hpp)
    g.branches.push_back({b.kind, b.from, b.to, b.kind == reference::BranchKind::empty ? 0.0 : v[next++]});
  return g;
}

namespace {

/// x_j = s_j x̃_j: coefficient a_j of a row in x̃ becomes a_j / s_j in x; the row is then divided by
/// its largest coefficient (display rows, %.17g text).
void unscale(Equation& e, const std::vector<double>& s) {
  std::vector<double> a;
  double big = 0;
  for (const auto& [var, coeff] : e.terms) {
    a.push_back(std::stod(coeff) / s[var]);
    big = std::max(big, std::abs(a.back()));
  }
  if (big == 0) big = 1;
  for (std::size_t i = 0; i < a.size(); ++i) e.terms[i].second = float_text(a[i] / big);
  if (const double rhs = std::stod(e.rhs); rhs != 0) e.rhs = float_text(rhs / big);
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

SolveReport solve_circuit_fast(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts) {
  // the twin without units: double sees values near 1 whatever the circuit's units (fF … kH)
  io::Units units;
  const io::Netlist n = io::dimensionless(deck, units);
  fast::Options opt;
  const fast::CircuitTower t = fast::circuit_tower(circuit_graph(n, opt), opt);
  const bool dense = n.circuit.branches.size() <= kDenseBranches;
  SolveReport out;
  out.certified = true;
  if (c.has_pontryagin && n.circuit.branches.size() <= kAdaptedBranches && parts.adapted) {  // §7 on T*TQ by the generic fast pipeline
    io::CaseFile twin = io::netlist_case(n, true);
    twin.variables = c.variables;
    Parts only_adapted{false, false, false, true};
    const SolveReport generic = solve_fast(twin, only_adapted);
    out.has_adapted = generic.has_adapted;
    out.adapted_setting = generic.adapted_setting;
    out.adapted_variables = generic.adapted_variables;
    out.s_prime = generic.s_prime;
    out.secondary_first_class = generic.secondary_first_class;
    out.adapted_chi = generic.adapted_chi;
    out.abridged_terms = generic.abridged_terms;
    out.certified = generic.certified;
  }
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
  if (dense && parts.reduced) {  // equations of motion by the structured route (fast/circuit_motion.hpp)
    const fast::CircuitMotion mo =
        fast::circuit_motion(circuit_graph(n, opt), t, std::vector<int>(c.coordinates.begin(), c.coordinates.end()), opt);
    out.certified = out.certified && mo.certain.yes();
    out.decisions_float += static_cast<long>(mo.decisions.size());
    out.has_reduced = true;
    out.coords.assign(mo.coords.begin(), mo.coords.end());
    const double tiny = 1e-13 * (1 + (mo.f_matrix.size() ? mo.f_matrix.cwiseAbs().maxCoeff() : 0.0));  // display: rounding-level as 0
    for (Eigen::Index i = 0; i < mo.f_matrix.rows(); ++i) {
      out.f_matrix.push_back({});
      for (Eigen::Index j = 0; j < mo.f_matrix.cols(); ++j)
        out.f_matrix.back().push_back(float_text(std::abs(mo.f_matrix(i, j)) <= tiny ? 0.0 : mo.f_matrix(i, j)));
      out.f.push_back("0");  // no sources: f = 0 exactly
      out.g.push_back({});
      for (Eigen::Index j = 0; j < mo.g.cols(); ++j) out.g.back().push_back(float_text(mo.g(i, j)));
    }
  }
  to_circuit_units(out, units, n.circuit.branches.size());
  out.decisions_float += static_cast<long>(t.decisions.size());
  out.certified = out.certified && t.certain.yes();
  std::string how = t.physical ? "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision)"
                               : "graph route (CEF §6 closed form in loop coordinates, signed values)";
  how += "; computed on the dimensionless twin (L / 1e" + std::to_string(units.a) + ", C / 1e" + std::to_string(units.b) +
         ", time unit 1e" + std::to_string(units.m()) + " s)";
  if (!dense)
    how += "; equations of motion omitted above " + std::to_string(kDenseBranches) + " branches (dense), see `dcad solve --backend reference`";
  const std::string caveat = fast::input_caveat(opt);
  out.note = how + (out.certified      ? ""
                    : !caveat.empty()  ? "; " + caveat
                                       : "; a rank decision fell between the zero and nonzero thresholds");
  return out;
}

SolveReport solve_circuit_certified(const io::Netlist& n, const io::CaseFile& c, const Parts& parts) {
  io::Units units;
  const io::Netlist twin = io::dimensionless(n, units);  // same graph, values near 1 for the cross-check
  fast::Options opt;
  const fast::CircuitGraph graph = circuit_graph(twin, opt);
  if (n.circuit.branches.size() > kDenseBranches && fast::is_physical(graph)) {
    SolveReport r = solve_circuit_fast(n, c, parts);  // the graph route decides nothing for L, C > 0 (CEF Thms 6.4, 6.6, 6.8)
    r.backend = "certified";
    return r;
  }
  std::function<SolveReport()> small;
  if (3 * n.circuit.branches.size() <= reference::kSmallFirstUpTo) small = [&] { return solve_circuit_small(n, c, parts); };
  SolveReport r = certify(small, [&](double& radius) { return solve_circuit_ball(n, c, radius, parts); },
                          [&] { return solve_circuit_rational(n, c, parts); });
  const fast::CircuitTower t = fast::circuit_tower(graph, opt);
  if (t.physical && t.dims != r.dims)  // a combinatorial theorem disagrees with a certified computation: a bug
    throw std::logic_error("graph route and certified CAD disagree on " + c.file + "; please report it");
  return r;
}

}  // namespace dcad::cli
