// dcad::api (issue 26): the library gives what the dcad binary prints — the same result JSON and
// report (formatted once, by dcad::io), the same check verdict, the same CSV — from typed solutions,
// and its errors come on the three channels (InputError naming the file, UsageError, InternalError),
// each with the CLI's exit code.
#include "cli_run.hpp"
#include "dcad/api.hpp"
#include "formulas.hpp"  // the api's own (reference/api/src): at_given on a chart

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <algorithm>
#include <cmath>
#include <string>

namespace {

std::string case_path(const std::string& name) { return std::string(DCAD_SOURCE_DIR) + "/cases/" + name; }

std::string slurp(const std::string& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

using dcad::api::Backend;

}  // namespace

// Two routes to one result: the library call and the binary, for every input form and backend.
TEST(Api, SolveEqualsTheBinary) {
  for (const char* name :
       {"lc-4port.json", "lc-4port.cir", "rlc-series.cir", "rolling-disk.json", "constrained-gauge.json"})
    for (const std::string backend : {"reference", "fast", "certified"}) {
      const dcad::io::Printed s = dcad::api::printed(
          dcad::api::solve(dcad::io::read_problem(case_path(name)), dcad::api::backend_named(backend)));
      const Outcome bin = run("solve " + case_path(name) + " --backend " + backend + " --json");
      ASSERT_EQ(bin.rc, 0) << name << bin.err;
      EXPECT_EQ(nlohmann::json::parse(dcad::io::result_json(s)), nlohmann::json::parse(bin.out))
          << name << " " << backend;
      EXPECT_EQ(dcad::io::report_text(s), run("solve " + case_path(name) + " --backend " + backend).out)
          << name << " " << backend;
    }
}

// The typed solution is what the JSON says, and a deck given as text is the deck in the file.
TEST(Api, TypedSolutionOfADeckGivenAsText) {
  const dcad::io::Problem from_file = dcad::io::read_problem(case_path("lc-4port.cir"));
  const dcad::io::Problem from_text = dcad::io::parse_netlist(slurp(case_path("lc-4port.cir")), "lc-4port.cir");
  const dcad::certified::Solution a = dcad::certified::solve(from_file), b = dcad::certified::solve(from_text);
  EXPECT_EQ(a.dims(), (std::vector<long>{12, 6, 5, 4}));  // CEF §6 (6.31)-(6.36)
  EXPECT_EQ(b.dims(), a.dims());
  EXPECT_TRUE(b.certified.yes());
  ASSERT_TRUE(b.motion);
  EXPECT_EQ(b.motion->f_matrix.size(), 4u);  // ż = F z on the 4-dimensional M_c
  for (const auto& row : b.motion->f_matrix)
    for (const dcad::certified::Number& x : row) EXPECT_TRUE(x.exact);
  EXPECT_EQ(b.variables, a.variables);
}

// `--with none` is the CONTRACT's required keys and the tower only.
TEST(Api, SolveComputesWhatIsAsked) {
  const dcad::io::Problem p = dcad::io::read_problem(case_path("lc-4port.json"));
  const dcad::reference::Solution all = dcad::reference::solve(p),
                                  none = dcad::reference::solve(p, dcad::Parts::none());
  EXPECT_TRUE(all.adapted.has_value());
  EXPECT_TRUE(all.motion.has_value());
  EXPECT_FALSE(none.adapted.has_value());
  EXPECT_FALSE(none.motion.has_value());
  EXPECT_EQ(all.dims(), none.dims());
}

// check: a result agrees with itself; the same result with one dimension changed disagrees, naming it.
TEST(Api, CheckAgreesAndDisagrees) {
  const std::string file = case_path("lc-4port.json");
  const dcad::io::Problem p = dcad::io::read_problem(file);
  nlohmann::json result = nlohmann::json::parse(
      dcad::io::result_json(dcad::api::printed(dcad::api::solve(p, Backend::fast, dcad::Parts::none()))));
  const std::string good = write_temp("dcad_api_good.json", result.dump());
  const dcad::api::Checked ok = dcad::api::check(good, p);
  EXPECT_TRUE(ok.agrees);
  EXPECT_TRUE(ok.disagreements.empty());
  result["dims"][1] = result["dims"][1].get<long>() + 1;
  const dcad::api::Checked bad = dcad::api::check(write_temp("dcad_api_bad.json", result.dump()), p);
  EXPECT_FALSE(bad.agrees);
  ASSERT_FALSE(bad.disagreements.empty());
  EXPECT_NE(bad.disagreements[0].find("dims"), std::string::npos) << bad.disagreements[0];
  EXPECT_EQ(run("check " + good + " " + file).rc, 0);
}

// simulate: the CSV the binary prints, row for row; the columns name its header.
TEST(Api, SimulateEqualsTheBinary) {
  for (const char* name : {"rlc-series.cir", "lc-4port.cir"}) {
    const dcad::io::Problem p = dcad::io::read_problem(case_path(name));
    std::ostringstream csv, log;
    const dcad::api::Simulated s = dcad::api::simulate(p, {1e-4, 1e-6, Backend::certified}, csv, log);
    EXPECT_EQ(s.rows, 101);
    EXPECT_LT(s.error_estimate, 1e-9);
    EXPECT_EQ(csv.str(), run("simulate " + case_path(name) + " --tstop 1e-4 --step 1e-6").out) << name;
    const std::vector<std::string> columns = dcad::api::simulate_columns(p);
    EXPECT_EQ(columns.front(), "t");
    std::string header;
    for (const std::string& c : columns) header += (header.empty() ? "" : ",") + c;
    EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')), header);
  }
}

// A caller's RowSink sees the header and the rows as they come and may stop the run by throwing: its own exception
// reaches the caller (not an InternalError, exit 4).  Killed by: the sink's exception mapped by the error channels.
TEST(Api, ASinkStopsTheRunWithItsOwnException) {
  struct FirstRows final : dcad::api::RowSink {
    std::vector<std::string> names;
    std::vector<std::vector<double>> rows;
    void header(const std::vector<std::string>& n) override { names = n; }
    void row(const std::vector<double>& v) override {
      rows.push_back(v);
      if (rows.size() == 3) throw std::runtime_error("enough");
    }
  } sink;
  dcad::api::SimulateOptions opt;
  opt.tstop = 1e-4;
  opt.step = 1e-6;
  std::ostringstream log;
  try {
    dcad::api::simulate(dcad::io::read_problem(case_path("rlc-series.cir")), opt, sink, log);
    ADD_FAILURE() << "the run went on after the sink threw";
  } catch (const dcad::api::InternalError& e) {
    ADD_FAILURE() << "the sink's exception became an internal error: " << e.what();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "enough");
  }
  EXPECT_EQ(sink.rows.size(), 3u);
  EXPECT_EQ(sink.names.front(), "t");
}

