// certified::Ball in the reference pipeline (pipeline/numbers.hpp): lifted as the enclosure of the
// exact input; a term is shown when its ball excludes 0 (a ball that contains 0 is not a term).
#pragma once

#include "dcad/certified/ball.hpp"
#include "dcad/reference/pipeline/numbers.hpp"

#include <cmath>

namespace dcad::reference::pipeline {

template <>
struct Numbers<certified::Ball> {
  static constexpr bool exact = false;
  static certified::Ball lift(const Rational& q) { return certified::Ball::enclosing(q); }
  static bool shown(const certified::Ball& b) { return std::abs(b.mid()) > b.rad(); }
};

}  // namespace dcad::reference::pipeline
