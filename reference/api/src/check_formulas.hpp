// `dcad check EQUATIONS DECK`: another tool's formulas against dcad's chart (check_formulas.cpp).
#pragma once

#include "dcad/api.hpp"

#include <nlohmann/json.hpp>

namespace dcad::api {

/// Compares `formulas` (the result's "formulas" object, read from `file`) with dcad's at `points`
/// points of M_c; adds to `out`'s compared keys and disagreements.  InputError for a malformed object.
void check_formulas(const std::string& file, const nlohmann::json& formulas, const io::Problem& p, std::size_t points,
                    Checked& out);

}  // namespace dcad::api
