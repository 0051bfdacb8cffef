// The fast twin of the forced route (YM §4).  Positive L, C, R without couplings: the graph route
// (dcad/rlc_graph.hpp), any size, deciding nothing, with the conditions on the sources (±1 rows) decided
// exactly against the waveforms.  Otherwise (couplings, signed values; at most kForcedBranches
// branches): fast::forced_tower on the forced system, built exactly (on the circuit's dimensionless
// twin, dcad/units.hpp) and rounded once — the tower's dims, consistency and solution rank with every
// rank decision's verdict; a source condition found there is not decided against the waveforms: the
// result says so and defers to the exact backends.
#include "dcad/fast/exact.hpp"
#include "dcad/fast/forced.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/rlc.hpp"

namespace dcad::fast {

namespace {

using Q = reference::Rational;

/// A matrix derived exactly from the assessed element values (circuit_options), rounded by exact.hpp's
/// conversion for its range check only: its heights are the values', already read.
MatrixXd rounded(const reference::Matrix<Q>& m) {
  Options range;
  MatrixXd d(m.rows(), m.cols());
  for (reference::Index i = 0; i < m.rows(); ++i)
    for (reference::Index j = 0; j < m.cols(); ++j) d(i, j) = to_double(m(i, j), range);
  return d;
}

/// The input assessment of the fast forced twin: the element values of the (dimensionless) circuit, as
/// the LC route's.  The exact system's matrices are derived from them exactly and rounded once, which
/// is less than computing them in double.
Options circuit_options(const reference::RlcCircuit<Q>& c, const Options& options) {
  std::vector<Q> values;
  for (const auto& b : c.branches)
    if (b.kind == reference::RlcKind::inductor || b.kind == reference::RlcKind::capacitor ||
        b.kind == reference::RlcKind::resistor)
      values.push_back(b.value);
  for (const auto& mu : c.mutuals) values.push_back(mu.m);
  Options opt = options;
  to_double_values(values, opt);
  return opt;
}

/// fast::forced_tower on the exact system rounded to double, with the input's assessment `opt`: a value
/// that rounding may have changed in a decisive digit makes every rank deficiency uncertain (a C of
/// -3.0000000000000000001 beside one of 3 read as their cancellation, certain, and gave a tower two
/// steps too long).
Solution forced_tower_of(const reference::ForcedSystem<Q>& f, const Options& opt) {
  ForcedSystem g;
  g.s.d.n = static_cast<int>(f.s.d.n);
  g.s.d.d = Subspace::span(rounded(f.s.d.d.basis()));
  g.s.hessian = rounded(f.s.hessian);
  g.s.gradient = VectorXd::Zero(f.s.d.n);
  g.force = rounded(f.force);
  g.sources = static_cast<int>(f.sources);
  g.source_force = rounded(f.source_force);
  g.shift = rounded(f.shift);
  g.given_conditions = rounded(f.given_conditions);
  const ForcedResult r = forced_tower(g, opt);
  Solution s;
  for (long d : r.dims) s.tower.push_back({d, {}});
  s.steps = r.steps;
  s.consistent = r.consistent;
  if (r.consistent) s.solution_rank = r.solution_rank;
  s.certified = r.certain;
  if (r.conditions.rows()) s.certified = unknown;  // a condition on the sources, not decided here
  s.decisions.float_tests = static_cast<long>(r.decisions.size());
  append_traced(s.trace, r.decisions, "forced CAD (YM §4)");
  s.note = "forced route, fast twin (double, SVD rank decisions)";
  const std::string caveat = input_caveat(opt);
  if (r.certain.unknown() && !caveat.empty()) s.note += "; " + caveat + ": use --backend certified";
  if (r.certain.unknown() && caveat.empty())
    for (std::size_t i = 0; i < r.decisions.size(); ++i)
      if (r.decisions[i].certain.unknown()) {
        s.note += "; rank decision " + std::to_string(i + 1) + " of " + std::to_string(r.decisions.size()) +
                  " was uncertain (" + r.decisions[i].describe() + "): use --backend certified";
        break;
      }
  if (r.conditions.rows())
    s.note +=
        "; " + std::to_string(r.conditions.rows()) +
        " source condition(s) that the fast backend does not decide against the waveforms: use --backend certified";
  return s;
}

}  // namespace

Solution solve_forced_netlist(const io::Netlist& deck, const std::vector<std::string>& variables,
                              const Options& options) {
  if (reference::pipeline::graph_route_holds(deck.rlc))  // any size, deciding nothing: certified by construction
    return reference::pipeline::graph_solution<double>(
        deck, variables,
        "forced graph route (cycle ranks of subgraphs: C, R > 0 and a positive definite inductance matrix decide "
        "nothing), certified by construction");
  if (deck.rlc.branches.size() > reference::pipeline::kForcedBranches)
    throw io::InputError(deck.file + ": expected at most " + std::to_string(reference::pipeline::kForcedBranches) +
                         " branches for a circuit with a non-positive R or C or an inductance matrix that is not "
                         "positive definite (k = 1, negative L), found " +
                         std::to_string(deck.rlc.branches.size()) +
                         " (the fast route for those is dense; the others take the graph route at any size)");
  const io::Netlist twin = io::dimensionless(deck, io::units_of(deck));  // the dimensionless twin: same tower
  Solution s = forced_tower_of(reference::rlc_system(twin.rlc), circuit_options(twin.rlc, options));
  if (reference::pipeline::rounded_coupling(deck.rlc)) {
    s.certified = unknown;
    s.note += "; " + std::string(reference::pipeline::kRoundedCoupling);
  }
  s.file = deck.file;
  s.name = deck.title;
  s.variables = variables;
  for (const io::Waveform& w : deck.waveforms) s.source_names.push_back(w.element);
  return s;
}

Solution solve_forced_case(const io::CaseFile& c, const Options& options) {
  Options opt = options;  // the case's own numbers, assessed (the matrices are discarded)
  to_fast(c.pontryagin, opt);
  to_double(c.pontryagin.fq, opt);
  to_double(c.pontryagin.fv, opt);
  Solution s = forced_tower_of(reference::pipeline::forced_system(c), opt);
  s.file = c.file;
  s.name = c.name;
  s.variables = c.variables;
  return s;
}

}  // namespace dcad::fast
