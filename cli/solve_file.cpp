#include "solve_file.hpp"

#include "circuit_report.hpp"
#include "lagrangian_case.hpp"
#include "solve.hpp"
#include "solve_circuit.hpp"
#include "solve_forced.hpp"
#include "solve_lagrangian.hpp"

namespace dcad::cli {

SolvedFile solve_file(const std::string& file, const std::string& backend) {
  SolvedFile out;
  if (io::is_expression_file(file)) {  // formulas: the pointwise CAD
    const io::LagrangianCase lc = io::read_lagrangian_case(file);
    const LagrangianReport lr = solve_lagrangian(lc, backend);
    out.json = to_json(lr, lc);
    out.text = to_text(lr, lc);
    return out;
  }
  const bool netlist = io::is_netlist_file(file);
  const io::Netlist deck = netlist ? io::read_netlist(file) : io::Netlist();
  const bool dense = !netlist || deck.circuit.branches.size() <= kDenseBranches;
  const io::CaseFile c = netlist ? io::netlist_case(deck, dense) : io::read_case(file);
  out.warnings = deck.warnings;
  if ((netlist && deck.forced) || (!netlist && c.has_pontryagin && c.pontryagin.has_forces)) {  // the forced route (YM §4)
    const ForcedReport fr = netlist ? solve_forced(deck, backend) : solve_forced_case(c, backend);
    out.json = to_json(fr, c);
    out.text = to_text(fr, c);
    return out;
  }
  SolveReport r;
  try {
    if (netlist) {  // the circuit routes (CEF §6): structured exact / ball, graph route + fast
      r = backend == "fast"        ? solve_circuit_fast(deck, c)
          : backend == "reference" ? solve_circuit_reference(deck, c)
                                   : solve_circuit_certified(deck, c);
    } else {
      r = backend == "reference" ? solve_reference(c) : backend == "fast" ? solve_fast(c) : solve_certified(c);
    }
  } catch (const io::InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw io::InputError(file + ": " + (c.has_pontryagin ? "/pontryagin" : c.has_constrained ? "/constrained" : c.dirac.path) + ": " + e.what());
  }
  out.json = to_json(r, c);
  out.text = to_text(r, c);
  if (netlist) {
    out.json["circuit"] = circuit_json(deck, r);
    out.text += circuit_text(deck, r);
  }
  return out;
}

}  // namespace dcad::cli
