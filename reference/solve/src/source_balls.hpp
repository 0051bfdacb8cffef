// Rigorous balls (Arb) of a source condition's left side at an exact time: how the reference proves that a
// condition b + Σ c_{j,d} σ_j^{(d)}(t) = 0 fails (YM §4's affine constraints, V §3's moving M_k(t)).  The
// waveforms are transcendental (SIN, EXP, SFFM: ngspice manual §4.1), so exact rationals cannot evaluate
// them; a ball that excludes 0 is a proof that the exact value is not 0.
#pragma once

#include "dcad/io/waveform.hpp"
#include "dcad/reference/matrix.hpp"
#include "dcad/reference/rational.hpp"

#include <optional>
#include <string>
#include <vector>

namespace dcad::reference::pipeline {

/// The left side of a row [b | σ⁽⁰⁾ | σ⁽¹⁾ | …] (orders blocks of the waveforms' columns) at the exact time
/// t ≥ 0 (σ's right limits there, as Waveform::value takes them), enclosed at `bits` of working precision.
struct ConditionBall {
  bool excludes_zero = false;  ///< proved: the exact value is not 0
  std::string text;            ///< the ball, "[mid +/- rad]"
};
/// nullopt where a waveform has no ball evaluation here (gnucap's periodic EXP, an EXP with TAU 0).
std::optional<ConditionBall> condition_ball(const Matrix<Rational>& row, const std::vector<io::Waveform>& waveforms,
                                            long orders, const Rational& t, long bits);

}  // namespace dcad::reference::pipeline
