// The golden corpus (cases/) for other projects, and the regression workflow (a property-test
// counterexample → a golden case with the reference's expectations).
#include "dcad/api.hpp"
#include "simulate.hpp"
#include "sparse_flow.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include <unistd.h>

#ifndef DCAD_CASES_DIR
#define DCAD_CASES_DIR "cases"
#endif
#ifndef DCAD_BIN_DIR
#define DCAD_BIN_DIR "bin"
#endif
#ifndef DCAD_DATA_DIR
#define DCAD_DATA_DIR "share"
#endif
#ifndef DCAD_INSTALLED_CASES_DIR
#define DCAD_INSTALLED_CASES_DIR "/usr/local/share/dcad/cases"
#endif

namespace dcad::api {

namespace fs = std::filesystem;
using nlohmann::json;
using ordered = nlohmann::ordered_json;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw io::InputError(p.string() + ": cannot read");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> corpus() {
  std::vector<fs::path> files;
  if (!fs::is_directory(cases_dir()))
    throw io::InputError(cases_dir() + ": expected the case directory (set DCAD_CASES), found none");
  for (const auto& e : fs::directory_iterator(cases_dir()))
    if (e.path().extension() == ".json" || io::is_netlist_file(e.path().string())) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// The reference result JSON for a case file or netlist (what `dcad solve --backend reference --json` prints).
json reference_result(const fs::path& file) {
  return json::parse(io::result_json(printed(solve(io::read_problem(file.string()), Backend::reference)), -1));
}

std::string summary(const fs::path& file) {
  if (io::is_netlist_file(file.string())) {
    std::istringstream in(slurp(file));
    std::string title;
    std::getline(in, title);
    return "netlist: " + title;
  }
  const json j = json::parse(slurp(file), nullptr, false);
  if (j.is_discarded()) return "(not JSON)";
  const std::string d = j.value("description", "");
  return (j.contains("pontryagin")    ? "pontryagin: "
          : j.contains("constrained") ? "constrained: "
          : j.contains("lagrangian")  ? "lagrangian: "
                                      : "dirac: ") +
         d.substr(0, d.find(". "));
}

fs::path find_case(const std::string& name) {
  for (const fs::path& p : corpus())
    if (p.stem() == name || p.filename() == name) return p;
  throw io::InputError("dcad cases show: expected a case name from `dcad cases list`, found \"" + name + "\"");
}

/// The keys a golden case pins (the CONTRACT's discrete keys, plus the circuit counts).
ordered expectations(const json& result) {
  ordered e;
  for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique"}) e[key] = result[key];
  if (result.contains("circuit"))
    e["circuit"] = {{"pc_loops", result["circuit"]["pc_loops"]}, {"empty_loops", result["circuit"]["empty_loops"]}};
  if (result.contains("reduced"))
    e["reduced"] = {{"coordinates", result["reduced"]["coordinates"]},
                    {"F", result["reduced"]["F"]},
                    {"f", result["reduced"]["f"]}};
  return e;
}

std::string freeze(const std::string& from_file, const std::string& wanted) {
  const fs::path from = from_file;
  std::string text = slurp(from);
  const bool netlist = io::is_netlist_file(from.string());
  if (!netlist) {  // a property log: the line "dcad case: {…}"
    const std::size_t at = text.find("dcad case: ");
    if (at != std::string::npos) text = text.substr(at + 11, text.find('\n', at) - at - 11);
  }
  const std::string name = !wanted.empty() ? wanted : "regression-" + from.stem().string();
  const fs::path to = fs::path(cases_dir()) / (name + (netlist ? from.extension().string() : ".json"));
  if (fs::exists(to)) throw io::InputError(to.string() + ": expected a new case name, found an existing case");
  // a file of this process's own (two freezes at once must not read each other's), removed however we leave
  const fs::path tmp = fs::temp_directory_path() / ("dcad_freeze_" + std::to_string(::getpid()) +
                                                    std::string(netlist ? from.extension().string() : ".json"));
  struct Removed {
    fs::path path;
    ~Removed() {
      std::error_code ignored;
      fs::remove(path, ignored);
    }
  } removed{tmp};
  {
    std::ofstream t(tmp);
    t << text;
  }
  json result;
  try {
    result = reference_result(tmp);
  } catch (const io::InputError& e) {  // bad input: the message names the user's file, not the copy
    std::string m = e.what();
    const std::string copy = tmp.string(), named = from.string() + (netlist ? "" : " (its \"dcad case:\" line)");
    for (std::size_t k; (k = m.find(copy)) != std::string::npos;) m.replace(k, copy.size(), named);
    throw io::InputError(m);
  }
  std::ofstream o(to);
  if (!o)
    throw io::InputError(to.string() +
                         ": expected a corpus directory dcad can write, found it cannot (set DCAD_CASES)");
  if (netlist) {
    std::istringstream in(text);
    std::string title;
    std::getline(in, title);
    o << title << "\n* dcad cases freeze " << from.string()
      << ": expectations by the reference backend\n* expect: " << expectations(result).dump() << "\n";
    for (std::string line; std::getline(in, line);)
      if (line.rfind("* expect:", 0) != 0) o << line << "\n";
  } else {
    ordered c = ordered::parse(text);
    c["name"] = name;
    if (!c.contains("description"))
      c["description"] = "regression case frozen from " + from.string() + " by `dcad cases freeze`";
    c["expect"] = expectations(result);
    o << c.dump(2) << "\n";
  }
  o.close();
  if (!o) throw io::InputError(to.string() + ": the write failed");
  return "wrote " + to.string() + " (expectations by the reference backend: dims " + result["dims"].dump() + ")";
}

}  // namespace

std::string cases_dir() {
  const char* env = std::getenv("DCAD_CASES");
  if (env && *env) return env;
  std::error_code ec;
  // an installed dcad, PREFIX/bin/dcad, reads PREFIX/share/dcad/cases (installed with it), wherever PREFIX is
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && exe.parent_path().filename() == fs::path(DCAD_BIN_DIR).filename()) {
    const fs::path beside = exe.parent_path().parent_path() / DCAD_DATA_DIR / "dcad" / "cases";
    if (fs::is_directory(beside, ec)) return beside.string();
  }
  // the build tree reads its source checkout; a program linking the installed dcad::api, the configured prefix
  return fs::is_directory(DCAD_CASES_DIR, ec) ? DCAD_CASES_DIR : DCAD_INSTALLED_CASES_DIR;
}

