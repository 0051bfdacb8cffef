// The twins' public namespaces, diffed (issue 15): every top-level function and type name declared in
// reference/include/dcad/reference/ and the fast twin's dcad/fast/ headers is in both, or is listed in
// proptests/twins.txt with the reason it is in one only.  A new name in one twin without its twin — or
// a listed difference that has gone — fails, so the list stays the truth about the twins.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

/// Names declared at column 0 of the headers in `dirs` and their subfolders: functions (a return type,
/// the name, "(") and types (struct, class, enum, alias `using X = …`).  Members are indented and so
/// not counted.
std::set<std::string> public_names(const std::vector<fs::path>& dirs) {
  static const std::regex function(
      R"(^(?!return|if|for|while|else|using|namespace|struct|class|template|static_assert|typedef)[A-Za-z][\w:<>, *&]*?[\s*&]+(~?[A-Za-z_]\w*)\()");
  static const std::regex type(R"(^(?:(?:struct|class|enum class|enum) (\w+)|using (\w+) =))");
  std::set<std::string> out;
  for (const fs::path& dir : dirs)
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (e.path().extension() != ".hpp") continue;
      std::ifstream in(e.path());
      std::smatch m;
      for (std::string line; std::getline(in, line);)
        if (std::regex_search(line, m, function))
          out.insert(m[1]);
        else if (std::regex_search(line, m, type))
          out.insert(m[1].matched ? m[1] : m[2]);
    }
  return out;
}

struct Listed {
  std::map<std::string, std::string> reference_only, fast_only;  ///< name → reason
};

Listed read_list(const fs::path& file) {
  Listed out;
  std::ifstream in(file);
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    const std::size_t colon = line.find(" : ");
    EXPECT_NE(colon, std::string::npos) << file << ":" << number << ": expected 'side NAME... : reason'";
    if (colon == std::string::npos) continue;
    std::istringstream words(line.substr(0, colon));
    std::string side, name;
    words >> side;
    EXPECT_TRUE(side == "reference-only" || side == "fast-only") << file << ":" << number << ": side " << side;
    auto& target = side == "fast-only" ? out.fast_only : out.reference_only;
    while (words >> name)
      EXPECT_TRUE(target.emplace(name, line.substr(colon + 3)).second)
          << file << ":" << number << ": " << name << " twice";
  }
  return out;
}

}  // namespace

TEST(Twins, PublicNamesDifferOnlyAsListed) {
  const fs::path root(DCAD_SOURCE_DIR);
  // the reference twin: the literal algorithms and, beside them, its pipelines (reference::solve)
  const std::set<std::string> ref =
      public_names({root / "reference/include/dcad/reference", root / "reference/solve/include/dcad/reference"});
  // namespace fast: the twin (dcad::fast, dcad::fast_nonlinear) and the fast backend (dcad::fast_exact, beside the
  // reference since it borrows the reference's algorithms where fast has no route of its own)
  const std::set<std::string> fast =
      public_names({root / "fast/include/dcad/fast", root / "fast/nonlinear/include/dcad/fast",
                    root / "reference/fast_backend/include/dcad/fast"});
  const Listed listed = read_list(root / "proptests/twins.txt");
  ASSERT_GE(ref.size(), 100u);  // the scan sees the headers
  ASSERT_GE(fast.size(), 60u);
  for (const std::string& n : {"constraint_tower", "gotay_nester", "foliated_tower", "velocities", "dirac_bergmann",
                               "classify_constraints", "adapted_to_primary", "reduced_equations", "pointwise_cad",
                               "pontryagin_system", "tangent_cotangent_embedding", "PontryaginInput"})
    EXPECT_TRUE(ref.count(n) && fast.count(n)) << n << " must be in both twins";
  for (const std::string& n : ref)
    if (!fast.count(n)) EXPECT_TRUE(listed.reference_only.count(n)) << "reference-only and not in twins.txt: " << n;
  for (const std::string& n : fast)
    if (!ref.count(n)) EXPECT_TRUE(listed.fast_only.count(n)) << "fast-only and not in twins.txt: " << n;
  for (const auto& [n, why] : listed.reference_only)
    EXPECT_TRUE(ref.count(n) && !fast.count(n))
        << "twins.txt lists " << n << " as reference-only; it is not (" << why << ")";
  for (const auto& [n, why] : listed.fast_only)
    EXPECT_TRUE(fast.count(n) && !ref.count(n))
        << "twins.txt lists " << n << " as fast-only; it is not (" << why << ")";
}

