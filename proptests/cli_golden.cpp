// Golden cases (issue 15: one ctest entry per case): every cases/*.json with expect.inspect or
// expect.dims and every cases/*.cir with a "* expect:" line, on every backend, through the dcad binary
// as a user runs it.
#include "cli_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// The files of cases/ with the extension whose JSON (or "* expect:" line) has expect.<key>, sorted.
std::vector<fs::path> cases_with(const std::string& ext, const std::string& key) {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(DCAD_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ext) continue;
    if (ext == ".json") {
      const nlohmann::json c = nlohmann::json::parse(slurp(e.path()), nullptr, false);
      if (c.is_discarded() || !c.contains("expect") || !c["expect"].contains(key)) continue;
    }
    out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string case_name(const testing::TestParamInfo<fs::path>& info) {
  std::string s = info.param.stem().string();
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

/// The report's tower lists M_0 … M_c in order, each with the dimension `dims` gives it (two fields of
/// one result that other tools read separately).
void expect_tower_is_dims(const nlohmann::json& got, const std::string& label) {
  if (!got.contains("tower")) return;
  const nlohmann::json& t = got["tower"];
  ASSERT_EQ(t.size(), got["dims"].size()) << label;
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_EQ(t[k]["k"], k) << label << " tower[" << k << "]";
    EXPECT_EQ(t[k]["dim"], got["dims"][k]) << label << " tower[" << k << "]";
  }
}

/// The published DAE benchmark set (cases/published/*.json), sorted.
std::vector<fs::path> published_cases() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(DCAD_SOURCE_DIR) / "cases" / "published"))
    if (e.path().extension() == ".json") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

class GoldenInspect : public testing::TestWithParam<fs::path> {};
class Published : public testing::TestWithParam<fs::path> {};
class GoldenSolve : public testing::TestWithParam<fs::path> {};
class GoldenNetlist : public testing::TestWithParam<fs::path> {};

}  // namespace

// Guards against an empty corpus (a moved directory would otherwise pass with no tests).
TEST(Golden, CorpusIsThere) {
  EXPECT_GE(cases_with(".json", "inspect").size(), 4u);
  EXPECT_GE(cases_with(".json", "dims").size(), 10u);
  EXPECT_GE(cases_with(".cir", "").size(), 3u);
}

TEST_P(GoldenInspect, EveryBackend) {
  const fs::path path = GetParam();
  const nlohmann::json c = nlohmann::json::parse(slurp(path));
  {
    for (const std::string backend : {"reference", "fast"}) {
      const Outcome r = run("inspect " + path.string() + " --backend " + backend + " --json");
      ASSERT_EQ(r.rc, 0) << path << " " << backend << ": " << r.err;
      const nlohmann::json got = nlohmann::json::parse(r.out);
      EXPECT_EQ(got["backend"], backend);
      EXPECT_TRUE(got["certified"].get<bool>()) << path << " " << backend;
      for (const auto& [key, want] : c["expect"]["inspect"].items())
        EXPECT_EQ(got[key], want) << path << " " << backend << " key " << key;
    }
  }
}

