// dcad::api (issue 15): the pipeline as a library gives what the dcad binary prints — the same result
// JSON, the same check verdict, the same CSV — and its errors come on the three channels (InputError
// naming the file, UsageError, InternalError), each with the CLI's exit code.
#include "cli_run.hpp"
#include "dcad/api.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>
#include <string>

namespace {

std::string case_path(const std::string& name) { return std::string(DCAD_SOURCE_DIR) + "/cases/" + name; }

}  // namespace

// Two routes to one result: the library call and the binary, for every input form and backend.
TEST(Api, SolveEqualsTheBinary) {
  for (const char* name : {"lc-4port.json", "lc-4port.cir", "rlc-series.cir", "rolling-disk.json", "constrained-gauge.json"})
    for (const std::string backend : {"reference", "fast", "certified"}) {
      const dcad::api::Solved s = dcad::api::solve(case_path(name), {backend, "all"});
      const Outcome bin = run("solve " + case_path(name) + " --backend " + backend + " --json");
      ASSERT_EQ(bin.rc, 0) << name << bin.err;
      EXPECT_EQ(s.result, nlohmann::json::parse(bin.out)) << name << " " << backend;
      EXPECT_EQ(s.report, run("solve " + case_path(name) + " --backend " + backend).out) << name << " " << backend;
    }
}

// `--with none` is the CONTRACT's required keys and the tower only.
TEST(Api, SolveComputesWhatIsAsked) {
  const nlohmann::json all = dcad::api::solve(case_path("lc-4port.json"), {"reference", "all"}).result;
  const nlohmann::json none = dcad::api::solve(case_path("lc-4port.json"), {"reference", "none"}).result;
  EXPECT_TRUE(all.contains("adapted"));
  EXPECT_FALSE(none.contains("adapted"));
  EXPECT_EQ(all["dims"], none["dims"]);
}

// check: a result agrees with itself; the same result with one dimension changed disagrees, naming it.
TEST(Api, CheckAgreesAndDisagrees) {
  const std::string file = case_path("lc-4port.json");
  nlohmann::json result = dcad::api::solve(file, {"fast", "none"}).result;
  const std::string good = write_temp("dcad_api_good.json", result.dump());
  const dcad::api::Checked ok = dcad::api::check(good, file);
  EXPECT_TRUE(ok.agrees);
  EXPECT_TRUE(ok.disagreements.empty());
  result["dims"][1] = result["dims"][1].get<long>() + 1;
  const dcad::api::Checked bad = dcad::api::check(write_temp("dcad_api_bad.json", result.dump()), file);
  EXPECT_FALSE(bad.agrees);
  ASSERT_FALSE(bad.disagreements.empty());
  EXPECT_NE(bad.disagreements[0].find("dims"), std::string::npos) << bad.disagreements[0];
  EXPECT_EQ(run("check " + good + " " + file).rc, 0);
}

// simulate: the CSV the binary prints, row for row; the layout names its columns.
TEST(Api, SimulateEqualsTheBinary) {
  for (const char* name : {"rlc-series.cir", "lc-4port.cir"}) {
    std::ostringstream csv, log;
    const dcad::api::Simulated s = dcad::api::simulate(case_path(name), {1e-4, 1e-6, "certified"}, csv, log);
    EXPECT_EQ(s.rows, 101);
    EXPECT_LT(s.error_estimate, 1e-9);
    EXPECT_EQ(csv.str(), run("simulate " + case_path(name) + " --tstop 1e-4 --step 1e-6").out) << name;
    const dcad::api::SimulateLayout layout = dcad::api::simulate_layout(case_path(name));
    EXPECT_EQ(layout.columns.front(), "t");
    std::string header;
    for (const std::string& c : layout.columns) header += (header.empty() ? "" : ",") + c;
    EXPECT_EQ(csv.str().substr(0, csv.str().find('\n')), header);
  }
}

// The channels: bad input names the file (exit 1), options that do not apply are usage (exit 2).
TEST(Api, ErrorChannels) {
  const std::string missing = case_path("no-such-case.json");
  try {
    dcad::api::solve(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const dcad::api::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    EXPECT_EQ(dcad::api::exit_code(e), 1);
  }
  const std::string bad = write_temp("dcad_api_bad_case.json", R"({"dcad": 1, "dirac": {"form": [[0, 1], [1, 0]]}})");
  try {
    dcad::api::solve(bad);
    ADD_FAILURE() << "no error for a symmetric form";
  } catch (const dcad::api::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dcad::api::solve(case_path("lc-4port.json"), {"exact", "all"}), dcad::api::UsageError);
  EXPECT_THROW(dcad::api::solve(case_path("lc-4port.json"), {"reference", "bracket,final"}), dcad::api::UsageError);
  std::ostringstream csv, log, energy;
  try {
    dcad::api::simulate(case_path("lc-4port.cir"), {1e-3, 1e-4, "certified"}, csv, log, &energy);
    ADD_FAILURE() << "--energy of a lossless circuit";
  } catch (const dcad::api::UsageError& e) {
    EXPECT_EQ(dcad::api::exit_code(e), 2);
    EXPECT_NE(std::string(e.what()).find("lossless"), std::string::npos) << e.what();
  }
  EXPECT_THROW(dcad::api::simulate(case_path("rlc-series.cir"), {-1, 1e-6, "certified"}, csv, log), dcad::api::InputError);
  EXPECT_EQ(dcad::api::exit_code(dcad::api::InternalError("x")), 4);
}

// A default-constructed verdict claims nothing: a caller that fills in a Checked itself (or forgets to)
// must not read "agrees".  (A survivor of the seed-25 mutation sample: `agrees = true` by default.)
TEST(Api, DefaultVerdictDoesNotAgree) {
  const dcad::api::Checked none;
  EXPECT_FALSE(none.agrees);
  EXPECT_TRUE(none.compared.empty());
}
