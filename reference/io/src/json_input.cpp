#include "json_input.hpp"

#include <optional>

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
    const std::string name = stack_.empty()              ? ""
                             : stack_.back()->is_array() ? std::to_string(stack_.back()->size())
                                                         : key_;
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

}  // namespace

std::string slurp(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot open the file for reading");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

namespace {

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
      if (escaped)
        escaped = false;
      else if (ch == '\\')
        escaped = true;
      else if (ch == '"')
        in_string = false;
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
      throw InputError(file + ": " + b.where() + ": expected each key once in an object, found \"" + b.duplicate_ +
                       "\" twice");
    if (b.too_deep_) {
      b.error_pos_ = opening_of_depth(text, ExactBuilder::kMaxDepth + 1);
      b.error_ =
          "nesting deeper than " + std::to_string(ExactBuilder::kMaxDepth) + " levels; no case needs more than 4";
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
                     (b.too_deep_ ? ": expected JSON nested at most " + std::to_string(ExactBuilder::kMaxDepth) +
                                        " deep, found " + b.error_
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
      row[j] =
          std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
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
    (at / key).fail("one of the keys " + list,
                    "unknown key \"" + key + "\"" + (!best.empty() ? " (did you mean \"" + best + "\"?)" : ""));
  }
}

void check_published(const json& j, const Where& root, const std::vector<std::string>& names) {
  if (!j.contains("published")) return;
  const json& p = j["published"];
  const Where w = root / "published";
  if (!p.is_object()) w.fail("an object {source, index, interval, solution}", describe(p));
  require_known_keys(p, w, {"source", "index", "interval", "solution"});
  if (!p.contains("source") || !p["source"].is_string() || p["source"].get<std::string>().empty())
    (w / "source")
        .fail("the source's citation as a nonempty string",
              p.contains("source") ? describe(p["source"]) : "no such key");
  if (p.contains("index") && !(p["index"].is_number_integer() && p["index"].get<long>() >= 0))
    (w / "index").fail("the published index as an integer >= 0", describe(p["index"]));
  std::optional<std::pair<Rational, Rational>> interval;
  if (p.contains("interval")) {
    const json& iv = p["interval"];
    if (!iv.is_array() || iv.size() != 2) (w / "interval").fail("[t0, t1]", describe(iv));
    interval.emplace(read_number(iv[0], w / "interval" / 0), read_number(iv[1], w / "interval" / 1));
    if (!(interval->first < interval->second)) (w / "interval").fail("t0 < t1", describe(iv));
  }
  if (!p.contains("solution")) return;
  const json& s = p["solution"];
  const Where ws = w / "solution";
  if (!s.is_object()) ws.fail("an object {t, values}", describe(s));
  require_known_keys(s, ws, {"t", "values"});
  if (!s.contains("t") || !s.contains("values")) ws.fail("the keys \"t\" and \"values\"", describe(s));
  const Rational t = read_number(s["t"], ws / "t");
  if (interval && (t < interval->first || t > interval->second))
    (ws / "t").fail(
        "a time within the published interval [" + interval->first.str() + ", " + interval->second.str() + "]",
        t.str());
  if (!s["values"].is_object()) (ws / "values").fail("an object {name: number}", describe(s["values"]));
  for (const auto& [key, v] : s["values"].items()) {
    if (std::find(names.begin(), names.end(), key) == names.end())
      (ws / "values" / key).fail("a variable of the case", "\"" + key + "\"");
    read_number(v, ws / "values" / key);
  }
}

json read_json_file(const std::string& file) { return parse_json_exact(slurp(file), file); }

Rational read_number(const json& j, const Where& at) {
  if (j.is_number_integer())
    return j.is_number_unsigned() ? Rational(j.get<std::uint64_t>()) : Rational(j.get<std::int64_t>());
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
  if (size >= 0 && static_cast<long>(j.size()) != size)
    at.fail(std::to_string(size) + " numbers", std::to_string(j.size()));
  std::vector<Rational> v;
  for (std::size_t i = 0; i < j.size(); ++i) v.push_back(read_number(j[i], at / i));
  return v;
}

}  // namespace dcad::io