// The channels: bad input names the file (exit 1), options that do not apply are usage (exit 2).
TEST(Api, ErrorChannels) {
  const std::string missing = case_path("no-such-case.json");
  try {
    dcad::io::read_problem(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const dcad::api::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    EXPECT_EQ(dcad::api::exit_code(e), 1);
  }
  const std::string bad = write_temp("dcad_api_bad_case.json", R"({"dcad": 1, "dirac": {"form": [[0, 1], [1, 0]]}})");
  try {
    dcad::api::solve(dcad::io::read_problem(bad), Backend::certified);
    ADD_FAILURE() << "no error for a symmetric form";
  } catch (const dcad::api::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dcad::api::backend_named("exact"), dcad::api::UsageError);
  EXPECT_THROW(dcad::api::parts_named("bracket,final"), dcad::api::UsageError);
  std::ostringstream csv, log, energy;
  try {
    dcad::api::simulate(dcad::io::read_problem(case_path("lc-4port.cir")), {1e-3, 1e-4, Backend::certified}, csv, log,
                        &energy);
    ADD_FAILURE() << "--energy of a lossless circuit";
  } catch (const dcad::api::UsageError& e) {
    EXPECT_EQ(dcad::api::exit_code(e), 2);
    EXPECT_NE(std::string(e.what()).find("lossless"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dcad::api::simulate(dcad::io::read_problem(case_path("rlc-series.cir")), {-1, 1e-6, Backend::certified},
                                   csv, log),
               dcad::api::InputError);
  EXPECT_EQ(dcad::api::exit_code(dcad::api::InternalError("x")), 4);
}

// A default-constructed verdict claims nothing: a caller that fills in a Checked itself (or forgets to)
// must not read "agrees".  (A survivor of the seed-25 mutation sample: `agrees = true` by default.)
TEST(Api, DefaultVerdictDoesNotAgree) {
  const dcad::api::Checked none;
  EXPECT_FALSE(none.agrees);
  EXPECT_TRUE(none.compared.empty());
}

namespace {
std::vector<std::vector<double>> sim_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<double> r;
    std::istringstream f(line);
    for (std::string x; std::getline(f, x, ',');) r.push_back(std::stod(x));
    rows.push_back(r);
  }
  return rows;
}

// simulate_trajectory: the typed rows are the CSV's, double for double (shortest round-trip text reads back
// exactly), on every route and form — dense, sparse, the certified enclosures, a Lagrangian case, a DAE — with --vars.
TEST(Api, TrajectoryIsTheCsvAsDoubles) {
  struct Run {
    const char* file;
    dcad::api::Route route;
    bool enclose;
    double tstop, step;
    std::vector<std::string> columns;
  };
  const std::vector<Run> runs = {{"rlc-series.cir", dcad::api::Route::dense, false, 2e-6, 1e-7, {}},
                                 {"rlc-series.cir", dcad::api::Route::sparse, false, 2e-6, 1e-7, {"v_L1", "q_C1"}},
                                 {"rlc-series.cir", dcad::api::Route::automatic, true, 2e-6, 1e-7, {}},
                                 {"lc-4port.cir", dcad::api::Route::automatic, false, 1e-4, 1e-5, {"q_C1"}},
                                 {"cartesian-pendulum.json", dcad::api::Route::automatic, false, 0.2, 0.1, {}},
                                 {"implicit-pendulum-index-1.json", dcad::api::Route::automatic, false, 0.2, 0.1, {}},
                                 {"dae-hessenberg-index-2.json", dcad::api::Route::automatic, false, 0.5, 0.1, {}}};
  for (const Run& r : runs) {
    const dcad::io::Problem p = dcad::io::read_problem(case_path(r.file));
    dcad::api::SimulateOptions opt;
    opt.tstop = r.tstop;
    opt.step = r.step;
    opt.route = r.route;
    opt.enclose = r.enclose;
    opt.columns = r.columns;
    std::ostringstream csv, log;
    const dcad::api::Simulated s = dcad::api::simulate(p, opt, csv, log);
    const dcad::api::Trajectory t = dcad::api::simulate_trajectory(p, opt, log);
    const std::string header = csv.str().substr(0, csv.str().find('\n'));
    std::string names;
    for (const std::string& n : t.names) names += (names.empty() ? "" : ",") + n;
    EXPECT_EQ(names, header) << r.file;
    EXPECT_EQ(t.rows, sim_rows(csv.str())) << r.file;
    EXPECT_EQ(static_cast<long>(t.rows.size()), s.rows) << r.file;
    EXPECT_EQ(t.summary.error_estimate, s.error_estimate) << r.file;
    EXPECT_EQ(t.column("t").size(), t.rows.size());
    EXPECT_THROW(t.column("q_C9"), std::out_of_range);
  }
}

}  // namespace

// prop_sparse's counterexample (SparseSimulate.IsTheDenseRoute): at a corner of V3's PULSE the dense
// route added to V2 — a SIN, continuous there — a "jump" 2δ·V2' measured across ±δ around the corner;
// the charge through V2, which holds C1 at V2(t), drifted by 2.5e-16 C per corner.  Closed form:
// q_V2(t) = −C (V2(t) − V2(0)) = −C sin(2π f t) on both routes.
TEST(Api, ASourceJumpsOnlyAtItsOwnCorners) {
  const std::string deck =
      "C across a SIN source, a PULSE elsewhere\nR0 0 n1 0.1\nC1 0 n2 40n\nV2 0 n2 SIN(0 1 2e9)\n"
      "V3 0 n1 PULSE(0 1 1n 1n 1n 3n 10n)\n.tran 0.25n 5n uic\n.end\n";
  const dcad::io::Problem p = dcad::io::parse_netlist(deck, "sin-beside-pulse.cir");
  for (dcad::api::Route route : {dcad::api::Route::dense, dcad::api::Route::sparse}) {
    dcad::api::SimulateOptions opt;
    opt.tstop = 5e-9;
    opt.step = 0.25e-9;
    opt.route = route;
    opt.columns = {"q_V2"};
    std::ostringstream csv, log;
    dcad::api::simulate(p, opt, csv, log);
    const auto rows = sim_rows(csv.str());
    ASSERT_EQ(rows.size(), 21u);
    const double pi = 3.14159265358979323846;
    for (const auto& r : rows)  // C1 sits from ground to n2 = −V2: q_C1 = C·V2 … and q_V2 carries −C·V2'
      EXPECT_NEAR(r[1], -40e-9 * std::sin(2 * pi * 2e9 * r[0]), 1e-12 * 40e-9)
          << "t = " << r[0] << (route == dcad::api::Route::dense ? " dense" : " sparse");
  }
}

// --vars (SimulateOptions::columns): the chosen columns are those of the full CSV, on either route; a
// name the problem does not have is a usage error before anything is written.
TEST(Api, SimulateColumnsAreTheFullCsvsColumns) {
  const dcad::io::Problem p = dcad::io::read_problem(case_path("rlc-series.cir"));
  for (dcad::api::Route route : {dcad::api::Route::dense, dcad::api::Route::sparse}) {
    dcad::api::SimulateOptions opt;
    opt.tstop = 2e-6;
    opt.step = 1e-7;
    opt.route = route;
    std::ostringstream all, some, log;
    dcad::api::simulate(p, opt, all, log);
    opt.columns = {"v_L1", "q_C1"};
    dcad::api::simulate(p, opt, some, log);
    const auto full = sim_rows(all.str()), part = sim_rows(some.str());
    const std::vector<std::string> names = dcad::api::simulate_columns(p);
    const auto at = [&](const std::string& n) {
      return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
    };
    ASSERT_EQ(full.size(), part.size());
    for (std::size_t i = 0; i < full.size(); ++i) {
      ASSERT_EQ(part[i].size(), 3u);
      EXPECT_EQ(part[i][0], full[i][0]);
      EXPECT_EQ(part[i][1], full[i][at("v_L1")]);
      EXPECT_EQ(part[i][2], full[i][at("q_C1")]);
    }
    opt.columns = {"q_C1", "q_C9"};
    std::ostringstream none;
    EXPECT_THROW(dcad::api::simulate(p, opt, none, log), dcad::api::UsageError);
    EXPECT_EQ(none.str(), "");
  }
}

// The review of the sparse route: on a stiff circuit the Krylov matrix's own rounding (eps·|A|·step) bounds
// the accuracy, and the route must say so — a warning with the estimate it reaches (R1·C1 = 1 ps against a
// 1 ms step: dense and sparse differ by ~4e-6 of v_C1's scale), and exit 1 (InputError) where it would
// print noise (1e-20 F: estimate above 1e-3 of the state).  Before, both reported ~1e-14.
TEST(Api, TheSparseRouteSaysWhenStiffnessCostsItsAccuracy) {
  const auto deck = [](const std::string& c) {
    return "stiff\nV1 a 0 SIN(0 1 1k)\nR1 a b 1\nC1 b 0 " + c +
           "\nL1 b c 1m\nR2 c 0 1k\nC2 c 0 1u\n.tran 1m 10m\n.end\n";
  };
  dcad::api::SimulateOptions opt;
  opt.tstop = 3e-3;
  opt.step = 1e-3;
  opt.route = dcad::api::Route::sparse;
  std::ostringstream csv, log;
  const dcad::api::Simulated s = dcad::api::simulate(dcad::io::parse_netlist(deck("1p"), "stiff.cir"), opt, csv, log);
  EXPECT_GT(s.error_estimate, 1e-8);
  EXPECT_NE(log.str().find("warning: the sparse route's error estimate"), std::string::npos) << log.str();
  std::ostringstream csv2, log2;
  EXPECT_THROW(dcad::api::simulate(dcad::io::parse_netlist(deck("1e-20"), "stiffer.cir"), opt, csv2, log2),
               dcad::io::InputError);
}

namespace {

/// The state equations of a deck (reference backend) as {block: {(row, col): exact value text}}.
std::map<std::string, std::map<std::pair<long, long>, std::string>> state_blocks(const std::string& deck,
                                                                                 dcad::StateEquations<std::string>& q) {
  const dcad::io::Printed s =
      dcad::api::printed(dcad::api::solve(dcad::io::parse_netlist(deck, "deck.cir"), Backend::reference));
  EXPECT_TRUE(s.state);
  if (!s.state) return {};
  q = *s.state;
  std::map<std::string, std::map<std::pair<long, long>, std::string>> out;
  for (const auto& [name, b] : q.blocks)
    for (const auto& [i, j, v] : b.entries) out[name][{i, j}] = v;
  return out;
}

}  // namespace

// The state equations against Kirchhoff's laws written out by hand (dcad/reference/rlc_state.hpp).
// V1 in–0 1 V, R1 in–a 1k, L1 a–b 1m, C1 b–0 1n, C2 b–c 2n, R2 c–0 3k: "in" is ground's supernode
// offset by V1; b and c hold ground through capacitors (w = e(b), e(c)); a has no capacitor and a
// resistor to ground (ρ = e(a)).  KCL at b: C1 ė_b + C2 (ė_b − ė_c) − i_L = 0; at c: C2 (ė_c − ė_b) +
// e_c/R2 = 0; at a: (e_a − V1)/R1 + i_L = 0; the inductor: L1 i̇_L = e_a − e_b.
TEST(Api, StateEquationsAreKirchhoffsLaws) {
  dcad::StateEquations<std::string> q;
  const auto b = state_blocks("rlc\nV1 in 0 DC 1\nR1 in a 1k\nL1 a b 1m\nC1 b 0 1n\nC2 b c 2n\nR2 c 0 3k\n.end\n", q);
  EXPECT_EQ(q.w, (std::vector<std::string>{"e(b)", "e(c)"}));
  EXPECT_EQ(q.r, (std::vector<std::string>{"e(a)"}));
  EXPECT_EQ(q.i, (std::vector<std::string>{"v_L1"}));
  EXPECT_TRUE(q.e.empty());
  using E = std::map<std::pair<long, long>, std::string>;
  EXPECT_EQ(b.at("C_ww"),
            (E{{{0, 0}, "3/1000000000"}, {{0, 1}, "-1/500000000"}, {{1, 0}, "-1/500000000"}, {{1, 1}, "1/500000000"}}));
  EXPECT_EQ(b.at("G_ww"), (E{{{1, 1}, "1/3000"}}));
  EXPECT_EQ(b.at("L_w"), (E{{{0, 0}, "-1"}}));       // −i_L in b's row
  EXPECT_EQ(b.at("G_rr"), (E{{{0, 0}, "1/1000"}}));  // e_a/R1
  EXPECT_EQ(b.at("L_r"), (E{{{0, 0}, "1"}}));
  EXPECT_EQ(b.at("H_r"), (E{{{0, 0}, "-1/1000"}}));  // −V1/R1
  EXPECT_EQ(b.at("Phi"), (E{{{0, 0}, "1/1000"}}));
  for (const char* empty : {"G_wr", "L_e", "H_w", "H_wd", "I_e", "O_L"}) EXPECT_EQ(b.count(empty), 0u) << empty;
}

// An island (an LI cutset): x and y joined by C1, tied to ground only by L1 and the current source
// I1.  y is the component's root (its first node), so w = e(x) − e(y) and the island's level e = e(y).
// KCL at x: C1 ẇ + i_L = 0; over the island: i_L − I1 = 0 (the constraint whose derivative fixes e);
// the inductor: L1 i̇_L = e_x = w + e.
TEST(Api, StateEquationsOfAnIsland) {
  dcad::StateEquations<std::string> q;
  const auto b = state_blocks("island\nI1 0 y 1m\nC1 x y 1n\nL1 x 0 1u\n.end\n", q);
  EXPECT_EQ(q.w, (std::vector<std::string>{"e(x)-e(y)"}));
  EXPECT_EQ(q.e, (std::vector<std::string>{"e(y)"}));
  EXPECT_TRUE(q.r.empty());
  using E = std::map<std::pair<long, long>, std::string>;
  EXPECT_EQ(b.at("C_ww"), (E{{{0, 0}, "1/1000000000"}}));
  EXPECT_EQ(b.at("L_w"), (E{{{0, 0}, "1"}}));
  EXPECT_EQ(b.at("L_e"), (E{{{0, 0}, "1"}}));
  EXPECT_EQ(b.at("I_e"), (E{{{0, 0}, "-1"}}));
  EXPECT_EQ(b.at("Phi"), (E{{{0, 0}, "1/1000000"}}));
  for (const char* empty : {"G_ww", "H_w", "H_wd", "O_L"}) EXPECT_EQ(b.count(empty), 0u) << empty;
}

// `.ic v(node)=` without uic (CONTRACT "Circuit initial state"): the operating point holds the node as
// ngspice does, through an ideal source whose current its KCL absorbs.  Two routes to one start and
// motion: the dense exact route (reference/pipeline/initial_state: KCL at the held node replaced by
// e = value) and the sparse route's contraction (the held DC node's level fixed, the hold current fed
// in at the node) — every variable at every row to 1e-9 of its kind's largest value.
TEST(Api, HeldNodesStartBothRoutesAlike) {
  const std::string circuit =
      "V1 in 0 DC 1\nR1 in a 1k\nC1 a 0 1n\nR2 a b 2k\nC2 b 0 2n\nL1 b c 10u IC=1m\nR3 c 0 50\n";
  // held: b and d (each its own DC node); contradicting: b and c, one DC node through L1 (both routes
  // then drop the holds, with a note)
  for (const std::string& tail :
       {std::string("R4 c d 100\nC3 d 0 1n\n.ic v(b)=0.5 v(d)=-0.25\n"), std::string(".ic v(b)=0.5 v(c)=-0.25\n")}) {
    const dcad::io::Problem p =
        dcad::io::parse_netlist("held node\n" + circuit + tail + ".tran 10n 2u\n.end\n", "held.cir");
    std::vector<std::vector<std::vector<double>>> runs;
    for (dcad::api::Route route : {dcad::api::Route::dense, dcad::api::Route::sparse}) {
      dcad::api::SimulateOptions opt;
      opt.tstop = 2e-6;
      opt.step = 2e-8;
      opt.route = route;
      std::ostringstream csv, log;
      dcad::api::simulate(p, opt, csv, log);
      runs.push_back(sim_rows(csv.str()));
    }
    const std::vector<std::string> names = dcad::api::simulate_columns(p);
    ASSERT_EQ(runs[0].size(), runs[1].size());
    std::map<char, double> largest;
    for (const auto& row : runs[0])
      for (std::size_t j = 1; j < row.size(); ++j)
        largest[names[j][0]] = std::max(largest[names[j][0]], std::abs(row[j]));
    for (std::size_t i = 0; i < runs[0].size(); ++i)
      for (std::size_t j = 1; j < runs[0][i].size(); ++j)
        EXPECT_NEAR(runs[1][i][j], runs[0][i][j], 1e-9 * largest[names[j][0]]) << tail << names[j] << " at row " << i;
    if (tail.find("v(d)") == std::string::npos) continue;
    // the held nodes start where .ic puts them: C2 holds v(b) = 0.5, C3 holds v(d) = -0.25
    const auto col = [&](const std::string& n) {
      return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
    };
    EXPECT_NEAR(runs[1][0][col("q_C2")], 0.5 * 2e-9, 1e-21);
    EXPECT_NEAR(runs[1][0][col("q_C3")], -0.25 * 1e-9, 1e-21);
  }
}

// Issue 28: a result key that `check` does not compare is named, never ignored in silence (a result
// with an extra `trajectory` passed with exit 0 and no word about it).
TEST(Api, CheckNamesTheKeysItDoesNotCompare) {
  const dcad::io::Problem p = dcad::io::read_problem(case_path("rlc-series.cir"));
  nlohmann::json r =
      nlohmann::json::parse(dcad::io::result_json(dcad::api::printed(dcad::api::solve(p, Backend::reference))));
  r["trajectory"] = {1, 2, 3};
  const dcad::api::Checked c = dcad::api::check_text(r.dump(), p);
  EXPECT_TRUE(c.agrees);
  std::string all;
  for (const std::string& n : c.not_compared) all += n + "\n";
  EXPECT_NE(all.find("trajectory"), std::string::npos) << all;
  EXPECT_NE(all.find("state_equations"), std::string::npos) << all;  // dcad's own informational keys too
  EXPECT_EQ(all.find("dims"), std::string::npos) << all;             // compared keys are not listed
}

#include "fuzz/typed_mutations.hpp"

// Issue 45 §5: a Problem built in code is validated at the API, like a file is by its reader.  Every
// malformation of every form (a missing variable name or f entry, a duplicate name, a node, source or
// variable index out of range, a null formula, sizes that do not match) is bad input on every entry point
// and every backend — never an answer, let alone a certified one (a DaeCase with a name short was solved
// as another system and certified).  The unmodified problems are answered (the check can fail).
TEST(TypedInput, MalformedIsNeverAnswered) {
  std::size_t mutations = 0;
  for (const dcad::io::Problem& base : dcad::fuzz::typed_bases()) {
    EXPECT_NO_THROW((void)dcad::api::solve(base, Backend::certified)) << base.file;
    for (unsigned which = 0; which < 8; ++which)
      for (unsigned k = 0; k < 3; ++k) {
        dcad::io::Problem p = base;
        if (!dcad::fuzz::malform(p, which, k)) continue;
        ++mutations;
        std::string what;
        EXPECT_TRUE(dcad::fuzz::all_refuse(p, what)) << what << " (mutation " << which << ", " << k << ")";
      }
  }
  EXPECT_GT(mutations, 100u);
  // Compositions, as fuzz_typed makes them: each field malformed once (a duplicate name pushed and then
  // popped is the valid problem again — the fuzzer's finding ))2\0\5 on lagrangian.json).
  std::size_t pairs = 0;
  for (const dcad::io::Problem& base : dcad::fuzz::typed_bases())
    for (unsigned first = 0; first < 8; ++first)
      for (unsigned second = 0; second < 8; ++second) {
        if (dcad::fuzz::malformed_field(base, first) == dcad::fuzz::malformed_field(base, second)) continue;
        dcad::io::Problem p = base;
        if (!dcad::fuzz::malform(p, first, 1) || !dcad::fuzz::malform(p, second, 2)) continue;
        ++pairs;
        std::string what;
        EXPECT_TRUE(dcad::fuzz::all_refuse(p, what)) << what << " (mutations " << first << ", " << second << ")";
      }
  EXPECT_GT(pairs, 200u);
  const dcad::io::Problem deck = dcad::fuzz::typed_bases()[3];
  for (unsigned which = 0; which < 5; ++which) {
    std::ostringstream log;
    EXPECT_THROW((void)dcad::api::check_waveform(dcad::fuzz::malformed_traces(which, 1), deck, {}, log),
                 std::invalid_argument)
        << which;
  }
}

namespace {

/// An ngspice binary raw file (one transient plot, time first) of the given points, as ngspice writes it.
std::string binary_raw(const std::vector<std::string>& names, const std::vector<double>& time,
                       const std::vector<std::vector<double>>& values) {
  std::ostringstream h;
  h << "Title: written by api_test\nDate: today\nPlotname: Transient Analysis\nFlags: real\nNo. Variables: "
    << names.size() + 1 << "\nNo. Points: " << time.size() << "\nVariables:\n\t0\ttime\ttime\n";
  for (std::size_t k = 0; k < names.size(); ++k) h << "\t" << k + 1 << "\t" << names[k] << "\tvoltage\n";
  h << "Binary:\n";
  std::string s = h.str();
  for (std::size_t i = 0; i < time.size(); ++i) {
    s.append(reinterpret_cast<const char*>(&time[i]), sizeof(double));
    for (const auto& v : values) s.append(reinterpret_cast<const char*>(&v[i]), sizeof(double));
  }
  return s;
}

}  // namespace

// ngspice writes a binary raw file's 'No. Points:' when the run ends: a run it aborts ("Timestep too small", as on
// Xyce's MINDUCTORS/cpldLMIs.cir) leaves 0 there with the points it wrote after it.  Those points are read and
// checked, and the check says why (it refused the file before: "found more data after them"); bytes that are
// not whole points stay bad input.
TEST(TraceStream, AbortedRawRunIsReadWithANote) {
  const dcad::io::Problem deck = dcad::fuzz::typed_bases()[3];  // the tank with a PULSE source, .tran 1u 40u
  const std::vector<double> time{0, 1e-6, 2e-6};
  const std::vector<std::vector<double>> values{{0, 0.1, 0.2}, {0, 1e-4, 2e-4}};
  std::string text = binary_raw({"v(b)", "i(l1)"}, time, values);
  text.replace(text.find("No. Points: 3"), 13, "No. Points: 0");
  const std::string file = write_temp("aborted.raw", text);
  const dcad::io::Traces t = dcad::io::read_traces(file);
  EXPECT_EQ(t.time, time);
  EXPECT_EQ(t.values, values);
  ASSERT_EQ(t.notes.size(), 1u);
  EXPECT_NE(t.notes[0].find("'No. Points: 0' with 3 points after it"), std::string::npos) << t.notes[0];
  std::ostringstream log;
  const dcad::api::WaveformChecked c = dcad::api::check_waveform(*dcad::io::open_traces(file), deck, {}, log);
  EXPECT_EQ(c.points, 3);
  EXPECT_NE(log.str().find("note: " + file + ": 'No. Points: 0'"), std::string::npos) << log.str();
  const std::string torn = write_temp("aborted-torn.raw", text.substr(0, text.size() - 4));
  EXPECT_THROW((void)dcad::io::read_traces(torn), dcad::io::InputError);
}

// Issue 45 §3: `dcad check` streams an ngspice binary raw file from disk (io::open_traces, chunks of
// points: memory bounded whatever the file's size) — and the verdict is the one of the file read whole
// (io::read_traces): the same JSON, over 10,001 points (three chunks), with a breakpoint's time written
// negative as ngspice does.  A time that decreases is the same bad input either way, naming the point.
TEST(TraceStream, BinaryRawStreamsAsReadWhole) {
  const dcad::io::Problem deck = dcad::fuzz::typed_bases()[3];  // the tank with a PULSE source, .tran 1u 40u
  const std::size_t n = 10001;
  std::vector<double> time(n);
  std::vector<std::vector<double>> values(2, std::vector<double>(n));
  for (std::size_t i = 0; i < n; ++i) {
    time[i] = 40e-6 * static_cast<double>(i) / static_cast<double>(n - 1);
    values[0][i] = std::sin(1e5 * time[i]), values[1][i] = 1e-3 * std::cos(3e5 * time[i]);
  }
  time[5000] = -time[5000];
  const std::string file = write_temp("stream.raw", binary_raw({"v(b)", "i(l1)"}, time, values));
  const std::unique_ptr<dcad::io::TraceStream> stream = dcad::io::open_traces(file);
  EXPECT_EQ(stream->format(), "ngspice raw (binary)");
  EXPECT_EQ(stream->points(), n);
  EXPECT_EQ(stream->last_time(), 40e-6);
  std::ostringstream log_a, log_b;
  const dcad::api::WaveformChecked a = dcad::api::check_waveform(*stream, deck, {}, log_a);
  const dcad::api::WaveformChecked b = dcad::api::check_waveform(dcad::io::read_traces(file), deck, {}, log_b);
  EXPECT_EQ(dcad::api::waveform_json(a, {}), dcad::api::waveform_json(b, {}));
  EXPECT_EQ(a.points, static_cast<long>(n));
  EXPECT_FALSE(a.agree);  // (values that are not the tank's: a verdict to compare, not a run)
  std::swap(time[7000], time[7001]);
  const std::string bad = write_temp("stream-bad.raw", binary_raw({"v(b)", "i(l1)"}, time, values));
  std::string streamed, whole;
  try {
    std::ostringstream log;
    (void)dcad::api::check_waveform(*dcad::io::open_traces(bad), deck, {}, log);
  } catch (const dcad::io::InputError& e) {
    streamed = e.what();
  }
  try {
    (void)dcad::io::read_traces(bad);
  } catch (const dcad::io::InputError& e) {
    whole = e.what();
  }
  EXPECT_NE(whole.find("point 7002: expected nondecreasing times"), std::string::npos) << whole;
  EXPECT_EQ(streamed, whole);
}

// ngspice's tests/general/rc.cir: `pulse (0 1)` with .tran 0.1 7 takes PW = PER = TSTOP = 7, so the pulse
// is cut at t = 7, where ngspice still gives V2 = 1 (it wraps only past PER: vsrcload.c).  That is the
// left value of the step at a corner (either side allowed): the double flow's left value was the next
// period's 0, and a right ngspice run was a disagreement.
TEST(TraceStream, PulseCutByItsPeriodHasBothValuesAtThePeriod) {
  const dcad::io::Problem deck = dcad::io::parse_netlist(
      "Basic RC circuit\nr 1 2 1.0\nc 2 0 1.0\nvin 1 0 pulse (0 1) ac 1\n.tran 0.1 7.0\n.end\n", "rc.cir");
  dcad::io::Traces t;
  t.file = "rc.raw";
  t.names = {"v(1)"};
  t.time = {0.0, 3.5, 7.0};
  t.values = {{0.0, 1.0, 1.0}};
  std::ostringstream log;
  const dcad::api::WaveformChecked c = dcad::api::check_waveform(t, deck, {}, log);
  ASSERT_EQ(c.vectors.size(), 1u);
  EXPECT_TRUE(c.agree) << dcad::api::waveform_json(c, {});
  t.values = {{0.0, 1.0, 0.5}};  // neither side
  EXPECT_FALSE(dcad::api::check_waveform(t, deck, {}, log).agree);
}

// The balls at the given values prove a zero of the chart's constraints; the chart is M_c's there only where what
// its elimination took as 0 (in double, at a generic point) vanishes.  An entry that is not 0 at the given values
// withdraws the proof (prop_pointwise's seed 733862999: -4/5625 beside terms of 10^5 passed the double check).
TEST(Api, BallsAtTheGivenValuesRefuseAChartWhoseZeroDecisionFails) {
  namespace ex = dcad::symbolic::expr;
  const dcad::io::LagrangianCase c = dcad::io::read_lagrangian_case(case_path("cartesian-pendulum.json"));
  const auto charted = dcad::api::chart_for(c, {9, 6, 5, 4, 3, 2}, 0);
  ASSERT_TRUE(std::holds_alternative<dcad::api::Charted>(charted)) << std::get<std::string>(charted);
  dcad::api::Charted ch = std::get<dcad::api::Charted>(charted);
  const auto sound = dcad::api::at_given(c, ch, false, true);
  ASSERT_TRUE(sound.proved) << sound.why;
  ch.chart.vanishing.push_back(ex::sub(ex::variable(0), ex::number(dcad::reference::Rational(1, 2))));  // x − 1/2
  const auto refused = dcad::api::at_given(c, ch, false, true);
  EXPECT_FALSE(refused.proved);
  EXPECT_NE(refused.why.find("as 0 on M_c"), std::string::npos) << refused.why;
  EXPECT_TRUE(refused.velocity.empty());
}
