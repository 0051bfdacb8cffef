#include "case_file.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace dcad::io {

using nlohmann::json;

namespace {

/// SAX handler building a json DOM; floats are kept as their source text.
class ExactBuilder {
 public:
  explicit ExactBuilder(json& root) : root_(root) {}
  bool null() { return put(nullptr); }
  bool boolean(bool b) { return put(b); }
  bool number_integer(json::number_integer_t v) { return put(v); }
  bool number_unsigned(json::number_unsigned_t v) { return put(v); }
  bool number_float(json::number_float_t, const std::string& text) { return put(text); }
  bool string(std::string& s) { return put(s); }
  bool binary(json::binary_t&) { return false; }
  bool start_object(std::size_t) { return open(json::object()); }
  static constexpr std::size_t kMaxDepth = 64;  ///< a case needs 4 (matrix in a form in the file)
  bool too_deep_ = false;
  bool key(std::string& k) {
    key_ = k;
    if (stack_.back()->contains(k)) {  // RFC 8259 leaves duplicates to the reader: the last would win silently
      duplicate_ = k;
      return false;
    }
    return true;
  }
  std::string duplicate_;
  bool end_object() { return close(); }
  bool start_array(std::size_t) { return open(json::array()); }
  bool end_array() { return close(); }
  bool parse_error(std::size_t pos, const std::string&, const nlohmann::detail::exception& e) {
    error_pos_ = pos;
    error_ = e.what();
    return false;
  }
  std::size_t error_pos_ = 0;
  std::string error_;

 private:
  json* place(json v) {
    if (stack_.empty()) {
      root_ = std::move(v);
      return &root_;
    }
    json& top = *stack_.back();
    if (top.is_array()) {
      top.push_back(std::move(v));
      return &top.back();
    }
    top[key_] = std::move(v);
    return &top[key_];
  }
  bool put(json v) {
    place(std::move(v));
    return true;
  }
  bool open(json v) {
    if (stack_.size() >= kMaxDepth) {
      too_deep_ = true;
      return false;
    }
    const std::string name =
        stack_.empty() ? "" : stack_.back()->is_array() ? std::to_string(stack_.back()->size()) : key_;
    stack_.push_back(place(std::move(v)));
    names_.push_back(name);
    return true;
  }
  bool close() {
    stack_.pop_back();
    names_.pop_back();
    return true;
  }

 public:
  /// JSON path of the innermost open container, e.g. /energy/hessian.
  std::string where() const {
    std::string p;
    for (std::size_t i = 1; i < names_.size(); ++i) p += "/" + names_[i];
    return p.empty() ? "/" : p;
  }

 private:
  std::vector<std::string> names_;
  json& root_;
  std::vector<json*> stack_;
  std::string key_;
};

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open the file for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string path_or_root(const std::string& p) { return p.empty() ? "/" : p; }

}  // namespace

void Where::fail(const std::string& expected, const std::string& found) const {
  throw InputError(file + ": " + path_or_root(path) + ": expected " + expected + ", found " + found);
}

std::string describe(const json& j) {
  std::string s = j.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return std::string(j.type_name()) + " " + s;
}

namespace {

/// Byte offset (1-based, as nlohmann counts) of the bracket that opens nesting level `depth`.
std::size_t opening_of_depth(const std::string& text, std::size_t depth) {
  std::size_t level = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (ch == '\\') escaped = true;
      else if (ch == '"') in_string = false;
    } else if (ch == '"') {
      in_string = true;
    } else if (ch == '[' || ch == '{') {
      if (++level == depth) return i + 1;
    } else if (ch == ']' || ch == '}') {
      --level;
    }
  }
  return text.size();
}

}  // namespace

