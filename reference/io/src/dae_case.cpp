// Reading the linear DAE form (dae_case.hpp).
#include "dcad/io/dae_case.hpp"

#include "expression_parse.hpp"
#include "forms.hpp"
#include "json_input.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

namespace dcad::io {

using nlohmann::json;

bool is_dae_case(const json& j) { return j.is_object() && j.contains("dae"); }

std::string source_name(std::size_t i, long order) {
  return "f_" + std::to_string(i + 1) + std::string(static_cast<std::size_t>(order), '\'') + "(t)";
}

namespace {

std::string text_at(const json& j, const Where& at, const std::string& what) {
  if (!j.is_string()) at.fail(what, describe(j));
  return j.get<std::string>();
}

/// One entry of E or A: a number or a string, a rational ("1/1000", "1e-12") or a formula in the
/// parameters ("1/C", "R*C"), which must be a number once they are substituted.
Rational read_entry(const json& x, const Where& at, const std::map<std::string, Rational>& parameters) {
  if (!x.is_string()) return read_number(x, at);
  const reference::expr::Expr e = parse_expression(x.get<std::string>(), {}, parameters, at);
  if (!reference::expr::is_number(e))
    at.fail("a number, or a formula in the parameters", "\"" + x.get<std::string>() + "\"");
  return e->value;
}

/// What an index was instead of an integer: JSON numbers that are not integers reach here as their
/// text (the loader keeps decimals exact), so "3.0" is named a number, not a string.
std::string not_an_index(const json& j) {
  if (j.is_string()) {
    const std::string t = j.get<std::string>();
    if (!t.empty() && t.find_first_not_of("+-0123456789.eE") == std::string::npos &&
        t.find_first_of("0123456789") != std::string::npos)
      return "number " + t + " (not an integer)";
  }
  return describe(j);
}

struct Entries {
  long rows = 0;
  std::vector<DaeCase::Entry> nonzeros;
};

/// E or A in either encoding: an array of m rows of N entries, or sparse, {"rows": m, "entries":
/// [[i, j, value], …]} with i and j counted from 0 (as in JSON paths and scipy's coo_matrix), j also
/// a variable's name; an entry given twice is bad input (it would be summed or dropped elsewhere).
Entries read_entries(const json& j, const Where& at, long rows, const std::vector<std::string>& variables,
                     const std::map<std::string, Rational>& parameters) {
  const long cols = static_cast<long>(variables.size());
  Entries out;
  if (j.is_object()) {
    require_known_keys(j, at, {"rows", "entries"});
    if (!j.contains("rows") && rows < 0) at.fail("the key \"rows\" (m, the number of equations)", "no such key");
    if (j.contains("rows")) {
      const json& r = j["rows"];
      if (!r.is_number_integer() || r.get<long>() < 0 || r.get<long>() > 1'000'000)
        (at / "rows").fail("a number of rows (an integer from 0 to 1,000,000)", not_an_index(r));
      if (rows >= 0 && r.get<long>() != rows)
        (at / "rows").fail(std::to_string(rows) + " rows (as E)", std::to_string(r.get<long>()));
      out.rows = r.get<long>();
    } else {
      out.rows = rows;
    }
    if (!j.contains("entries")) at.fail("the key \"entries\" ([[row, column, value], …])", "no such key");
    const json& es = j["entries"];
    if (!es.is_array()) (at / "entries").fail("an array of [row, column, value]", describe(es));
    std::map<std::string, long> column_of;
    for (long k = 0; k < cols; ++k) column_of[variables[static_cast<std::size_t>(k)]] = k;
    std::unordered_map<long, std::size_t> seen;  // row · N + column → the entry's index
    for (std::size_t k = 0; k < es.size(); ++k) {
      const Where ek = at / "entries" / k;
      const json& e = es[k];
      if (!e.is_array() || e.size() != 3)
        ek.fail("[row, column, value] (row and column from 0; the column may be a variable's name)", describe(e));
      if (!e[0].is_number_integer() || e[0].get<long>() < 0 || e[0].get<long>() >= out.rows)
        (ek / 0).fail("a row from 0 to " + std::to_string(out.rows - 1), not_an_index(e[0]));
      long col = -1;
      if (e[1].is_string() && not_an_index(e[1]) != describe(e[1])) {
        (ek / 1).fail("a column from 0 to " + std::to_string(cols - 1) + " or a variable's name", not_an_index(e[1]));
      } else if (e[1].is_string()) {
        const auto it = column_of.find(e[1].get<std::string>());
        if (it == column_of.end()) {
          const std::string best = nearest_name(e[1].get<std::string>(), variables);
          (ek / 1).fail("a column from 0 to " + std::to_string(cols - 1) + " or a variable's name",
                        "unknown name " + describe(e[1]) + (best.empty() ? "" : " (did you mean \"" + best + "\"?)"));
        }
        col = it->second;
      } else if (e[1].is_number_integer() && e[1].get<long>() >= 0 && e[1].get<long>() < cols) {
        col = e[1].get<long>();
      } else {
        (ek / 1).fail("a column from 0 to " + std::to_string(cols - 1) + " or a variable's name", describe(e[1]));
      }
      const long row = e[0].get<long>();
      const auto [it, fresh] = seen.emplace(row * cols + col, k);
      if (!fresh)
        ek.fail("each entry once", "row " + std::to_string(row) + ", column " + std::to_string(col) +
                                       " again (first at " + at.path + "/entries/" + std::to_string(it->second) + ")");
      Rational v = read_entry(e[2], ek / 2, parameters);
      if (v != 0) out.nonzeros.push_back({row, col, std::move(v)});
    }
    return out;
  }
  if (!j.is_array())
    at.fail("a matrix (array of rows, or {\"rows\": m, \"entries\": [[row, column, value], …]})", describe(j));
  if (rows >= 0 && static_cast<long>(j.size()) != rows)
    at.fail(std::to_string(rows) + " rows", std::to_string(j.size()) + " rows");
  out.rows = static_cast<long>(j.size());
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Where ri = at / i;
    if (!j[i].is_array()) ri.fail("a row (array of numbers)", describe(j[i]));
    if (static_cast<long>(j[i].size()) != cols)
      ri.fail("a row of length " + std::to_string(cols), "length " + std::to_string(j[i].size()));
    for (std::size_t k = 0; k < j[i].size(); ++k) {
      Rational v = read_entry(j[i][k], ri / k, parameters);
      if (v != 0) out.nonzeros.push_back({static_cast<long>(i), static_cast<long>(k), std::move(v)});
    }
  }
  return out;
}

QMatrix densely(const Entries& x, long cols) {
  QMatrix m(x.rows, cols);
  for (const DaeCase::Entry& e : x.nonzeros) m(e.row, e.col) = e.value;
  return m;
}

/// e at time t in double (a sanity check of the input, never a result): NaN where undefined.
double value_at(const reference::expr::Expr& e, double t) {
  using reference::expr::ExprOp;
  switch (e->op) {
    case ExprOp::Number: return e->value.convert_to<double>();
    case ExprOp::Variable: return t;
    case ExprOp::Add: return value_at(e->a, t) + value_at(e->b, t);
    case ExprOp::Sub: return value_at(e->a, t) - value_at(e->b, t);
    case ExprOp::Mul: return value_at(e->a, t) * value_at(e->b, t);
    case ExprOp::Div: {
      const double d = value_at(e->b, t);
      return d == 0 ? NAN : value_at(e->a, t) / d;
    }
    case ExprOp::Neg: return -value_at(e->a, t);
    case ExprOp::Pow: {
      const double b = value_at(e->a, t);
      return b == 0 && e->exponent < 0 ? NAN : std::pow(b, static_cast<double>(e->exponent));
    }
    case ExprOp::Sin: return std::sin(value_at(e->a, t));
    case ExprOp::Cos: return std::cos(value_at(e->a, t));
    case ExprOp::Exp: return std::exp(value_at(e->a, t));
    case ExprOp::Sqrt: {
      const double a = value_at(e->a, t);
      return a < 0 ? NAN : std::sqrt(a);
    }
  }
  return NAN;
}

/// /dae/f: one expression in the time per equation (numbers allowed), each defined for generic t.
void read_sources(const json& f, const Where& at_f, DaeCase& c) {
  const std::size_t m = c.f.size();
  if (!f.is_array() || f.size() != m)
    at_f.fail("an array of " + std::to_string(m) + " expressions in the time (one per equation)", describe(f));
  std::map<std::string, std::size_t> vars;
  if (!c.time_name.empty()) vars[c.time_name] = 0;
  for (std::size_t i = 0; i < m; ++i) {
    const Where at = at_f / i;
    if (f[i].is_number()) {
      c.f[i] = reference::expr::number(read_number(f[i], at));
      continue;
    }
    try {
      c.f[i] = parse_expression(text_at(f[i], at, "an expression in the time (a string)"), vars, c.parameters, at);
    } catch (const InputError& e) {
      if (!c.time_name.empty()) throw;
      throw InputError(std::string(e.what()) +
                       " (a source that depends on the time needs its name in /dae/time, e.g. \"time\": \"t\")");
    }
    bool defined = false;  // a source must be defined for generic t: 1/(t - t) or sqrt(-1 - t^2) is no function
    for (double t : {0.5, 1.0, 2.0, 3.7}) defined = defined || std::isfinite(value_at(c.f[i], t));
    if (!defined)
      at.fail("a formula defined (finite and real) for generic t",
              "\"" + f[i].get<std::string>() + "\", undefined at t = 0.5, 1, 2 and 3.7");
  }
}

/// /initial: exact values of variables (and of the time, by its name).
void read_initial_values(const json& j, const Where& root, DaeCase& c) {
  const std::size_t n = c.variables.size();
  c.initial.assign(n, std::nullopt);
  if (j.contains("initial")) {
    const json& in = j["initial"];
    const Where wi = root / "initial";
    if (!in.is_object()) wi.fail("an object {name: exact value} (variables, the time)", describe(in));
    c.has_initial = true;
    for (const auto& [k, v] : in.items()) {
      const Rational value = read_number(v, wi / k);
      if (!c.time_name.empty() && k == c.time_name) {
        c.initial_time = value;
        continue;
      }
      const auto it = std::find(c.variables.begin(), c.variables.end(), k);
      if (it == c.variables.end()) {
        std::vector<std::string> known = c.variables;
        if (!c.time_name.empty()) known.push_back(c.time_name);
        const std::string best = nearest_name(k, known);
        (wi / k).fail("a variable or the time",
                      "unknown name \"" + k + "\"" + (best.empty() ? "" : " (did you mean \"" + best + "\"?)"));
      }
      c.initial[static_cast<std::size_t>(it - c.variables.begin())] = value;
    }
  }
}

}  // namespace

