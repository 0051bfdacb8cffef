#include "dcad/fast/pointwise.hpp"

#include <cmath>
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
    if (certain.yes()) evidence = "decision " + std::to_string(probe->uncertain_at) + " reported uncertain (DecisionProbe)";
    certain = unknown;
  }
  return answer;
}

bool ToleranceDecisions::zero(const Tracked& x) {
  ++decisions;
  const double a = std::abs(x.v), tiny = 1e-300;
  if (a > nonzero_factor * x.e + tiny) return probed(false);
  if (x.v == 0 && x.e == 0) return probed(true);  // nothing was ever added to it
  if (a <= zero_factor * x.e + tiny && well_scaled && x.e <= 0x1p-26 * scale) return probed(true);
  if (probe) ++probe->made;  // an uncertain decision, counted as one
  if (certain.yes()) {
    std::ostringstream s;
    s << "a value " << x.v << " with a rounding-error bound " << x.e
      << (a > zero_factor * x.e + tiny ? " (between 8 and 64 times it: rounding or not?)"
          : !well_scaled              ? " on graded data (the step's nonzero data span more than 1/sqrt(eps)): zero or a small nonzero?"
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

}  // namespace

reference::PointwiseResult<double> pointwise_cad(const reference::LagrangianSystem& sys, const std::vector<double>& start,
                                                 const std::vector<bool>& fixed, ToleranceDecisions& decide,
                                                 const std::vector<std::vector<std::size_t>>* plan) {
  std::vector<Tracked> x;
  for (double v : start) x.push_back(Tracked::input(v));
  return to_double(reference::pointwise_cad<Tracked>(sys, x, fixed, decide,
                                                     [](const reference::Rational& q) { return Tracked::input(q.convert_to<double>()); }, 3, 60, plan));
}

}  // namespace dcad::fast
