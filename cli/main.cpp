// dcad: the command-line tool, a shell over dcad::api (reference/api/include/dcad/api.hpp): it parses
// arguments, prints what the library returns (text and JSON by dcad/io/report.hpp) and sets exit codes.
// Exit codes per ../shared/CONTRACT.md: 0 success, 1 bad input (file + line or JSON path, expected vs
// found), 2 bad usage, 3 check disagrees; 4 internal error.
#include "dcad/api.hpp"

#include "dcad/io/netlist.hpp"  // parse_spice_value: --tstop 20n
#include "plot.hpp"

#include <new>
#include <CLI/CLI.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <tuple>
#include <iostream>

#ifndef DCAD_VERSION
#define DCAD_VERSION "0"
#endif

namespace {

/// `dcad solve FILE…`: each file solved in this one process, in order.  One file: the report, or with
/// `json` the result JSON (indented).  With `lines` (or `json` and several files): one compact JSON
/// object per file and line, with "file"; a file that fails gives {"file", "error", "exit"} and the
/// others still run.  Returns the exit code: 0, else the largest of a file's (1 bad input, 4 internal
/// error); messages go to `err` as for one file.
int solve_files(const std::vector<std::string>& files, const dcad::io::ReadOptions& read, dcad::api::Backend backend,
                const dcad::Parts& parts, bool json, bool lines, std::ostream& out, std::ostream& err) {
  lines = lines || (json && files.size() > 1);
  int worst = 0;
  for (const std::string& file : files) {
    std::string message;
    int code = 0;
    try {
      const dcad::io::Printed s =
          dcad::api::printed(dcad::api::solve(dcad::io::read_problem(file, read), backend, parts));
      for (const std::string& w : s.warnings) err << "warning: " << w << "\n";
      if (lines) {
        out << dcad::io::result_json_line(s, file) << "\n";
      } else {
        out << (json ? dcad::io::result_json(s) + "\n" : dcad::io::report_text(s));
        if (files.size() > 1) out << "\n";
      }
      continue;
    } catch (const dcad::api::InternalError& e) {  // an internal invariant: never an answer, never a crash
      message = std::string("dcad: internal error: ") + e.what() + "; please report it with the input";
      code = 4;
    } catch (const std::bad_alloc&) {  // a resource limit, not a wrong answer
      const char* name = backend == dcad::api::Backend::fast        ? "fast"
                         : backend == dcad::api::Backend::reference ? "reference"
                                                                    : "certified";
      message = file + ": out of memory on backend " + name + " (no answer; another backend may need less)";
      code = 4;
    } catch (const std::exception& e) {
      message = e.what();
      code = dcad::api::exit_code(e);
    }
    err << message << "\n";
    if (lines) out << dcad::io::error_json_line(file, message, code) << "\n";
    worst = std::max(worst, code);
  }
  return worst;
}

/// `dcad cases list|show|export|freeze`: the corpus functions of dcad::api, printed.
int cases_command(const std::string& action, const std::vector<std::string>& args, bool waveforms) {
  if (action == "list") {
    for (const dcad::api::CaseEntry& e : dcad::api::list_cases()) std::cout << e.file << "\t" << e.summary << "\n";
    return 0;
  }
  if (action == "show") {
    if (args.empty()) throw dcad::io::InputError("dcad cases show: expected a case name, found nothing");
    std::cout << dcad::api::show_case(args[0]);
    return 0;
  }
  if (action == "export" && waveforms) {
    if (args.empty()) throw dcad::io::InputError("dcad cases export --waveforms: expected a directory, found nothing");
    const int n = dcad::api::export_waveforms(args[0], std::cerr);
    std::cout << "exported " << n
              << " decks of cases/waveforms with their exact waveforms (NAME.csv, ngspice's vector names) to "
              << args[0] << "\n";
    return 0;
  }
  if (action == "export") {
    if (args.empty()) throw dcad::io::InputError("dcad cases export: expected a directory, found nothing");
    const int n = dcad::api::export_cases(args[0]);
    std::cout << "exported " << n
              << " cases with their reference results (NAME.expected.json) and result.schema.json to " << args[0]
              << "\n";
    return 0;
  }
  // freeze
  std::cout << dcad::api::freeze_case(args.empty() ? "" : args[0], args.size() > 1 ? args[1] : "") << "\n";
  return 0;
}

/// `--dialect NAME` on a subcommand that reads decks: how `1a` and `1x` are read (dcad::io::Dialect).
void add_dialect(CLI::App* command, std::string& dialect) {
  command
      ->add_option("--dialect", dialect,
                   "netlists: whose deck it is, for the scale factors SPICEs read differently (1a: atto in ngspice (40 "
                   "on), hspice, "
                   "gnucap; 1 in ngspice39, xyce. 1x: mega in hspice, xyce; 1 in ngspice, gnucap) and `$` (a name's "
                   "character in xyce, "
                   "else an inline comment); strict (default) refuses 1a and 1x")
      ->check(CLI::IsMember({"strict", "ngspice", "ngspice39", "xyce", "hspice", "gnucap"}));
}

/// `dcad simulate`: its options and its run (dcad::api::simulate, the CSV to stdout or --csv, --energy, --plot).
struct SimulateCommand {
  CLI::App* app = nullptr;
  std::string file, csv, backend = "certified";
  std::string tstop, step;  // SPICE values: "1e-3", "20n", "0.5us"
  std::string initial = "deck", route = "auto", columns, png, vars, energy;
  dcad::api::SimulateOptions opt;

