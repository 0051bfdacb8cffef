// dcad::api — everything the dcad tool does, as a library (issue 26): a Problem in (dcad::io reads any
// input form, from a file or from text), a typed Solution out, by the backend asked for; `dcad check`,
// `simulate`, `inspect` and the golden corpus.  The tool (cli/main.cpp) only parses arguments, prints
// and sets exit codes.  Each twin's own solve is a library call too: reference::solve
// (dcad/reference/solve.hpp), fast::solve (dcad/fast/solve.hpp), certified::solve
// (dcad/certified/solve.hpp); text and JSON are written by dcad/io/report.hpp.
//
// Three error channels, as the CLI's exit codes (CONTRACT; 4 is dcad's own):
//   io::InputError — bad input (exit 1): the message names the file, the line or JSON path, what was
//                    expected and what was found;
//   a result       — a case a backend cannot decide is not an error: the solution says certified
//                    unknown and gives the evidence in `note`;
//   UsageError     — options that do not apply (exit 2);
//   InternalError  — a broken invariant of dcad (exit 4): never an answer; please report it.
#pragma once

#include "dcad/certified/solve.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/initial_rule.hpp"
#include "dcad/inspection.hpp"
#include "dcad/io/problem.hpp"
#include "dcad/io/report.hpp"
#include "dcad/io/traces.hpp"
#include "dcad/reference/solve.hpp"

#include <iosfwd>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

namespace dcad::api {

using io::InputError;
struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};
struct InternalError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The CLI's exit code for an exception these functions throw: 1 input, 2 usage, 4 anything else.
int exit_code(const std::exception& e) noexcept;

using dcad::Backend;  // certified, reference, fast (dcad/backend.hpp)
/// "certified", "reference" or "fast" (UsageError otherwise).
Backend backend_named(const std::string& name);
/// `--with`: "all", "none" or a comma-separated list of final, reduced, classes, adapted (UsageError otherwise).
Parts parts_named(const std::string& list);

/// A solution of one backend, typed by its numbers: exact rationals, doubles, or certified numbers.
using Solved = std::variant<reference::Solution, fast::Solution, certified::Solution>;

/// The CAD of any problem by one backend.  `certified` answers by double precision (not certified,
/// and its note says why) only where no exact tier can run: the expression form at a point where a
/// formula is irrational.
Solved solve(const io::Problem& p, Backend backend, const Parts& parts = {});
/// The solution with its numbers printed by its own twin's printer (for io::result_json, io::report_text).
io::Printed printed(const Solved& s);

/// `dcad check RESULT FILE`: another implementation's result for the problem against the reference.
struct Checked {
  bool agrees = false;                     ///< exit 0 (true) or 3
  std::vector<std::string> compared;       ///< the keys compared
  std::vector<std::string> disagreements;  ///< "key: expected …, found …"
  std::vector<std::string> not_compared;   ///< what the reference has and the result does not say, and why
};
/// InputError if the result file is not a result for this problem.  A result with `formulas` (another
/// tool's constraints and equations of motion for an expression-form case) is compared with dcad's
/// chart at `points` points of M_c (CONTRACT "Formulas for nonlinear results").
Checked check(const std::string& result_file, const io::Problem& p, std::size_t points = 20);
/// The same for a result given as JSON text (`name` stands for it in messages): no file needed.
Checked check_text(const std::string& result_json, const io::Problem& p, const std::string& name = "<result>",
                   std::size_t points = 20);

/// `dcad inspect`: what the problem's Dirac structure is (a `dirac` case; InputError otherwise).
Inspection inspect(const io::Problem& p, Backend backend);