json parse_json_exact(const std::string& text, const std::string& file) {
  json root;
  ExactBuilder b(root);
  if (!json::sax_parse(text, &b)) {
    if (!b.duplicate_.empty())
      throw InputError(file + ": " + b.where() + ": expected each key once in an object, found \"" + b.duplicate_ + "\" twice");
    if (b.too_deep_) {
      b.error_pos_ = opening_of_depth(text, ExactBuilder::kMaxDepth + 1);
      b.error_ = "nesting deeper than " + std::to_string(ExactBuilder::kMaxDepth) + " levels; no case needs more than 4";
    }
    std::size_t line = 1, col = 1;
    for (std::size_t i = 0; i + 1 < b.error_pos_ && i < text.size(); ++i) {
      if (text[i] == '\n') {
        ++line;
        col = 1;
      } else {
        ++col;
      }
    }
    throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(col) +
                     (b.too_deep_ ? ": expected JSON nested at most " + std::to_string(ExactBuilder::kMaxDepth) + " deep, found " + b.error_
                                  : ": expected valid JSON, found a syntax error (" + b.error_ + ")"));
  }
  return root;
}

namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {  // Levenshtein
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string nearest_name(const std::string& key, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t best_d = std::string::npos;
  for (const std::string& a : allowed) {
    const std::size_t d = edit_distance(key, a);
    if (d < best_d) {
      best_d = d;
      best = a;
    }
  }
  return best_d <= std::max<std::size_t>(2, best.size() / 3) ? best : "";
}

void require_known_keys(const json& j, const Where& at, const std::vector<std::string>& allowed) {
  for (const auto& [key, value] : j.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
    const std::string best = nearest_name(key, allowed);
    (at / key).fail("one of the keys " + list, "unknown key \"" + key + "\"" + (!best.empty() ? " (did you mean \"" + best + "\"?)" : ""));
  }
}

json read_json_file(const std::string& file) { return parse_json_exact(slurp(file), file); }

Rational read_number(const json& j, const Where& at) {
  if (j.is_number_integer()) return j.is_number_unsigned() ? Rational(j.get<std::uint64_t>()) : Rational(j.get<std::int64_t>());
  if (!j.is_string()) at.fail("a number (JSON number or exact string such as \"-2/7\")", describe(j));
  try {
    return reference::parse_rational(j.get<std::string>());
  } catch (const std::invalid_argument& e) {
    throw InputError(at.file + ": " + path_or_root(at.path) + ": " + e.what());
  }
}

QMatrix read_matrix(const json& j, const Where& at, long rows, long cols) {
  if (!j.is_array()) at.fail("a matrix (array of rows)", describe(j));
  if (rows >= 0 && static_cast<long>(j.size()) != rows)
    at.fail(std::to_string(rows) + " rows", std::to_string(j.size()) + " rows");
  long c = cols;
  if (c < 0) c = j.empty() ? 0 : (j[0].is_array() ? static_cast<long>(j[0].size()) : -1);
  QMatrix m(j.size(), c < 0 ? 0 : c);
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Where ri = at / i;
    if (!j[i].is_array()) ri.fail("a row (array of numbers)", describe(j[i]));
    if (static_cast<long>(j[i].size()) != c)
      ri.fail("a row of length " + std::to_string(c), "length " + std::to_string(j[i].size()));
    for (std::size_t k = 0; k < j[i].size(); ++k) m(i, k) = read_number(j[i][k], ri / k);
  }
  return m;
}

std::vector<Rational> read_vector(const json& j, const Where& at, long size) {
  if (!j.is_array()) at.fail("an array of numbers", describe(j));
  if (size >= 0 && static_cast<long>(j.size()) != size) at.fail(std::to_string(size) + " numbers", std::to_string(j.size()));
  std::vector<Rational> v;
  for (std::size_t i = 0; i < j.size(); ++i) v.push_back(read_number(j[i], at / i));
  return v;
}

