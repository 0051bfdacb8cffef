// Shared exact algebra, now dcad::symbolic (dcad/symbolic/polynomial.hpp): the reference's names for it.
#pragma once

#include "dcad/reference/rational.hpp"
#include "dcad/symbolic/polynomial.hpp"

namespace dcad::reference {
namespace expr = symbolic::expr;
}  // namespace dcad::reference
