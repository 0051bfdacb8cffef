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

/// `dcad solve FILE…`: each file solved in this one process, in order.  One file: the report, or
/// with `json` the result JSON (indented).  With `lines` (or `json` and several files): one compact
/// JSON object per file and line, with "file"; a file that fails gives {"file", "error", "exit"}
/// and the others still run.  Returns the exit code: 0, else the largest of a file's (1 bad input,
/// 4 internal error); messages go to `err` as for one file.
int solve_files(const std::vector<std::string>& files, const std::string& backend, const Parts& parts, bool json,
                bool lines, std::ostream& out, std::ostream& err);

}  // namespace dcad::cli
