// dcad::api::simulate: each input form dispatched once, to its integration route.
#include "guarded.hpp"
#include "simulate.hpp"

#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/initial_state.hpp"

#include <algorithm>
#include <map>
#include <streambuf>

namespace dcad::api {

std::vector<std::string> simulate_columns(const io::Problem& p) {
  std::vector<std::string> out{"t"};
  const std::vector<std::string> vars = p.variables();
  out.insert(out.end(), vars.begin(), vars.end());
  return out;
}

/// The state a netlist starts from (SPICE's rule, the jump onto M_c), told on `log`; as per-variable
/// values: charges, flux linkages and inductor currents fixed, the other currents left to M_c.
std::vector<std::optional<io::Rational>> netlist_start(const io::Netlist& deck,
                                                       const std::vector<std::string>& variables, Initial rule,
                                                       std::ostream& log, long* jumps,
                                                       std::vector<std::string>* jumped) {
  namespace pl = reference::pipeline;
  const pl::InitialState st = pl::initial_state(deck,
                                                rule == Initial::op    ? pl::InitialRule::op
                                                : rule == Initial::uic ? pl::InitialRule::uic
                                                                       : pl::InitialRule::deck,
                                                variables);
  log << "initial state: " << st.rule << "\n";
  if (jumps) *jumps = static_cast<long>(st.jumps.size());
  if (jumped)
    for (const pl::Jump& j : st.jumps) jumped->push_back(j.variable);
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

namespace {

/// Keeps the CSV columns t and `names` of every line written through it (the dense routes write every
/// variable; --vars picks some).  The header line maps the names; UsageError for one not in it.
class ColumnFilter : public std::streambuf {
 public:
  ColumnFilter(std::ostream& out, std::vector<std::string> names, std::string file)
      : out_(out), names_(std::move(names)), file_(std::move(file)) {}

 protected:
  int overflow(int ch) override {
    if (ch == traits_type::eof()) return 0;
    if (ch != '\n') {
      line_ += static_cast<char>(ch);
      return ch;
    }
    fields_.clear();
    std::size_t start = 0;
    while (true) {
      const std::size_t comma = line_.find(',', start);
      fields_.push_back(line_.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (keep_.empty()) {
      std::map<std::string, std::size_t> at;
      for (std::size_t i = 0; i < fields_.size(); ++i) at[fields_[i]] = i;
      keep_.push_back(0);
      for (const std::string& n : names_) {
        const auto it = at.find(n);
        if (it == at.end()) throw UsageError("--vars: expected variables of " + file_ + ", found " + n);
        keep_.push_back(it->second);
      }
    }
    std::string o;
    for (std::size_t i = 0; i < keep_.size(); ++i) {
      if (i) o += ',';
      if (keep_[i] < fields_.size()) o += fields_[keep_[i]];
    }
    o += '\n';
    out_ << o;
    line_.clear();
    return ch;
  }

 private:
  std::ostream& out_;
  std::vector<std::string> names_;
  std::string file_, line_;
  std::vector<std::string> fields_;
  std::vector<std::size_t> keep_;
};

/// Whether a netlist goes to the sparse route: asked for, or beyond the dense route's size where the
/// sparse route holds.
bool sparse_netlist(const io::Netlist& d, const SimulateOptions& opt) {
  if (opt.route == Route::sparse) return true;
  if (opt.route == Route::dense) return false;
  const std::size_t n = d.rlc.branches.size();
  const bool beyond = d.forced ? n > reference::pipeline::kForcedBranches : n > kSimulateBranches;
  return beyond && sparse_route_takes(d);
}

}  // namespace

Simulated simulate(const io::Problem& p, const SimulateOptions& options, std::ostream& csv, std::ostream& log,
                   std::ostream* energy) {
  return guarded(p, [&] {
    io::validate(p);
    if (p.form == io::Form::netlist && !p.netlist.indefinite_inductance.empty())
      throw io::InputError(
          p.netlist.indefinite_inductance +
          "; simulate: expected a positive semidefinite inductance matrix, found another (lower the couplings)");
    if (!options.columns.empty()) {  // checked here: the filter sits inside a stream, whose errors are not exceptions
      std::vector<std::string> all = simulate_columns(p);
      if (options.enclose) all.insert(all.end(), {"rad_q", "rad_v", "rad_p"});
      for (const std::string& n : options.columns)
        if (n == "t" || std::find(all.begin(), all.end(), n) == all.end())
          throw UsageError("--vars: expected variables of " + p.file + ", found " + n);
    }
    ColumnFilter filter(csv, options.columns, p.file);
    std::ostream filtered(&filter);
    std::ostream& rows = options.columns.empty() ? csv : filtered;
    if (p.form == io::Form::dae) {  // the exact velocities on M_c, Dormand–Prince
      if (energy)
        throw UsageError(p.file + ": --energy: expected a netlist with resistors or sources, found the dae form");
      if (options.route == Route::sparse || options.enclose)
        throw UsageError(p.file + ": --route sparse and --enclose: expected a netlist, found the dae form");
      const Summary sum = simulate_dae(p.dae, options, rows, log);
      rows.flush();
      return sum;
    }
    if (p.form == io::Form::implicit) {  // RK4 on the pointwise CEF (1.6), projected onto M_c
      if (energy)
        throw UsageError(p.file + ": --energy: expected a netlist with resistors or sources, found the implicit form");
      if (options.route == Route::sparse || options.enclose)
        throw UsageError(p.file + ": --route sparse and --enclose: expected a netlist, found the implicit form");
      const Summary sum = simulate_implicit(p.expression, options, rows, log);
      rows.flush();
      return sum;
    }
    if (p.form == io::Form::expression) {  // formulas: RK4 on the pointwise CAD, projected onto M_c
      if (energy)
        throw UsageError(p.file +
                         ": --energy: expected a netlist with resistors or sources, found the expression form");
      if (options.route == Route::sparse)
        throw UsageError(p.file + ": --route sparse: expected a netlist, found a case file");
      const Summary sum = simulate_lagrangian(p.expression, options, rows, log);
      rows.flush();
      return sum;
    }
    const bool netlist = p.form == io::Form::netlist;
    if (netlist)
      if (const auto which = io::without_exosystem(p.netlist.waveforms))
        throw io::InputError(p.file +
                             ": simulate: expected sources with a finite exosystem (DC, SIN, PULSE, PWL, EXP), found " +
                             *which +
                             ", frequency modulated: solve decides its circuit; write the waveform as PWL(t1 v1 t2 v2 "
                             "…) to simulate it");
    const io::CaseFile& c = p.linear;
    const bool forced_deck = netlist && p.netlist.forced,
               forced_case = !netlist && c.has_pontryagin && c.pontryagin.has_forces;
    if (energy && !forced_deck && !forced_case && !(netlist && sparse_netlist(p.netlist, options)))
      throw UsageError(
          p.file +
          ": --energy: expected a netlist with resistors or sources, found a lossless system (E is conserved)");
    for (const std::string& w : p.warnings()) log << "warning: " << w << "\n";
    if (!netlist && options.route == Route::sparse)
      throw UsageError(p.file + ": --route sparse: expected a netlist, found a case file");
    if (netlist && sparse_netlist(p.netlist, options) && !options.enclose) {
      const Summary sum = simulate_sparse(p.netlist, c, options, csv, log, energy);
      log << "simulate: " << sum.rows << " rows; estimated error " << io::float_text(sum.error_estimate) << " ("
          << sum.estimate_kind << ")\n";
      return sum;
    }
    if (options.enclose) {
      if (!netlist)
        throw UsageError(p.file +
                         ": --certified: expected a netlist, found a case file (enclosures are built for circuits)");
      if (energy) throw UsageError(p.file + ": --certified and --energy: expected one of them");
      const Summary sum = simulate_enclosed(p.netlist, c, options, rows, log);
      rows.flush();
      return sum;
    }
    std::vector<std::optional<io::Rational>> init(c.n);
    if (netlist) init = netlist_start(p.netlist, c.variables, options.initial, log);
    if (!c.initial.empty())
      for (std::size_t i = 0; i < c.n; ++i) init[i] = c.initial[i];
    const Summary sum = forced_deck   ? simulate_forced(p.netlist, c, init, options, rows, log, energy)
                        : forced_case ? simulate_forced_case(c, init, options, rows, log, energy)
                                      : simulate_linear(c, netlist ? &p.netlist : nullptr, init, options, rows, log);
    rows.flush();
    log << "simulate: " << sum.rows << " rows; estimated error " << io::float_text(sum.error_estimate)
        << " relative to the largest magnitude of each variable's kind, at least the state's size in the circuit's "
           "natural units (worst "
        << sum.worst_variable << "; difference from the same exact flow in long double)\n";
    return sum;
  });
}

}  // namespace dcad::api
