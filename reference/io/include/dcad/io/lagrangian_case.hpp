// Case files in the CONTRACT's expression form: `parameters`, `lagrangian` {coordinates, L,
// constraints, forces, time}, `initial` {name: value}.  Read exactly; every error names the file,
// the JSON path (and the column inside an expression), what was expected and what was found.
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/reference/nonlinear/lagrangian_system.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dcad::io {

struct LagrangianCase {
  std::string file, name, description;
  reference::LagrangianSystem system;
  std::map<std::string, Rational> parameters;
  /// `initial`: values of q, v (indices of LagrangianSystem), then p (2n + 1 + i for p_i: see
  /// `initial_p`) and the time (index 2n); absent values are empty.
  std::vector<std::optional<Rational>> initial;    ///< size 2n + 1: q, v, t
  std::vector<std::optional<Rational>> initial_p;  ///< size n
  bool has_initial = false;
  /// What the reader did that the result should say (the implicit form's lift to TQ), each naming file and JSON path.
  std::vector<std::string> warnings;
};

/// FILE is a .json case in the expression form (false if it is not, or cannot be read: read_case
/// then reports why).
bool is_expression_file(const std::string& file);
LagrangianCase read_lagrangian_case(const std::string& file);
/// A formula of another tool's result (`text`, found at FILE's JSON `path`) in the case's names (q,
/// v_*, the time) and parameters; InputError naming file, path and column.
reference::expr::Expr parse_case_formula(const LagrangianCase& c, const std::string& text, const std::string& file,
                                         const std::string& path);

}  // namespace dcad::io
