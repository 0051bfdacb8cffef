// The expression form's results as formulas on a chart, and the certified balls at the given values
// computed on that chart (formulas.cpp).
#pragma once

#include "dcad/fast/chart.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "dcad/solution.hpp"

#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace dcad::api {

/// A chart of the case's CAD with the double route's completed point it was decided near.
struct Charted {
  fast::Chart chart;
  std::vector<double> point;  ///< (q, v, t): the double route's point of M_c at the given values
  bool fast_certain = false;  ///< every decision of that double route was proved (no zero assumed)
};

/// The chart near the double route's point, its tower required to have `dims` and `solution_rank` free rates (the
/// backend's); else why not.
std::variant<Charted, std::string> chart_for(const io::LagrangianCase& c, const std::vector<long>& dims,
                                             std::optional<long> solution_rank);

/// The chart as text in the case's names.
Formulas formulas_of(const io::LagrangianCase& c, const fast::Chart& ch);

/// The values at the case's given point in balls (certified/zero_enclosure.hpp): the chart's constraints
/// (and given momenta) solved by Krawczyk's test for as many coordinates as constraints, given values
/// held exactly where possible; the chart's equations of motion and momenta evaluated on the proved box.
/// `at_place`: the backend's tower was decided exactly at a rational place near the given values (else in
/// double); `tower_certain`: that tower is certain (exact, or fast's decisions all certain) — else the
/// balls are not `certified` however tight, as they rest on it.
AtGiven at_given(const io::LagrangianCase& c, const Charted& ch, bool at_place, bool tower_certain);

}  // namespace dcad::api
