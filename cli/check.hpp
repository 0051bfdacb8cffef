// `dcad check RESULT.json FILE` (CONTRACT): another implementation's result for FILE against the
// reference.  Discrete keys exactly; richer optional keys (`final_constraints`, `reduced`,
// `dirac_bracket`) as subspaces or within a condition-aware tolerance (documented in the README).
#pragma once

#include "dcad/io/netlist.hpp"
#include "solve.hpp"
#include "dcad/io/lagrangian_case.hpp"

#include <ostream>

namespace dcad::cli {

struct CheckOutcome {
  std::vector<std::string> compared;       ///< the keys that were compared
  std::vector<std::string> disagreements;  ///< "key: expected …, found …"
  std::vector<std::string> not_compared;   ///< what the reference has and the result does not say, and why
};

/// RESULT read (exactly, depth-limited) with its required keys and their types checked:
/// io::InputError (exit 1, naming the JSON path) otherwise.
nlohmann::json read_result(const std::string& result_file);

/// Throws io::InputError (exit 1) for a RESULT that is not a result for this case: missing required
/// keys (dims, steps, consistent, solution_rank), wrong types, another case's name or variables.
CheckOutcome check_result(const std::string& result_file, const io::CaseFile& c, const io::Netlist* deck);

/// The expression form: the discrete keys against the reference at the case's own point; if the
/// result gives `point` and `velocity`, its velocity against the reference's at that point (exact
/// if every number is), modulo the gauge directions.  A point off M_c is a disagreement.
CheckOutcome check_lagrangian_result(const std::string& result_file, const io::LagrangianCase& c);

}  // namespace dcad::cli
