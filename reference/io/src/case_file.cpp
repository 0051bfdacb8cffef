#include "dcad/io/case_file.hpp"
#include "forms.hpp"
#include "json_input.hpp"

#include <algorithm>

namespace dcad::io {

using nlohmann::json;

namespace {

void require_symmetric_input(const QMatrix& w, const Where& at) {
  for (std::size_t i = 0; i < w.rows(); ++i)
    for (std::size_t k = 0; k < w.cols(); ++k)
      if (w(i, k) != w(k, i))
        (at / i / k)
            .fail("a symmetric matrix (entry (" + std::to_string(i) + "," + std::to_string(k) + ") = entry (" +
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
    if (!j["forces"].is_object())
      f.fail("an object {q, v} of n×n matrices (F(q, v) = F_q q + F_v v)", describe(j["forces"]));
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
        (at / i / k)
            .fail("a skew matrix (entry (" + std::to_string(i) + "," + std::to_string(k) + ") = -entry (" +
                      std::to_string(k) + "," + std::to_string(i) + "))",
                  w(i, k).str() + " vs " + w(k, i).str());
}

DiracInput read_dirac(const json& j, const Where& at, long n) {
  if (!j.is_object() || j.empty())
    at.fail("an object with one of presymplectic, distribution+form, poisson, basis", describe(j));
  require_known_keys(j, at, {"presymplectic", "distribution", "form", "poisson", "basis"});
  const int forms =
      j.contains("presymplectic") + j.contains("distribution") + j.contains("poisson") + j.contains("basis");
  if (forms > 1)
    at.fail("exactly one form (presymplectic, distribution + form, poisson or basis)",
            std::to_string(forms) + " forms");
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
    if (n < 0 && d.g.cols() != 2 * d.g.rows()) (at / "basis").fail("N rows of length 2N", reference::shape(d.g));
  } else {
    at.fail("one of the forms presymplectic, distribution (+form), poisson, basis", "keys " + describe(j));
  }
  return d;
}

/// "variables": distinct non-empty names.
std::vector<std::string> read_variable_names(const json& v, const Where& at) {
  if (!v.is_array()) at.fail("an array of names", describe(v));
  std::vector<std::string> names;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_string() || v[i].get<std::string>().empty())
      (at / i).fail("a name (non-empty string)", describe(v[i]));
    const auto seen = std::find(names.begin(), names.end(), v[i].get<std::string>());
    if (seen != names.end())
      (at / i).fail("a new name", "\"" + *seen + "\", already variable " + std::to_string(seen - names.begin()));
    names.push_back(v[i].get<std::string>());
  }
  return names;
}

/// "energy", "initial" and "coordinates", once c.n and c.variables are known.
void read_energy_and_start(const json& j, const Where& root, CaseFile& c) {
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
}

}  // namespace

CaseFile read_case(const std::string& file) { return read_case(parse_json_exact(slurp(file), file), file); }

CaseFile read_case(const json& j, const std::string& file) {
  const Where root{file, ""};
  if (!j.is_object()) root.fail("a JSON object (a dcad case file)", describe(j));
  if (!j.contains("dcad")) root.fail("the key \"dcad\": 1 (format version)", "no such key");
  if (j.contains("lagrangian") || j.contains("parameters"))
    (root / (j.contains("lagrangian") ? "lagrangian" : "parameters"))
        .fail(
            "a linear case (dirac, pontryagin or constrained) here; the expression form is taken by solve, check and "
            "simulate",
            "the expression form");
  require_known_keys(j, root,
                     {"dcad", "name", "description", "variables", "dirac", "energy", "pontryagin", "constrained",
                      "initial", "coordinates", "expect", "known_failures"});
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
    c.variables = read_variable_names(j["variables"], root / "variables");
    n = static_cast<long>(c.variables.size());
  }
  const int forms = j.contains("dirac") + j.contains("pontryagin") + j.contains("constrained");
  if (forms > 1)
    root.fail("one of \"dirac\", \"pontryagin\", \"constrained\"",
              "both" + std::string(forms > 2 ? " (all three)" : ""));
  if (j.contains("constrained")) {
    const json& k = j["constrained"];
    const Where at = root / "constrained";
    if (!k.is_object() || !k.contains("symplectic")) at.fail("an object {symplectic, primary}", describe(k));
    require_known_keys(k, at, {"symplectic", "primary"});
    c.has_constrained = true;
    c.constrained.w = read_matrix(k["symplectic"], at / "symplectic", n, n);
    require_skew_input(c.constrained.w, at / "symplectic");
    c.n = c.constrained.w.rows();
    c.constrained.primary = k.contains("primary")
                                ? read_matrix(k["primary"], at / "primary", -1, static_cast<long>(c.n) + 1)
                                : QMatrix(0, c.n + 1);
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
      (root / "variables")
          .fail(std::to_string(c.n) + " names (q, v, p for Q of dim " + std::to_string(c.pontryagin.n) + ")",
                std::to_string(n));
    if (j.contains("energy"))
      (root / "energy").fail("no energy next to `pontryagin` (E = p·v − L)", describe(j["energy"]));
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
  read_energy_and_start(j, root, c);
  return c;
}

}  // namespace dcad::io
