// `dcad solve FILE` for every input form, in one place: case files (linear Dirac, `pontryagin`,
// `constrained`), `pontryagin` cases with forces (the forced route), the expression form (the
// pointwise CAD), LC and RLC netlists (the circuit routes and the forced route).  Used by the CLI's
// solve, by `dcad cases export/freeze` (their reference results) and by nothing else, so that each
// form is dispatched once.
#pragma once

#include "solve.hpp"

#include <nlohmann/json.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace dcad::cli {

struct SolvedFile {
  nlohmann::json json;                ///< what `--json` prints
  std::string text;                   ///< the report for people
  std::vector<std::string> warnings;  ///< the netlist's (ignored cards …)
};

/// Throws io::InputError (bad input, naming the file) as the readers and solvers do.  `parts`
/// applies to linear case files and netlists; the expression form and the forced route compute
/// everything they report.
SolvedFile solve_file(const std::string& file, const std::string& backend, const Parts& parts = {});

}  // namespace dcad::cli
