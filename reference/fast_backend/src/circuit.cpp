// The fast twin on an LC netlist: the graph route (fast/circuit.hpp) on the circuit's dimensionless
// twin (dcad/units.hpp, made exactly by dcad::io), mapped back to the circuit's units; the equations of
// motion by fast::circuit_motion up to kDenseBranches branches, the §7 constraints by the generic fast
// pipeline up to kAdaptedBranches.
#include "dcad/fast/circuit_motion.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/io/report.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/reference/pipeline/forced.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dcad::fast {

Solution solve_linear(const io::CaseFile& c, const Parts& parts, const Options& options);
Solution solve_lc_in_range(const io::Netlist& deck, const io::CaseFile& names, const Parts& parts,
                           const Options& options);

namespace {

/// The netlist for the graph route, values rounded to double (opt records whether exactly).
CircuitGraph graph_of(const io::Netlist& n, Options& opt) {
  std::vector<reference::Rational> values;  // of the elements (an empty branch has none)
  for (const auto& b : n.circuit.branches)
    if (b.kind != BranchKind::empty) values.push_back(b.value);
  const std::vector<double> v = to_double_values(values, opt);
  CircuitGraph g;
  g.nodes = n.circuit.nodes;
  std::size_t next = 0;
  for (const auto& b : n.circuit.branches)
    g.branches.push_back({b.kind, b.from, b.to, b.kind == BranchKind::empty ? 0.0 : v[next++]});
  return g;
}

/// A coefficient of the twin in the circuit's units, computed in long double (range 1e±4932) and
/// returned in double; std::invalid_argument (exit 1) when a nonzero coefficient leaves double's range
/// there (a 1e400 F capacitor: 1 / (L C) underflows), never a silent 0 or inf.
double in_units(long double x, const char* what) {
  const double r = static_cast<double>(x);
  if (x != 0 && (r == 0 || !std::isfinite(r)))
    throw std::invalid_argument(
        std::string("expected the circuit's ") + what +
        " within double's range for the fast backend, found one beyond it (the circuit's scales reach "
        "past 1e±308): the exact backends (--backend reference or certified) take any value");
  return r;
}

/// x_j = s_j x̃_j: coefficient a_j of a row in x̃ becomes a_j / s_j in x; the row is then divided by
/// its largest coefficient (in long double, so that a row p = 1e309 v is 1e-309 p − v, in range).
void unscale(Equation<double>& e, const std::vector<long double>& s) {
  std::vector<long double> c;
  long double big = 0;
  for (const auto& [var, coeff] : e.terms) {
    c.push_back(static_cast<long double>(coeff) / s[var]);
    big = std::max(big, std::abs(c.back()));
  }
  if (big == 0) big = 1;
  for (std::size_t k = 0; k < c.size(); ++k) e.terms[k].second = in_units(c[k] / big, "constraint coefficients");
  if (e.rhs != 0) e.rhs = in_units(e.rhs / big, "constraint coefficients");
}

/// The solution of the dimensionless twin in the circuit's units: rows x̃ → x, and the equations of
/// motion dz/dt = (S F̃ S⁻¹ / T) z + S f̃ / T + S G̃ λ / T.
void to_circuit_units(Solution& r, const Units& u, std::size_t branches) {
  const std::vector<long double> s = u.variable_scales(branches, false), s_nu = u.variable_scales(branches, true);
  const long double t = u.time();
  for (Level<double>& level : r.tower)
    for (Equation<double>& e : level.constraints) unscale(e, s);
  if (r.adapted) {
    for (Equation<double>& e : r.adapted->chi) unscale(e, s_nu);
    for (Equation<double>& e : r.adapted->abridged) unscale(e, s_nu);
  }
  if (r.motion) {
    Motion<double>& m = *r.motion;
    for (std::size_t i = 0; i < m.coordinates.size(); ++i) {
      const long double per_time = s[m.coordinates[i]] / t;
      for (std::size_t j = 0; j < m.coordinates.size(); ++j)
        m.f_matrix[i][j] = in_units(m.f_matrix[i][j] * per_time / s[m.coordinates[j]], "equations of motion");
      m.f[i] = in_units(m.f[i] * per_time, "equations of motion");
      for (double& g : m.g[i]) g = in_units(g * per_time, "equations of motion");
    }
  }
}

}  // namespace

namespace {
/// The elements of largest and smallest |value| (L, C), for a message about double's range.
std::string extreme_elements(const io::Netlist& deck) {
  const reference::Branch<reference::Rational>* lo = nullptr;
  const reference::Branch<reference::Rational>* hi = nullptr;
  for (const auto& b : deck.circuit.branches) {
    if (b.kind == BranchKind::empty || b.value == 0) continue;
    if (!hi || abs(b.value) > abs(hi->value)) hi = &b;
    if (!lo || abs(b.value) < abs(lo->value)) lo = &b;
  }
  if (!hi) return "";
  const auto shown = [](const reference::Rational& v) {
    const std::string n = boost::multiprecision::numerator(v).str(), d = boost::multiprecision::denominator(v).str();
    const long digits = static_cast<long>(n.size()) - static_cast<long>(d.size()) - (v < 0 ? 1 : 0);
    if (digits > 300 || digits < -300) return std::string("about 1e") + std::to_string(digits);
    return io::float_text(v.convert_to<double>());
  };
  return " (the circuit's extremes: " + hi->name + " = " + shown(hi->value) + ", " + lo->name + " = " +
         shown(lo->value) + ")";
}
}  // namespace