/// Every case with solve expectations, on every backend: discrete keys exactly (fast: when it says
/// certified), reduced equations exactly (reference, certified-exact) or to 1e-9 (fast).
TEST_P(GoldenSolve, EveryBackend) {
  const fs::path path = GetParam();
  const nlohmann::json c = nlohmann::json::parse(slurp(path));
  {
    const nlohmann::json& want = c["expect"];
    nlohmann::json adapted_variables;  // the reference's
    for (const std::string backend : {"reference", "fast", "certified"}) {
      const Outcome r = run("solve " + path.string() + " --backend " + backend + " --json");
      ASSERT_EQ(r.rc, 0) << path << " " << backend << ": " << r.err;
      const nlohmann::json got = nlohmann::json::parse(r.out);
      const bool exact = got["backend"] == "reference" || got.value("route", "") == "pointwise exact" ||
                         got.value("decisions", nlohmann::json::object()).value("exact_recomputation", 0) == 1;
      for (const char* key : {"dcad", "backend", "certified", "dims", "steps", "consistent", "solution_rank", "unique"})
        EXPECT_TRUE(got.contains(key)) << key;
      if (backend != "fast") EXPECT_TRUE(got["certified"].get<bool>());
      expect_tower_is_dims(got, path.string() + " " + backend);
      // fast's own decisions are held to the reference on every case: its confirmation by the certified tier
      // (reference/fast_backend/src/solve.cpp) keeps a wrong certain answer from saying certified, and saying why
      // here is a failure of the fast twin unless the case documents it. Killed by: the separation hypothesis
      // missing on cases/regression-pointwise-height.json with its known failure removed.
      const bool refuted =
          got.value("note", "").find("the exact route (the certified tier) finds") != std::string::npos;
      EXPECT_TRUE(!refuted || (c.contains("known_failures") && c["known_failures"].contains(backend)))
          << path << " " << backend << ": " << got.value("note", "");
      if (c.contains("known_failures") && c["known_failures"].contains(backend)) {  // documented, must stay visible
        const bool differs = got["dims"] != want["dims"] || got["solution_rank"] != want["solution_rank"];
        EXPECT_TRUE(!got["certified"].get<bool>() || differs)
            << path << " " << backend << ": the known failure is gone; remove known_failures from the case";
        continue;
      }
      if (got["certified"].get<bool>()) {
        for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique", "constraint_classes",
                                "regular_pencil", "index"}) {
          if (!want.contains(key)) continue;
          nlohmann::json g = got[key];
          if (g.is_object()) g.erase("second_class_constraints");  // compared: the counts
          EXPECT_EQ(g, want[key]) << path << " " << backend << " " << key;
        }
      }
      if (got.contains("adapted")) {  // the coordinates the chi are written in: certain or not, the reference's
        if (backend == "reference") adapted_variables = got["adapted"]["variables"];
        EXPECT_EQ(got["adapted"]["variables"], adapted_variables) << path << " " << backend;
      }
      if (want.contains("adapted") && got["certified"].get<bool>()) {  // Theorem 3.28 / 7.4
        const nlohmann::json& wa = want["adapted"];
        const nlohmann::json& ga = got["adapted"];
        EXPECT_EQ(ga["setting"], wa["setting"]) << path;
        EXPECT_EQ(ga["s_prime"], wa["s_prime"]) << path;
        EXPECT_EQ(ga["second_class"].size(), wa["second_class_count"].get<std::size_t>()) << path;
        EXPECT_EQ(ga["abridged_total_energy_constraints"].size(), wa["abridged_count"].get<std::size_t>()) << path;
        EXPECT_EQ(ga["secondary_first_class"], wa["secondary_first_class"]) << path;
      }
      if (!want.contains("reduced")) continue;
      const nlohmann::json& wr = want["reduced"];
      const nlohmann::json& gr = got["reduced"];
      EXPECT_EQ(gr["coordinates"], wr["coordinates"]);
      const auto num = [](const nlohmann::json& x) {
        const std::string s = x.is_string() ? x.get<std::string>() : x.dump();
        const auto slash = s.find('/');
        return slash == std::string::npos ? std::stod(s)
                                          : std::stod(s.substr(0, slash)) / std::stod(s.substr(slash + 1));
      };
      for (const char* key : {"F", "f"}) {
        if (!wr.contains(key)) continue;
        if (exact) {
          EXPECT_EQ(gr[key], wr[key]) << path << " " << backend << " " << key;
          continue;
        }
        const nlohmann::json a =
            wr[key].is_array() && wr[key][0].is_array() ? wr[key] : nlohmann::json::array({wr[key]});
        const nlohmann::json b =
            gr[key].is_array() && gr[key][0].is_array() ? gr[key] : nlohmann::json::array({gr[key]});
        for (std::size_t i = 0; i < a.size(); ++i)
          for (std::size_t j = 0; j < a[i].size(); ++j)
            EXPECT_NEAR(num(b[i][j]), num(a[i][j]), 1e-9 * (1 + std::abs(num(a[i][j])))) << path << " " << key;
      }
    }
  }
}

