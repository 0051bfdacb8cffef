// dcad::api — the pipeline as a library (issue 15): read an input file (a case file, the expression
// form or a netlist; ../shared/CONTRACT.md), solve it, simulate it, check another implementation's
// result for it against the reference.  The dcad command-line tool is a shell over these functions
// (cli/main.cpp): what it prints, a caller gets as values.
//
// Three error channels, as the CLI's exit codes (CONTRACT; 4 is dcad's own):
//   InputError    — bad input (exit 1): the message names the file, the line or JSON path, what was
//                   expected and what was found;
//   a result      — a case the backend cannot decide is not an error: the result says certified =
//                   false and gives the evidence in "note";
//   UsageError    — options that do not apply (exit 2);
//   InternalError — a broken invariant of dcad (exit 4): never an answer; please report it.
#pragma once

#include <nlohmann/json.hpp>

#include <iosfwd>
#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::api {

struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
struct InternalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The CLI's exit code for an exception these functions throw: 1 input, 2 usage, 4 anything else.
int exit_code(const std::exception& e) noexcept;

struct SolveOptions {
  std::string backend = "certified";  ///< reference | fast | certified
  std::string with = "all";           ///< all | none | a comma list of final, reduced, classes, adapted
};

struct Solved {
  nlohmann::json result;              ///< the result JSON of the CONTRACT (`dcad solve --json`)
  std::string report;                 ///< the report for people (`dcad solve`)
  std::vector<std::string> warnings;  ///< e.g. a netlist's ignored cards
};

/// `dcad solve FILE`: the constraint algorithm on any input form.
Solved solve(const std::string& file, const SolveOptions& options = {});

struct Checked {
  bool agrees = false;                     ///< exit 0 (true) or 3
  std::vector<std::string> compared;       ///< the keys compared
  std::vector<std::string> disagreements;  ///< "key: expected …, found …"
  std::vector<std::string> not_compared;   ///< what the reference has and the result does not say, and why
};

/// `dcad check RESULT FILE`: another implementation's result for FILE against the reference.
/// InputError if RESULT is not a result for FILE.
Checked check(const std::string& result_file, const std::string& file);

struct SimulateOptions {
  double tstop = 0, step = 0;  ///< seconds (or the case's time unit); 0 < step, 0 ≤ tstop
  std::string backend = "certified";
};

struct Simulated {
  long rows = 0;
  double error_estimate = 0;   ///< largest |double − long double| over the run, relative to each variable's magnitude
  std::string worst_variable;  ///< where it is largest
};

struct SimulateLayout {
  std::string title;                 ///< the case's name, else the file
  std::vector<std::string> columns;  ///< the CSV header `simulate` writes: t and every variable
};

/// What `simulate` will write for FILE, without running it (reads FILE; InputError).
SimulateLayout simulate_layout(const std::string& file);

/// `dcad simulate FILE`: the motion from the file's initial condition on M_c, one CSV row per output
/// step to `csv` as it is computed; warnings, notes and the run's summary to `log`.  With `energy`
/// (systems with resistors, sources or forces only; UsageError otherwise), the energy balance per row.
Simulated simulate(const std::string& file, const SimulateOptions& options, std::ostream& csv, std::ostream& log,
                   std::ostream* energy = nullptr);

}  // namespace dcad::api
