// Running the dcad binary from a test as a user would: exit code, stdout, stderr; temporary files;
// the simulation CSV as numbers.  Shared by the CLI test executables (DCAD_BINARY, DCAD_SOURCE_DIR
// are compile definitions of each).
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <map>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

struct Outcome {
  int rc = -1;
  std::string out, err;
};

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline Outcome run(const std::string& args) {
  const fs::path dir = fs::temp_directory_path();
  const std::string tag = std::to_string(getpid());  // test executables run in parallel
  const std::string out = (dir / ("dcad_cli_out_" + tag)).string(), err = (dir / ("dcad_cli_err_" + tag)).string();
  const int status = std::system((std::string(DCAD_BINARY) + " " + args + " >" + out + " 2>" + err).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

/// A path for a temporary file `name` in a directory of this process's own: test executables run in
/// parallel, and two runs of the suite (a mutation run beside a developer's) read each other's fixed
/// /tmp names (Check.EveryCaseValidatesAndRoundTrips checked another case's result that way).
inline std::string temp_path(const std::string& name) {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / ("dcad_test_" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }();
  return (dir / name).string();
}

inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::string p = temp_path(name);
  std::ofstream(p) << text;
  return p;
}

/// The non-empty lines of a text.
inline std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

/// CSV rows as numbers (header skipped).
inline std::vector<std::vector<double>> csv_rows(const std::string& text) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
    rows.push_back(row);
  }
  return rows;
}

struct BadCase {
  const char* name;
  const char* text;
  const char* needle;  // must appear in stderr
};

/// Bad input: exit 1, and stderr names the file, contains `needle`, and says expected/found.
inline void expect_input_error(const Outcome& r, const std::string& file, const std::string& needle,
                               const std::string& label) {
  EXPECT_EQ(r.rc, 1) << label << "\n" << r.out << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << label << ": " << r.err;
  EXPECT_NE(r.err.find(needle), std::string::npos) << label << ": " << r.err;
  EXPECT_NE(r.err.find("expected"), std::string::npos) << label << ": " << r.err;
  EXPECT_NE(r.err.find("found"), std::string::npos) << label << ": " << r.err;
}

/// Two decks that are the same circuit: `dcad simulate` prints the same table for both (exit 0); the table.
inline std::string expect_same_simulation(const std::string& deck, const std::string& twin, const std::string& args) {
  const Outcome a = run("simulate " + deck + " " + args), b = run("simulate " + twin + " " + args);
  EXPECT_EQ(a.rc, 0) << deck << ": " << a.err;
  EXPECT_EQ(b.rc, 0) << twin << ": " << b.err;
  EXPECT_EQ(a.out, b.out) << deck << " and " << twin;
  return a.out;
}

/// Two decks that are the same circuit: `dcad solve --json ARGS` gives the same `keys` for both (exit 0);
/// the deck's outcome (its warnings on err).
inline Outcome expect_same_solution(const std::string& deck, const std::string& twin,
                                    std::initializer_list<const char*> keys, const std::string& args = "") {
  const Outcome a = run("solve " + deck + " --json " + args), b = run("solve " + twin + " --json " + args);
  EXPECT_EQ(a.rc, 0) << deck << ": " << a.err;
  EXPECT_EQ(b.rc, 0) << twin << ": " << b.err;
  if (a.rc != 0 || b.rc != 0) return a;
  const nlohmann::json ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  for (const char* key : keys) EXPECT_EQ(ja.at(key), jb.at(key)) << key << " of " << deck << " and " << twin;
  return a;
}

/// `dcad simulate DECK ARGS` as rows of named numbers (the CSV header names the columns); exit 0 expected.
inline std::vector<std::map<std::string, double>> simulate_rows(const std::string& deck, const std::string& args,
                                                                std::string* err = nullptr) {
  const Outcome r = run("simulate " + deck + " " + args);
  EXPECT_EQ(r.rc, 0) << r.err;
  if (err) *err = r.err;
  std::istringstream in(r.out);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> head;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');) head.push_back(c);
  }
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::map<std::string, double> row;
    std::size_t k = 0;
    for (std::string c; std::getline(l, c, ',') && k < head.size(); ++k) row[head[k]] = std::stod(c);
    rows.push_back(row);
  }
  return rows;
}

inline double case_value(const std::string& text, const std::string& key) {  // "balance ... holds to X"
  const std::size_t at = text.find(key);
  return at == std::string::npos ? 1.0 : std::stod(text.substr(at + key.size()));
}
