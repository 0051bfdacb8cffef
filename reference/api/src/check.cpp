// `dcad check RESULT.json FILE` (CONTRACT): another implementation's result for FILE against the
// reference.  Discrete keys exactly; richer optional keys (`final_constraints`, `reduced`,
// `dirac_bracket`) as subspaces or within a condition-aware tolerance (documented in the README).
#include "dcad/api.hpp"
#include "dcad/reference/pipeline/exact_place.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/certified/dae_sparse.hpp"
#include "check_formulas.hpp"
#include "guarded.hpp"
#include "json_input.hpp"  // dcad::io's exact JSON reader (build tree)

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

namespace dcad::api {

namespace {

using nlohmann::json;

[[noreturn]] void bad(const std::string& file, const std::string& path, const std::string& expected,
                      const std::string& found) {
  throw io::InputError(file + ": " + path + ": expected " + expected + ", found " + found);
}

std::string shown(const json& j) {
  std::string s = j.dump();
  return s.size() > 200 ? s.substr(0, 200) + "…" : s;
}

/// A number of the result: exact if an integer or fraction string ("-3/7"); a decimal string
/// ("0.99999999999999967", as `--backend fast` prints) or a JSON number is a float.
struct Number {
  bool exact = false;
  io::Rational q;
  double d = 0;
};

Number number(const std::string& file, const std::string& path, const json& j) {
  Number n;
  if (j.is_number()) {
    n.d = j.get<double>();
    return n;
  }
  if (j.is_string()) {
    try {
      const std::string t = j.get<std::string>();
      n.exact = t.find_first_of(".eE") == std::string::npos;
      if (!n.exact) {
        std::size_t used = 0;
        n.d = std::stod(t, &used);
        if (used != t.size()) throw std::invalid_argument(t);
        return n;
      }
      n.q = reference::parse_rational(t);
      n.d = n.q.convert_to<double>();
      return n;
    } catch (const std::exception&) {
    }
  }
  bad(file, path, "a number or an exact string such as \"-3/7\"", shown(j));
}

/// found ≈ want: exactly if found is exact, else |found − want| ≤ tol·scale.
bool close(const Number& found, const io::Rational& want, double tol, double scale) {
  if (found.exact) return found.q == want;
  return std::abs(found.d - want.convert_to<double>()) <= tol * scale;
}

struct Checker {
  std::string file;
  Checked out;
  void compare(const std::string& key, const json& want, const json& found) {
    out.compared.push_back(key);
    if (want != found) out.disagreements.push_back(key + ": expected " + shown(want) + ", found " + shown(found));
  }
};

/// Tolerance for floating-point entries: 1e-9 relative to the largest exact entry, times the number
/// of entries (accumulated rounding of a backward-stable computation on well-conditioned data).
double matrix_tolerance(std::size_t entries) { return 1e-9 * static_cast<double>(std::max<std::size_t>(entries, 1)); }

void compare_matrix(Checker& k, const std::string& key, const Rows<io::Rational>& want, const json& found) {
  k.out.compared.push_back(key);
  if (!found.is_array() || found.size() != want.size()) {
    k.out.disagreements.push_back(key + ": expected " + std::to_string(want.size()) + " rows, found " + shown(found));
    return;
  }
  double scale = 1;
  for (const auto& row : want)
    for (const io::Rational& x : row) scale = std::max(scale, std::abs(x.convert_to<double>()));
  const double tol = matrix_tolerance(want.size() * (want.empty() ? 0 : want[0].size()));
  for (std::size_t i = 0; i < want.size(); ++i) {
    if (!found[i].is_array() || found[i].size() != want[i].size()) {
      k.out.disagreements.push_back(key + "[" + std::to_string(i) + "]: expected " + std::to_string(want[i].size()) +
                                    " entries, found " + shown(found[i]));
      continue;
    }
    for (std::size_t j = 0; j < want[i].size(); ++j) {
      std::string path = "/" + key + "/" + std::to_string(i) + "/" + std::to_string(j);
      std::replace(path.begin(), path.end(), '.', '/');
      const Number f = number(k.file, path, found[i][j]);
      if (!close(f, want[i][j], tol, scale))
        k.out.disagreements.push_back(key + "[" + std::to_string(i) + "][" + std::to_string(j) + "]: expected " +
                                      want[i][j].str() + ", found " + shown(found[i][j]) + " (tolerance " +
                                      std::to_string(tol * scale) + ")");
    }
  }
}

io::Rational exact_value(const Number& x) { return x.exact ? x.q : io::Rational(x.d); }

/// The result's matrix at `path` (rows × cols of numbers) with the exact value of every entry as
/// given; nullopt (and a disagreement) if its shape is not rows × cols.
std::optional<io::QMatrix> found_matrix(Checker& k, const std::string& key, const json& found, std::size_t rows,
                                        std::size_t cols, std::vector<std::vector<Number>>& numbers) {
  if (!found.is_array() || found.size() != rows) {
    k.out.disagreements.push_back(key + ": expected " + std::to_string(rows) + " rows, found " + shown(found));
    return std::nullopt;
  }
  io::QMatrix m(rows, cols);
  numbers.assign(rows, {});
  for (std::size_t i = 0; i < rows; ++i) {
    if (!found[i].is_array() || found[i].size() != cols) {
      k.out.disagreements.push_back(key + "[" + std::to_string(i) + "]: expected " + std::to_string(cols) +
                                    " entries, found " + shown(found[i]));
      return std::nullopt;
    }
    for (std::size_t j = 0; j < cols; ++j) {
      std::string path = "/" + key + "/" + std::to_string(i) + "/" + std::to_string(j);
      std::replace(path.begin(), path.end(), '.', '/');
      numbers[i].push_back(number(k.file, path, found[i][j]));
      m(i, j) = exact_value(numbers[i].back());
    }
  }
  return m;
}

io::QMatrix exact_matrix(const Rows<io::Rational>& m, std::size_t cols) {
  io::QMatrix out(m.size(), cols);
  for (std::size_t i = 0; i < m.size(); ++i)
    for (std::size_t j = 0; j < cols; ++j) out(i, j) = m[i][j];
  return out;
}

double max_abs(const io::QMatrix& m) {
  double s = 0;
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t j = 0; j < m.cols(); ++j) s = std::max(s, std::abs(m(i, j).convert_to<double>()));
  return s;
}

/// The equations of motion ż = F z + f + G λ are determined only as the affine family
/// {(F + G K, f + G k)} with span(G) (CEF (5.12): λ is free), so a correct result may differ from
/// the reference by any G K.  Compared: N F, N f against the reference's (N = rows spanning the
/// left null space of the reference's G, exact), N G_found = 0 and rank G_found = rank G, i.e.
/// span(G_found) = span(G).  Exact where the result's numbers are exact strings, else within
/// 1e-9 × entries × scale.  Without free multipliers N = I: F and f entry by entry.
/// Whether every number of x is exact (then a comparison is exact too).
bool exact_all(const std::vector<std::vector<Number>>& x) {
  for (const auto& row : x)
    for (const Number& v : row)
      if (!v.exact) return false;
  return true;
}

/// reduced.G against the reference's g free directions: as many independent columns, each in span(G) (N G = 0,
/// N the rows annihilating the reference's G), exactly or to the matrices' tolerance.
void compare_free_directions(Checker& k, const io::QMatrix& n, std::size_t g, std::size_t g_cols,
                             const std::optional<io::QMatrix>& g_found, bool exact) {
  k.out.compared.push_back("reduced.G (span)");
  if (!g_found) return;
  const long rank = static_cast<long>(reference::rref(*g_found).pivots.size());
  if (g_cols != g || rank != static_cast<long>(g)) {
    k.out.disagreements.push_back("reduced.G: expected " + std::to_string(g) +
                                  " independent free directions (solution rank), found " + std::to_string(rank) +
                                  " among " + std::to_string(g_cols) + " columns");
    return;
  }
  const io::QMatrix ngf = n * *g_found;
  const double tol =
      exact ? 0 : matrix_tolerance(g_found->rows() * g) * std::max(1.0, max_abs(n)) * std::max(1.0, max_abs(*g_found));
  for (std::size_t i = 0; i < ngf.rows(); ++i)
    for (std::size_t j = 0; j < ngf.cols(); ++j)
      if (std::abs(ngf(i, j).convert_to<double>()) > tol || (tol == 0 && ngf(i, j) != 0)) {
        k.out.disagreements.push_back("reduced.G: column " + std::to_string(j) + " is not in the reference's span(G)");
        return;
      }
}

void compare_reduced(Checker& k, const reference::Solution& truth, const json& red) {
  const Motion<io::Rational>& mo = *truth.motion;
  const std::size_t m = mo.coordinates.size(), g = mo.g.empty() ? 0 : mo.g[0].size();
  const io::QMatrix f_ref = exact_matrix(mo.f_matrix, m), g_ref = exact_matrix(mo.g, g);
  io::QMatrix fv_ref(m, 1);
  for (std::size_t i = 0; i < m; ++i) fv_ref(i, 0) = mo.f[i];
  // N: rows y with yᵀ G = 0 (the whole of (Q^m)* without multipliers)
  const io::QMatrix n = reference::annihilator(reference::Subspace<io::Rational>::span(g_ref.transpose())).basis();
  const std::string modulo = g ? " modulo span(G)" : "";
  std::vector<std::vector<Number>> nf, nv, ng;
  const json fv_json = [&] {
    json col = json::array();
    for (const json& x : red.value("f", json::array())) col.push_back(json::array({x}));
    return col;
  }();
  const auto f_found = found_matrix(k, "reduced.F", red.value("F", json()), m, m, nf);
  const auto v_found = found_matrix(k, "reduced.f", fv_json, m, 1, nv);
  // G: m rows of g numbers; [] stands for no free multipliers
  const json g_json = red.contains("G") && red["G"].is_array() && red["G"].empty()
                          ? json(std::vector<json>(m, json::array()))
                          : red.value("G", json());
  const std::size_t g_cols = g_json.is_array() && !g_json.empty() && g_json[0].is_array() ? g_json[0].size() : 0;
  const auto g_found =
      red.contains("G") ? found_matrix(k, "reduced.G", g_json, m, g_cols, ng) : std::optional<io::QMatrix>();
  const auto same_modulo = [&](const std::string& key, const io::QMatrix& want, const io::QMatrix& found, bool exact) {
    k.out.compared.push_back(key + modulo);
    const io::QMatrix d = n * found - n * want;
    const double scale = std::max(1.0, max_abs(n)) * std::max({1.0, max_abs(want), max_abs(found)});
    const double tol = exact ? 0 : matrix_tolerance(want.rows() * want.cols()) * scale;
    for (std::size_t i = 0; i < d.rows(); ++i)
      for (std::size_t j = 0; j < d.cols(); ++j)
        if (std::abs(d(i, j).convert_to<double>()) > tol || (exact && d(i, j) != 0)) {
          k.out.disagreements.push_back(
              key + ": differs from the reference" + modulo + " (component " + std::to_string(i) + "," +
              std::to_string(j) + " of the difference, projected off span(G): " +
              io::float_text(d(i, j).convert_to<double>()) + ", tolerance " + io::float_text(tol) + ")");
          return;
        }
  };
  if (f_found) same_modulo("reduced.F", f_ref, *f_found, exact_all(nf));
  if (v_found) same_modulo("reduced.f", fv_ref, *v_found, exact_all(nv));
  if (!mo.source_columns.empty()) {  // the forced route: the sources' terms S over the jet columns
    const json& src = red.value("sources", json());
    if (!src.is_object() || src.value("columns", json()) != json(mo.source_columns)) {
      k.out.disagreements.push_back("reduced.sources: expected columns " + json(mo.source_columns).dump() +
                                    " and S, found " +
                                    (src.is_object() ? src.value("columns", json()).dump() : std::string("none")));
    } else {
      std::vector<std::vector<Number>> ns;
      const auto s_found =
          found_matrix(k, "reduced.sources.S", src.value("S", json()), m, mo.source_columns.size(), ns);
      if (s_found)
        same_modulo("reduced.sources.S", exact_matrix(mo.s, mo.source_columns.size()), *s_found, exact_all(ns));
    }
  }
  if (!red.contains("G")) {
    if (g) k.out.not_compared.push_back("reduced.G (absent: the result does not say which directions are free)");
    return;
  }
  compare_free_directions(k, n, g, g_cols, g_found, exact_all(ng));
}

/// `final_constraints`: rows [a…, b] of equations whose solution set the result claims is M_c.
/// Compared as affine subspaces: same dimension, and every equation holds on M_c (exact point and
/// directions) to within 1e-9·κ(A)·‖row‖ (κ = condition of the result's rows: rounding in a
/// well-posed computation moves the subspace by about ε·κ).
void compare_final_constraints(Checker& k, const json& found, const io::QMatrix& basis,
                               const std::vector<io::Rational>& point, long dim) {
  k.out.compared.push_back("final_constraints");
  const std::size_t n = basis.cols();
  if (!found.is_array()) bad(k.file, "/final_constraints", "an array of rows [a_1, …, a_N, b]", shown(found));
  std::vector<std::vector<Number>> rows;
  for (std::size_t i = 0; i < found.size(); ++i) {
    if (!found[i].is_array() || found[i].size() != n + 1)
      bad(k.file, "/final_constraints/" + std::to_string(i), "a row of " + std::to_string(n + 1) + " numbers [a…, b]",
          shown(found[i]));
    rows.emplace_back();
    for (std::size_t j = 0; j <= n; ++j)
      rows.back().push_back(
          number(k.file, "/final_constraints/" + std::to_string(i) + "/" + std::to_string(j), found[i][j]));
  }
  // rank of the result's rows (their dimension claim) by exact elimination on the numbers as given
  io::QMatrix a(rows.size(), n);
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < n; ++j) a(i, j) = rows[i][j].exact ? rows[i][j].q : io::Rational(rows[i][j].d);
  const long claimed = static_cast<long>(n) - static_cast<long>(reference::rref(a).pivots.size());
  if (claimed != dim) {
    k.out.disagreements.push_back("final_constraints: expected equations of a " + std::to_string(dim) +
                                  "-dimensional M_c, found " + std::to_string(claimed) + "-dimensional");
    return;
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double norm = 0, at_point = 0, size = 0;
    for (std::size_t j = 0; j < n; ++j) {
      norm = std::max(norm, std::abs(rows[i][j].d));
      at_point += rows[i][j].d * point[j].convert_to<double>();
      size += std::abs(rows[i][j].d * point[j].convert_to<double>());
    }
    const double tol = 1e-9 * static_cast<double>(n) * std::max(1.0, norm);
    bool ok = std::abs(at_point - rows[i][n].d) <= tol * std::max(1.0, size + std::abs(rows[i][n].d));
    for (std::size_t b = 0; ok && b < basis.rows(); ++b) {
      double s = 0, sz = 0;
      for (std::size_t j = 0; j < n; ++j) {
        s += rows[i][j].d * basis(b, j).convert_to<double>();
        sz += std::abs(rows[i][j].d * basis(b, j).convert_to<double>());
      }
      ok = std::abs(s) <= tol * std::max(1.0, sz);
    }
    if (!ok)
      k.out.disagreements.push_back("final_constraints[" + std::to_string(i) + "]: does not hold on the reference M_c");
  }
}

