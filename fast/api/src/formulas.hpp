// The expression form's results as formulas on a chart (formulas.cpp).
#pragma once

#include "dcad/io/lagrangian_case.hpp"
#include "dcad/solution.hpp"

#include <string>
#include <variant>
#include <vector>

namespace dcad::api {

/// The case's CAD as formulas, the chart's tower required to have `dims` (the backend's); else why not.
std::variant<Formulas, std::string> formulas(const io::LagrangianCase& c, const std::vector<long>& dims);

}  // namespace dcad::api
