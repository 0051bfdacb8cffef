// `dcad cases list|show|export|freeze`: the golden corpus (cases/) for other projects, and the
// regression workflow (a property-test counterexample → a golden case with reference expectations).
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace dcad::cli {

/// The corpus directory: $DCAD_CASES, else the source tree's cases/ (compiled in).
std::string cases_dir();

/// list; show NAME; export DIR (every case + NAME.expected.json from the reference + the schema);
/// freeze FILE [NAME] (FILE: a case file, a netlist, or a property log with a "dcad case: {…}"
/// line; writes cases/NAME.json|.cir with the reference's expectations).  Returns the exit code;
/// throws io::InputError for bad input.
int cases_command(const std::string& action, const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace dcad::cli
