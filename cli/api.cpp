// dcad::api (include/dcad/api.hpp): each entry point dispatches the input forms once and maps what the
// readers and solvers throw onto the three error channels.
#include "dcad/api.hpp"

#include "check.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "dcad/io/netlist.hpp"
#include "simulate.hpp"
#include "simulate_forced.hpp"
#include "solve_circuit.hpp"
#include "solve_file.hpp"

#include <ostream>

namespace dcad::api {

namespace {

/// f() with its exceptions on the three channels: the readers' io::InputError as it is (it names the
/// file), a library precondition (std::invalid_argument) on the input prefixed with the file, and
/// anything else an internal error.
template <class F>
auto guarded(const std::string& file, F f) {
  try {
    return f();
  } catch (const InputError&) {
    throw;
  } catch (const UsageError&) {
    throw;
  } catch (const io::InputError& e) {
    throw InputError(e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError(file + ": " + e.what());
  } catch (const std::exception& e) {
    throw InternalError(e.what());
  }
}

void require_backend(const std::string& backend) {
  if (backend != "reference" && backend != "fast" && backend != "certified")
    throw UsageError("backend: expected reference, fast or certified, found \"" + backend + "\"");
}

/// The file as the linear pipelines see it: its netlist (if it is one) and its case.
struct Input {
  bool netlist = false;
  io::Netlist deck;
  io::CaseFile c;
};

Input read_linear(const std::string& file, bool dense_netlist) {
  Input in;
  in.netlist = io::is_netlist_file(file);
  if (in.netlist) in.deck = io::read_netlist(file);
  in.c = in.netlist ? io::netlist_case(in.deck, dense_netlist && in.deck.circuit.branches.size() <= cli::kDenseBranches)
                    : io::read_case(file);
  return in;
}

}  // namespace

int exit_code(const std::exception& e) noexcept {
  if (dynamic_cast<const UsageError*>(&e)) return 2;
  if (dynamic_cast<const std::invalid_argument*>(&e)) return 1;  // InputError, io::InputError
  return 4;
}

Solved solve(const std::string& file, const SolveOptions& options) {
  require_backend(options.backend);
  cli::Parts parts;
  try {
    parts = cli::parse_parts(options.with);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return guarded(file, [&] {
    cli::SolvedFile s = cli::solve_file(file, options.backend, parts);
    return Solved{std::move(s.json), std::move(s.text), std::move(s.warnings)};
  });
}

Checked check(const std::string& result_file, const std::string& file) {
  return guarded(file, [&] {
    const cli::CheckOutcome o = io::is_expression_file(file)
                                    ? cli::check_lagrangian_result(result_file, io::read_lagrangian_case(file))
                                    : [&] {
                                        const Input in = read_linear(file, true);
                                        return cli::check_result(result_file, in.c, in.netlist ? &in.deck : nullptr);
                                      }();
    return Checked{o.disagreements.empty(), o.compared, o.disagreements, o.not_compared};
  });
}

SimulateLayout simulate_layout(const std::string& file) {
  return guarded(file, [&] {
    SimulateLayout out{file, {"t"}};
    std::vector<std::string> vars;
    if (io::is_expression_file(file)) {
      const io::LagrangianCase lc = io::read_lagrangian_case(file);
      vars = lc.system.state_names();
      if (!lc.name.empty()) out.title = lc.name;
    } else {
      const Input in = read_linear(file, false);
      vars = in.c.variables;
      if (!in.c.name.empty()) out.title = in.c.name;
    }
    out.columns.insert(out.columns.end(), vars.begin(), vars.end());
    return out;
  });
}

Simulated simulate(const std::string& file, const SimulateOptions& options, std::ostream& csv, std::ostream& log, std::ostream* energy) {
  require_backend(options.backend);
  const cli::SimulateOptions opt{options.tstop, options.step, options.backend};
  return guarded(file, [&] {
    cli::SimulateSummary sum;
    if (io::is_expression_file(file)) {  // formulas: RK4 on the pointwise CAD, projected onto M_c
      if (energy) throw UsageError(file + ": --energy: expected a netlist with resistors or sources, found the expression form");
      sum = cli::simulate_lagrangian(io::read_lagrangian_case(file), opt, csv, log);
      return Simulated{sum.rows, sum.error_estimate, sum.worst_variable};
    }
    const Input in = read_linear(file, false);
    const bool forced_deck = in.netlist && in.deck.forced, forced_case = !in.netlist && in.c.has_pontryagin && in.c.pontryagin.has_forces;
    if (energy && !forced_deck && !forced_case)
      throw UsageError(file + ": --energy: expected a netlist with resistors or sources, found a lossless system (E is conserved)");
    for (const std::string& w : in.deck.warnings) log << "warning: " << w << "\n";
    std::vector<std::optional<io::Rational>> init(in.c.n);
    if (in.netlist) init = cli::netlist_initial(in.deck);
    else if (!in.c.initial.empty())
      for (std::size_t i = 0; i < in.c.n; ++i) init[i] = in.c.initial[i];
    sum = forced_deck   ? cli::simulate_forced(in.deck, in.c, init, opt, csv, log, energy)
          : forced_case ? cli::simulate_forced_case(in.c, init, opt, csv, log, energy)
                        : cli::simulate(in.c, in.netlist ? &in.deck : nullptr, init, opt, csv, log);
    log << "simulate: " << sum.rows << " rows; estimated error " << cli::float_text(sum.error_estimate)
        << " relative to each variable's largest magnitude (worst " << sum.worst_variable
        << "; difference from the same exact flow in long double)\n";
    return Simulated{sum.rows, sum.error_estimate, sum.worst_variable};
  });
}

}  // namespace dcad::api