/// RESULT read (exactly, depth-limited) with its required keys and their types checked: io::InputError
/// (exit 1, naming the JSON path) otherwise.
json read_result(const std::string& result_file, const std::string* text) {
  const json r = text ? io::parse_json_exact(*text, result_file)
                      : io::read_json_file(result_file);  // floats kept as text; depth limited
  if (!r.is_object()) bad(result_file, "/", "a JSON object (the result of CONTRACT `dcad solve --json`)", shown(r));
  if (r.contains("dcad") && r["dcad"] != 1) bad(result_file, "/dcad", "1", shown(r["dcad"]));
  if (r.contains("formulas") && !r.contains("dims")) return r;  // formulas only (check_formulas reads them)
  for (const char* key : {"dims", "steps", "consistent", "solution_rank"})
    if (!r.contains(key))
      bad(result_file, std::string("/") + key, std::string("the required key \"") + key + "\"", "nothing");
  if (!r["dims"].is_array()) bad(result_file, "/dims", "an array of integers", shown(r["dims"]));
  for (std::size_t i = 0; i < r["dims"].size(); ++i)
    if (!r["dims"][i].is_number_integer())
      bad(result_file, "/dims/" + std::to_string(i), "an integer", shown(r["dims"][i]));
  if (!r["steps"].is_number_integer()) bad(result_file, "/steps", "an integer", shown(r["steps"]));
  if (!r["consistent"].is_boolean() && !r["consistent"].is_null())  // null: undecided at a singular point (dcad's own)
    bad(result_file, "/consistent", "true, false or null (undecided at a singular point)", shown(r["consistent"]));
  if (!r["solution_rank"].is_null() && !r["solution_rank"].is_number_integer())
    bad(result_file, "/solution_rank", "an integer (null if inconsistent)", shown(r["solution_rank"]));
  if (r.contains("reduced") && !r["reduced"].is_object())
    bad(result_file, "/reduced", "an object (CONTRACT: coordinates, F, f, G)", shown(r["reduced"]));
  return r;
}