/// Where a netlist starts (CONTRACT "Circuit initial state"): as its `.tran` says (uic, or the DC
/// operating point without it; no `.tran`: uic), or forced by `--initial op|uic`.
using Initial = InitialRule;  // deck, op, uic (dcad/initial_rule.hpp)
/// Netlists: the dense route (the exact model's matrix exponential: ≤ 60 branches with R, sources or
/// couplings, ≤ 400 LC) or the sparse one (any size where every R, L, C > 0 and |k| < 1: Krylov on the
/// sparse equations of motion); automatic takes the dense route where it fits.
enum class Route { automatic, dense, sparse };
struct SimulateOptions {
  double tstop = 0, step = 0;  ///< seconds (or the case's time unit); 0 < step, 0 ≤ tstop
  Backend backend = Backend::certified;
  Initial initial = Initial::deck;
  Route route = Route::automatic;
  std::vector<std::string>
      columns;  ///< the CSV's variables after t (empty: every variable); UsageError for a name not in the problem
  bool enclose =
      false;  ///< netlists: rigorous enclosures (Arb balls on the exact model); columns rad_q, rad_v, rad_p added
};
struct Simulated {
  long rows = 0;
  double error_estimate =
      0;  ///< largest |double − long double| over the run, relative to the scale of each variable's kind
  std::string worst_variable;  ///< where it is largest
  std::string estimate_kind;   ///< what error_estimate measures (empty: the long-double shadow's difference)
};
/// Where `simulate` puts its motion as it computes it: the names once (t, the variables or those of
/// SimulateOptions::columns, then rad_q, rad_v, rad_p with `enclose`), then one row per output step (t first, as
/// many values as names).  The tool's sink writes the CONTRACT's CSV; a Trajectory keeps the doubles; a caller's
/// own sink may do anything else with them, and stop the run by throwing: its exception reaches simulate's caller
/// as it was thrown.
class RowSink {
 public:
  virtual ~RowSink() = default;
  virtual void header(const std::vector<std::string>& names) = 0;
  virtual void row(const std::vector<double>& values) = 0;
  /// After a row that was slow to compute (the ODE routes): a stream passes it on at once.
  virtual void flush() {}
};
/// A run's motion as doubles: the typed form of simulate's CSV, row for row.
struct Trajectory {
  std::vector<std::string> names;         ///< simulate's CSV header (RowSink::header)
  std::vector<std::vector<double>> rows;  ///< one per output step: t, then each variable's value
  Simulated summary;                      ///< the run's error estimate
  /// The values of one name over the run, row by row; std::out_of_range for a name it does not have.
  std::vector<double> column(const std::string& name) const;
};

/// The CSV header `simulate` writes for the problem: t and every variable.
std::vector<std::string> simulate_columns(const io::Problem& p);
/// `dcad simulate`: the motion from the problem's initial condition on M_c, one CSV row per output step
/// to `csv` as it is computed; warnings, notes and the run's summary to `log`.  With `energy` (systems
/// with resistors, sources or forces only; UsageError otherwise), the energy balance per row.
Simulated simulate(const io::Problem& p, const SimulateOptions& options, std::ostream& csv, std::ostream& log,
                   std::ostream* energy = nullptr);
/// The same run into `rows`, a caller's sink (the header, then each row as it is computed).
Simulated simulate(const io::Problem& p, const SimulateOptions& options, RowSink& rows, std::ostream& log,
                   std::ostream* energy = nullptr);
/// The same run kept as a Trajectory (every row in memory: mind tstop/step × the variables).
Trajectory simulate_trajectory(const io::Problem& p, const SimulateOptions& options, std::ostream& log);

