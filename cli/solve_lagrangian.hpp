// `dcad solve` on the expression form: the pointwise CAD (reference/pointwise.hpp) at the case's
// initial point (completed onto M_c) or at a generic point, exactly (reference), in double (fast),
// or exactly where the point's values are rational and in double otherwise (certified).
#pragma once

#include "dcad/io/lagrangian_case.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

namespace dcad::cli {

struct LagrangianReport {
  std::string backend, route;  ///< route: "pointwise exact" or "pointwise double"
  bool certified = true;
  std::vector<long> dims;
  long steps = 0;
  bool consistent = true;
  bool regular = true;
  std::string why;             ///< inconsistent or singular: the reason
  long solution_rank = -1;     ///< −1: not defined (inconsistent or singular)
  std::string time;
  std::vector<std::string> point, velocity;  ///< x = (q, v, p) and one ẋ at the point
  std::vector<std::vector<std::string>> gauge;
  struct Level {
    long dim = 0;
    std::vector<std::array<std::string, 2>> constraints;  ///< (solved for, tangent equation)
    std::vector<std::array<std::string, 3>> pivots;       ///< (row, column, value)
  };
  std::vector<Level> levels;  ///< levels[k]: M_{k+1}
  std::vector<std::string> first_constraints;  ///< M_1 as formulas: p = ∂L/∂v and the constraints
  long order = 0, checked_order = 0, moves = 0;
  double seconds = 0;
  std::string note;
};

/// The starting values of (q, v, t) (LagrangianSystem's indices): the given ones (`fixed`), the others
/// 0; without `initial`, a fixed pseudo-random point of small rationals (a generic point, the same on
/// every run), t = 0.
std::vector<io::Rational> start_point(const io::LagrangianCase& c, std::vector<bool>& fixed);

/// Throws io::InputError for given values that are not on M_c (or that the exact route cannot
/// complete to a rational point of M_c) and for a `reference` run at a point whose values are
/// irrational.
LagrangianReport solve_lagrangian(const io::LagrangianCase& c, const std::string& backend);

nlohmann::json to_json(const LagrangianReport& r, const io::LagrangianCase& c);
std::string to_text(const LagrangianReport& r, const io::LagrangianCase& c);

}  // namespace dcad::cli
