// Shared exact algebra, now dcad::symbolic (dcad/symbolic/lagrangian_system.hpp): the reference's names for it.
#pragma once

#include "dcad/reference/rational.hpp"
#include "dcad/symbolic/lagrangian_system.hpp"

namespace dcad::reference {
namespace expr = symbolic::expr;
using symbolic::derivatives;
using symbolic::first_non_affine_constraint;
using symbolic::LagrangianDerivatives;
using symbolic::LagrangianSystem;
using symbolic::PointwiseNoPoint;
}  // namespace dcad::reference
