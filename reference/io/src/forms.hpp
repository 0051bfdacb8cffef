// The JSON forms from parsed JSON: one read of a file decides its form (problem.cpp).
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/io/dae_case.hpp"
#include "dcad/io/lagrangian_case.hpp"

#include <nlohmann/json.hpp>

namespace dcad::io {

/// The case holds `lagrangian` (or `parameters`): the expression form.
bool is_expression_case(const nlohmann::json& j);
LagrangianCase read_lagrangian_case(const nlohmann::json& j, const std::string& file);
/// The case holds `implicit`: φ(t, x, ẋ) = 0 affine in ẋ (CEF (1.6)), read as a LagrangianCase
/// whose system is `implicit` (lagrangian_system.hpp).
bool is_implicit_case(const nlohmann::json& j);
LagrangianCase read_implicit_case(const nlohmann::json& j, const std::string& file);
CaseFile read_case(const nlohmann::json& j, const std::string& file);
/// The case holds `dae`: the linear DAE form E ẋ = A x + f(t) (dae_case.hpp).
bool is_dae_case(const nlohmann::json& j);
DaeCase read_dae_case(const nlohmann::json& j, const std::string& file);

}  // namespace dcad::io
