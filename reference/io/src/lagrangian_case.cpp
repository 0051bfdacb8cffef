#include "dcad/io/lagrangian_case.hpp"
#include "dcad/reference/nonlinear/polynomial.hpp"

#include "expression_parse.hpp"
#include "json_input.hpp"
#include "forms.hpp"

#include <algorithm>
#include <set>

namespace dcad::io {

using nlohmann::json;
namespace ex = reference::expr;

bool is_expression_case(const json& j) {
  return j.is_object() && (j.contains("lagrangian") || j.contains("parameters"));
}

bool is_expression_file(const std::string& file) {
  if (file.size() < 5 || file.compare(file.size() - 5, 5, ".json") != 0) return false;
  try {
    return is_expression_case(read_json_file(file));
  } catch (const InputError&) {
    return false;
  }
}

namespace {

std::string read_string(const json& j, const Where& at, const std::string& what) {
  if (!j.is_string()) at.fail(what, describe(j));
  return j.get<std::string>();
}

/// A new name for a coordinate, parameter or the time: an identifier not taken by anything else.
void claim(const std::string& name, const Where& at, std::set<std::string>& taken, const std::string& what) {
  if (!is_identifier(name))
    at.fail(what + " that is a name (a letter or _, then letters, digits, _)", "\"" + name + "\"");
  const auto& f = expression_functions();
  if (std::find(f.begin(), f.end(), name) != f.end())
    at.fail(what + " that is not a function name", "\"" + name + "\"");
  if (!taken.insert(name).second)
    at.fail(what + " not used for anything else", "\"" + name + "\" given twice (or a velocity/momentum name)");
}

/// The format version, `name` and `description`.
LagrangianCase read_header(const json& j, const Where& root, const std::string& file) {
  if (!j.contains("dcad")) root.fail("the key \"dcad\": 1 (format version)", "no such key");
  if (!(j["dcad"].is_number_integer() && j["dcad"].get<long>() == 1))
    (root / "dcad").fail("format version 1", describe(j["dcad"]));
  LagrangianCase c;
  c.file = file;
  if (j.contains("name")) c.name = read_string(j["name"], root / "name", "a string");
  if (j.contains("description")) c.description = read_string(j["description"], root / "description", "a string");
  return c;
}

/// The names both formula forms declare, in order: `coordinates` (each claiming v_<name>, and p_<name>
/// when the form has momenta), the optional `time`, the case's `parameters`.
void read_names(const json& j, const json& form, const Where& root, const Where& l, bool momenta, std::size_t most,
                LagrangianCase& c, std::set<std::string>& taken) {
  reference::LagrangianSystem& s = c.system;
  const json& coords = form["coordinates"];
  if (!coords.is_array() || coords.empty()) (l / "coordinates").fail("a non-empty array of names", describe(coords));
  if (coords.size() > most)
    (l / "coordinates").fail("at most " + std::to_string(most) + " coordinates", std::to_string(coords.size()));
  for (std::size_t i = 0; i < coords.size(); ++i) {
    const std::string name = read_string(coords[i], l / "coordinates" / i, "a coordinate name");
    claim(name, l / "coordinates" / i, taken, "a coordinate name");
    s.names.push_back(name);
  }
  s.n = s.names.size();
  for (std::size_t i = 0; i < s.n; ++i) {
    claim("v_" + s.names[i], l / "coordinates" / i, taken,
          "a coordinate whose velocity name v_" + s.names[i] + " is free");
    if (momenta)
      claim("p_" + s.names[i], l / "coordinates" / i, taken,
            "a coordinate whose momentum name p_" + s.names[i] + " is free");
  }
  if (form.contains("time")) {
    s.has_time = true;
    s.time_name = read_string(form["time"], l / "time", "the name of the time variable");
    claim(s.time_name, l / "time", taken, "a time name");
  }
  if (j.contains("parameters")) {
    const json& p = j["parameters"];
    if (!p.is_object()) (root / "parameters").fail("an object {name: exact value}", describe(p));
    for (const auto& [k, v] : p.items()) {
      claim(k, root / "parameters" / k, taken, "a parameter name");
      c.parameters[k] = read_number(v, root / "parameters" / k);
    }
  }
}

/// The arguments of the formulas: t, q, v (LagrangianSystem's indices).
std::map<std::string, std::size_t> formula_variables(const reference::LagrangianSystem& s) {
  std::map<std::string, std::size_t> vars;
  for (std::size_t i = 0; i < s.n; ++i) {
    vars[s.names[i]] = s.q(i);
    vars["v_" + s.names[i]] = s.v(i);
  }
  if (s.has_time) vars[s.time_name] = s.t();
  return vars;
}

}  // namespace

namespace {
/// "initial": exact values by name — coordinates, velocities v_*, momenta p_* and the time — into c.initial
/// (q, v, t) and c.initial_p; every slot not named stays free.
/// c.initial and c.initial_p empty for the system's size, and the case's "initial" object (null if none).
const json* initial_object(const json& j, const Where& w, const char* expected, LagrangianCase& c) {
  c.initial.assign(2 * c.system.n + 1, std::nullopt);
  c.initial_p.assign(c.system.n, std::nullopt);
  if (!j.contains("initial")) return nullptr;
  const json& in = j["initial"];
  if (!in.is_object()) w.fail(expected, describe(in));
  c.has_initial = true;
  return &in;
}

void read_initial(const json& j, const Where& root, const std::map<std::string, std::size_t>& vars, LagrangianCase& c) {
  const reference::LagrangianSystem& s = c.system;
  const Where w = root / "initial";
  if (const json* initial =
          initial_object(j, w, "an object {name: exact value} (coordinates, v_*, p_*, the time)", c)) {
    const json& in = *initial;
    std::vector<std::string> known;
    for (const auto& [k, v] : vars) known.push_back(k);
    for (const std::string& n : s.names) known.push_back("p_" + n);
    for (const auto& [k, v] : in.items()) {
      const Rational value = read_number(v, w / k);
      if (const auto it = vars.find(k); it != vars.end()) {
        c.initial[it->second] = value;
        continue;
      }
      const auto p = std::find(s.names.begin(), s.names.end(),
                               k.size() > 2 && k.compare(0, 2, "p_") == 0 ? k.substr(2) : std::string());
      if (p != s.names.end()) {
        c.initial_p[static_cast<std::size_t>(p - s.names.begin())] = value;
        continue;
      }
      const std::string best = nearest_name(k, known);
      (w / k).fail("a coordinate, velocity (v_*), momentum (p_*) or time name",
                   "unknown name \"" + k + "\"" + (best.empty() ? "" : " (did you mean \"" + best + "\"?)"));
    }
  }
}
}  // namespace

LagrangianCase read_lagrangian_case(const json& j, const std::string& file) {
  const Where root{file, ""};
  require_known_keys(
      j, root,
      {"dcad", "name", "description", "parameters", "lagrangian", "initial", "expect", "known_failures", "published"});
  if (!j.contains("lagrangian")) root.fail("the key \"lagrangian\" (the expression form)", "\"parameters\" without it");
  LagrangianCase c = read_header(j, root, file);
  const json& lag = j["lagrangian"];
  const Where l = root / "lagrangian";
  if (!lag.is_object()) l.fail("an object {coordinates, L, constraints, forces, time}", describe(lag));
  require_known_keys(lag, l, {"coordinates", "L", "constraints", "forces", "time"});
  if (!lag.contains("coordinates")) l.fail("the key \"coordinates\"", "no such key");
  if (!lag.contains("L")) l.fail("the key \"L\" (the Lagrangian)", "no such key");
  reference::LagrangianSystem& s = c.system;
  std::set<std::string> taken;
  read_names(j, lag, root, l, true, 64, c, taken);
  check_published(j, root, s.names);
  const std::map<std::string, std::size_t> vars = formula_variables(s);  // the arguments of L, constraints and forces
  const auto parse = [&](const json& e, const Where& at, const std::string& what) {
    return parse_expression(read_string(e, at, what), vars, c.parameters, at);
  };
  s.lagrangian = parse(lag["L"], l / "L", "the Lagrangian as a string expression");
  if (lag.contains("constraints")) {
    const json& k = lag["constraints"];
    if (!k.is_array()) (l / "constraints").fail("an array of expressions affine in the velocities", describe(k));
    for (std::size_t a = 0; a < k.size(); ++a)
      s.constraints.push_back(parse(k[a], l / "constraints" / a, "a constraint as a string expression"));
    // affinity is decided after expanding and collecting terms ((v+1)^2 - v^2 - 2v is the constant 1):
    // a constraint that is affine only so is replaced by its form a(t, q)·v + b(t, q)
    std::vector<std::size_t> vs;
    for (std::size_t i = 0; i < s.n; ++i) vs.push_back(s.v(i));
    for (std::size_t bad; (bad = reference::first_non_affine_constraint(s)) < s.m();) {
      const auto form =
          reference::expr::affine_form(s.constraints[bad], vs, [&](std::size_t i) { return i >= s.n && i < 2 * s.n; });
      if (!form)
        (l / "constraints" / bad)
            .fail("a constraint affine in the velocities, a(t, q)·v + b(t, q) (CONTRACT)",
                  "\"" + k[bad].get<std::string>() + "\", not affine in v (after expanding and collecting terms)");
      reference::expr::Expr e = form->second;
      for (std::size_t i = 0; i < s.n; ++i)
        e = reference::expr::add(reference::expr::mul(form->first[i], reference::expr::variable(s.v(i))), e);
      s.constraints[bad] = e;
    }
    if (s.m() > s.n)
      (l / "constraints")
          .fail("at most as many constraints as coordinates (" + std::to_string(s.n) + ")", std::to_string(s.m()));
  }
  if (lag.contains("forces")) {
    const json& f = lag["forces"];
    if (!f.is_array() || f.size() != s.n)
      (l / "forces").fail("an array of " + std::to_string(s.n) + " expressions (one per coordinate)", describe(f));
    for (std::size_t i = 0; i < s.n; ++i)
      s.forces.push_back(parse(f[i], l / "forces" / i, "a force component as a string expression"));
  }
  read_initial(j, root, vars, c);
  return c;
}

LagrangianCase read_lagrangian_case(const std::string& file) {
  return read_lagrangian_case(read_json_file(file), file);
}

bool is_implicit_case(const json& j) { return j.is_object() && j.contains("implicit"); }

/// CEF (1.6) with φ not affine in ẋ (PAPER-ITEMS N1): the IDE φ(t, x, ẋ) = 0 on Q is the first-order system
/// {ẋ = w, φ(t, x, w) = 0} on TQ, affine in the derivatives of its coordinates (x, w) — the implicit form again, with
/// 2n coordinates named x and x_dot (with more underscores where that name, or v_ of it, is taken: a coordinate, the
/// time, a parameter).  Its tower N_0 = TQ ⊃ N_1 = {φ = 0} ⊃ … is, near the point (x, w), the branch of φ = 0 through
/// w: τ(N_k) ⊆ M_k = {x ∈ M_{k−1} : ∃ v ∈ T_xM_{k−1}, φ(x, v) = 0}, CEF's M_k the union over the branches (equal
/// where τ maps N_k onto M_k as a submersion).  Returns the names that give w in "initial" (v_x, x_dot).
std::map<std::string, std::size_t> lift_to_tangent_bundle(reference::LagrangianSystem& s,
                                                          const std::map<std::string, Rational>& parameters) {
  namespace ex = reference::expr;
  const std::size_t n = s.n;
  std::map<std::string, std::size_t> derivative_state;
  for (ex::Expr& e : s.constraints)  // v_i (index n + i) is now the coordinate w_i (index n + i); t moves to 4n
    if (s.has_time) e = ex::substitute(e, 2 * n, ex::variable(4 * n));
  for (std::size_t i = 0; i < n; ++i) {
    const auto taken = [&](const std::string& x) {
      return std::find(s.names.begin(), s.names.end(), x) != s.names.end() || x == s.time_name ||
             parameters.count(x) > 0;
    };
    std::string name = s.names[i] + "_dot";  // a name the formulas can use (check reads results back)
    while (taken(name) || taken("v_" + name) || (name.rfind("v_", 0) == 0 && taken(name.substr(2)))) name += "_";
    s.names.push_back(name);
    derivative_state["v_" + s.names[i]] = n + i;
    derivative_state[name] = n + i;
  }
  s.n = 2 * n;
  for (std::size_t i = 0; i < n; ++i)  // ẋ_i − w_i = 0
    s.constraints.push_back(ex::sub(ex::variable(s.v(i)), ex::variable(s.q(n + i))));
  return derivative_state;
}

/// The implicit form's "initial": coordinates and the time by name (in the lifted form also the derivatives, as v_x or
/// x_dot, once each) into c.initial; a derivative v_* of the form's own coordinates is not state.
void read_implicit_initial(const json& j, const Where& root, const std::map<std::string, std::size_t>& vars,
                           const std::map<std::string, std::size_t>& derivative_state, LagrangianCase& c) {
  const reference::LagrangianSystem& s = c.system;
  const Where w = root / "initial";
  if (const json* initial = initial_object(j, w, "an object {name: exact value} (coordinates, the time)", c)) {
    const json& in = *initial;
    std::vector<std::string> known = s.names;
    if (s.has_time) known.push_back(s.time_name);
    const std::map<std::string, std::size_t> lifted = formula_variables(s);  // the lifted form's names, if lifted
    const std::map<std::string, std::size_t>& names = derivative_state.empty() ? vars : lifted;
    for (const auto& [key, v] : in.items()) {
      const Rational value = read_number(v, w / key);
      if (const auto d = derivative_state.find(key); d != derivative_state.end()) {
        if (c.initial[d->second])  // v_x and x_dot name one coordinate
          (w / key).fail("one value for " + s.names[d->second] + " (given as v_ of its coordinate or by its name)",
                         "a second one");
        c.initial[d->second] = value;
        continue;
      }
      const auto it = names.find(key);
      if (it != names.end() && !(it->second >= s.n && it->second < 2 * s.n)) {
        c.initial[it->second] = value;
        continue;
      }
      const std::string best = nearest_name(key, known);
      (w / key).fail("a coordinate or the time name (the derivatives v_* are not state: the equations give them)",
                     "\"" + key + "\"" + (best.empty() ? "" : " (did you mean \"" + best + "\"?)"));
    }
  }
}

LagrangianCase read_implicit_case(const json& j, const std::string& file) {
  const Where root{file, ""};
  require_known_keys(
      j, root,
      {"dcad", "name", "description", "parameters", "implicit", "initial", "expect", "known_failures", "published"});
  LagrangianCase c = read_header(j, root, file);
  const json& im = j["implicit"];
  const Where l = root / "implicit";
  if (!im.is_object()) l.fail("an object {coordinates, equations, time}", describe(im));
  require_known_keys(im, l, {"coordinates", "equations", "time"});
  if (!im.contains("coordinates")) l.fail("the key \"coordinates\"", "no such key");
  if (!im.contains("equations")) l.fail("the key \"equations\" (phi(t, x, v_x) = 0, affine in the v_*)", "no such key");
  reference::LagrangianSystem& s = c.system;
  s.implicit = true;
  s.lagrangian = reference::expr::number(0);
  std::set<std::string> taken;
  read_names(j, im, root, l, false, 1000, c, taken);
  check_published(j, root, s.names);
  const std::map<std::string, std::size_t> vars = formula_variables(s);  // the arguments of the equations: t, x, v_x
  const json& k = im["equations"];
  const Where ke = l / "equations";
  if (!k.is_array())
    ke.fail("an array of equations phi(t, x, v_x) = 0 as string expressions, affine in the v_*", describe(k));
  for (std::size_t a = 0; a < k.size(); ++a)
    s.constraints.push_back(
        parse_expression(read_string(k[a], ke / a, "an equation as a string expression"), vars, c.parameters, ke / a));
  std::vector<std::size_t> vs;
  for (std::size_t i = 0; i < s.n; ++i) vs.push_back(s.v(i));
  std::map<std::string, std::size_t> derivative_state;  // the lifted form's v_x and x_dot: the coordinate x_dot
  for (std::size_t bad;
       (bad = reference::first_non_affine_constraint(s)) < s.m();) {  // as for constraints: affine after expanding
    const auto form =
        reference::expr::affine_form(s.constraints[bad], vs, [&](std::size_t i) { return i >= s.n && i < 2 * s.n; });
    if (!form) {
      const std::size_t n0 = s.n;
      derivative_state = lift_to_tangent_bundle(s, c.parameters);
      std::string lifted;
      for (std::size_t i = 0; i < n0; ++i) lifted += (i ? ", " : "") + s.names[n0 + i] + " = v_" + s.names[i];
      c.warnings.push_back(
          file + ": " + (ke / bad).path + ": \"" + k[bad].get<std::string>() +
          "\" is not affine in the derivatives: the equations are solved as CEF (1.6)'s IDE lifted to TQ, "
          "{x' = w, phi(t, x, w) = 0}, with the derivatives as coordinates (" +
          lifted +
          ", given by either name in \"initial\"): the tower is the lifted system's on TQ (dims over 2n coordinates; "
          "steps and index count its differentiations) on the branch of phi = 0 through the given (or completed) "
          "derivatives, whose projection to the x lies in CEF's M_k (the union over the branches)");
      break;
    }
    reference::expr::Expr e = form->second;
    for (std::size_t i = 0; i < s.n; ++i)
      e = reference::expr::add(reference::expr::mul(form->first[i], reference::expr::variable(s.v(i))), e);
    s.constraints[bad] = e;
  }
  read_implicit_initial(j, root, vars, derivative_state, c);
  return c;
}

reference::expr::Expr parse_case_formula(const LagrangianCase& c, const std::string& text, const std::string& file,
                                         const std::string& path) {
  const std::map<std::string, std::size_t> vars = formula_variables(c.system);
  const Where at{file, path};
  return parse_expression(text, vars, c.parameters, at);
}

}  // namespace dcad::io