  void add(CLI::App& parent, std::string& dialect) {
    app = parent.add_subcommand(
        "simulate",
        "Integrate the equations of motion on M_c from the file's initial condition (netlists: SPICE's, see --initial; "
        "a state off M_c jumps onto it at t = 0); "
        "exact flow of the linear reduced system (matrix exponential); netlists beyond the dense sizes take the sparse "
        "route "
        "(Krylov exponential action on sparse equations of motion, error-controlled, see --route). CSV: t, then every "
        "variable (or --vars).");
    app->add_option("FILE", file, "LC/RLC netlist (.cir, .sp, .net), `pontryagin` case or expression-form case (.json)")
        ->required();
    app->add_option("--tstop", tstop, "final time (seconds; SPICE suffixes: 20n, 1.5u)")->required();
    add_dialect(app, dialect);
    app->add_option("--step", step, "output step (seconds; SPICE suffixes)")->required();
    app->add_option("--backend", backend,
                    "certified|reference|fast (the dense route's model is built exactly in this version; the sparse "
                    "route is double throughout)")
        ->check(CLI::IsMember({"reference", "fast", "certified"}));
    app->add_option("--csv", csv, "write the CSV here instead of stdout");
    app->add_option("--initial", initial,
                    "netlists: op (the DC operating point) or uic (IC= and .ic values, the rest 0); default: as the "
                    "deck's .tran says")
        ->check(CLI::IsMember({"deck", "op", "uic"}));
    app->add_option("--route", route,
                    "netlists: dense (the exact model's matrix exponential; <= 60 branches with R, sources or K, <= "
                    "400 LC) or sparse (any size with "
                    "every R, L, C > 0 and |k| < 1: Krylov exponential action on the sparse equations of motion); "
                    "default auto: dense where it fits. "
                    "With --certified: the exact model the enclosure is built on")
        ->check(CLI::IsMember({"auto", "dense", "sparse"}));
    app->add_option("--vars", columns, "comma-separated variables for the CSV after t (default: every variable)");
    app->add_flag("--certified", opt.enclose,
                  "netlists up to 200 branches (--route picks the exact model: dense up to 60, sparse = the state "
                  "equations with every R, L, C > 0): "
                  "every value the midpoint of a rigorous enclosure (Arb balls on the exact model) of the motion at "
                  "the exact time k*step (printed rounded to double), with the largest radius of the row's charges, "
                  "currents and flux "
                  "linkages in columns rad_q, rad_v, rad_p");
    app->add_option(
        "--energy", energy,
        "circuits with R or sources: write the energy balance (E, dissipated and supplied power and work) as CSV here");
    app->add_option("--plot", png, "also draw a PNG plot here (gnuplot)");
    app->add_option("--plot-vars", vars, "comma-separated variables to plot (default: every q_*)");
  }

