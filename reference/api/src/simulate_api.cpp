// dcad::api::simulate: each input form dispatched once, to its integration route.
#include "guarded.hpp"
#include "simulate.hpp"

#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/initial_state.hpp"

#include <algorithm>
#include <exception>
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
  const pl::InitialState st = pl::initial_state(deck, rule, variables);
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

/// Keeps t and the columns `names` of the rows passed through it (the dense routes write every variable; --vars
/// picks some).  simulate() has checked the names against the problem's columns.
class ColumnFilter final : public RowSink {
 public:
  ColumnFilter(RowSink& out, std::vector<std::string> names) : out_(out), names_(std::move(names)) {}
  void header(const std::vector<std::string>& all) override {
    keep_ = {0};
    for (const std::string& n : names_)
      keep_.push_back(static_cast<std::size_t>(std::find(all.begin(), all.end(), n) - all.begin()));
    out_.header(pick(all));
  }
  void row(const std::vector<double>& values) override { out_.row(pick(values)); }
  void flush() override { out_.flush(); }

 private:
  template <class T>
  std::vector<T> pick(const std::vector<T>& all) const {
    std::vector<T> out;
    for (std::size_t k : keep_)
      if (k < all.size()) out.push_back(all[k]);
    return out;
  }
  RowSink& out_;
  std::vector<std::string> names_;
  std::vector<std::size_t> keep_;
};

/// The caller's sink, its exceptions carried past guarded() unchanged: a sink that stops the run by throwing gets
/// its own exception back, not an InternalError.
struct SinkStopped {};  // not a std::exception: guarded() lets it through
class Relay final : public RowSink {
 public:
  explicit Relay(RowSink& to) : to_(to) {}
  void header(const std::vector<std::string>& names) override {
    relay([&] { to_.header(names); });
  }
  void row(const std::vector<double>& values) override {
    relay([&] { to_.row(values); });
  }
  void flush() override {
    relay([&] { to_.flush(); });
  }
  std::exception_ptr thrown;

 private:
  template <class F>
  void relay(F f) {
    try {
      f();
    } catch (...) {
      thrown = std::current_exception();
      throw SinkStopped{};
    }
  }
  RowSink& to_;
};

/// Keeps every row: simulate_trajectory's sink.
class Collect final : public RowSink {
 public:
  explicit Collect(Trajectory& t) : t_(t) {}
  void header(const std::vector<std::string>& names) override { t_.names = names; }
  void row(const std::vector<double>& values) override { t_.rows.push_back(values); }

 private:
  Trajectory& t_;
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

/// The case forms with formulas: a DAE (the exact velocities on M_c, Dormand–Prince), an implicit system (RK4 on
/// the pointwise CEF (1.6), projected onto M_c) or an expression-form system (RK4 on the pointwise CAD, projected).
Summary simulate_formulas(const io::Problem& p, const SimulateOptions& options, RowSink& rows, std::ostream& log,
                          std::ostream* energy) {
  const std::string form = p.form() == io::Form::dae        ? "dae"
                           : p.form() == io::Form::implicit ? "implicit"
                                                            : "expression";
  if (energy)
    throw UsageError(p.file + ": --energy: expected a netlist with resistors or sources, found the " + form + " form");
  if (p.form() != io::Form::expression && (options.route == Route::sparse || options.enclose))
    throw UsageError(p.file + ": --route sparse and --enclose: expected a netlist, found the " + form + " form");
  if (options.route == Route::sparse)
    throw UsageError(p.file + ": --route sparse: expected a netlist, found a case file");
  if (p.form() == io::Form::dae) return simulate_dae(p.dae(), options, rows, log);
  if (p.form() == io::Form::implicit) return simulate_implicit(p.expression(), options, rows, log);
  return simulate_lagrangian(p.expression(), options, rows, log);
}

}  // namespace

Simulated simulate(const io::Problem& p, const SimulateOptions& options, std::ostream& csv, std::ostream& log,
                   std::ostream* energy) {
  CsvRows rows(csv);
  const Simulated sum = simulate(p, options, rows, log, energy);
  csv.flush();
  return sum;
}

Trajectory simulate_trajectory(const io::Problem& p, const SimulateOptions& options, std::ostream& log) {
  Trajectory t;
  Collect rows(t);
  t.summary = simulate(p, options, rows, log);
  return t;
}

std::vector<double> Trajectory::column(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::out_of_range("Trajectory::column: expected one of its names, found " + name);
  const auto k = static_cast<std::size_t>(it - names.begin());
  std::vector<double> out;
  out.reserve(rows.size());
  for (const std::vector<double>& r : rows) out.push_back(r.at(k));
  return out;
}

