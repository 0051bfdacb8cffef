// The expression form's results as formulas on a chart (CONTRACT "Formulas for nonlinear results"):
// fast/chart.hpp's chart near the backend's point, its tower checked against the backend's dims; and
// the certified tier's balls at the given values on that chart.
#include "formulas.hpp"

#include "dcad/certified/zero_enclosure.hpp"
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"

#include <algorithm>
#include <cmath>

namespace dcad::api {

namespace ex = reference::expr;

std::variant<Charted, std::string> chart_for(const io::LagrangianCase& c, const std::vector<long>& dims,
                                             std::optional<long> solution_rank) {
  fast::Solution near;
  try {  // a point on (or near) M_c in double; its failure is no formulas, never a failed solve
    near = fast::solve_expression(c);
  } catch (const std::exception& e) {
    return std::string("the double route reaches no point of M_c: ") + e.what();
  }
  if (!near.consistent || !near.pointwise || !near.pointwise->regular)
    return std::string("the double route reaches no regular point of M_c");
  const std::size_t n = c.system.n;
  Charted out;
  // certain without the separation hypothesis only: no zero was assumed (the balls at the given values rest on it
  // where no exact route runs, as at an irrational angle)
  out.fast_certain = near.certified.yes() && near.decisions.float_tests == 0;
  out.point.assign(near.pointwise->point.begin(), near.pointwise->point.begin() + static_cast<long>(2 * n));
  out.point.push_back(near.pointwise->time);
  try {
    const std::vector<double> v(near.pointwise->velocity.begin(),
                                near.pointwise->velocity.begin() + static_cast<long>(2 * n));
    out.chart = fast::chart_near(c.system, out.point, dims, near.pointwise->gauge.empty() ? &v : nullptr,
                                 fast::pointwise_completion(c.system));
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  // the chart's pivots are decided in double: a last pivot below rounding (an integer kinetic matrix of height
  // 10^6 with determinant 2, cases/regression-pointwise-pulled-back.json) leaves a rate free that the result
  // determines — then its equations are another system's, and there are none
  if (solution_rank && static_cast<long>(out.chart.free.size()) != *solution_rank)
    return "the chart's pivots, decided in double, leave " + std::to_string(out.chart.free.size()) +
           " rate(s) free where this result's solution rank is " + std::to_string(*solution_rank);
  return out;
}

Formulas formulas_of(const io::LagrangianCase& c, const fast::Chart& ch) {
  const std::size_t n = c.system.n;
  const std::vector<std::string> names = c.system.variable_names();
  const auto text = [&](const ex::Expr& e) { return ex::to_text(e, names); };
  Formulas f;
  for (std::size_t k = 0; k < ch.levels.size(); ++k)
    for (const ex::Expr& e : ch.levels[k]) {
      f.constraints.push_back(text(e));
      f.levels.push_back(static_cast<long>(k + 1));
    }
  for (std::size_t i = 0; i < 2 * n; ++i) f.equations.emplace_back(names[i], text(ch.rates[i]));
  for (std::size_t i = 0; i < n; ++i) f.momenta.emplace_back("p_" + c.system.names[i], text(ch.momenta[i]));
  for (std::size_t i : ch.free) f.free.push_back(names[i]);
  for (std::size_t i : ch.kept) f.kept.push_back(names[i]);
  for (std::size_t i : ch.solved) f.solved.push_back(names[i]);
  for (const auto& v : ch.valid_where) {
    f.valid_where.push_back(text(v.formula));
    f.valid_where_why.push_back(v.what);
  }
  f.decided = "pivots and zero tests in double at a generic point of M_c (";
  for (std::size_t i = 0; i < ch.point.size(); ++i)
    f.decided += (i ? ", " : "") + names[i] + " = " + io::float_text(ch.point[i]);
  f.decided += "); the formulas are exact and their tower equals this result's dims";
  return f;
}

AtGiven at_given(const io::LagrangianCase& c, const Charted& charted, bool at_place, bool tower_certain) {
  const fast::Chart& ch = charted.chart;
  const std::size_t n = c.system.n, m = 2 * n + 1;  // variables (q, v, t)
  const std::vector<std::string> names = c.system.variable_names();
  certified::ZeroProblem z;
  z.equations = ch.constraints;
  z.gradients = ch.gradients;
  for (auto& g : z.gradients) g.push_back(ex::number(0));  // ∂/∂t: t is held
  z.given.assign(c.initial.begin(), c.initial.end());
  if (!z.given[2 * n]) z.given[2 * n] = reference::Rational(charted.point[2 * n]);  // the time is never solved for
  z.approx = charted.point;
  for (std::size_t i = 0; i < n; ++i)
    if (c.initial_p[i]) {  // a given momentum: ∂L/∂v_i = p_i
      z.equations.push_back(ex::sub(ch.momenta[i], ex::number(*c.initial_p[i])));
      std::vector<ex::Expr> g;
      for (std::size_t j = 0; j < m; ++j) g.push_back(j < 2 * n ? ex::diff(ch.momenta[i], j) : ex::number(0));
      z.gradients.push_back(g);
    }
  for (const auto& v : ch.valid_where) z.nonzero.push_back(v.formula);
  z.outputs = ch.rates;
  z.outputs.insert(z.outputs.end(), ch.momenta.begin(), ch.momenta.end());
  const std::size_t zeros = z.outputs.size();  // what the chart's elimination took as 0 on M_c, enclosed there too
  z.outputs.insert(z.outputs.end(), ch.vanishing.begin(), ch.vanishing.end());
  certified::ZeroEnclosure e = certified::enclose_zero(z);
  for (std::size_t k = 0; e.proved && k < ch.vanishing.size(); ++k)
    if (const certified::Enclosure& b = e.outputs[zeros + k]; !(std::abs(b.mid) <= b.rad)) {
      // a ball without 0: the chart's zero decision, made in double at a generic point, fails at the given values
      // (an entry of -4/5625 beside terms of 10^5, below the double route's drift tolerance): its equations are
      // another component's there, whatever the balls of its constraints say
      e.proved = false;
      e.why = "the chart took " + ex::to_text(ch.vanishing[k], names) +
              " as 0 on M_c (decided in double at a generic point); at the given values it is " +
              io::float_text(b.mid) + " +- " + io::float_text(b.rad) + ", not 0";
    }
  AtGiven a;
  a.proved = e.proved && tower_certain;
  a.why = !e.proved       ? e.why
          : tower_certain ? ""
                          : "the balls rest on a tower decided in double that is not certain (`note`)";
  if (!e.proved) {  // no proof: no balls (a failed box is no enclosure) and no claim
    a.claim = "not proved: " + e.why;
    return a;
  }
  for (std::size_t i : e.solved) {
    a.solved.push_back(names[i]);
    if (c.initial[i]) {  // moved: its ball does not contain the given value exactly
      const reference::Rational& g = *c.initial[i];
      const reference::Rational mid(e.values[i].mid), rad(e.values[i].rad);
      if (!(mid - rad <= g && g <= mid + rad)) a.moved.push_back(names[i]);
    }
  }
  for (std::size_t i = 0; i < 2 * n && i < e.values.size(); ++i)
    a.point.push_back({names[i], e.values[i].mid, e.values[i].rad});
  for (std::size_t i = 0; i < n; ++i)
    a.point.push_back({"p_" + c.system.names[i], e.outputs[2 * n + i].mid, e.outputs[2 * n + i].rad});
  for (std::size_t i = 0; i < 2 * n; ++i) a.velocity.push_back({names[i], e.outputs[i].mid, e.outputs[i].rad});
  std::string held;
  for (std::size_t i = 0; i < 2 * n; ++i)
    if (!c.initial[i] && std::find(e.solved.begin(), e.solved.end(), i) == e.solved.end())
      held += (held.empty() ? "" : ", ") + names[i];
  a.claim =
      "proved in Arb's balls (Krawczyk's test): the chart's constraint formulas (`formulas`) have exactly one zero in "
      "these balls with "
      "the given values held exactly" +
      std::string(a.moved.empty() ? "" : " (except those in `moved`, whose decimals miss M_c)") +
      (held.empty() ? "" : " and " + held + " (not given) held at the double route's values, exactly as printed") +
      "; the chart's conditions (`valid_where`) are nonzero there, what its elimination took as 0 has balls "
      "containing 0, and the velocity is the chart's equations of motion "
      "there; that this "
      "chart is M_c's near the given values rests on " +
      (at_place ? std::string("the tower decided exactly at the rational place (`place`), generic on the component")
                : std::string("the tower decided in double (`note`)"));
  return a;
}

}  // namespace dcad::api