namespace {

void require_symmetric_input(const QMatrix& w, const Where& at) {
  for (std::size_t i = 0; i < w.rows(); ++i)
    for (std::size_t k = 0; k < w.cols(); ++k)
      if (w(i, k) != w(k, i))
        (at / i / k).fail("a symmetric matrix (entry (" + std::to_string(i) + "," + std::to_string(k) + ") = entry (" +
                              std::to_string(k) + "," + std::to_string(i) + "))",
                          w(i, k).str() + " vs " + w(k, i).str());
}

PontryaginInput read_pontryagin(const json& j, const Where& at) {
  if (!j.is_object()) at.fail("an object {Q, constraints, lagrangian}", describe(j));
  require_known_keys(j, at, {"Q", "constraints", "lagrangian", "forces"});
  PontryaginInput p;
  if (!j.contains("Q") || !j["Q"].is_number_integer() || j["Q"].get<long>() < 1)
    (at / "Q").fail("a positive integer n = dim Q", j.contains("Q") ? describe(j["Q"]) : "nothing");
  p.n = j["Q"].get<std::size_t>();
  const long n = static_cast<long>(p.n);
  p.k = j.contains("constraints") ? read_matrix(j["constraints"], at / "constraints", -1, n) : QMatrix(0, p.n);
  const json lag = j.contains("lagrangian") ? j["lagrangian"] : json::object();
  if (!lag.is_object()) (at / "lagrangian").fail("an object {vv, qv, qq, q, v}", describe(lag));
  const Where l = at / "lagrangian";
  p.vv = lag.contains("vv") ? read_matrix(lag["vv"], l / "vv", n, n) : QMatrix(p.n, p.n);
  p.qv = lag.contains("qv") ? read_matrix(lag["qv"], l / "qv", n, n) : QMatrix(p.n, p.n);
  p.qq = lag.contains("qq") ? read_matrix(lag["qq"], l / "qq", n, n) : QMatrix(p.n, p.n);
  require_symmetric_input(p.vv, l / "vv");
  require_symmetric_input(p.qq, l / "qq");
  p.q = lag.contains("q") ? read_vector(lag["q"], l / "q", n) : std::vector<Rational>(p.n, 0);
  p.v = lag.contains("v") ? read_vector(lag["v"], l / "v", n) : std::vector<Rational>(p.n, 0);
  require_known_keys(lag, l, {"vv", "qv", "qq", "q", "v"});
  p.fq = QMatrix(p.n, p.n);
  p.fv = QMatrix(p.n, p.n);
  if (j.contains("forces")) {  // F(q, v) = F_q q + F_v v on δq (YM §4, (4.3)); a damper is F_v = −diag(c)
    const Where f = at / "forces";
    if (!j["forces"].is_object()) f.fail("an object {q, v} of n×n matrices (F(q, v) = F_q q + F_v v)", describe(j["forces"]));
    require_known_keys(j["forces"], f, {"q", "v"});
    if (j["forces"].contains("q")) p.fq = read_matrix(j["forces"]["q"], f / "q", n, n);
    if (j["forces"].contains("v")) p.fv = read_matrix(j["forces"]["v"], f / "v", n, n);
    p.has_forces = true;
  }
  return p;
}

void require_skew_input(const QMatrix& w, const Where& at) {
  if (!reference::is_square(w)) at.fail("a square matrix", reference::shape(w));
  for (std::size_t i = 0; i < w.rows(); ++i)
    for (std::size_t k = 0; k < w.cols(); ++k)
      if (w(i, k) != -w(k, i))
        (at / i / k).fail("a skew matrix (entry (" + std::to_string(i) + "," + std::to_string(k) + ") = -entry (" +
                              std::to_string(k) + "," + std::to_string(i) + "))",
                          w(i, k).str() + " vs " + w(k, i).str());
}

DiracInput read_dirac(const json& j, const Where& at, long n) {
  if (!j.is_object() || j.empty()) at.fail("an object with one of presymplectic, distribution+form, poisson, basis", describe(j));
  require_known_keys(j, at, {"presymplectic", "distribution", "form", "poisson", "basis"});
  const int forms = j.contains("presymplectic") + j.contains("distribution") + j.contains("poisson") + j.contains("basis");
  if (forms > 1) at.fail("exactly one form (presymplectic, distribution + form, poisson or basis)", std::to_string(forms) + " forms");
  if (j.contains("form") && !j.contains("distribution"))
    (at / "form").fail("`form` only next to `distribution`", "`form` without `distribution`");
  DiracInput d;
  if (j.contains("presymplectic")) {
    d.form = "presymplectic";
    d.path = (at / "presymplectic").path;
    d.w = read_matrix(j["presymplectic"], at / "presymplectic", n, n);
    require_skew_input(d.w, at / "presymplectic");
  } else if (j.contains("distribution")) {
    d.form = "distribution";
    d.path = (at / "distribution").path;
    if (!j.contains("form")) at.fail("a `form` matrix next to `distribution`", "none");
    d.w = read_matrix(j["form"], at / "form", n, n);
    require_skew_input(d.w, at / "form");
    d.b = read_matrix(j["distribution"], at / "distribution", -1, static_cast<long>(d.w.rows()));
  } else if (j.contains("poisson")) {
    d.form = "poisson";
    d.path = (at / "poisson").path;
    d.p = read_matrix(j["poisson"], at / "poisson", n, n);
    require_skew_input(d.p, at / "poisson");
  } else if (j.contains("basis")) {
    d.form = "basis";
    d.path = (at / "basis").path;
    d.g = read_matrix(j["basis"], at / "basis", n, n < 0 ? -1 : 2 * n);
    if (n < 0 && d.g.cols() != 2 * d.g.rows())
      (at / "basis").fail("N rows of length 2N", reference::shape(d.g));
  } else {
    at.fail("one of the forms presymplectic, distribution (+form), poisson, basis", "keys " + describe(j));
  }
  return d;
}

}  // namespace