/// Every netlist in cases/ with a "* expect: {json}" comment (the deck still runs in ngspice).
TEST_P(GoldenNetlist, EveryBackend) {
  const fs::path path = GetParam();
  {
    std::istringstream in(slurp(path));
    nlohmann::json want;
    bool fast_uncertain = false;  // "* fast-uncertain: why" in the deck
    for (std::string line; std::getline(in, line);) {
      if (line.rfind("* expect:", 0) == 0) want = nlohmann::json::parse(line.substr(9));
      fast_uncertain = fast_uncertain || line.rfind("* fast-uncertain:", 0) == 0;
    }
    ASSERT_FALSE(want.is_null()) << path << " has no '* expect:' line";
    // fast twice: with everything (often not certified: the reduced equations of inexact values) and
    // with the tower alone, which the graph route decides without a rank decision
    for (const std::string backend : {"reference", "fast", "fast --with none", "certified"}) {
      const Outcome r = run("solve " + path.string() + " --backend " + backend + " --json");
      ASSERT_EQ(r.rc, 0) << path << " " << backend << ": " << r.err;
      const nlohmann::json got = nlohmann::json::parse(r.out);
      expect_tower_is_dims(got, path.string() + " " + backend);
      // the certainty floor: these decks are small and well conditioned, at their realistic values;
      // the tower in double must be certain where the deck does not say why not.
      // Killed by: the forced route's projection residual with + (seed-26 survivor [94]: every
      // forced deck went uncertain, two with wrong dims, and the test skipped them)
      if (backend == "fast --with none" && !fast_uncertain)
        EXPECT_TRUE(got["certified"].get<bool>()) << path << " " << got["note"];
      if (!got["certified"].get<bool>()) continue;
      for (const auto& [key, value] : want.items()) {
        if (key == "circuit") {
          for (const auto& [ck, cv] : value.items()) EXPECT_EQ(got["circuit"][ck], cv) << path << " circuit." << ck;
        } else {
          EXPECT_EQ(got[key], value) << path << " " << backend << " " << key;
        }
      }
    }
  }
}