DaeCase read_dae_case(const json& j, const std::string& file) {
  const Where root{file, ""};
  require_known_keys(j, root,
                     {"dcad", "name", "description", "variables", "parameters", "dae", "initial", "expect",
                      "known_failures", "published"});
  if (!j.contains("dcad")) root.fail("the key \"dcad\": 1 (format version)", "no such key");
  if (!(j["dcad"].is_number_integer() && j["dcad"].get<long>() == 1))
    (root / "dcad").fail("format version 1", describe(j["dcad"]));
  DaeCase c;
  c.file = file;
  if (j.contains("name")) c.name = text_at(j["name"], root / "name", "a string");
  if (j.contains("description")) c.description = text_at(j["description"], root / "description", "a string");
  if (!j.contains("variables")) root.fail("the key \"variables\" (the names of x, in order)", "no such key");
  const json& vs = j["variables"];
  if (!vs.is_array() || vs.empty()) (root / "variables").fail("a non-empty array of names", describe(vs));
  std::set<std::string> taken;
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const std::string name = text_at(vs[i], root / "variables" / i, "a variable name");
    if (!is_identifier(name))
      (root / "variables" / i).fail("a name (a letter or _, then letters, digits, _)", "\"" + name + "\"");
    if (!taken.insert(name).second) (root / "variables" / i).fail("a name not used before", "\"" + name + "\" again");
    c.variables.push_back(name);
  }
  check_published(j, root, c.variables);
  const std::size_t n = c.variables.size();
  const json& d = j["dae"];
  const Where w = root / "dae";
  if (!d.is_object()) w.fail("an object {E, A, f, time}", describe(d));
  require_known_keys(d, w, {"E", "A", "f", "time"});
  if (!d.contains("E")) w.fail("the key \"E\" (m×N, N = " + std::to_string(n) + " variables)", "no such key");
  if (!d.contains("A")) w.fail("the key \"A\" (m×N, N = " + std::to_string(n) + " variables)", "no such key");
  if (d.contains("time")) {
    c.time_name = text_at(d["time"], w / "time", "the name of the time variable");
    if (!is_identifier(c.time_name)) (w / "time").fail("a name", "\"" + c.time_name + "\"");
    if (taken.count(c.time_name)) (w / "time").fail("a name other than the variables'", "\"" + c.time_name + "\"");
  }
  if (j.contains("parameters")) {
    const json& p = j["parameters"];
    if (!p.is_object()) (root / "parameters").fail("an object {name: exact value}", describe(p));
    for (const auto& [k, v] : p.items()) {
      if (taken.count(k) || k == c.time_name)
        (root / "parameters" / k).fail("a name not used by a variable or the time", "\"" + k + "\"");
      c.parameters[k] = read_number(v, root / "parameters" / k);
    }
  }
  Entries e = read_entries(d["E"], w / "E", -1, c.variables, c.parameters);
  if (e.rows == 0) (w / "E").fail("at least one equation (row)", "none");
  Entries a = read_entries(d["A"], w / "A", e.rows, c.variables, c.parameters);
  c.rows = e.rows;
  c.dense = e.rows * static_cast<long>(n) <= DaeCase::dense_limit && e.rows <= DaeCase::dense_side &&
            static_cast<long>(n) <= DaeCase::dense_side;
  if (c.dense) c.e = densely(e, static_cast<long>(n)), c.a = densely(a, static_cast<long>(n));
  c.e_entries = std::move(e.nonzeros);
  c.a_entries = std::move(a.nonzeros);
  const std::size_t m = static_cast<std::size_t>(c.rows);
  c.f.assign(m, reference::expr::number(0));
  if (d.contains("f")) read_sources(d["f"], w / "f", c);
  read_initial_values(j, root, c);
  return c;
}

}  // namespace dcad::io