/// What the reference prints for its solution (the keys the result is compared with).
template <class N>
json printed_json(const dcad::Solution<N>& s) {
  return json::parse(io::result_json(io::printed(s), -1));
}

/// The reference's solution of a linear case or netlist: the structured circuit route (exact), or above
/// certified::kDenseBranches with L, C > 0 the graph route (a theorem's answer, exact too).
reference::Solution truth_of(const io::Problem& p) {
  if (p.form() == io::Form::netlist && !p.netlist().forced &&
      p.netlist().circuit.branches.size() > certified::kDenseBranches) {
    const certified::Solution c = certified::solve(p);
    return map_numbers<io::Rational>(c, [](const certified::Number& x) {
      if (!x.exact) throw InternalError("check: the certified graph route gave an inexact number");
      return x.q;
    });
  }
  return reference::solve(p);
}

/// A result for a system with forces or sources against the forced route's exact tower: dims, steps, consistency,
/// solution rank and the reduced equations in the reference's coordinates (M_c not yet compared).
Checked check_forced(const std::string& result_file, const json& r, const io::Problem& p) {
  const reference::Solution fr = reference::solve(p);
  const json want = printed_json(fr);
  Checker k{result_file, {}};
  for (const char* key : {"dims", "steps", "consistent", "solution_rank"}) k.compare(key, want[key], r[key]);
  if (r.contains("unique")) k.compare("unique", want["unique"], r["unique"]);
  if (r.contains("final_constraints"))
    k.out.not_compared.push_back("final_constraints (not yet for systems with forces or sources)");
  if (r.contains("reduced") && fr.motion) {
    const json coords = r["reduced"].value("coordinates", json());
    if (coords != want["reduced"]["coordinates"])
      k.out.not_compared.push_back("reduced (in coordinates other than the reference's " +
                                   want["reduced"]["coordinates"].dump() +
                                   ": not yet for systems with forces or sources)");
    else
      compare_reduced(k, fr, r["reduced"]);
  }
  return k.out;
}

