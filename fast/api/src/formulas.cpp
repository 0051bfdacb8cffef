// The expression form's results as formulas on a chart (CONTRACT "Formulas for nonlinear results"):
// fast/chart.hpp's chart near the backend's point, its tower checked against the backend's dims.
#include "formulas.hpp"

#include "dcad/fast/chart.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"

namespace dcad::api {

namespace ex = reference::expr;

std::variant<Formulas, std::string> formulas(const io::LagrangianCase& c, const std::vector<long>& dims) {
  fast::Solution near;
  try {  // a point on (or near) M_c in double; its failure is no formulas, never a failed solve
    near = fast::solve_expression(c);
  } catch (const std::exception& e) {
    return std::string("the double route reaches no point of M_c: ") + e.what();
  }
  if (!near.consistent || !near.pointwise || !near.pointwise->regular) return std::string("the double route reaches no regular point of M_c");
  const std::size_t n = c.system.n;
  std::vector<double> at(near.pointwise->point.begin(), near.pointwise->point.begin() + static_cast<long>(2 * n));
  at.push_back(near.pointwise->time);
  fast::Chart ch;
  try {
    const std::vector<double> v(near.pointwise->velocity.begin(), near.pointwise->velocity.begin() + static_cast<long>(2 * n));
    ch = fast::chart_near(c.system, at, dims, near.pointwise->gauge.empty() ? &v : nullptr);
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
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

}  // namespace dcad::api