/// The published DAE benchmark set (issues 49 and 51): each problem's tower derived by hand in its description
/// (`expect`) has the source's own index (`published.index`); on every backend a certified answer is that tower,
/// exactly; the reference and certified backends answer certified unless `known_failures` names the backend and
/// why (then it must still fail: a fixed gap shows here); a refusal is exit 1 with a message naming the file.
/// A known failure whose reason starts "time:" (more than minutes) is not run here: bench/published_daes.py times it.
TEST_P(Published, EveryBackendAgreesWithTheSource) {
  const fs::path path = GetParam();
  const nlohmann::json c = nlohmann::json::parse(slurp(path));
  ASSERT_TRUE(c.contains("published") && c["published"].contains("index")) << path;
  EXPECT_EQ(c["expect"]["index"], c["published"]["index"]) << path << ": the hand derivation against the source";
  const nlohmann::json known = c.value("known_failures", nlohmann::json::object());
  for (const std::string backend : {"reference", "fast", "certified"}) {
    if (known.contains(backend) && known[backend].get<std::string>().rfind("time:", 0) == 0) continue;
    const Outcome r = run("solve " + path.string() + " --backend " + backend + " --json");
    if (known.contains(backend)) {
      EXPECT_TRUE(r.rc == 1 || (r.rc == 0 && !nlohmann::json::parse(r.out)["certified"].get<bool>()))
          << path << " " << backend << ": the known failure is gone; remove it from known_failures";
      if (r.rc == 1) EXPECT_NE(r.err.find(path.string()), std::string::npos) << r.err;
      if (r.rc == 1) continue;
    } else {
      ASSERT_EQ(r.rc, 0) << path << " " << backend << ": " << r.err;
    }
    const nlohmann::json got = nlohmann::json::parse(r.out);
    if (backend != "fast" && !known.contains(backend))
      EXPECT_TRUE(got["certified"].get<bool>()) << path << " " << backend;
    if (!got["certified"].get<bool>()) continue;
    for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique", "index"})
      EXPECT_EQ(got[key], c["expect"][key]) << path << " " << backend << " " << key;
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, Published, testing::ValuesIn(published_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Cases, GoldenInspect, testing::ValuesIn(cases_with(".json", "inspect")), case_name);
INSTANTIATE_TEST_SUITE_P(Cases, GoldenSolve, testing::ValuesIn(cases_with(".json", "dims")), case_name);
INSTANTIATE_TEST_SUITE_P(Cases, GoldenNetlist, testing::ValuesIn(cases_with(".cir", "")), case_name);

// The report cites a theorem of CEF §6 only where its hypotheses hold: Thm 6.6 (L, C > 0 and no empty
// branch) on the 4-port with its c, not on a tank with wires; Thm 6.8 (C > 0) on both, with its
// verdict.  (A survivor of the seed-25 mutation sample: Thm 6.6 cited when either hypothesis held.)
TEST(GoldenReport, TheoremsCitedOnlyUnderTheirHypotheses) {
  const Outcome four = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.cir");
  ASSERT_EQ(four.rc, 0) << four.err;
  EXPECT_NE(four.out.find("CEF Thm 6.6 (L, C > 0, no empty branch): c ∈ {1, 3}, c = 3 iff a purely capacitive loop "
                          "exists — here c = 3"),
            std::string::npos)
      << four.out;
  EXPECT_NE(four.out.find("there are no empty loops — here symplectic"), std::string::npos) << four.out;
  const Outcome wires = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/lc-empty-loop.cir");
  ASSERT_EQ(wires.rc, 0) << wires.err;
  EXPECT_EQ(wires.out.find("CEF Thm 6.6"), std::string::npos) << wires.out;
  EXPECT_NE(wires.out.find("there are no empty loops — here not symplectic"), std::string::npos) << wires.out;
}

// What fast may certify is decided by the heights of the exact input (dcad/fast/exact.hpp), not by
// whether double holds it.  Small heights: the 4-port of CEF §6 as a `pontryagin` case (1/C = 1/3, 1/5,
// 1/7: the README's worked example) is certified by fast with every part, as by the exact backends
// (fast used to say "NOT certified" on it: 1/3 is not a double).  Large heights decide the answer and
// fast must not certify: the cancelling pair of capacitors (C2 = -3.0000000000000000001, the forced
// route: it certified a tower two steps too long), input-rounding.json (1 + 10^-17 reads as 1) and
// C2 = -(3 + 3·2^-50), a double of height 2^50 + 1 (the graph route certified a tower one step short); the
// note names the cause.
TEST(GoldenFast, CertainExactlyWhereTheInputsHeightAllows) {
  const std::string dir = std::string(DCAD_SOURCE_DIR) + "/cases/";
  const nlohmann::json exact = nlohmann::json::parse(run("solve " + dir + "lc-4port.json --json").out);
  const Outcome four = run("solve " + dir + "lc-4port.json --backend fast --json");
  ASSERT_EQ(four.rc, 0) << four.err;
  const nlohmann::json got = nlohmann::json::parse(four.out);
  EXPECT_TRUE(got["certified"].get<bool>()) << got["note"];
  for (const char* key : {"dims", "steps", "solution_rank", "unique"}) EXPECT_EQ(got[key], exact[key]) << key;
  EXPECT_EQ(got["adapted"]["s_prime"], exact["adapted"]["s_prime"]);
  const std::string rounded = "a value that double rounds has height above 67108864",
                    digits = "magnitudes and digits span more than 67108864";
  for (const auto& [file, cause] :
       std::vector<std::pair<std::string, std::string>>{{"regression-fast-forced-rounded-cancellation.cir", rounded},
                                                        {"input-rounding.json", rounded},
                                                        {"regression-fast-exact-double-cancellation.cir", digits}}) {
    const Outcome r = run("solve " + dir + file + " --backend fast --json --with none");
    ASSERT_EQ(r.rc, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["certified"].get<bool>()) << file << ": " << j["dims"];
    EXPECT_NE(j["note"].get<std::string>().find("no rank deficiency is certain in double: "), std::string::npos)
        << file << ": " << j["note"];
    EXPECT_NE(j["note"].get<std::string>().find(cause), std::string::npos) << file << ": " << j["note"];
    const nlohmann::json e = nlohmann::json::parse(run("solve " + dir + file + " --json --with none").out);
    EXPECT_TRUE(j["dims"] != e["dims"] || j["solution_rank"] != e["solution_rank"])
        << file << ": the rounded input's answer differs from the exact one (else this case shows nothing)";
  }
}