Checked check_linear(const std::string& result_file, const json& r, const io::Problem& p_in) {
  const io::CaseFile& c_in = p_in.linear();
  for (const char* key :
       {"dims", "steps", "consistent", "solution_rank"})  // formulas alone are for the expression form
    if (!r.contains(key))
      bad(result_file, std::string("/") + key,
          std::string("the required key \"") + key + "\" (formulas are compared for expression-form cases only)",
          "nothing");
  if (r.contains("name") && r["name"] != c_in.name)
    bad(result_file, "/name", "the name of " + c_in.file + " (\"" + c_in.name + "\")",
        shown(r["name"]) + ": a result for another case");
  if (r.contains("variables") && r["variables"] != json(c_in.variables))
    bad(result_file, "/variables", "the variables of " + c_in.file,
        shown(r["variables"]) + ": a result for another case");
  io::Problem p = p_in;
  io::CaseFile& c = p.linear();
  if (r.contains("reduced")) {  // the reference's reduced equations in the result's coordinates
    const json& coords = r["reduced"].value("coordinates", json());
    if (!coords.is_array()) bad(result_file, "/reduced/coordinates", "an array of variable names", shown(coords));
    c.coordinates.clear();
    for (std::size_t i = 0; i < coords.size(); ++i) {
      const auto it =
          std::find(c.variables.begin(), c.variables.end(), coords[i].is_string() ? coords[i].get<std::string>() : "");
      if (it == c.variables.end())
        bad(result_file, "/reduced/coordinates/" + std::to_string(i), "a variable of " + c.file, shown(coords[i]));
      c.coordinates.push_back(static_cast<std::size_t>(it - c.variables.begin()));
    }
  }
  const bool forced = (p.form() == io::Form::netlist && p.netlist().forced) ||
                      (p.form() == io::Form::linear && c.has_pontryagin && c.pontryagin.has_forces);
  if (forced) return check_forced(result_file, r, p_in);
  const reference::Solution truth = truth_of(p);
  const json want = printed_json(truth);
  Checker k{result_file, {}};
  for (const char* key : {"dims", "steps", "consistent", "solution_rank"}) k.compare(key, want[key], r[key]);
  if (r.contains("unique")) k.compare("unique", want["unique"], r["unique"]);
  if (r.contains("circuit") && want.contains("circuit"))
    for (const char* key : {"pc_loops", "empty_loops", "branches", "nodes"})
      if (r["circuit"].contains(key)) k.compare(std::string("circuit.") + key, want["circuit"][key], r["circuit"][key]);
  if (r.contains("constraint_classes") && want.contains("constraint_classes"))
    for (const char* key : {"first_class", "second_class"})
      if (r["constraint_classes"].contains(key))
        k.compare(std::string("constraint_classes.") + key, want["constraint_classes"][key],
                  r["constraint_classes"][key]);
  if (r.contains("reduced")) {
    if (!truth.motion) {
      k.out.compared.push_back("reduced");
      k.out.disagreements.push_back("reduced: expected none (no equations of motion: " +
                                    std::string(truth.consistent ? "too large" : "inconsistent") + "), found some");
    } else {
      compare_reduced(k, truth, r["reduced"]);
    }
  }
  if (r.contains("dirac_bracket")) {
    if (!truth.classes || truth.classes->dirac_bracket.empty()) {
      k.out.compared.push_back("dirac_bracket");
      k.out.disagreements.push_back("dirac_bracket: expected none (only `constrained` cases have one), found one");
    } else {
      compare_matrix(k, "dirac_bracket", truth.classes->dirac_bracket, r["dirac_bracket"]);
    }
  }
  if (r.contains("final_constraints")) {
    if (!truth.final_exact || !truth.consistent) {
      k.out.compared.push_back("final_constraints");
      if (truth.consistent)
        k.out.disagreements.push_back("final_constraints: the reference has no exact M_c here (use a case of at most " +
                                      std::to_string(certified::kDenseBranches) + " branches)");
      else if (!r["final_constraints"].is_null())
        k.out.disagreements.push_back("final_constraints: expected null (M_c is empty), found some");
    } else {
      compare_final_constraints(k, r["final_constraints"], exact_matrix(truth.final_exact->basis, c.n),
                                truth.final_exact->point, truth.tower.back().dim);
    }
  }
  return k.out;
}

/// found − want ∈ span(gauge): exactly if every number is exact, else the residual of the least-
/// squares projection (Gram–Schmidt in double) within 1e-9 × N × the largest magnitude.
bool equal_modulo(const std::vector<Number>& found, const std::vector<std::string>& want,
                  const std::vector<std::vector<std::string>>& gauge, bool exact) {
  const std::size_t n = want.size();
  if (exact) {
    io::QMatrix g(gauge.size() + 1, n);
    for (std::size_t i = 0; i < gauge.size(); ++i)
      for (std::size_t j = 0; j < n; ++j) g(i, j) = reference::parse_rational(gauge[i][j]);
    for (std::size_t j = 0; j < n; ++j) g(gauge.size(), j) = found[j].q - reference::parse_rational(want[j]);
    return reference::rank(g) == reference::rank(g.block(0, gauge.size(), 0, n));
  }
  std::vector<double> d(n);
  double scale = 1;
  for (std::size_t j = 0; j < n; ++j) {
    const double w = std::stod(want[j]);
    d[j] = found[j].d - w;
    scale = std::max({scale, std::abs(w), std::abs(found[j].d)});
  }
  std::vector<std::vector<double>> basis;
  for (const auto& gv : gauge) {
    std::vector<double> b(n);
    for (std::size_t j = 0; j < n; ++j) b[j] = std::stod(gv[j]);
    for (int pass = 0; pass < 2; ++pass)
      for (const auto& e : basis) {
        double p = 0;
        for (std::size_t j = 0; j < n; ++j) p += b[j] * e[j];
        for (std::size_t j = 0; j < n; ++j) b[j] -= p * e[j];
      }
    double nb = 0;
    for (double x : b) nb += x * x;
    if (nb <= 1e-24) continue;
    for (double& x : b) x /= std::sqrt(nb);
    basis.push_back(b);
  }
  for (const auto& e : basis) {
    double p = 0;
    for (std::size_t j = 0; j < n; ++j) p += d[j] * e[j];
    for (std::size_t j = 0; j < n; ++j) d[j] -= p * e[j];
  }
  double r = 0;
  for (double x : d) r = std::max(r, std::abs(x));
  return r <= 1e-9 * static_cast<double>(n) * scale;
}

/// The result's /point: every coordinate and velocity (and the time) into `at`'s initial values, an angle given
/// as "2*atan(t)" (+ N*pi, N even) into `angles` (its coordinate then 0, the translated angle); whether every
/// value is exact.
bool read_result_point(const std::string& result_file, const json& pt, const io::LagrangianCase& c,
                       io::LagrangianCase& at, std::vector<reference::pipeline::PlacedAngle>& angles) {
  bool exact = true;
  std::vector<std::string> names = c.system.variable_names();  // q, v, t
  const std::vector<std::size_t> angle_coordinates = reference::pipeline::angle_coordinates(c.system);
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i == c.system.t() && !c.system.has_time) continue;
    if (!pt.contains(names[i]))
      bad(result_file, "/point/" + names[i], "a value for every coordinate and velocity (and the time)", "nothing");
    const std::string text = pt[names[i]].is_string() ? pt[names[i]].get<std::string>() : "";
    if (text.rfind("2*atan(", 0) == 0) {  // 2*atan(t), or 2*atan(t) + N*pi with N even (whole turns)
      const std::string path = "/point/" + names[i];
      if (std::find(angle_coordinates.begin(), angle_coordinates.end(), i) == angle_coordinates.end())
        bad(result_file, path, "2*atan(t) only for an angle (a coordinate that occurs only in sin and cos)",
            shown(pt[names[i]]));
      reference::pipeline::PlacedAngle g;
      g.q = i;
      const std::size_t close = text.find(')');
      const std::string rest = close == std::string::npos ? "" : text.substr(close + 1);
      bool ok = close != std::string::npos;
      if (ok && !rest.empty()) {  // " + N*pi" / " - N*pi", N even
        ok = rest.size() > 6 && (rest.rfind(" + ", 0) == 0 || rest.rfind(" - ", 0) == 0) &&
             rest.substr(rest.size() - 3) == "*pi";
        const std::string digits = ok ? rest.substr(3, rest.size() - 6) : "";
        ok = ok && !digits.empty() && digits.size() < 18 &&
             digits.find_first_not_of("0123456789") == std::string::npos && (digits.back() - '0') % 2 == 0;
      }
      try {
        if (!ok) throw std::invalid_argument(text);
        g.tan_half = reference::parse_rational(text.substr(7, close - 7));
      } catch (const std::exception&) {
        bad(result_file, path, "2*atan(t), or 2*atan(t) + N*pi with N even, t an exact rational such as \"-3/7\"",
            shown(pt[names[i]]));
      }
      g.cos = (1 - g.tan_half * g.tan_half) / (1 + g.tan_half * g.tan_half);
      g.sin = 2 * g.tan_half / (1 + g.tan_half * g.tan_half);
      angles.push_back(g);
      at.initial[i] = reference::Rational(0);  // the translated angle, φ = 2*atan(t) + φ'
      continue;
    }
    const Number x = number(result_file, "/point/" + names[i], pt[names[i]]);
    exact = exact && x.exact;
    at.initial[i] = exact_value(x);
  }
  return exact;
}

