// Shared exact algebra, now dcad::symbolic (dcad/symbolic/jet.hpp): the reference's names for it.
#pragma once

#include "dcad/reference/rational.hpp"
#include "dcad/symbolic/jet.hpp"

namespace dcad::reference {
using symbolic::cos;
using symbolic::exp;
using symbolic::Jet;
using symbolic::JetFunctions;
using symbolic::JetSpace;
using symbolic::NotExactHere;
using symbolic::pow_int;
using symbolic::sin;
using symbolic::sin_or_cos;
using symbolic::sqrt;
}  // namespace dcad::reference
