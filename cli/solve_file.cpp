#include "solve_file.hpp"

#include "circuit_report.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "solve.hpp"
#include "solve_circuit.hpp"
#include "solve_forced.hpp"
#include "solve_lagrangian.hpp"

#include <algorithm>

namespace dcad::cli {

namespace {

/// The optional keys not asked for, dropped from what a route printed (the routes that do not
/// take `parts` compute them anyway; the linear ones did not compute them).
void keep_parts(nlohmann::json& j, const Parts& parts) {
  if (!parts.final_constraints) j.erase("final_constraints");
  if (!parts.reduced) j.erase("reduced");
  if (!parts.classes) {
    j.erase("constraint_classes");
    j.erase("dirac_bracket");
  }
  if (!parts.adapted) j.erase("adapted");
}

SolvedFile solve_any(const std::string& file, const std::string& backend, const Parts& parts);

}  // namespace

SolvedFile solve_file(const std::string& file, const std::string& backend, const Parts& parts) {
  SolvedFile out = solve_any(file, backend, parts);
  keep_parts(out.json, parts);
  return out;
}

namespace {

SolvedFile solve_any(const std::string& file, const std::string& backend, const Parts& parts) {
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
      r = backend == "fast"        ? solve_circuit_fast(deck, c, parts)
          : backend == "reference" ? solve_circuit_reference(deck, c, parts)
                                   : solve_circuit_certified(deck, c, parts);
    } else {
      r = backend == "reference" ? solve_reference(c, parts) : backend == "fast" ? solve_fast(c, parts) : solve_certified(c, parts);
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

}  // namespace

}  // namespace dcad::cli