/// The velocity at the result's own point against the reference there (exact if the point is; else fast's answer,
/// confirmed, at the decimal point), modulo the gauge.
void compare_velocity(Checker& k, const json& r, const io::Problem& p, const json& want) {
  const std::string& result_file = k.file;
  const io::LagrangianCase& c = p.expression();
  const std::vector<std::string> st = c.system.state_names();
  // the velocity at the result's own point: the reference there (exact if the point is), modulo the gauge
  const json& pt = r["point"];
  const json& vel = r["velocity"];
  if (!pt.is_object()) bad(result_file, "/point", "an object {variable: value}", shown(pt));
  if (!vel.is_object()) bad(result_file, "/velocity", "an object {variable: d/dt of it}", shown(vel));
  io::LagrangianCase at = c;
  at.has_initial = true;
  at.initial.assign(at.initial.size(), std::nullopt);
  at.initial_p.assign(at.initial_p.size(), std::nullopt);
  std::vector<reference::pipeline::PlacedAngle> angles;  // "2*atan(t)": the exact tiers' rational place (issue 29)
  bool exact = read_result_point(result_file, pt, c, at, angles);
  const std::size_t n = c.system.n;
  if (!angles.empty()) {
    if (!exact) bad(result_file, "/point", "exact values with an angle 2*atan(t)", "a decimal among them");
    at.system = reference::pipeline::translate_angles(at.system, angles);  // a translation of Q: the same velocities
  }
  for (std::size_t i = 0; i < n; ++i)
    if (pt.contains("p_" + c.system.names[i]))
      at.initial_p[i] = exact_value(number(result_file, "/point/p_" + c.system.names[i], pt["p_" + c.system.names[i]]));
  std::vector<Number> found;
  for (std::size_t i = 0; i < st.size(); ++i) {
    if (!vel.contains(st[i])) bad(result_file, "/velocity/" + st[i], "d/dt of every variable", "nothing");
    found.push_back(number(result_file, "/velocity/" + st[i], vel[st[i]]));
    exact = exact && found.back().exact;
  }
  k.out.compared.push_back("velocity");
  io::Printed truth_at;
  try {
    io::Problem there = p;
    there.expression() = at;
    truth_at = exact ? io::printed(reference::solve(there)) : io::printed(fast::solve(there));
  } catch (const io::InputError& e) {
    k.out.disagreements.push_back(std::string("point: expected a point of M_c, found one where ") + e.what());
    return;
  }
  const Pointwise<std::string>& truth = *truth_at.pointwise;
  // fast's answer at a decimal point: judged where it is certified, or where its tower and solution rank are the
  // certified tier's (exact at the case's point or a rational place on the component); else a zero assumed in
  // double may have left a spurious gauge direction, and no verdict rests on it
  const bool structure =
      json(truth_at.dims()) == want["dims"] &&
      (truth_at.solution_rank ? json(*truth_at.solution_rank) : json(nullptr)) == want["solution_rank"];
  if (!truth_at.certified.yes() && !structure) {
    k.out.compared.pop_back();
    k.out.not_compared.push_back(
        "velocity (dcad's double answer at the result's decimal point is not certified: " + truth_at.note + ")");
    return;
  }
  if (!truth.regular || !truth_at.consistent) {
    k.out.disagreements.push_back("point: expected a regular point of M_c, found one where " + truth.why);
    return;
  }
  if (!equal_modulo(found, truth.velocity, truth.gauge, exact)) {
    std::string w;
    for (std::size_t i = 0; i < st.size(); ++i) w += (i ? ", " : "") + st[i] + "' = " + truth.velocity[i];
    k.out.disagreements.push_back(
        "velocity: expected (" + w + ")" +
        (truth.gauge.empty() ? "" : " modulo " + std::to_string(truth.gauge.size()) + " gauge directions") +
        " at the result's point, found " + shown(vel));
  }
}

Checked check_expression(const std::string& result_file, const json& r, const io::Problem& p, std::size_t points) {
  const io::LagrangianCase& c = p.expression();
  const std::vector<std::string> st = c.system.state_names();
  if (r.contains("name") && r["name"] != c.name)
    bad(result_file, "/name", "the name of " + c.file + " (\"" + c.name + "\")",
        shown(r["name"]) + ": a result for another case");
  if (r.contains("variables") && r["variables"] != json(st))
    bad(result_file, "/variables", "the variables of " + c.file, shown(r["variables"]) + ": a result for another case");
  Checker k{result_file, {}};
  if (r.contains("formulas") &&
      r["formulas"].is_null()) {  // a result without formulas (dcad's own, formulas_why says why)
    k.out.not_compared.push_back("formulas (null in the result)");
  } else if (r.contains("formulas")) {  // another tool's formulas (CONTRACT "Formulas for nonlinear results")
    check_formulas(result_file, r["formulas"], p, points, k.out);
    if (!r.contains("dims")) return k.out;
  }
  const json want = json::parse(io::result_json(printed(solve(p, Backend::certified)), -1));
  if (!want.value("certified", false)) {  // the certified tier fell back to double: no verdict rests on that
    const std::string why = " (dcad's own answer is not certified here: " + want.value("note", std::string()) + ")";
    for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique"})
      if (r.contains(key)) k.out.not_compared.push_back(key + why);
    if (k.out.compared.empty())  // nothing judged is no agreement
      k.out.disagreements.push_back("no claim could be judged" + why);
    return k.out;
  }
  for (const char* key : {"dims", "steps", "consistent", "solution_rank"}) k.compare(key, want[key], r[key]);
  if (r.contains("unique")) k.compare("unique", want["unique"], r["unique"]);
  if (!r.contains("point") || !r.contains("velocity")) {
    if (r.contains("velocity") || r.contains("point"))
      k.out.not_compared.push_back("velocity (it needs both `point` and `velocity`)");
    return k.out;
  }
  compare_velocity(k, r, p, want);
  return k.out;
}

