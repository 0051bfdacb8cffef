// The reference's exact field: dcad::symbolic's (symbolic/rational.hpp), shared with the readers and fast's
// routes on formulas.
#pragma once

#include "dcad/symbolic/rational.hpp"

namespace dcad::reference {
using symbolic::parse_rational;
using symbolic::Rational;
using symbolic::to_string;
}  // namespace dcad::reference
