// Reading the CONTRACT's expressions exactly: rational numbers (decimal text is exact: "0.1" is
// 1/10), parameters (exact values, substituted), variables, + - * / ^ (integer exponent), unary
// minus, parentheses, sin cos exp sqrt.  Errors are InputError naming the file, the JSON path and
// the column: "FILE: /lagrangian/L: column 7: expected …, found …".
#pragma once

#include "json_input.hpp"
#include "dcad/reference/nonlinear/expression.hpp"

#include <map>
#include <string>

namespace dcad::io {

/// `text` (found at `at`) as an expression over `variables` (name → index), with `parameters`
/// substituted.  Unknown names are bad input with the nearest known name suggested.
reference::expr::Expr parse_expression(const std::string& text, const std::map<std::string, std::size_t>& variables,
                                       const std::map<std::string, Rational>& parameters, const Where& at);

/// A name as the expressions use them: a letter or _, then letters, digits, _.
bool is_identifier(const std::string& s);

/// The function names of the expressions (not usable as names of variables or parameters).
const std::vector<std::string>& expression_functions();

}  // namespace dcad::io
