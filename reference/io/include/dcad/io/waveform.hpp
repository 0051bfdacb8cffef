// Independent-source waveforms as ngspice defines them (ngspice manual §4.1): DC, SIN, PULSE, PWL.
// Parameters are read exactly; values and derivatives are evaluated in floating point (SIN is
// transcendental), PULSE and PWL piecewise linear.  Each waveform is, between its breakpoints, the
// output of a small linear system (an "exosystem"), which is how simulate integrates sources
// exactly: a ramp is (σ, σ') with σ'' = 0, a damped sine is a 2×2 rotation-and-decay block.
#pragma once

#include "dcad/reference/rational.hpp"

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace dcad::io {

using reference::Rational;

struct Waveform {
  enum class Kind { dc, sin, pulse, pwl };
  Kind kind = Kind::dc;
  std::vector<Rational> p;  ///< DC: {V}; SIN: VO VA FREQ TD THETA PHASE(deg); PULSE: V1 V2 TD TR TF PW PER; PWL: t1 v1 t2 v2 …
  std::string element;      ///< the source's name (V1, I.x1.i2)
  std::string text;         ///< as written, for messages

  bool constant() const;
  /// σ^{(order)}(t), right limit at breakpoints (t ≥ 0).  order ≥ 2 of PULSE/PWL is 0 (away from corners).
  double value(double t, int order = 0) const;
  /// σ^{(order)}(0) (right limit) exactly, when it is rational (DC, PULSE, PWL; SIN before its
  /// delay, or at a quarter-turn phase for order 0); nullopt when it involves π.
  std::optional<Rational> exact_at_zero(int order) const;
  /// The times in (0, tstop] where σ or a derivative is discontinuous (corners, SIN's TD), sorted.
  /// Throws std::invalid_argument beyond kMaxPeriods periods of a PULSE.
  std::vector<double> breakpoints(double tstop) const;
  /// The exosystem state (3 numbers) at t (right limit): ramp (σ, σ', 0); SIN (VO, Re z, Im z) with
  /// z = VA e^{(−θ+iω)(t−TD) + iφ} (0 before TD).
  void exo_state(double t, long double* w) const;
  /// DC, PULSE, PWL: the exact value and slope at the exact time t (right limit).  SIN: invalid_argument.
  void exact_piece(const Rational& t, Rational& v, Rational& slope) const;
  /// The first corner after t, exact (TD + k·PER + {0, TR, TR+PW, TR+PW+TF}, PWL's times, SIN's TD > 0);
  /// nullopt when there is none.  The exact counterpart of breakpoints().
  std::optional<Rational> next_corner(const Rational& t) const;
  bool is_sine() const { return kind == Kind::sin; }
  /// A time by which the waveform has shown every feature (delay, two periods, last PWL point).
  double horizon() const;
  static constexpr long kMaxPeriods = 1000000;
  /// SIN: −θ and ω (rad/s) of the exosystem block.
  double decay() const;
  double omega() const;
};

/// Parses the source specification after the nodes: "[DC] v", "SIN(...)", "PULSE(...)", "PWL(...)",
/// optionally preceded by "DC v" (ignored for the transient when a function follows, as ngspice
/// does).  `number` converts one token exactly.  Throws std::invalid_argument.
Waveform parse_waveform(const std::string& spec, const std::function<Rational(const std::string&)>& number);

}  // namespace dcad::io