Solution solve_lc(const io::Netlist& deck, const io::CaseFile& names, const Parts& parts, const Options& options) {
  try {
    return solve_lc_in_range(deck, names, parts, options);
  } catch (const std::invalid_argument& e) {  // double's range: name the elements that leave it
    const std::string what = e.what();
    if (what.find("double's range") == std::string::npos) throw;
    throw std::invalid_argument(what + extreme_elements(deck));
  }
}

/// The tower's decisions: the graph's theorems (positive L, C: no rank decided), or the signed route's ranks.
static std::vector<Decision> tower_trace(const CircuitTower& t, const std::vector<long>& dims) {
  std::vector<Decision> tower =
      t.physical ? exact_trace(dims, DecidedBy::graph, "CEF Thms 6.4, 6.6, 6.8 on the circuit's graph: no rank decided")
                 : std::vector<Decision>{};
  append_traced(tower, t.decisions, "circuit tower (CEF §6, signed values)");
  return tower;
}

Solution solve_lc_in_range(const io::Netlist& deck, const io::CaseFile& names, const Parts& parts,
                           const Options& options) {
  // the twin without units: double sees values near 1 whatever the circuit's units (fF … kH)
  const Units units = io::units_of(deck);
  const io::Netlist n = io::dimensionless(deck, units);
  Options opt = options;
  const CircuitTower t = circuit_tower(graph_of(n, opt), opt);
  const std::size_t branches = n.circuit.branches.size();
  const bool dense = branches <= kDenseBranches;
  Solution out;
  out.certified = yes;  // until a decision below is uncertain
  out.file = deck.file;
  out.name = deck.title;
  out.variables = names.variables;
  if (branches <= kAdaptedBranches && parts.adapted) {  // §7 on T*TQ by the generic fast pipeline
    io::CaseFile twin = io::netlist_case(n, true);
    twin.variables = names.variables;
    const Solution generic = solve_linear(twin, Parts{false, false, false, true}, options);
    out.adapted = generic.adapted;
    out.certified = generic.certified;
    for (Decision d : generic.trace) {
      d.what = "T*TQ (CEF §7): " + d.what;
      out.trace.push_back(d);
    }
  }
  out.steps = t.steps;
  out.consistent = true;  // no sources: x = 0 solves
  out.solution_rank = t.solution_rank;
  for (std::size_t k = 0; k < t.dims.size(); ++k) {
    Level<double> level{t.dims[k], {}};
    for (const SparseRow& row : t.equations[k]) {
      Equation<double> e;
      for (const Term& term : row) e.terms.emplace_back(term.var, term.coeff);
      e.rhs = 0;
      level.constraints.push_back(e);
    }
    out.tower.push_back(level);
  }
  const std::vector<Decision> tower = tower_trace(t, out.dims());  // the tower's decisions come first
  out.trace.insert(out.trace.begin(), tower.begin(), tower.end());
  if (dense && parts.reduced) {  // equations of motion by the structured route (fast/circuit_motion.hpp)
    const CircuitMotion mo =
        circuit_motion(graph_of(n, opt), t, std::vector<int>(names.coordinates.begin(), names.coordinates.end()), opt);
    out.certified &= mo.certain;
    out.decisions.float_tests += static_cast<long>(mo.decisions.size());
    append_traced(out.trace, mo.decisions, "equations of motion on the graph (CEF (5.12))");
    Motion<double> m;
    m.coordinates.assign(mo.coords.begin(), mo.coords.end());
    const double tiny =
        1e-13 * (1 + (mo.f_matrix.size() ? mo.f_matrix.cwiseAbs().maxCoeff() : 0.0));  // display: rounding-level as 0
    for (Eigen::Index i = 0; i < mo.f_matrix.rows(); ++i) {
      m.f_matrix.emplace_back();
      for (Eigen::Index j = 0; j < mo.f_matrix.cols(); ++j)
        m.f_matrix.back().push_back(std::abs(mo.f_matrix(i, j)) <= tiny ? 0.0 : mo.f_matrix(i, j));
      m.f.push_back(0);  // no sources: f = 0
      m.g.emplace_back();
      for (Eigen::Index j = 0; j < mo.g.cols(); ++j) m.g.back().push_back(mo.g(i, j));
    }
    out.motion = m;
  }
  to_circuit_units(out, units, branches);
  if (parts.reduced && reference::pipeline::graph_route_holds(deck.rlc))
    out.state = reference::pipeline::deck_state_equations<double>(deck);
  out.decisions.float_tests += static_cast<long>(t.decisions.size());
  out.certified &= t.certain;
  std::string how = t.physical ? "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision)"
                               : "graph route (CEF §6 closed form in loop coordinates, signed values)";
  how += "; computed on the dimensionless twin (L / 1e" + std::to_string(units.a) + ", C / 1e" +
         std::to_string(units.b) + ", time unit 1e" + std::to_string(units.m()) + " s)";
  if (!dense)
    how += "; the motion in (q, v, p) omitted above " + std::to_string(kDenseBranches) +
           " branches (dense): the state equations hold it at any size";
  const std::string caveat = input_caveat(opt);
  out.note = how + (out.certified.yes() ? ""
                    : !caveat.empty()   ? "; " + caveat
                                        : "; a rank decision fell between the zero and nonzero thresholds");
  return out;
}

}  // namespace dcad::fast