std::vector<CaseEntry> list_cases() {
  std::vector<CaseEntry> out;
  for (const fs::path& p : corpus()) out.push_back({p.filename().string(), summary(p)});
  return out;
}

std::string show_case(const std::string& name) { return slurp(find_case(name)); }

int export_cases(const std::string& dir_name) {
  const fs::path dir = dir_name;
  fs::create_directories(dir);
  int n = 0;
  for (const fs::path& p : corpus()) {
    fs::copy_file(p, dir / p.filename(), fs::copy_options::overwrite_existing);
    std::ofstream(dir / (p.stem().string() + ".expected.json")) << reference_result(p).dump(2) << "\n";
    ++n;
  }
  fs::copy_file(fs::path(cases_dir()) / "schema" / "result.schema.json", dir / "result.schema.json",
                fs::copy_options::overwrite_existing);
  return n;
}

int export_waveforms(const std::string& dir_name, std::ostream& log) {
  const fs::path dir = dir_name, from = fs::path(cases_dir()) / "waveforms";
  fs::create_directories(dir);
  std::vector<fs::path> decks;
  for (const auto& e : fs::directory_iterator(from))
    if (e.path().extension() == ".cir") decks.push_back(e.path());
  std::sort(decks.begin(), decks.end());
  for (const fs::path& p : decks) {
    const io::Problem prob = io::read_problem(p.string());
    const io::Netlist& deck = prob.netlist();
    if (!deck.tran_step || !deck.tran_stop || !(*deck.tran_step > 0) || *deck.tran_stop < 0)
      throw io::InputError(p.string() +
                           ": expected a .tran TSTEP TSTOP card with numbers for its waveforms, found none");
    const double step = deck.tran_step->convert_to<double>(), stop = deck.tran_stop->convert_to<double>();
    std::vector<std::string> names;
    for (const std::string& n : deck.node_names) names.push_back("v(" + n + ")");
    for (std::size_t b = 0; b < deck.rlc.branches.size(); ++b)
      if (deck.rlc.branches[b].kind == reference::RlcKind::inductor ||
          deck.rlc.branches[b].kind == reference::RlcKind::voltage) {
        std::string name = deck.rlc.branches[b].name;
        for (char& ch : name) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        names.push_back("i(" + name + ")");
      }
    const long rows = static_cast<long>(std::floor(stop / step + 1e-9));
    std::vector<double> times(static_cast<std::size_t>(rows + 1));
    for (long k = 0; k <= rows; ++k) times[static_cast<std::size_t>(k)] = static_cast<double>(k) * step;
    // the enclosures' midpoints and radii (NAME.bounds.csv) where dcad builds them, else the double flow
    const WaveformEnclosures enc = enclose_waveforms(prob, names, times, Initial::deck, step);
    std::vector<std::vector<double>> value(names.size(), std::vector<double>(times.size())), radius = value;
    std::string how;
    if (enc.ok) {
      for (std::size_t k = 0; k < names.size(); ++k)
        for (std::size_t i = 0; i < times.size(); ++i)
          value[k][i] = enc.right[k][i].mid,
          radius[k][i] = io::printed_radius(enc.right[k][i].mid, enc.right[k][i].rad);
      how = "enclosures (certified), radii in " + p.stem().string() + ".bounds.csv";
    } else {
      std::ostringstream quiet;
      SparseFlow flow(deck, p.string(), Initial::deck, step, stop, quiet);
      for (std::size_t i = 0; i < times.size(); ++i) {
        flow.advance_to(times[i]);
        const Eigen::VectorXd e = flow.node_potentials();
        const sr::BranchValues v = flow.values();
        std::size_t k = 0;
        for (; k < deck.node_names.size(); ++k) value[k][i] = e(static_cast<Eigen::Index>(k));
        for (std::size_t b = 0; b < deck.rlc.branches.size(); ++b)
          if (deck.rlc.branches[b].kind == reference::RlcKind::inductor ||
              deck.rlc.branches[b].kind == reference::RlcKind::voltage)
            value[k++][i] = v.i(static_cast<Eigen::Index>(b));
      }
      how = "the double flow, error estimate " + io::float_text(flow.error_estimate()) +
            " of the state (no enclosure: " + enc.why + ")";
    }
    fs::copy_file(p, dir / p.filename(), fs::copy_options::overwrite_existing);
    for (int file = 0; file < (enc.ok ? 2 : 1); ++file) {
      std::ofstream csv(dir / (p.stem().string() + (file ? ".bounds.csv" : ".csv")));
      csv.precision(17);
      csv << "time";
      for (const std::string& n : names) csv << "," << n;
      csv << "\n";
      const auto& table = file ? radius : value;
      for (std::size_t i = 0; i < times.size(); ++i) {
        csv << times[i];
        for (std::size_t k = 0; k < names.size(); ++k) csv << "," << table[k][i] + 0.0;  // never "-0"
        csv << "\n";
      }
    }
    log << p.filename().string() << ": " << rows + 1 << " rows, " << how << "\n";
  }
  return static_cast<int>(decks.size());
}

std::string freeze_case(const std::string& from, const std::string& name) {
  if (from.empty()) throw io::InputError("dcad cases freeze: expected FILE [NAME], found nothing");
  return freeze(from, name);
}

}  // namespace dcad::api
