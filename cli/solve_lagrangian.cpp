#include "solve_lagrangian.hpp"

#include "dcad/fast/pointwise.hpp"
#include "dcad/reference/pointwise.hpp"
#include "solve.hpp"

#include <chrono>
#include <sstream>

namespace dcad::cli {

namespace ref = reference;
using io::Rational;

namespace {

std::string text_of(const Rational& q) { return q.str(); }
std::string text_of(double x) { return float_text(x); }

}  // namespace

std::vector<Rational> start_point(const io::LagrangianCase& c, std::vector<bool>& fixed) {
  const std::size_t w = 2 * c.system.n + 1;
  std::vector<Rational> x(w, 0);
  fixed.assign(w, false);
  for (std::size_t i = 0; i < w; ++i) {
    if (c.initial[i]) {
      x[i] = *c.initial[i];
      fixed[i] = true;
    } else if (!c.has_initial && i < 2 * c.system.n) {
      x[i] = Rational(static_cast<long>((i * 7 + 3) % 11) - 5, static_cast<long>(3 + i % 4));
    }
  }
  return x;
}

namespace {

/// The tangent equation Σ g_j s_j = rhs as text in the variable names.
template <class T>
std::string tangent_text(const ref::PointwiseConstraint<T>& c, const std::vector<std::string>& names) {
  std::string s;
  for (const auto& [j, g] : c.gradient) {
    std::string coef = text_of(g);
    const bool neg = !coef.empty() && coef[0] == '-';
    if (neg) coef = coef.substr(1);
    const bool one = coef == "1" || coef == "1.0";
    s += (s.empty() ? (neg ? "-" : "") : (neg ? " - " : " + ")) + (one ? "" : coef + "*") + names[j];
  }
  return s + " = " + text_of(c.rhs);
}

template <class T>
LagrangianReport report_of(const ref::PointwiseResult<T>& r, const io::LagrangianCase& c) {
  LagrangianReport out;
  out.dims = r.dims;
  out.steps = static_cast<long>(r.steps);
  out.consistent = r.consistent;
  out.regular = r.regular;
  out.why = r.why;
  out.solution_rank = r.consistent && r.regular ? static_cast<long>(r.solution_rank) : -1;
  out.time = text_of(r.time);
  for (const T& x : r.point) out.point.push_back(text_of(x));
  for (const T& x : r.velocity) out.velocity.push_back(text_of(x));
  for (const auto& g : r.gauge) {
    out.gauge.emplace_back();
    for (const T& x : g) out.gauge.back().push_back(text_of(x));
  }
  const std::vector<std::string> names = c.system.variable_names();
  for (const auto& l : r.levels) {
    LagrangianReport::Level lv;
    lv.dim = l.dim;
    for (const auto& k : l.added) lv.constraints.push_back({names[k.solved_for], tangent_text(k, names)});
    for (const auto& p : l.pivots) lv.pivots.push_back({p.row, p.column, text_of(p.value)});
    out.levels.push_back(lv);
  }
  {  // M_1 = {p = ∂L/∂v, a·v + b = 0} as formulas (symbolic derivatives of L)
    const ref::LagrangianDerivatives d = ref::derivatives(c.system);
    const std::vector<std::string> st = c.system.state_names();
    for (std::size_t i = 0; i < c.system.n; ++i) out.first_constraints.push_back(st[2 * c.system.n + i] + " = " + ref::expr::to_text(d.dl_dv[i], names));
    for (const auto& k : c.system.constraints) out.first_constraints.push_back(ref::expr::to_text(k, names) + " = 0");
  }
  out.order = r.order;
  out.checked_order = r.checked_order;
  out.moves = static_cast<long>(r.moves);
  return out;
}

/// Given values must hold at the final point: a given value that the CAD had to change is not on M_c.
template <class T>
void check_given(const ref::PointwiseResult<T>& r, const io::LagrangianCase& c, const std::function<bool(const T&, const Rational&)>& same) {
  const std::vector<std::string> st = c.system.state_names();
  const std::size_t n = c.system.n;
  const auto bad = [&](std::size_t idx, const Rational& given, const T& found) {
    throw io::InputError(c.file + ": /initial/" + st[idx] + ": expected a value on M_c (the constraints give " + st[idx] + " = " +
                         text_of(found) + " with the other given values), found " + given.str());
  };
  if (!r.consistent || r.point.size() != 3 * n) return;  // no point of M_c to hold them against
  for (std::size_t i = 0; i < 2 * n; ++i)
    if (c.initial[i] && !same(r.point[i], *c.initial[i])) bad(i, *c.initial[i], r.point[i]);
  for (std::size_t i = 0; i < n; ++i)
    if (c.initial_p[i] && !same(r.point[2 * n + i], *c.initial_p[i])) bad(2 * n + i, *c.initial_p[i], r.point[2 * n + i]);
}

LagrangianReport solve_exact(const io::LagrangianCase& c) {
  std::vector<bool> fixed;
  const std::vector<Rational> start = start_point(c, fixed);
  ref::ExactDecisions<Rational> decide;
  const auto r = ref::pointwise_cad<Rational>(c.system, start, fixed, decide, [](const Rational& q) { return q; });
  check_given<Rational>(r, c, [](const Rational& a, const Rational& b) { return a == b; });
  LagrangianReport out = report_of(r, c);
  out.route = "pointwise exact";
  out.certified = r.regular;  // a singular point decides no tower
  return out;
}

LagrangianReport solve_double(const io::LagrangianCase& c) {
  std::vector<bool> fixed;
  const std::vector<Rational> start = start_point(c, fixed);
  std::vector<double> x;
  for (const Rational& q : start) x.push_back(q.convert_to<double>());
  fast::ToleranceDecisions decide;
  const auto r = fast::pointwise_cad(c.system, x, fixed, decide);
  check_given<double>(r, c, [](const double& a, const Rational& b) {
    const double bb = b.convert_to<double>();
    return std::abs(a - bb) <= 1e-9 * (1 + std::abs(bb));
  });
  LagrangianReport out = report_of(r, c);
  out.route = "pointwise double";
  out.certified = decide.certain.yes() && r.regular;
  if (decide.certain.unknown()) out.note = "not certified: " + decide.evidence;
  return out;
}

}  // namespace

LagrangianReport solve_lagrangian(const io::LagrangianCase& c, const std::string& backend) {
  const auto t0 = std::chrono::steady_clock::now();
  LagrangianReport r;
  try {
    if (backend == "fast") {
      r = solve_double(c);
    } else {
      try {
        r = solve_exact(c);
      } catch (const ref::NotExactHere& e) {
        if (backend == "reference")
          throw io::InputError(c.file + ": /initial: expected a point where every value of the formulas is rational (the exact route), found " +
                               e.what() + "; give such a point (e.g. angles 0) or use --backend fast or certified");
        r = solve_double(c);
        r.note = std::string("the exact route cannot run here (") + e.what() + "): double precision" + (r.note.empty() ? "" : "; " + r.note);
        r.certified = false;
      }
    }
  } catch (const ref::PointwiseNoPoint& e) {
    throw io::InputError(c.file + ": /initial: expected values that extend to a point of M_c, found " + e.what());
  } catch (const std::domain_error& e) {
    throw io::InputError(c.file + ": /initial: expected a point where the formulas are defined and differentiable, found " + e.what());
  } catch (const std::length_error& e) {
    throw io::InputError(c.file + ": /lagrangian/coordinates: expected a system whose tower fits in jets of at most 200000 monomials, found " +
                         std::to_string(c.system.n) + " coordinates: " + e.what());
  }
  r.backend = backend;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

nlohmann::json to_json(const LagrangianReport& r, const io::LagrangianCase& c) {
  using nlohmann::json;
  json j;
  j["dcad"] = 1;
  j["backend"] = r.backend;
  j["certified"] = r.certified;
  j["dims"] = r.dims;
  j["steps"] = r.steps;
  j["consistent"] = r.consistent;
  j["solution_rank"] = r.solution_rank >= 0 ? json(r.solution_rank) : json(nullptr);
  j["unique"] = r.solution_rank >= 0 ? json(r.solution_rank == 0) : json(nullptr);
  if (!c.name.empty()) j["name"] = c.name;
  j["variables"] = c.system.state_names();
  j["route"] = r.route;
  j["regular"] = r.regular;
  if (!r.why.empty()) j["why"] = r.why;
  json pt = json::object();
  if (c.system.has_time) pt[c.system.time_name] = r.time;
  const std::vector<std::string> st = c.system.state_names();
  for (std::size_t i = 0; i < r.point.size(); ++i) pt[st[i]] = r.point[i];
  j["point"] = pt;
  json tower = json::array();
  tower.push_back({{"k", 0}, {"dim", r.dims[0]}, {"new_constraints", json::array()}});
  for (std::size_t k = 0; k < r.levels.size(); ++k) {
    const auto& l = r.levels[k];
    json cs = json::array(), solved = json::array(), ps = json::array();
    if (k == 0) {
      cs = r.first_constraints;
    } else {
      for (const auto& con : l.constraints) {
        cs.push_back(con[1]);
        solved.push_back(con[0]);
      }
    }
    for (const auto& p : l.pivots) ps.push_back({{"row", p[0]}, {"column", p[1]}, {"value", p[2]}});
    json step = {{"k", k + 1}, {"dim", k + 1 < r.dims.size() ? r.dims[k + 1] : l.dim}, {"new_constraints", cs}};
    step["form"] = k == 0 ? "formula" : "tangent at the point";
    if (k > 0) step["solved_for"] = solved;
    step["pivots"] = ps;  // of the linear system for (d/dt s, lambda) on this M_k
    tower.push_back(step);
  }
  if (!r.consistent) tower.push_back({{"k", r.dims.size() - 1}, {"dim", -1}, {"new_constraints", json::array({r.why})}});
  j["tower"] = tower;
  if (!r.velocity.empty()) {
    json v = json::object();
    for (std::size_t i = 0; i < r.velocity.size(); ++i) v[st[i]] = r.velocity[i];
    j["velocity"] = v;
    j["gauge"] = r.gauge;
  }
  j["jets"] = {{"order", r.order}, {"checked_order", r.checked_order}, {"moves", r.moves}};
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

std::string to_text(const LagrangianReport& r, const io::LagrangianCase& c) {
  std::ostringstream o;
  const std::vector<std::string> st = c.system.state_names();
  o << c.file << (c.name.empty() ? "" : " (" + c.name + ")") << ": CAD (CEF §5) at a point, " << r.route << ", backend " << r.backend << ", "
    << (r.certified ? "certified" : "NOT certified") << "\n";
  o << "  point" << (c.system.has_time ? " at " + c.system.time_name + " = " + r.time : "") << ":";
  for (std::size_t i = 0; i < r.point.size(); ++i) o << (i % 6 == 0 ? "\n     " : "") << " " << st[i] << " = " << r.point[i] << (i + 1 < r.point.size() ? "," : "");
  o << "\n";
  if (r.moves > 0) o << "  (the given values were completed onto M_c by " << r.moves << " Newton step" << (r.moves > 1 ? "s" : "") << ")\n";
  o << "  M_0: dim " << r.dims[0] << "\n";
  for (std::size_t k = 0; k < r.levels.size() && k + 1 < r.dims.size(); ++k) {
    o << "  M_" << k + 1 << ": dim " << r.dims[k + 1] << "\n";
    if (k == 0)
      for (const std::string& f : r.first_constraints) o << "      " << f << "\n";
    for (const auto& cs : r.levels[k].constraints) o << "      " << cs[1] << "   (tangent at the point; solved for " << cs[0] << ")\n";
  }
  if (!r.consistent) o << "  M_" << r.dims.size() - 1 << " is empty: " << r.why << "\n";
  if (!r.regular) o << "  SINGULAR POINT: " << r.why << " (the tower is not decided here; try another point)\n";
  if (r.consistent && r.regular) {
    o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << r.dims.back() << " (regular at the point; the last step's "
      << "constraints vanish on M_c to order " << r.checked_order << ")\n";
    o << "  solution rank dim(ker omega_D ∩ T M_c) = " << r.solution_rank << (r.solution_rank == 0 ? " (unique)" : "") << "\n";
    o << "  velocity at the point (one solution" << (r.solution_rank ? " of a " + std::to_string(r.solution_rank) + "-parameter family" : "") << "):";
    for (std::size_t i = 0; i < r.velocity.size(); ++i) o << (i % 4 == 0 ? "\n     " : "") << " d/dt " << st[i] << " = " << r.velocity[i] << (i + 1 < r.velocity.size() ? "," : "");
    o << "\n";
  }
  if (!r.note.empty()) o << "  note: " << r.note << "\n";
  return o.str();
}

}  // namespace dcad::cli