  /// --tstop, --step, --backend, --initial, --route and --vars into `opt`: false after saying what is wrong.
  bool read_options() {
    for (auto [flag, text, out] : {std::tuple{"--tstop", &tstop, &opt.tstop}, std::tuple{"--step", &step, &opt.step}}) {
      try {
        *out = static_cast<double>(dcad::io::parse_spice_value(*text));
      } catch (const std::invalid_argument&) {
        std::cerr << "dcad simulate: " << flag << ": expected a time in seconds such as 1e-3 or 20n, found \"" << *text
                  << "\"\n";
        return false;
      }
    }
    opt.backend = dcad::api::backend_named(backend);
    opt.initial = initial == "op"    ? dcad::api::Initial::op
                  : initial == "uic" ? dcad::api::Initial::uic
                                     : dcad::api::Initial::deck;
    opt.route = route == "dense"    ? dcad::api::Route::dense
                : route == "sparse" ? dcad::api::Route::sparse
                                    : dcad::api::Route::automatic;
    for (std::size_t start = 0; !columns.empty();) {
      const std::size_t comma = columns.find(',', start);
      opt.columns.push_back(columns.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    return true;
  }

  int run(const dcad::io::ReadOptions& read) {
    if (!read_options()) return 2;
    const dcad::io::Problem problem = dcad::io::read_problem(file, read);
    if (problem.form() == dcad::io::Form::implicit)  // how the equations were read (lifted to TQ)
      for (const std::string& w : problem.warnings()) std::cerr << "warning: " << w << "\n";
    std::vector<std::string> header = dcad::api::simulate_columns(problem);
    if (!opt.columns.empty()) {
      header.assign(1, "t");
      header.insert(header.end(), opt.columns.begin(), opt.columns.end());
    }
    const std::string title = problem.name().empty() ? file : problem.name();
    std::vector<std::size_t> plot_cols;
    if (!png.empty()) {
      try {
        plot_cols = dcad::cli::plot_columns(header, vars);
      } catch (const std::invalid_argument& e) {
        std::cerr << e.what() << "\n";
        return 2;
      }
    }
    // rows go out as they are computed: to --csv, or to a temporary file for --plot (then copied
    // to stdout), or straight to stdout
    const std::string csv_path = !csv.empty() ? csv : !png.empty() ? png + ".csv" : "";
    std::ofstream file_out;
    if (!csv_path.empty()) {
      file_out.open(csv_path);
      if (!file_out) {
        std::cerr << csv_path << ": cannot open for writing\n";
        return 1;
      }
    }
    std::ofstream energy_out;
    if (!energy.empty()) {
      energy_out.open(energy);
      if (!energy_out) {
        std::cerr << energy << ": cannot open for writing\n";
        return 1;
      }
    }
    dcad::api::simulate(problem, opt, csv_path.empty() ? std::cout : file_out, std::cerr,
                        energy.empty() ? nullptr : &energy_out);
    if (!csv_path.empty()) {
      file_out.close();
      if (!file_out) {
        std::cerr << csv_path << ": cannot write\n";
        return 1;
      }
    }
    if (!std::cout) {
      std::cerr << "simulate: cannot write to standard output\n";
      return 1;
    }
    if (csv.empty() && !png.empty()) {
      std::ifstream copy(csv_path);
      std::cout << copy.rdbuf();
    }
    if (!png.empty()) {
      const std::string why = dcad::cli::plot_png(csv_path, header, plot_cols, png, title);
      if (csv.empty()) std::remove(csv_path.c_str());
      if (!why.empty()) {
        std::cerr << png << ": " << why << "\n";
        return 1;
      }
    }
    return 0;
  }
};

/// `dcad check`: a simulator's waveforms against the exact flow, or another tool's result JSON against the reference.
struct CheckCommand {
  CLI::App* app = nullptr;
  std::string result_file, file, initial = "deck", png, vars;
  dcad::api::WaveformOptions wave;
  bool json = false;
  std::size_t points = 20;

  void add(CLI::App& parent, std::string& dialect) {
    app = parent.add_subcommand(
        "check",
        "Compare another implementation's result (JSON, the keys of `dcad solve --json`) for FILE against the "
        "reference, or a simulator's transient output (ngspice raw or wrdata, gnucap .print, CSV) against the exact "
        "flow "
        "of the netlist FILE at the file's own time points: exit 0 if it agrees, 3 with the list of disagreements, 1 "
        "if "
        "RESULT is not a result or waveform for FILE.");
    app->add_option("RESULT", result_file,
                    "the other implementation's result (.json), or a simulator's transient output "
                    "(ngspice raw or wrdata, gnucap .print, CSV)")
        ->required();
    app->add_option("FILE", file, "the case file or netlist it was computed for")->required();
    add_dialect(app, dialect);
    app->add_option("--rtol", wave.rtol,
                    "waveforms: relative tolerance, of each vector's largest |exact| over the run (default 1e-3)");
    app->add_option("--atol", wave.atol, "waveforms: absolute tolerance (default 0)");
    app->add_option("--initial", initial, "waveforms: the simulator's initial state: deck (its .tran), op or uic")
        ->check(CLI::IsMember({"deck", "op", "uic"}));
    app->add_flag("--json", json, "waveforms: the report as JSON");
    app->add_option(
        "--points", points,
        "formulas: compare another tool's constraints and equations of motion at this many points of M_c (default 20)");
    app->add_option(
        "--plot", png,
        "waveforms: also draw the simulator's and the exact waveforms, the worst point marked, as a PNG (gnuplot)");
    app->add_option("--plot-vars", vars,
                    "waveforms: comma-separated vectors to plot (default: the one with the largest relative error)");
  }

  int run_waveform(const dcad::io::ReadOptions& read) {
    wave.initial = initial == "op"    ? dcad::api::Initial::op
                   : initial == "uic" ? dcad::api::Initial::uic
                                      : dcad::api::Initial::deck;
    // the file streams (bounded memory at any size) unless a plot needs its points in memory
    const dcad::io::Traces traces = png.empty() ? dcad::io::Traces{} : dcad::io::read_traces(result_file);
    const std::unique_ptr<dcad::io::TraceStream> stream =
        png.empty() ? dcad::io::open_traces(result_file) : dcad::io::stream_of(traces);
    wave.keep_exact = !png.empty();
    std::vector<std::size_t> plotted;  // vectors to plot, by index
    if (!vars.empty()) {
      std::istringstream in(vars);
      for (std::string name; std::getline(in, name, ',');) {
        std::size_t k = 0;
        while (k < stream->names().size() && stream->names()[k] != name) ++k;
        if (k == stream->names().size()) {
          std::cerr << "dcad check: --plot-vars: expected vectors of " << result_file << ", found \"" << name << "\"\n";
          return 2;
        }
        plotted.push_back(k);
      }
    }
    const dcad::api::WaveformChecked w =
        dcad::api::check_waveform(*stream, dcad::io::read_problem(file, read), wave, std::cerr);
    std::cout << (json ? dcad::api::waveform_json(w, wave) + "\n"
                       : dcad::api::waveform_text(w, result_file, file, wave));
    if (!png.empty() && !w.vectors.empty()) {
      if (plotted.empty()) plotted.push_back(w.worst);
      const std::string csv = png + ".csv";
      {
        std::ofstream f(csv);
        f.precision(17);
        f << "t";
        for (std::size_t k : plotted) f << "," << traces.names[k] << "," << traces.names[k] << " (exact)";
        f << "\n";
        for (std::size_t i = 0; i < traces.time.size(); ++i) {
          f << traces.time[i];
          for (std::size_t k : plotted) f << "," << traces.values[k][i] << "," << w.exact[k][i];
          f << "\n";
        }
      }
      std::vector<std::string> names;
      std::vector<double> wt, wf;
      for (std::size_t k : plotted) {
        names.push_back(traces.names[k] + (w.vectors[k].agree ? " (agrees)" : " (DISAGREES)"));
        wt.push_back(w.vectors[k].at);
        wf.push_back(w.vectors[k].found);
      }
      const std::string why =
          dcad::cli::plot_check_png(csv, names, wt, wf, png, result_file + " against the exact flow of " + file);
      std::remove(csv.c_str());
      if (!why.empty())
        std::cerr << "dcad check: --plot: " << why << "\n";
      else
        std::cerr << "dcad check: plot written to " << png << "\n";
    }
    return w.agree ? 0 : 3;
  }

  int run_result(const dcad::io::ReadOptions& read) {
    const dcad::api::Checked o = dcad::api::check(result_file, dcad::io::read_problem(file, read), points);
    std::string keys;
    for (const std::string& k : o.compared) keys += (keys.empty() ? "" : ", ") + k;
    for (const std::string& k : o.not_compared) std::cout << "dcad check: not compared: " << k << "\n";
    if (o.agrees) {
      std::cout << "dcad check: " << result_file << " agrees with the reference on " << file << " (compared: " << keys
                << ")\n";
      return 0;
    }
    std::cout << "dcad check: " << result_file << " disagrees with the reference on " << file << ":\n";
    for (const std::string& d : o.disagreements) std::cout << "  " << d << "\n";
    std::cout << o.disagreements.size() << " disagreement(s) among the compared keys: " << keys << "\n";
    return 3;
  }
};

/// `dcad inspect FILE`: a Dirac structure's validity and invariants.
struct InspectCommand {
  CLI::App* app = nullptr;
  std::string file, backend = "reference";
  bool as_json = false;

  void add(CLI::App& parent) {
    app = parent.add_subcommand(
        "inspect",
        "Inspect a Dirac structure given in a case file (any `dirac` form): validity (CEF Lemma 4.1), "
        "dim E_D, rank and kernel of omega_D (Prop. 4.3), presymplectic or Poisson.");
    app->add_option("FILE", file, "case file (.json)")->required();
    app->add_option("--backend", backend, "reference (exact) or fast (double, with certainty verdicts)")
        ->check(CLI::IsMember({"reference", "fast"}));
    app->add_flag("--json", as_json, "print the result as JSON");
  }

  int run() const {
    const dcad::io::Problem p = dcad::io::read_problem(file);
    const dcad::Inspection r = dcad::api::inspect(p, dcad::api::backend_named(backend));
    std::cout << (as_json ? dcad::io::inspection_json(r) + "\n" : dcad::io::inspection_text(r));
    if (r.valid) return 0;
    std::cerr << file << ": " << p.linear().dirac.path << ": expected a Dirac structure (CEF Lemma 4.1), found "
              << r.why << "\n";
    return 1;
  }
};

/// `dcad solve FILE...`: the CAD on case files and netlists.
struct SolveCommand {
  CLI::App* app = nullptr;
  std::vector<std::string> files;
  std::string backend = "certified", with = "all";
  bool json = false, lines = false;

  void add(CLI::App& parent, std::string& dialect) {
    app = parent.add_subcommand(
        "solve",
        "Run the constraint algorithm (CAD, CEF §5) on a case file: the constraint tower M_0 ⊇ M_1 ⊇ …, "
        "the final constraint submanifold, the solution rank (Thm 5.4) and the equations of motion (5.12).");
    app->add_option("FILE", files,
                    "case files (.json) or LC netlists (.cir, .sp, .net); several are solved in one process, in order")
        ->required();
    app->add_option(
           "--backend", backend,
           "certified (default: the reference in machine words, in FLINT's fmpq past 128 bits), reference, fast")
        ->check(CLI::IsMember({"reference", "fast", "certified"}));
    app->add_flag("--json", json, "print the result JSON of the CONTRACT (several files: JSON lines, as --jsonl)");
    app->add_flag("--jsonl", lines,
                  "one compact result JSON per file and line, with \"file\"; a failing file gives {\"file\", "
                  "\"error\", \"exit\"} "
                  "and the rest still run (exit code: the worst file's)");
    add_dialect(app, dialect);
    app->add_option(
        "--with", with,
        "what to compute beyond the CONTRACT's required keys and the tower, for linear case files and netlists: "
        "all (default), none, or a comma-separated list of final (final_constraints), reduced (equations of "
        "motion), classes (first/second class, Dirac bracket), adapted (Thm 3.28 / 7.4)");
  }

  int run(const dcad::io::ReadOptions& read) const {
    dcad::Parts parts;
    try {
      parts = dcad::api::parts_named(with);
    } catch (const dcad::api::UsageError& e) {
      std::cerr << "solve: " << e.what() << "\n";
      return 2;  // bad usage
    }
    return solve_files(files, read, dcad::api::backend_named(backend), parts, json, lines, std::cout, std::cerr);
  }
};

/// `dcad cases ACTION`: the golden corpus.
struct CasesCommand {
  CLI::App* app = nullptr;
  std::string action;
  std::vector<std::string> args;
  bool waveforms = false;

  void add(CLI::App& parent) {
    app = parent.add_subcommand(
        "cases",
        "The golden corpus: `list`, `show NAME`, `export DIR` (cases + their reference results + the result schema), "
        "`freeze FILE [NAME]` (a property-test counterexample or any case → a golden case in the corpus directory, "
        "cases/ of the checkout, with the reference's expectations; DCAD_CASES overrides the directory).");
    app->add_option("ACTION", action, "list, show, export or freeze")
        ->required()
        ->check(CLI::IsMember({"list", "show", "export", "freeze"}));
    app->add_option("ARGS", args, "NAME, DIR or FILE [NAME]");
    app->add_flag("--waveforms", waveforms,
                  "export: the waveform corpus (cases/waveforms) with each deck's exact waveforms as CSV under "
                  "ngspice's vector names");
  }
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dcad: verified reference implementation of linear Dirac structures and constraint algorithms"};
  app.set_version_flag("--version", std::string("dcad ") + DCAD_VERSION);
  app.require_subcommand(1);
  std::string dialect = "strict";
  InspectCommand inspect;
  inspect.add(app);
  SolveCommand solve;
  solve.add(app, dialect);
  SimulateCommand sim;
  sim.add(app, dialect);
  CheckCommand check;
  check.add(app, dialect);
  CasesCommand cases;
  cases.add(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }

  const dcad::io::ReadOptions read{*dcad::io::dialect_named(dialect)};  // checked by add_dialect
  try {
    if (inspect.app->parsed()) return inspect.run();
    if (solve.app->parsed()) return solve.run(read);
    if (cases.app->parsed()) return cases_command(cases.action, cases.args, cases.waveforms);
    if (check.app->parsed())
      return dcad::io::looks_like_json(check.result_file) ? check.run_result(read) : check.run_waveform(read);
    if (sim.app->parsed()) return sim.run(read);
  } catch (const dcad::io::InputError& e) {  // the message names the file
    std::cerr << e.what() << "\n";
    return 1;
  } catch (const dcad::api::UsageError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {  // a library function's precondition on the input
    const std::string file = sim.app->parsed()                             ? sim.file
                             : check.app->parsed()                         ? check.file
                             : inspect.app->parsed()                       ? inspect.file
                             : solve.app->parsed() && !solve.files.empty() ? solve.files.front()
                                                                           : std::string("dcad");
    std::cerr << file << ": " << e.what() << "\n";
    return 1;
  } catch (const std::bad_alloc&) {  // a resource limit, not a wrong answer
    std::cerr << "dcad: out of memory (no answer)\n";
    return 4;
  } catch (const std::exception& e) {  // an internal invariant: never an answer, never a crash
    std::cerr << "dcad: internal error: " << e.what() << "; please report it with the input\n";
    return 4;
  }
  return 0;
}