/// A linear DAE's M_c(t) = {C x = G u(t)} (u the sources' jets) against a claim of rows [a…, b]: the
/// same subspace of directions (ker C: the rows' x-coefficients span C's rows), and where the system has
/// no sources (M_c a fixed subspace through 0) the same right sides; with sources the right sides are
/// G u(t), which constant rows cannot state: those are named as not compared.
void compare_dae_final_constraints(Checker& k, const json& r, const reference::Solution& truth, std::size_t n) {
  const json& found = r["final_constraints"];
  if (!truth.certified.yes()) {
    k.out.not_compared.push_back("final_constraints (the reference left a condition on the sources undecided)");
    return;
  }
  if (truth.final_constraints &&
      static_cast<double>(truth.final_constraints->size()) * static_cast<double>(n + truth.jets.size()) > 4e6) {
    k.out.not_compared.push_back("final_constraints (" + std::to_string(truth.final_constraints->size()) +
                                 " rows over " + std::to_string(n) +
                                 " variables: beyond the dense subspace comparison's 4e6 entries)");
    return;
  }
  if (!truth.consistent || !truth.final_constraints) {
    k.out.compared.push_back("final_constraints");
    if (!found.is_null()) k.out.disagreements.push_back("final_constraints: expected null (M_c is empty), found some");
    return;
  }
  // dcad's own form: rows over (x, the sources' jets `source_jets`, b) — compared as a subspace of (x, u)
  const std::size_t jets = truth.jets.size();
  if (jets > 0 && r.contains("source_jets") && found.is_array() && !found.empty() && found[0].is_array() &&
      found[0].size() == n + jets + 1) {
    k.out.compared.push_back("source_jets");
    if (r["source_jets"] != json(truth.jets)) {
      k.out.disagreements.push_back("source_jets: expected " + json(truth.jets).dump() +
                                    " (the columns after the variables), found " + shown(r["source_jets"]));
      return;
    }
    io::QMatrix cu(truth.final_constraints->size(), n + jets);
    for (std::size_t i = 0; i < truth.final_constraints->size(); ++i)
      for (const auto& [j, v] : (*truth.final_constraints)[i].terms) cu(i, j) = v;
    const io::QMatrix kernel = reference::nullspace(cu);
    compare_final_constraints(k, found, kernel, std::vector<io::Rational>(n + jets, io::Rational(0)),
                              static_cast<long>(kernel.rows()));
    return;
  }
  io::QMatrix c(truth.final_constraints->size(), n);
  bool sources = false;
  for (std::size_t i = 0; i < truth.final_constraints->size(); ++i)
    for (const auto& [j, v] : (*truth.final_constraints)[i].terms) {
      if (j < n)
        c(i, j) = v;
      else if (v != 0)
        sources = true;
    }
  const io::QMatrix kernel = reference::nullspace(c);  // rows: a basis of ker C
  json rows = found;
  if (sources && rows.is_array())  // the right sides are the sources' jets: the directions only
    for (auto& row : rows)
      if (row.is_array() && !row.empty()) row.back() = 0;
  compare_final_constraints(k, rows, kernel, std::vector<io::Rational>(n, io::Rational(0)), truth.tower.back().dim);
  if (sources)
    k.out.not_compared.push_back(
        "final_constraints' right sides (M_c(t) = {C x = G u(t)} moves with the sources' jets: its directions were "
        "compared)");
}

/// The result's reduced coordinates z = P x: indices of the case's variables, each named once.
std::vector<std::size_t> reduced_coordinates(Checker& k, const json& coords,
                                             const std::vector<std::string>& variables) {
  std::vector<std::size_t> z;
  for (std::size_t i = 0; i < coords.size(); ++i) {
    const auto it =
        std::find(variables.begin(), variables.end(), coords[i].is_string() ? coords[i].get<std::string>() : "");
    if (it == variables.end())
      bad(k.file, "/reduced/coordinates/" + std::to_string(i), "a variable of the case", shown(coords[i]));
    if (std::find(z.begin(), z.end(), static_cast<std::size_t>(it - variables.begin())) != z.end())
      bad(k.file, "/reduced/coordinates/" + std::to_string(i), "a variable not named before in the list",
          shown(coords[i]));
    z.push_back(static_cast<std::size_t>(it - variables.begin()));
  }
  return z;
}

/// The result's S over dcad's jet columns (`sources.columns` named as dcad names them, each once; a column it does
/// not name: 0) added into `s_found`; false when S itself is malformed (found_matrix said why).
bool reduced_sources(Checker& k, const json& src, const std::vector<std::string>& jets, std::size_t m,
                     std::vector<std::vector<Number>>& ns, io::QMatrix& s_found) {
  const json& cols = src.is_object() ? src.value("columns", json()) : json();
  if (!cols.is_array())
    bad(k.file, "/reduced/sources/columns", "an array of the sources' jets as dcad names them (source_jets)",
        shown(cols));
  const auto sm = found_matrix(k, "reduced.sources.S", src.value("S", json()), m, cols.size(), ns);
  if (!sm) return false;
  for (std::size_t c = 0; c < cols.size(); ++c) {
    const auto it = std::find(jets.begin(), jets.end(), cols[c].is_string() ? cols[c].get<std::string>() : "");
    if (it == jets.end())
      bad(k.file, "/reduced/sources/columns/" + std::to_string(c), "one of " + json(jets).dump(), shown(cols[c]));
    for (std::size_t c2 = 0; c2 < c; ++c2)
      if (cols[c2] == cols[c])
        bad(k.file, "/reduced/sources/columns/" + std::to_string(c), "a jet not named before in the list",
            shown(cols[c]));
    for (std::size_t i = 0; i < m; ++i) s_found(i, static_cast<std::size_t>(it - jets.begin())) += (*sm)(i, c);
  }
  return true;
}

/// The consistent (x, u) of M_c's rows [C D] (x, u) = b over w = N + jets columns: a basis of the directions (rows)
/// and a point (x0, u0) in `point`.
io::QMatrix consistent_states(const std::vector<Equation<io::Rational>>& rows, std::size_t w,
                              std::vector<io::Rational>& point) {
  io::QMatrix cd(rows.size(), w + 1);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (const auto& [j, v] : rows[i].terms) cd(i, j) = v;
    cd(i, w) = rows[i].rhs;
  }
  const io::QMatrix lhs = cd.block(0, cd.rows(), 0, w), dirs = reference::nullspace(lhs);  // rows
  std::vector<io::Rational> b(cd.rows());
  for (std::size_t i = 0; i < cd.rows(); ++i) b[i] = cd(i, w);
  if (!reference::solve_particular(lhs, b, point)) throw InternalError("check: the reference's M_c has no point");
  return dirs;
}

/// The residual map (x, u, 1) ↦ P (X x + W u) − (F P x + S u + f) of claimed F, f, S against the reference's motion,
/// as an m × (N + jets + 1) matrix.
io::QMatrix residual_map(const Motion<io::Rational>& mo, const std::vector<std::size_t>& z, const io::QMatrix& f_found,
                         const io::QMatrix& v_found, const io::QMatrix& s_found, std::size_t n) {
  const std::size_t m = z.size(), nj = s_found.cols(), w = n + nj;
  io::QMatrix res(m, w + 1);
  for (std::size_t a = 0; a < m; ++a) {
    const std::size_t i = z[a];
    for (std::size_t j = 0; j < n; ++j) res(a, j) = mo.f_matrix[i][j];
    for (std::size_t j = 0; j < nj; ++j) res(a, n + j) = mo.s[i][j] - s_found(a, j);
    for (std::size_t b = 0; b < m; ++b) res(a, z[b]) -= f_found(a, b);
    res(a, w) = mo.f[i] - v_found(a, 0);
  }
  return res;
}