/// `dcad check WAVEFORM DECK` (CONTRACT "Checking a simulator's waveform"): another simulator's
/// transient output against DECK's exact flow from the state the simulator started from, at the file's
/// own time points.
struct WaveformOptions {
  double rtol = 1e-3, atol = 0;  ///< a vector agrees where |found − exact| ≤ atol + rtol · max |exact| over the run
  Initial initial = Initial::deck;
  bool keep_exact = false;  ///< also return the exact values at every time point (for a plot)
  bool enclose = true;      ///< build rigorous enclosures where dcad can (certified: true); false: the double flow only
};
struct WaveformVector {
  std::string name;      ///< as the file names it
  std::string meaning;   ///< what dcad computes for it: "e(n1) - e(n2)", "current of L1 (n+ to n-)", …
  double max_error = 0;  ///< largest |found − exact| over the compared points
  double at = 0;         ///< its time
  double exact = 0, found = 0;
  double scale = 0;  ///< max |exact| over the run (its kind's largest, for a vector near 0: kind_scale)
  bool kind_scale =
      false;  ///< the vector's largest |exact| is below 1e-12 of its kind's, which is its scale (CONTRACT)
  bool agree = true;
  bool at_corner = false;    ///< the worst point is a source corner (either one-sided value was allowed)
  long skipped_at_jump = 0;  ///< points at t = 0 after a jump onto M_c, not compared
  /// how far dcad's own value may be off: the flow's error estimate times the largest value of the
  /// vector's kind over the run (every node potential for a voltage, every branch current for a
  /// current …)
  double exact_uncertainty = 0;
  /// false when the difference lies within exact_uncertainty of the tolerance: dcad cannot tell (then
  /// agree is false too — an exit 0 is never a guess — and the report says to raise --atol)
  bool decided = true;
};
struct WaveformChecked {
  bool agree = true;             ///< exit 0 (true) or 3
  bool certified = false;        ///< every exact value a rigorous enclosure
  std::string certified_reason;  ///< why not
  std::string format;            ///< the file's format
  long points = 0;               ///< time points in the file
  double error_estimate = 0;     ///< the exact flow's own error estimate (relative to the state)
  /// the variables (q_C, v_L, p_L) that jump onto M_c at t = 0, decided on the exact model (the dense
  /// route's rationals up to kForcedBranches branches; beyond it the loops and cutsets that can move them)
  std::vector<std::string> jumped;
  double first_after_zero = 0;  ///< the file's first time after 0
  std::vector<WaveformVector> vectors;
  std::size_t worst = 0;  ///< the vector with the largest error relative to its scale (what --plot draws by default)
  std::vector<std::vector<double>>
      exact;  ///< with keep_exact: exact[k][i], vector k at the file's time i (the value compared)
};
/// InputError for an unreadable file, a vector name that DECK cannot map, or a circuit outside the
/// route that evaluates its flow.
WaveformChecked check_waveform(const io::Traces& traces, const io::Problem& p, const WaveformOptions& options,
                               std::ostream& log);
/// The same on a stream of points (io::open_traces: an ngspice binary raw file is read from disk in chunks,
/// so memory does not grow with the file; it is read once per precision of the enclosures).
WaveformChecked check_waveform(io::TraceStream& traces, const io::Problem& p, const WaveformOptions& options,
                               std::ostream& log);
/// Its report: for people, or the CONTRACT's JSON ({"agree", "certified", "vectors": [{"name", "max_error",
/// "at", "exact", "found", "scale", "agree"}]} and more keys).
std::string waveform_text(const WaveformChecked& c, const std::string& waveform_file, const std::string& deck_file,
                          const WaveformOptions& options);
std::string waveform_json(const WaveformChecked& c, const WaveformOptions& options);

/// The golden corpus: $DCAD_CASES; else, for an installed dcad (PREFIX/bin/dcad, the executable in a directory named
/// as CMAKE_INSTALL_BINDIR), PREFIX/share/dcad/cases, installed with it; else the source checkout's cases/ where it
/// exists (the build tree, a program linking dcad::api on the build machine); else the configured install prefix's.
std::string cases_dir();
struct CaseEntry {
  std::string file, summary;
};
std::vector<CaseEntry> list_cases();
/// The case's file contents (InputError for a name not in the corpus).
std::string show_case(const std::string& name);
/// Every case, NAME.expected.json (the reference's result) and result.schema.json into `dir`; the count.
int export_cases(const std::string& dir);
/// The waveform corpus (cases/waveforms/*.cir) into `dir`: per deck NAME.cir and NAME.csv — the exact
/// waveforms on the deck's .tran grid (TSTEP to TSTOP) under ngspice's vector names (v(node) for every
/// node, i(x) for inductors and voltage sources) — for other simulators' CI; the count.
int export_waveforms(const std::string& dir, std::ostream& log);
/// A case file, netlist or property log (its "dcad case: {…}" line) → cases/NAME with the reference's
/// expectations; returns what was written.
std::string freeze_case(const std::string& from, const std::string& name = "");

}  // namespace dcad::api
