#include "solve_file.hpp"

#include "circuit_report.hpp"
#include "lagrangian_case.hpp"
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

int solve_files(const std::vector<std::string>& files, const std::string& backend, const Parts& parts, bool json,
                bool lines, std::ostream& out, std::ostream& err) {
  lines = lines || (json && files.size() > 1);
  int worst = 0;
  for (const std::string& file : files) {
    std::string message;
    int code = 0;
    try {
      const SolvedFile sf = solve_file(file, backend, parts);
      for (const std::string& w : sf.warnings) err << "warning: " << w << "\n";
      if (lines) {
        nlohmann::json j = {{"file", file}};
        j.update(sf.json);
        out << j.dump() << "\n";
      } else {
        out << (json ? sf.json.dump(2) + "\n" : sf.text);
        if (files.size() > 1) out << "\n";
      }
      continue;
    } catch (const io::InputError& e) {
      message = e.what();
      code = 1;
    } catch (const std::invalid_argument& e) {  // a library function's precondition on the input
      message = file + ": " + e.what();
      code = 1;
    } catch (const std::exception& e) {  // an internal invariant: never an answer, never a crash
      message = std::string("dcad: internal error: ") + e.what() + "; please report it with the input";
      code = 4;
    }
    err << message << "\n";
    if (lines) out << nlohmann::json({{"file", file}, {"error", message}, {"exit", code}}).dump() << "\n";
    worst = std::max(worst, code);
  }
  return worst;
}

}  // namespace dcad::cli