/// A JSON vector [x, …] as the column [[x], …] (nlohmann iterates a single value as itself, null as nothing).
json as_column(const json& v) {
  json col = json::array();
  for (const json& x : v) col.push_back(json::array({x}));
  return col;
}

/// The first entry of `m` that `nonzero` says is not zero, row and column.
std::optional<std::pair<std::size_t, std::size_t>> first_nonzero(
    const io::QMatrix& m, const std::function<bool(const io::Rational&)>& nonzero) {
  for (std::size_t a = 0; a < m.rows(); ++a)
    for (std::size_t c = 0; c < m.cols(); ++c)
      if (nonzero(m(a, c))) return std::make_pair(a, c);
  return std::nullopt;
}

/// A linear DAE's equations of motion on M_c, claimed in the result's own coordinates z = P x (a subset of
/// the variables, as an index reducer leaves the differential ones): ż = F z + f + S u + G λ with u the
/// sources' jets (`sources.columns`, named as dcad names them) and λ free.  They are right iff along every
/// solution — at every consistent (x, u) (M_c's equations, over x and u) and for every velocity the DAE
/// allows there (ẋ = X x + W u + gauge·μ, the reference's) — P ẋ − (F P x + f + S u) lies in span(G), and
/// span(G) is no more than the free directions P·gauge.  Compared exactly on a basis of the consistent
/// (x, u) (the kernel of M_c's rows) and at a point of it; within 1e-9 × entries × scale for floats.  F
/// itself is not unique where z does not parametrize M_c: any F that gives the right ż passes.
void compare_dae_reduced(Checker& k, const json& red, const reference::Solution& truth,
                         const std::vector<std::string>& variables) {
  const std::string key = "reduced";
  if (!truth.certified.yes()) {
    k.out.not_compared.push_back("reduced (the reference left a condition on the sources undecided)");
    return;
  }
  if (truth.consistent && !truth.motion) {
    k.out.not_compared.push_back("reduced (dcad forms no equations of motion at this size: dense N x N)");
    return;
  }
  k.out.compared.push_back("reduced (on the consistent states and sources' jets" +
                           std::string(truth.jets.empty() ? "" : ", " + json(truth.jets).dump()) + ")");
  if (!truth.consistent || !truth.motion || !truth.final_constraints) {
    k.out.disagreements.push_back("reduced: expected none (M_c is empty), found some");
    return;
  }
  const std::size_t n = variables.size(), nj = truth.jets.size();
  const json& coords = red.value("coordinates", json());
  if (!coords.is_array()) bad(k.file, "/reduced/coordinates", "an array of variable names", shown(coords));
  const std::vector<std::size_t> z = reduced_coordinates(k, coords, variables);
  const std::size_t m = z.size();
  std::vector<std::vector<Number>> nf, nv, ng, ns;
  const auto f_found = found_matrix(k, "reduced.F", red.value("F", json()), m, m, nf);
  const auto v_found = red.contains("f") ? found_matrix(k, "reduced.f", as_column(red["f"]), m, 1, nv)
                                         : std::optional<io::QMatrix>(io::QMatrix(m, 1));
  const json g_json = red.contains("G") && red["G"].is_array() && red["G"].empty()
                          ? json(std::vector<json>(m, json::array()))
                          : red.value("G", json());
  const std::size_t g_cols = g_json.is_array() && !g_json.empty() && g_json[0].is_array() ? g_json[0].size() : 0;
  const auto g_found = red.contains("G") ? found_matrix(k, "reduced.G", g_json, m, g_cols, ng)
                                         : std::optional<io::QMatrix>(io::QMatrix(m, 0));
  io::QMatrix s_found(m, nj);  // over dcad's jet columns (a column the result does not name: 0)
  if (red.contains("sources") && !reduced_sources(k, red["sources"], truth.jets, m, ns, s_found)) return;
  if (!f_found || !v_found || !g_found) return;
  bool exact = true;
  for (const auto* nums : {&nf, &nv, &ng, &ns})
    for (const auto& row : *nums)
      for (const Number& v : row) exact = exact && v.exact;
  const std::size_t w = n + nj;
  std::vector<io::Rational> point;
  const io::QMatrix dirs = consistent_states(*truth.final_constraints, w, point);
  const Motion<io::Rational>& mo = *truth.motion;
  const io::QMatrix res = residual_map(mo, z, *f_found, *v_found, s_found, n);
  io::QMatrix at(w + 1, dirs.rows() + 1);  // columns: the directions (0 in the last row), and the point (1)
  for (std::size_t c = 0; c < dirs.rows(); ++c)
    for (std::size_t j = 0; j < w; ++j) at(j, c) = dirs(c, j);
  for (std::size_t j = 0; j < w; ++j) at(j, dirs.rows()) = point[j];
  at(w, dirs.rows()) = 1;
  // projected off span(G) (N: the annihilator of their G's columns); the true free directions P·gauge too
  const io::QMatrix n_g = reference::annihilator(reference::Subspace<io::Rational>::span(g_found->transpose())).basis();
  io::QMatrix pg(m, mo.g.empty() ? 0 : mo.g[0].size());
  for (std::size_t a = 0; a < m; ++a)
    for (std::size_t c = 0; c < pg.cols(); ++c) pg(a, c) = mo.g[z[a]][c];
  const io::QMatrix off = n_g * res * at, free_off = n_g * pg;
  const double scale = std::max(1.0, max_abs(n_g)) * std::max({1.0, max_abs(res), max_abs(at)});
  const double tol = exact ? 0 : matrix_tolerance(m * (w + 1)) * scale;
  const auto nonzero = [&](const io::Rational& v) { return exact ? v != 0 : std::abs(v.convert_to<double>()) > tol; };
  if (const auto ac = first_nonzero(off, nonzero)) {
    const auto [a, c] = *ac;
    k.out.disagreements.push_back(
        "reduced: d/dt of the coordinates " + coords.dump() + " differs from the DAE's on M_c" +
        (c + 1 == off.cols() ? " at its point" : " along a consistent direction of (x, u)") + " (component " +
        std::to_string(a) + " of the difference, off span(G): " + io::float_text(off(a, c).convert_to<double>()) + ")");
    return;
  }
  if (first_nonzero(free_off, nonzero)) {
    k.out.disagreements.push_back("reduced.G: the DAE leaves a direction of d/dt " + coords.dump() +
                                  " free that span(G) does not contain (solution rank " + std::to_string(pg.cols()) +
                                  ")");
    return;
  }
  const io::QMatrix n_pg = reference::annihilator(reference::Subspace<io::Rational>::span(pg.transpose())).basis(),
                    extra = n_pg * *g_found;
  if (const auto ac = first_nonzero(extra, nonzero))
    k.out.disagreements.push_back("reduced.G: column " + std::to_string(ac->second) +
                                  " frees a direction the DAE determines");
}