namespace {
Simulated simulate_guarded(const io::Problem& p, const SimulateOptions& options, RowSink& csv, std::ostream& log,
                           std::ostream* energy);
}  // namespace

Simulated simulate(const io::Problem& p, const SimulateOptions& options, RowSink& sink, std::ostream& log,
                   std::ostream* energy) {
  Relay relay(sink);
  try {
    return simulate_guarded(p, options, relay, log, energy);
  } catch (const SinkStopped&) {
    std::rethrow_exception(relay.thrown);
  }
}

namespace {

Simulated simulate_guarded(const io::Problem& p, const SimulateOptions& options, RowSink& csv, std::ostream& log,
                           std::ostream* energy) {
  return guarded(p, [&] {
    io::validate(p);
    if (p.form() == io::Form::netlist && !p.netlist().indefinite_inductance.empty())
      throw io::InputError(
          p.netlist().indefinite_inductance +
          "; simulate: expected a positive semidefinite inductance matrix, found another (lower the couplings)");
    if (!options.columns.empty()) {  // checked before any row is computed
      std::vector<std::string> all = simulate_columns(p);
      if (options.enclose) all.insert(all.end(), {"rad_q", "rad_v", "rad_p"});
      for (const std::string& n : options.columns)
        if (n == "t" || std::find(all.begin(), all.end(), n) == all.end())
          throw UsageError("--vars: expected variables of " + p.file + ", found " + n);
    }
    ColumnFilter filtered(csv, options.columns);
    RowSink& rows = options.columns.empty() ? csv : filtered;
    if (p.form() == io::Form::dae || p.form() == io::Form::implicit || p.form() == io::Form::expression)
      return simulate_formulas(p, options, rows, log, energy);
    const bool netlist = p.form() == io::Form::netlist;
    if (netlist)
      if (const auto which = io::without_exact_flow(p.netlist().waveforms))
        throw io::InputError(p.file +
                             ": simulate: expected continuous sources with a finite exosystem (DC, SIN, PULSE, PWL, "
                             "EXP), found " +
                             *which +
                             ": solve decides its circuit; write the waveform as a continuous PWL(t1 v1 t2 v2 …) to "
                             "simulate it");
    const io::CaseFile& c = p.linear();
    const bool forced_deck = netlist && p.netlist().forced,
               forced_case = !netlist && c.has_pontryagin && c.pontryagin.has_forces;
    if (energy && !forced_deck && !forced_case && !(netlist && sparse_netlist(p.netlist(), options)))
      throw UsageError(
          p.file +
          ": --energy: expected a netlist with resistors or sources, found a lossless system (E is conserved)");
    for (const std::string& w : p.warnings()) log << "warning: " << w << "\n";
    if (!netlist && options.route == Route::sparse)
      throw UsageError(p.file + ": --route sparse: expected a netlist, found a case file");
    if (netlist && sparse_netlist(p.netlist(), options) && !options.enclose) {
      const Summary sum = simulate_sparse(p.netlist(), c, options, csv, log, energy);
      log << "simulate: " << sum.rows << " rows; estimated error " << io::float_text(sum.error_estimate) << " ("
          << sum.estimate_kind << ")\n";
      return sum;
    }
    if (options.enclose) {
      if (!netlist)
        throw UsageError(p.file +
                         ": --certified: expected a netlist, found a case file (enclosures are built for circuits)");
      if (energy) throw UsageError(p.file + ": --certified and --energy: expected one of them");
      return simulate_enclosed(p.netlist(), c, options, rows, log);
    }
    std::vector<std::optional<io::Rational>> init(c.n);
    if (netlist) init = netlist_start(p.netlist(), c.variables, options.initial, log);
    if (!c.initial.empty())
      for (std::size_t i = 0; i < c.n; ++i) init[i] = c.initial[i];
    const Summary sum = forced_deck   ? simulate_forced(p.netlist(), c, init, options, rows, log, energy)
                        : forced_case ? simulate_forced_case(c, init, options, rows, log, energy)
                                      : simulate_linear(c, netlist ? &p.netlist() : nullptr, init, options, rows, log);
    log << "simulate: " << sum.rows << " rows; estimated error " << io::float_text(sum.error_estimate)
        << " relative to the largest magnitude of each variable's kind, at least the state's size in the circuit's "
           "natural units (worst "
        << sum.worst_variable << "; difference from the same exact flow in long double)\n";
    return sum;
  });
}

}  // namespace

}  // namespace dcad::api
