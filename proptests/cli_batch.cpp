// `dcad solve` as a CI runs it (issue 14): several files in one process (JSON lines) and `--with`,
// which computes only the parts asked for (linear cases and netlists) or prints only them (the
// forced route and the expression form compute everything they report).  Each test compares two routes to the same
// answer: a file solved alone against the same file in a batch; `--with none` or one part against `--with all` (the
// default), on every case and netlist of cases/ and on all three backends.
#include "cli_run.hpp"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

using nlohmann::json;

namespace {

const std::vector<std::string> kRequired = {"dcad",  "backend",    "certified",     "dims",
                                            "steps", "consistent", "solution_rank", "unique"};
const std::vector<std::string> kOptional = {"final_constraints", "reduced", "constraint_classes", "dirac_bracket",
                                            "adapted"};

/// Every case file and netlist of cases/ (linear, forced, expression form: --with applies to all).
std::vector<std::string> corpus() {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(fs::path(DCAD_SOURCE_DIR) / "cases")) {
    const std::string ext = e.path().extension().string();
    if (ext == ".cir" || ext == ".json") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

json solved(const std::string& args) {
  const Outcome o = run("solve --json " + args);
  EXPECT_EQ(o.rc, 0) << args << "\n" << o.err;
  return o.rc == 0 ? json::parse(o.out) : json();
}

}  // namespace

// --with none keeps every required key with the value --with all gives, and drops the optional
// parts; --with P gives part P exactly as --with all does.  Killed by: a part computed from a
// different tower, a required key computed only when a part is asked for, a flag read wrongly.
TEST(SolveWith, PartsAgreeWithTheFullResult) {
  int files = 0;
  for (const std::string& f : corpus()) {
    for (const std::string backend : {"reference", "fast", "certified"}) {
      const json all = solved("--backend " + backend + " " + f);
      if (all.is_null()) continue;
      const json none = solved("--backend " + backend + " --with none " + f);
      for (const std::string& k : kRequired)
        if (k != "certified") EXPECT_EQ(none[k], all[k]) << f << " " << backend << " " << k;
      // fewer parts, fewer decisions: what is certified with all parts is certified without them
      if (all["certified"] == true) EXPECT_EQ(none["certified"], true) << f << " " << backend;
      EXPECT_EQ(none["tower"], all["tower"]) << f << " " << backend;  // every route's tower is exact or fast's own
      for (const std::string& k : {"final_constraints", "reduced", "adapted", "dirac_bracket"})
        EXPECT_FALSE(none.contains(k)) << f << " " << backend << " --with none printed " << k;
      for (const auto& [part, key] : std::vector<std::pair<std::string, std::string>>{{"final", "final_constraints"},
                                                                                      {"reduced", "reduced"},
                                                                                      {"classes", "constraint_classes"},
                                                                                      {"adapted", "adapted"}}) {
        const json one = solved("--backend " + backend + " --with " + part + " " + f);
        EXPECT_EQ(one.contains(key), all.contains(key)) << f << " " << backend << " --with " << part;
        if (all.contains(key) && backend != "certified")
          EXPECT_EQ(one[key], all[key]) << f << " " << backend << " --with " << part;
        for (const std::string& other : kOptional)
          if (other != key && !(part == "classes" && other == "dirac_bracket"))
            EXPECT_FALSE(one.contains(other)) << f << " " << backend << " --with " << part << " printed " << other;
      }
      ++files;
    }
  }
  EXPECT_GE(files, 30);  // the corpus is there and was read
}

TEST(SolveWith, UnknownPartIsBadUsage) {
  const Outcome o = run("solve --with final,bracket " + std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.json");
  EXPECT_EQ(o.rc, 2);
  EXPECT_NE(o.err.find("found 'bracket'"), std::string::npos) << o.err;
  EXPECT_TRUE(o.out.empty());
}

// Several files in one process: line k is file k's result, as when it is solved alone; a bad
// file is a line with its error and exit code, the others still run, the process exits 1.
TEST(SolveBatch, JsonLinesMatchOneFileAtATime) {
  const std::vector<std::string> files = corpus();
  ASSERT_GE(files.size(), 10u);
  const std::string bad =
      write_temp("dcad_batch_bad.json", "{\"dcad\": 1, \"variables\": [\"x\"], \"dirac\": {\"presymplectic\": [[1]]}}");
  std::string args = "solve --jsonl --backend reference";
  for (std::size_t i = 0; i < 6; ++i) args += " " + files[i];
  args += " " + bad + " " + files[6];
  const Outcome o = run(args);
  EXPECT_EQ(o.rc, 1);
  const std::vector<std::string> lines = split_lines(o.out);
  ASSERT_EQ(lines.size(), 8u) << o.out << o.err;
  for (std::size_t i = 0; i < 8; ++i) {
    const json line = json::parse(lines[i]);
    if (i == 6) {
      EXPECT_EQ(line["file"], bad);
      EXPECT_EQ(line["exit"], 1);
      EXPECT_NE(line["error"].get<std::string>().find(bad), std::string::npos) << line;
      EXPECT_NE(o.err.find(line["error"].get<std::string>()), std::string::npos);  // and on stderr, as for one file
      continue;
    }
    const std::string f = files[i < 6 ? i : 6];
    EXPECT_EQ(line["file"], f);
    json alone = solved("--backend reference " + f);
    alone["file"] = f;
    EXPECT_EQ(line, alone) << f;
  }
  // --json with several files is JSON lines too; one file with --json stays one indented object
  const Outcome two = run("solve --json --with none " + files[0] + " " + files[1]);
  EXPECT_EQ(two.rc, 0);
  EXPECT_EQ(split_lines(two.out).size(), 2u);
  const Outcome one = run("solve --json --with none " + files[0]);
  EXPECT_GT(split_lines(one.out).size(), 2u);
}

// Issue 15, three error channels: an input property fast cannot decide is a result that says so
// (exit 0, "certified": false, the evidence in the note), never "bad input"; a property that
// certainly fails is bad input (exit 1) on every backend.
TEST(ErrorChannels, UndecidedInputIsAResultNotBadInput) {
  const auto constrained = [](const std::string& tiny) {
    return "{\"dcad\": 1, \"variables\": [\"q1\", \"p1\", \"q2\", \"p2\"], \"constrained\": {\"symplectic\": "
           "[[\"0\", \"1\", \"0\", \"0\"], [\"-1\", \"0\", \"0\", \"0\"], [\"0\", \"0\", \"0\", \"" +
           tiny + "\"], [\"0\", \"0\", \"-" + tiny +
           "\", \"0\"]], \"primary\": [[\"0\", \"0\", \"1\", \"0\", \"0\"]]}, \"energy\": {\"hessian\": "
           "[[\"1\", \"0\", \"0\", \"0\"], [\"0\", \"1\", \"0\", \"0\"], [\"0\", \"0\", \"1\", \"0\"], [\"0\", \"0\", "
           "\"0\", \"1\"]]}}";
  };
  const std::string band = write_temp("dcad_channels_band.json", constrained("1e-10"));  // σ = 1e-10: between τ0 and τ1
  const Outcome fast = run("solve --json --backend fast " + band);
  ASSERT_EQ(fast.rc, 0) << fast.err;
  const json r = json::parse(fast.out);
  EXPECT_EQ(r["certified"], false);
  EXPECT_NE(r["note"].get<std::string>().find("nondegenerate is uncertain"), std::string::npos) << r["note"];
  const Outcome exact = run("solve --json --backend reference " + band);  // exactly nondegenerate: a plain result
  ASSERT_EQ(exact.rc, 0) << exact.err;
  EXPECT_EQ(json::parse(exact.out)["certified"], true);
  const std::string degenerate = write_temp("dcad_channels_degenerate.json", constrained("0"));
  for (const std::string backend : {"fast", "reference", "certified"}) {
    const Outcome o = run("solve --backend " + backend + " " + degenerate);
    EXPECT_EQ(o.rc, 1) << backend << ": " << o.err;
    EXPECT_NE(o.err.find("nondegenerate"), std::string::npos) << backend << ": " << o.err;
    EXPECT_NE(o.err.find(degenerate), std::string::npos) << backend << ": " << o.err;
  }
}

// Issue 14: the reference in machine words goes on in 128-bit words when a number outgrows 64 bits
// (ω perturbed by 2^-50: products of 2^-50 need more than 64 bits), instead of recomputing in mpq; the
// result is the mpq run's (the same JSON but for the note and decisions), and certified says which.
TEST(SolveWords, WideWordsWhenSixtyFourBitsGiveUp) {
  const std::string file = std::string(DCAD_SOURCE_DIR) + "/cases/regression-fast-perturbed-2e-50.json";
  const Outcome cert = run("solve " + file + " --backend certified --json");
  ASSERT_EQ(cert.rc, 0) << cert.err;
  const nlohmann::json c = nlohmann::json::parse(cert.out);
  EXPECT_EQ(c["decisions"]["exact_machine_words"], 1);
  EXPECT_NE(c["note"].get<std::string>().find("128-bit"), std::string::npos) << c["note"];
  const Outcome ref = run("solve " + file + " --backend reference --json");
  ASSERT_EQ(ref.rc, 0) << ref.err;
  nlohmann::json r = nlohmann::json::parse(ref.out), cc = c;
  for (nlohmann::json* j : {&r, &cc})
    for (const char* k : {"backend", "note", "decisions"}) j->erase(k);
  EXPECT_EQ(r, cc);
  EXPECT_EQ(r["dims"], c["dims"]);
}
