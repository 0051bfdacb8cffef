#include "dcad/fast/pointwise.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <sstream>

namespace dcad::fast {

void ToleranceDecisions::step_data(const std::vector<Tracked>& data) {
  double lo = HUGE_VAL, hi = 0;
  for (const Tracked& x : data)
    if (x.v != 0) {
      lo = std::min(lo, std::abs(x.v));
      hi = std::max(hi, std::abs(x.v));
    }
  well_scaled = !(hi > graded * lo);
  scale = hi;
}

bool ToleranceDecisions::probed(bool answer) {
  if (probe && probe->made++ == probe->uncertain_at) {
    if (certain.yes())
      evidence = "decision " + std::to_string(probe->uncertain_at) + " reported uncertain (DecisionProbe)";
    certain = unknown;
  }
  return answer;
}

bool ToleranceDecisions::zero(const Tracked& x) {
  ++decisions;
  const double a = std::abs(x.v), tiny = 1e-300;
  if (a > nonzero_factor * x.e + tiny) return probed(false);
  if (x.v == 0 && x.e == 0) return probed(true);  // nothing was ever added to it
  if (a <= zero_factor * x.e + tiny && well_scaled && x.e <= 0x1p-26 * scale) {
    ++assumed;
    return probed(true);
  }
  if (probe) ++probe->made;  // an uncertain decision, counted as one
  if (certain.yes()) {
    std::ostringstream s;
    s << "a value " << x.v << " with a rounding-error bound " << x.e
      << (a > zero_factor * x.e + tiny ? " (between 8 and 64 times it: rounding or not?)"
          : !well_scaled
              ? " on graded data (the step's nonzero data span more than 1/sqrt(eps)): zero or a small nonzero?"
              : " too large against the step's data scale " + std::to_string(scale) + ": zero or a small nonzero?");
    evidence = s.str();
  }
  certain = unknown;
  return a <= zero_factor * x.e + tiny;
}

bool ToleranceDecisions::zero(const reference::Jet<Tracked>& j) {
  for (const auto& [i, c] : j.entries())
    if (!zero(c)) return false;
  return true;
}

std::size_t ToleranceDecisions::pivot(const std::vector<Tracked>& values) {
  double largest = 0;
  for (const Tracked& x : values)
    if (std::abs(x.v) > nonzero_factor * x.e) largest = std::max(largest, std::abs(x.v));
  // threshold pivoting (as in sparse LU): the first certainly nonzero value, in the caller's order of
  // preference, that is at least 1/8 of the largest — stable, and the preferred chart where it can be
  for (std::size_t i = 0; i < values.size(); ++i)
    if (largest > 0 && std::abs(values[i].v) > nonzero_factor * values[i].e && std::abs(values[i].v) >= largest / 8) {
      probed(true);  // one decision: values[i] ≠ 0
      return i;
    }
  for (const Tracked& x : values)  // none is certainly nonzero: a value in the band makes this uncertain
    if (!zero(x)) return static_cast<std::size_t>(&x - values.data());
  return values.size();
}

namespace {

reference::PointwiseResult<double> to_double(const reference::PointwiseResult<Tracked>& r) {
  reference::PointwiseResult<double> o;
  const auto d = [](const std::vector<Tracked>& v) {
    std::vector<double> out;
    for (const Tracked& x : v) out.push_back(x.v);
    return out;
  };
  o.dims = r.dims;
  o.steps = r.steps;
  o.consistent = r.consistent;
  o.regular = r.regular;
  o.why = r.why;
  o.solution_rank = r.solution_rank;
  o.point = d(r.point);
  o.time = r.time.v;
  o.velocity = d(r.velocity);
  for (const auto& g : r.gauge) o.gauge.push_back(d(g));
  for (const auto& g : r.tangent) o.tangent.push_back(d(g));
  for (const auto& l : r.levels) {
    reference::PointwiseLevel<double> lv;
    lv.dim = l.dim;
    lv.chart = l.chart;
    for (const auto& c : l.added) {
      reference::PointwiseConstraint<double> k;
      k.solved_for = c.solved_for;
      for (const auto& [j, g] : c.gradient) k.gradient.emplace_back(j, g.v);
      k.rhs = c.rhs.v;
      lv.added.push_back(k);
    }
    for (const auto& p : l.pivots) lv.pivots.push_back({p.row, p.column, p.value.v});
    o.levels.push_back(lv);
  }
  o.order = r.order;
  o.checked_order = r.checked_order;
  o.moves = r.moves;
  o.plan = r.plan;
  return o;
}

/// Every number of the result is finite.
bool finite(const reference::PointwiseResult<double>& r) {
  const auto all = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  bool ok = all(r.point) && all(r.velocity) && std::isfinite(r.time);
  for (const auto& g : r.gauge) ok = ok && all(g);
  for (const auto& g : r.tangent) ok = ok && all(g);
  for (const auto& l : r.levels) {
    for (const auto& c : l.added) {
      ok = ok && std::isfinite(c.rhs);
      for (const auto& [j, g] : c.gradient) ok = ok && std::isfinite(g);
    }
    for (const auto& p : l.pivots) ok = ok && std::isfinite(p.value);
  }
  return ok;
}

/// The value of e at `at` in double; `bad` gets the first subexpression (post-order) that is not
/// finite while its operands are.
double value_of(const reference::expr::Expr& e, const std::vector<double>& at, const std::vector<std::string>& names,
                std::string& bad, std::unordered_map<const reference::expr::ExprNode*, double>& memo) {
  using reference::expr::ExprOp;
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  const auto sub = [&](const reference::expr::Expr& x) { return value_of(x, at, names, bad, memo); };
  double a = e->a ? sub(e->a) : 0, b = e->b ? sub(e->b) : 0, r = 0;
  switch (e->op) {
    case ExprOp::Number: r = e->value.convert_to<double>(); break;
    case ExprOp::Variable: r = at.at(e->var); break;
    case ExprOp::Add: r = a + b; break;
    case ExprOp::Sub: r = a - b; break;
    case ExprOp::Neg: r = -a; break;
    case ExprOp::Mul: r = a * b; break;
    case ExprOp::Div: r = a / b; break;
    case ExprOp::Pow: r = std::pow(a, static_cast<double>(e->exponent)); break;
    case ExprOp::Sin: r = std::sin(a); break;
    case ExprOp::Cos: r = std::cos(a); break;
    case ExprOp::Exp: r = std::exp(a); break;
    case ExprOp::Sqrt: r = std::sqrt(a); break;
  }
  if (!std::isfinite(r) && std::isfinite(a) && std::isfinite(b) && bad.empty())
    bad = reference::expr::to_text(e, names) + " = " +
          (std::isnan(r) ? std::string("NaN")
           : r > 0       ? std::string("inf")
                         : std::string("-inf"));
  memo.emplace(e.get(), r);
  return r;
}

}  // namespace

std::pair<std::string, std::string> nonfinite_formula(const reference::LagrangianSystem& sys,
                                                      const std::vector<double>& at) {
  const std::vector<std::string> names = sys.variable_names();
  std::vector<double> x(at);
  x.resize(2 * sys.n + 1, 0.0);
  using Found = std::pair<std::string, std::string>;
  const auto check = [&](const reference::expr::Expr& e, const std::string& path) -> Found {
    std::string bad;
    std::unordered_map<const reference::expr::ExprNode*, double> memo;
    const double v = value_of(e, x, names, bad, memo);
    if (std::isfinite(v)) return {};
    return {path, bad.empty() ? reference::expr::to_text(e, names) + " not finite" : bad};
  };
  Found found = check(sys.lagrangian, "/lagrangian/L");
  const reference::LagrangianDerivatives d = reference::derivatives(sys);
  for (std::size_t i = 0; i < sys.n && found.first.empty(); ++i) {
    found = check(d.dl_dq[i], "/lagrangian/L (its derivative in " + names[i] + ")");
    if (found.first.empty()) found = check(d.dl_dv[i], "/lagrangian/L (its derivative in " + names[sys.v(i)] + ")");
  }
  for (std::size_t a = 0; a < sys.m() && found.first.empty(); ++a)
    found = check(sys.constraints[a],
                  (sys.implicit ? "/implicit/equations/" : "/lagrangian/constraints/") + std::to_string(a));
  for (std::size_t i = 0; i < sys.forces.size() && found.first.empty(); ++i)
    found = check(sys.forces[i], "/lagrangian/forces/" + std::to_string(i));
  return found;
}

reference::PointwiseResult<double> pointwise_cad(const reference::LagrangianSystem& sys,
                                                 const std::vector<double>& start, const std::vector<bool>& fixed,
                                                 ToleranceDecisions& decide,
                                                 const std::vector<std::vector<std::size_t>>* plan) {
  std::vector<Tracked> x;
  for (double v : start) x.push_back(Tracked::input(v));
  reference::PointwiseResult<double> r = to_double(reference::pointwise_cad<Tracked>(
      sys, x, fixed, decide, [](const reference::Rational& q) { return Tracked::input(q.convert_to<double>()); }, 3, 60,
      plan));
  if (finite(r)) return r;
  // name the overflow: at the point reached (the given one if the CAD stopped before moving it)
  std::vector<double> at(r.point.begin(),
                         r.point.begin() + static_cast<std::ptrdiff_t>(std::min(r.point.size(), 2 * sys.n)));
  at.resize(2 * sys.n, 0.0);
  at.push_back(r.time);
  std::string where;
  const std::vector<std::string> names = sys.variable_names();
  for (std::size_t i = 0; i < 2 * sys.n + (sys.has_time ? 1 : 0); ++i) {
    std::ostringstream v;
    v.precision(17);
    v << at[i];
    where += (i ? ", " : "") + names[i] + " = " + v.str();
  }
  const auto [path, text] = nonfinite_formula(sys, at);
  if (!path.empty())
    throw std::range_error(path +
                           ": expected formulas whose values at the point are within double's range (the fast route "
                           "computes in double), found " +
                           text + " at " + where);
  throw std::range_error(
      std::string(sys.implicit ? "/implicit" : "/lagrangian") + ": expected a pointwise CAD within double's range at " +
      where + ", found a value that overflowed in the elimination (every formula is finite there): rescale the case");
}

Completion pointwise_completion(const reference::LagrangianSystem& sys) {
  return [&sys](const std::vector<double>& start) -> std::optional<std::vector<double>> {
    ToleranceDecisions dec;
    const reference::PointwiseResult<double> r = pointwise_cad(sys, start, std::vector<bool>(start.size(), false), dec);
    if (!r.consistent || !r.regular) return std::nullopt;
    std::vector<double> at(r.point.begin(), r.point.begin() + static_cast<long>(2 * sys.n));
    at.push_back(r.time);
    return at;
  };
}

}  // namespace dcad::fast