// Issue 47: the twins are independent — no library target under fast/ reaches a reference target (defined under
// reference/, except dcad_core and the targets of reference/core — the plain types and the exact algebra of
// formulas, dcad::symbolic, both share) through its links, except those listed in
// proptests/style/fast_links_reference.txt, a list that may only shrink.  The graph is CMake's own
// (build/link_graph.tsv, written at configure time from each target's LINK_LIBRARIES).
TEST(Twins, FastLinksNoReference) {
  std::ifstream graph(DCAD_LINK_GRAPH);
  ASSERT_TRUE(graph) << "no link graph at " << DCAD_LINK_GRAPH << " (configure writes it)";
  std::map<std::string, std::string> folder;              // target -> the folder that defines it
  std::map<std::string, std::vector<std::string>> links;  // target -> its direct links, aliases as targets
  for (std::string line; std::getline(graph, line);) {
    std::istringstream row(line);
    std::string target, dir, all;
    std::getline(row, target, '\t');
    std::getline(row, dir, '\t');
    std::getline(row, all);
    folder[target] = dir;
    std::istringstream items(all);
    for (std::string item; std::getline(items, item, ';');) {
      if (item.rfind("$<LINK_ONLY:", 0) == 0 && item.back() == '>')  // a static library's private link
        item = item.substr(12, item.size() - 13);
      links[target].push_back(item.rfind("dcad::", 0) == 0 ? "dcad_" + item.substr(6) : item);
    }
  }
  ASSERT_TRUE(folder.count("dcad_fast") && folder.count("dcad_reference")) << "the graph names the twins";
  const auto is_reference = [&](const std::string& t) {
    // dcad::core and dcad::symbolic (reference/core/: plain types and the shared exact algebra of formulas) are
    // shared by both twins; every other target under reference/ is the reference or is built on it
    return folder.count(t) && t != "dcad_core" && folder[t].rfind("reference/core", 0) != 0 &&
           folder[t].rfind("reference", 0) == 0;
  };
  std::map<std::string, std::string> listed;  // target -> reason
  std::ifstream list(fs::path(DCAD_SOURCE_DIR) / "proptests/style/fast_links_reference.txt");
  for (std::string line; std::getline(list, line);) {
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    const std::size_t colon = line.find(" : ");
    EXPECT_NE(colon, std::string::npos) << "fast_links_reference.txt: expected 'TARGET : reason', found " << line;
    if (colon != std::string::npos) listed[line.substr(0, colon)] = line.substr(colon + 3);
  }
  for (const auto& [target, dir] : folder) {
    if (dir.rfind("fast", 0) != 0) continue;
    std::string reached;  // the first reference target its links reach, with the path to it
    std::vector<std::pair<std::string, std::string>> stack = {{target, target}};
    std::set<std::string> seen;
    while (!stack.empty() && reached.empty()) {
      const auto [t, path] = stack.back();
      stack.pop_back();
      if (!seen.insert(t).second) continue;
      for (const std::string& l : links[t]) {
        if (is_reference(l)) reached = path + " -> " + l;
        stack.emplace_back(l, path + " -> " + l);
      }
    }
    if (listed.count(target))
      EXPECT_FALSE(reached.empty()) << target << " no longer links the reference: delete its line in "
                                    << "proptests/style/fast_links_reference.txt (" << listed[target] << ")";
    else
      EXPECT_TRUE(reached.empty()) << "a target under fast/ links the reference: " << reached;
  }
  for (const auto& [target, why] : listed) EXPECT_TRUE(folder.count(target)) << "listed and not a target: " << target;
}

// Issue 47: where the fast backend still runs the reference's code, each place is named.  Every
// `#include "dcad/reference/…"` under reference/fast_backend must be listed in
// proptests/style/fast_backend_borrows.txt, and every listed one must still be there: the list only shrinks.
TEST(Twins, FastBackendBorrowsOnlyTheListed) {
  const fs::path root = fs::path(DCAD_SOURCE_DIR) / "reference/fast_backend";
  std::set<std::string> found;  // "FILE : HEADER"
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path());
    const std::string file = fs::relative(entry.path(), root).generic_string();
    const std::string tag = "#include \"dcad/reference/";
    for (std::string line; std::getline(in, line);)
      if (line.rfind(tag, 0) == 0) found.insert(file + " : " + line.substr(10, line.find('"', 10) - 10));
  }
  ASSERT_GE(found.size(), 1u) << "the scan sees " << root;
  std::set<std::string> listed;
  std::ifstream list(fs::path(DCAD_SOURCE_DIR) / "proptests/style/fast_backend_borrows.txt");
  for (std::string line; std::getline(list, line);) {
    if (line.find_first_not_of(" \t") == std::string::npos || line[0] == '#') continue;
    const std::size_t second = line.find(" : ", line.find(" : ") + 3);
    EXPECT_NE(second, std::string::npos) << "fast_backend_borrows.txt: expected 'FILE : HEADER : why', found " << line;
    if (second != std::string::npos) listed.insert(line.substr(0, second));
  }
  for (const std::string& f : found)
    EXPECT_TRUE(listed.count(f)) << "the fast backend borrows the reference here and it is not listed: " << f;
  for (const std::string& l : listed)
    EXPECT_TRUE(found.count(l)) << "listed in fast_backend_borrows.txt and no longer borrowed: " << l;
}

// README "dcad from C++" says its C++ examples are proptests/consumer/consumer.cpp's tests, verbatim (the
// install_consumer test builds and runs that file): each ```cpp block of the section must stand in the file as is.
TEST(Readme, CppExamplesAreTheConsumersVerbatim) {
  const auto slurp = [](const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream o;
    o << in.rdbuf();
    return o.str();
  };
  const std::string readme = slurp(fs::path(DCAD_SOURCE_DIR) / "README.md");
  const std::string consumer = slurp(fs::path(DCAD_SOURCE_DIR) / "proptests/consumer/consumer.cpp");
  const std::size_t from = readme.find("\n## dcad from C++"), to = readme.find("\n## ", from + 1);
  ASSERT_NE(from, std::string::npos);
  int blocks = 0;
  for (std::size_t at = readme.find("```cpp\n", from); at < to; at = readme.find("```cpp\n", at + 1)) {
    const std::size_t begin = at + 7, end = readme.find("```", begin);
    const std::string block = readme.substr(begin, end - begin);
    EXPECT_NE(consumer.find(block), std::string::npos) << "README's block is not in consumer.cpp:\n" << block;
    ++blocks;
  }
  EXPECT_GE(blocks, 8);  // the includes and seven tests
}