CaseFile read_case(const std::string& file) {
  const json j = parse_json_exact(slurp(file), file);
  const Where root{file, ""};
  if (!j.is_object()) root.fail("a JSON object (a dcad case file)", describe(j));
  if (!j.contains("dcad")) root.fail("the key \"dcad\": 1 (format version)", "no such key");
  if (j.contains("lagrangian") || j.contains("parameters"))
    (root / (j.contains("lagrangian") ? "lagrangian" : "parameters"))
        .fail("a linear case (dirac, pontryagin or constrained) here; the expression form is taken by solve, check and simulate",
              "the expression form");
  require_known_keys(j, root, {"dcad", "name", "description", "variables", "dirac", "energy", "pontryagin", "constrained", "initial",
                               "coordinates", "expect", "known_failures"});
  if (!(j["dcad"].is_number_integer() && j["dcad"].get<long>() == 1))
    (root / "dcad").fail("format version 1", describe(j["dcad"]));
  CaseFile c;
  c.file = file;
  if (j.contains("name")) {
    if (!j["name"].is_string()) (root / "name").fail("a string", describe(j["name"]));
    c.name = j["name"].get<std::string>();
  }
  if (j.contains("description") && j["description"].is_string()) c.description = j["description"].get<std::string>();
  long n = -1;
  if (j.contains("variables")) {
    const json& v = j["variables"];
    if (!v.is_array()) (root / "variables").fail("an array of names", describe(v));
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (!v[i].is_string() || v[i].get<std::string>().empty()) (root / "variables" / i).fail("a name (non-empty string)", describe(v[i]));
      const auto seen = std::find(c.variables.begin(), c.variables.end(), v[i].get<std::string>());
      if (seen != c.variables.end())
        (root / "variables" / i).fail("a new name", "\"" + *seen + "\", already variable " + std::to_string(seen - c.variables.begin()));
      c.variables.push_back(v[i].get<std::string>());
    }
    n = static_cast<long>(v.size());
  }
  const int forms = j.contains("dirac") + j.contains("pontryagin") + j.contains("constrained");
  if (forms > 1) root.fail("one of \"dirac\", \"pontryagin\", \"constrained\"", "both" + std::string(forms > 2 ? " (all three)" : ""));
  if (j.contains("constrained")) {
    const json& k = j["constrained"];
    const Where at = root / "constrained";
    if (!k.is_object() || !k.contains("symplectic")) at.fail("an object {symplectic, primary}", describe(k));
    require_known_keys(k, at, {"symplectic", "primary"});
    c.has_constrained = true;
    c.constrained.w = read_matrix(k["symplectic"], at / "symplectic", n, n);
    require_skew_input(c.constrained.w, at / "symplectic");
    c.n = c.constrained.w.rows();
    c.constrained.primary =
        k.contains("primary") ? read_matrix(k["primary"], at / "primary", -1, static_cast<long>(c.n) + 1) : QMatrix(0, c.n + 1);
  } else if (j.contains("dirac")) {
    c.has_dirac = true;
    c.dirac = read_dirac(j["dirac"], root / "dirac", n);
    const QMatrix& m = c.dirac.form == "basis" ? c.dirac.g : c.dirac.form == "poisson" ? c.dirac.p : c.dirac.w;
    c.n = m.rows();
  } else if (j.contains("pontryagin")) {
    c.has_pontryagin = true;
    c.pontryagin = read_pontryagin(j["pontryagin"], root / "pontryagin");
    c.n = 3 * c.pontryagin.n;
    if (n >= 0 && static_cast<std::size_t>(n) != c.n)
      (root / "variables").fail(std::to_string(c.n) + " names (q, v, p for Q of dim " + std::to_string(c.pontryagin.n) + ")",
                                std::to_string(n));
    if (j.contains("energy")) (root / "energy").fail("no energy next to `pontryagin` (E = p·v − L)", describe(j["energy"]));
  } else if (!c.has_constrained) {
    root.fail("a \"dirac\", \"pontryagin\" or \"constrained\" member", "none");
  }
  if (c.variables.empty()) {
    if (c.has_pontryagin) {
      for (const char* s : {"q", "v", "p"})
        for (std::size_t i = 0; i < c.pontryagin.n; ++i) c.variables.push_back(s + std::to_string(i + 1));
    } else {
      for (std::size_t i = 0; i < c.n; ++i) c.variables.push_back("x" + std::to_string(i + 1));
    }
  }
  const long nn = static_cast<long>(c.n);
  c.energy.hessian = QMatrix(c.n, c.n);
  c.energy.gradient.assign(c.n, 0);
  if (j.contains("energy")) {
    const json& e = j["energy"];
    const Where at = root / "energy";
    if (!e.is_object()) at.fail("an object {hessian, gradient, constant}", describe(e));
    require_known_keys(e, at, {"hessian", "gradient", "constant"});
    if (e.contains("hessian")) c.energy.hessian = read_matrix(e["hessian"], at / "hessian", nn, nn);
    require_symmetric_input(c.energy.hessian, at / "hessian");
    if (e.contains("gradient")) c.energy.gradient = read_vector(e["gradient"], at / "gradient", nn);
    if (e.contains("constant")) c.energy.constant = read_number(e["constant"], at / "constant");
  }
  if (j.contains("initial")) c.initial = read_vector(j["initial"], root / "initial", static_cast<long>(c.n));
  if (j.contains("coordinates")) {
    const json& cs = j["coordinates"];
    if (!cs.is_array()) (root / "coordinates").fail("an array of variable names", describe(cs));
    for (std::size_t i = 0; i < cs.size(); ++i) {
      const auto it = cs[i].is_string() ? std::find(c.variables.begin(), c.variables.end(), cs[i].get<std::string>())
                                        : c.variables.end();
      if (it == c.variables.end()) (root / "coordinates" / i).fail("one of the variables' names", describe(cs[i]));
      c.coordinates.push_back(static_cast<std::size_t>(it - c.variables.begin()));
    }
  }
  if (j.contains("expect")) c.expect = j["expect"];
  return c;
}

}  // namespace dcad::io