/// A linear DAE (CONTRACT "Linear and implicit DAEs"): another tool's discrete claims — dims, steps,
/// consistency, solution rank, regularity of the pencil and its index — against the reference's
/// CEF (1.6); its M_c (`final_constraints`) as a subspace, and its equations of motion (`reduced`).
Checked check_dae(const std::string& result_file, const json& r, const io::Problem& p) {
  const io::DaeCase& c = p.dae();
  if (!r.is_object()) bad(result_file, "", "a result object", shown(r));
  if (r.contains("name") && r["name"] != c.name)
    bad(result_file, "/name", "the name of " + c.file + " (\"" + c.name + "\")",
        shown(r["name"]) + ": a result for another case");
  if (r.contains("variables") && r["variables"] != json(c.variables))
    bad(result_file, "/variables", "the variables of " + c.file, shown(r["variables"]) + ": a result for another case");
  // beyond the dense reference's size, the certified sparse route's exact tower (certified/dae_sparse.hpp)
  const reference::Solution truth = c.dense ? reference::solve(p) : certified::solve_dae_sparse(c);
  const json want = printed_json(truth);
  Checker k{result_file, {}};
  bool any = false;
  for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique", "regular_pencil", "index"})
    if (r.contains(key)) {
      any = true;
      // a condition on the sources the reference left undecided: what depends on it is not judged
      if (!truth.certified.yes() && std::string(key) != "regular_pencil") {
        k.out.not_compared.push_back(std::string(key) +
                                     " (the reference left a condition on the sources undecided: dcad solve lists it)");
        continue;
      }
      k.compare(key, want.contains(key) ? want[key] : json(nullptr), r[key]);
    }
  if (!any)
    bad(result_file, "", "at least one of dims, steps, consistent, solution_rank, unique, regular_pencil, index",
        "none of them");
  if (r.contains("final_constraints")) compare_dae_final_constraints(k, r, truth, c.variables.size());
  if (r.contains("reduced")) {
    if (!r["reduced"].is_object())
      bad(result_file, "/reduced", "an object (coordinates, F, f, G, sources)", shown(r["reduced"]));
    compare_dae_reduced(k, r["reduced"], truth, c.variables);
  }
  if (r.contains("tower")) k.out.not_compared.push_back("tower (not yet for the dae form)");
  return k.out;
}

/// An implicit DAE (CONTRACT "Linear and implicit DAEs"): another tool's discrete claims — dims,
/// steps, consistency, solution rank, uniqueness and index — against the reference's CEF (1.6) at the
/// case's point (exact); its constraints of M_c and equations of motion as `formulas` (check_formulas.cpp).
Checked check_implicit(const std::string& result_file, const json& r, const io::Problem& p, std::size_t points) {
  const io::LagrangianCase& c = p.expression();
  if (!r.is_object()) bad(result_file, "", "a result object", shown(r));
  if (r.contains("name") && r["name"] != c.name)
    bad(result_file, "/name", "the name of " + c.file + " (\"" + c.name + "\")",
        shown(r["name"]) + ": a result for another case");
  if (r.contains("variables") && r["variables"] != json(c.system.names))
    bad(result_file, "/variables", "the variables of " + c.file, shown(r["variables"]) + ": a result for another case");
  reference::Solution truth;
  std::string unjudged;  // why no claim can be judged, if none can
  try {
    truth = reference::solve(p);
    if (!truth.certified.yes())
      unjudged = "the reference is not certified at its point (" +
                 (truth.note.empty() ? truth.pointwise->why : truth.note) +
                 "); give `initial` at a regular point of M_c";
  } catch (const reference::NoExactPoint& e) {  // an irrational point (a published start): the exact route cannot run
    unjudged = "the exact route cannot run at the case's point (" + e.cause +
               "); give `initial` at a point of M_c where every value of the equations is rational";
  }
  const json want = unjudged.empty() ? printed_json(truth) : json();
  Checker k{result_file, {}};
  bool any = false;
  for (const char* key : {"dims", "steps", "consistent", "solution_rank", "unique", "index"})
    if (r.contains(key)) {
      any = true;
      if (!unjudged.empty()) {  // judged below: nothing can be
        k.out.not_compared.push_back(std::string(key) + " (no claim could be judged: see the disagreement)");
        continue;
      }
      k.compare(key, want.contains(key) ? want[key] : json(nullptr), r[key]);
    }
  const bool formulas = r.contains("formulas") && !r["formulas"].is_null();
  if (!any && !formulas)
    bad(result_file, "", "at least one of dims, steps, consistent, solution_rank, unique, index, or formulas",
        "none of them");
  if (!unjudged.empty()) k.out.disagreements.push_back("no claim could be judged: " + unjudged);  // none: no agreement
  if (r.contains("formulas") && r["formulas"].is_null())
    k.out.not_compared.push_back("formulas (null in the result)");
  else if (formulas && unjudged.empty())
    check_formulas(result_file, r["formulas"], p, points, k.out);  // their constraints and equations of motion
  for (const char* key : {"tower", "final_constraints", "reduced"})
    if (r.contains(key))
      k.out.not_compared.push_back(
          std::string(key) + " (not yet for the implicit form: give the constraints and equations as `formulas`)");
  return k.out;
}

Checked checked(const std::string& result_file, const std::string* text, const io::Problem& p, std::size_t points) {
  return guarded(p, [&] {
    io::validate(p);
    const json r = read_result(result_file, text);
    Checked o = p.form() == io::Form::expression ? check_expression(result_file, r, p, points)
                : p.form() == io::Form::dae      ? check_dae(result_file, r, p)
                : p.form() == io::Form::implicit ? check_implicit(result_file, r, p, points)
                                                 : check_linear(result_file, r, p);
    o.agrees = o.disagreements.empty();
    // every top-level key of the result that nothing above compared is named, never ignored in silence
    std::string quiet;
    if (r.is_object())
      for (const auto& item : r.items()) {
        const std::string& key = item.key();
        if (key == "dcad") continue;  // the format's version, checked by read_result
        const auto covers = [&](const std::string& c) {
          return c == key || c.rfind(key + ".", 0) == 0 || c.rfind(key + " ", 0) == 0;
        };
        if (std::any_of(o.compared.begin(), o.compared.end(), covers) ||
            std::any_of(o.not_compared.begin(), o.not_compared.end(), covers))
          continue;
        quiet += (quiet.empty() ? "" : ", ") + key;
      }
    if (!quiet.empty()) o.not_compared.push_back(quiet + " (keys dcad check does not compare)");
    return o;
  });
}

}  // namespace

Checked check(const std::string& result_file, const io::Problem& p, std::size_t points) {
  return checked(result_file, nullptr, p, points);
}

Checked check_text(const std::string& result_json, const io::Problem& p, const std::string& name, std::size_t points) {
  return checked(name, &result_json, p, points);
}

}  // namespace dcad::api
