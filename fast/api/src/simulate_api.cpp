// dcad::api::simulate: each input form dispatched once, to its integration route.
#include "guarded.hpp"
#include "simulate.hpp"

#include "dcad/reference/pipeline/initial_state.hpp"

namespace dcad::api {

std::vector<std::string> simulate_columns(const io::Problem& p) {
  std::vector<std::string> out{"t"};
  const std::vector<std::string> vars = p.variables();
  out.insert(out.end(), vars.begin(), vars.end());
  return out;
}

namespace {

/// The state a netlist starts from (SPICE's rule, the jump onto M_c), told on `log`; as per-variable
/// values: charges, flux linkages and inductor currents fixed, the other currents left to M_c.
std::vector<std::optional<io::Rational>> netlist_start(const io::Netlist& deck, const std::vector<std::string>& variables, Initial rule,
                                                       std::ostream& log) {
  namespace pl = reference::pipeline;
  const pl::InitialState st =
      pl::initial_state(deck, rule == Initial::op ? pl::InitialRule::op : rule == Initial::uic ? pl::InitialRule::uic : pl::InitialRule::deck, variables);
  log << "initial state: " << st.rule << "\n";
  for (const std::string& note : st.notes) log << "note: " << note << "\n";
  for (const pl::Jump& j : st.jumps)
    log << "jump at t = 0: " << j.variable << " from " << io::float_text(j.from.convert_to<double>()) << " to "
        << io::float_text(j.to.convert_to<double>()) << ", forced by " << j.constraint << "\n";
  if (!st.computed) {  // not moved: the IC= values as constraints on the start, the rest free (uic) — or 0 (op)
    if (rule == Initial::op || (rule == Initial::deck && deck.tran == io::Netlist::Transient::op))
      return std::vector<std::optional<io::Rational>>(st.after.begin(), st.after.end());
    return netlist_initial(deck);
  }
  const std::size_t n = deck.rlc.branches.size();
  std::vector<std::optional<io::Rational>> x(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i)
    if (i < n || i >= 2 * n || deck.rlc.branches[i - n].kind == reference::RlcKind::inductor) x[i] = st.after[i];
  return x;
}

}  // namespace

Simulated simulate(const io::Problem& p, const SimulateOptions& options, std::ostream& csv, std::ostream& log, std::ostream* energy) {
  return guarded(p, [&] {
    if (p.form == io::Form::expression) {  // formulas: RK4 on the pointwise CAD, projected onto M_c
      if (energy) throw UsageError(p.file + ": --energy: expected a netlist with resistors or sources, found the expression form");
      return simulate_lagrangian(p.expression, options, csv, log);
    }
    const bool netlist = p.form == io::Form::netlist;
    const io::CaseFile& c = p.linear;
    const bool forced_deck = netlist && p.netlist.forced, forced_case = !netlist && c.has_pontryagin && c.pontryagin.has_forces;
    if (energy && !forced_deck && !forced_case)
      throw UsageError(p.file + ": --energy: expected a netlist with resistors or sources, found a lossless system (E is conserved)");
    for (const std::string& w : p.warnings()) log << "warning: " << w << "\n";
    std::vector<std::optional<io::Rational>> init(c.n);
    if (netlist) init = netlist_start(p.netlist, c.variables, options.initial, log);
    else if (!c.initial.empty())
      for (std::size_t i = 0; i < c.n; ++i) init[i] = c.initial[i];
    const Summary sum = forced_deck   ? simulate_forced(p.netlist, c, init, options, csv, log, energy)
                        : forced_case ? simulate_forced_case(c, init, options, csv, log, energy)
                                      : simulate_linear(c, netlist ? &p.netlist : nullptr, init, options, csv, log);
    log << "simulate: " << sum.rows << " rows; estimated error " << io::float_text(sum.error_estimate)
        << " relative to the largest magnitude of each variable's kind, at least the state's size in the circuit's natural units (worst " << sum.worst_variable << "; difference from the same exact flow in long double)\n";
    return sum;
  });
}

}  // namespace dcad::api
