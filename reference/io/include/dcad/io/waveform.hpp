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
  enum class Kind { dc, sin, pulse, pwl, exp, sffm };
  Kind kind = Kind::dc;
  /// DC: {V}; SIN: VO VA FREQ TD THETA PHASE(deg); PULSE: V1 V2 TD TR TF PW PER; PWL: t1 v1 t2 v2 … (TD= added);
  /// EXP: V1 V2 TD1 TAU1 TD2 TAU2; SFFM: VO VA FC MDI FS (VO + VA sin(2π FC t + MDI sin(2π FS t)))
  std::vector<Rational> p;
  /// PWL's R= (ngspice): from this time point (one of the t_i) to the last the waveform repeats; none: holds
  std::optional<Rational> repeat;
  std::string element;  ///< the source's name (V1, I.x1.i2)
  std::string text;     ///< as written, for messages
  /// PULSE's 8th value NP (ngspice): the number of pulses, V1 after them; 0: unbounded.
  long pulses = 0;
  /// gnucap's EXP period= (> 0; 0: none): the EXP started again at every multiple of it and summed (bm_exp.cc), so
  /// σ stays continuous and its corners repeat; solve takes it (value(), breakpoints()), the exact flows refuse it
  /// (without_exact_flow: its exosystem grows by two states a period).
  Rational period = 0;
  /// How many values the deck gave: PULSE and SIN take ngspice's defaults for the rest from .tran's TSTEP
  /// and TSTOP (complete()); until then p may be shorter than its kind's.
  std::size_t given = 0;
  /// Read from gnucap's keyword form ("exp iv=0 pv=1 td1=1n tau1=5n td2=10n tau2=5n"): every value is as
  /// gnucap means it, so complete() adds none of SPICE's defaults (gnucap's TD1 = 0 is 0, not TSTEP).
  bool literal = false;
  /// What the specification holds that the transient does not use (an AC or distortion specification, a
  /// port's number and impedance, a DC value before a function), as written: the reader notes it.
  std::string ignored;

  /// ngspice's defaults and limits for what the deck left out (vsrcload.c): PULSE TD = 0, TR and TF = TSTEP
  /// (also for a TR or TF <= 0), PW = TSTOP (0 with five values), PER = TSTOP (also for PER <= 0); SIN FREQ
  /// = 1/TSTOP (also for 0).  std::invalid_argument when one is needed and .tran gives no TSTEP or TSTOP.
  void complete(const std::optional<Rational>& tstep, const std::optional<Rational>& tstop);
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
  /// DC, PULSE, PWL: the exact value and slope at the exact time t (right limit).  SIN, EXP: invalid_argument.
  void exact_piece(const Rational& t, Rational& v, Rational& slope) const;
  /// The first corner after t, exact (TD + k·PER + {0, TR, TR+PW, TR+PW+TF}, PWL's times, SIN's TD > 0);
  /// nullopt when there is none.  The exact counterpart of breakpoints().
  std::optional<Rational> next_corner(const Rational& t) const;
  bool is_sine() const { return kind == Kind::sin; }
  /// EXP: between its corners V + a e^{-(t-TD1)/TAU1} + b e^{-(t-TD2)/TAU2}, an exosystem (c, e1, e2) with
  /// rates (0, -e1/TAU1, -e2/TAU2); σ continuous, σ' jumps at TD1 and TD2.
  bool is_exp() const { return kind == Kind::exp; }
  /// SFFM (SPICE3, ngspice 39, Xyce): frequency modulated, no finite exosystem — solve decides source
  /// conditions on its values and derivatives (value()), simulate and check refuse it (without_exosystem).
  bool is_sffm() const { return kind == Kind::sffm; }
  /// The first time t >= 0 where σ itself jumps (gnucap's PULSE with RISE or FALL 0 — a PWL with two points
  /// at one time —, a repeated PWL whose part does not start where it ends; a PULSE cut by its PER is refused
  /// where a run reaches it, by breakpoints() and next_corner()): the
  /// transient is then a distribution there, which solve's tower and source conditions take (σ's right
  /// limits; a condition on a derivative of it is never decided "holds" by sampling) and the exact flows
  /// refuse (without_exact_flow).  nullopt when σ is continuous on t >= 0.
  std::optional<Rational> step_at() const;
  /// EXP and SIN: the jump of σ^{(order)} at the corner tb (one of breakpoints()), from their closed forms —
  /// EXP at TD1 (V1 − V2)(−1/TAU1)^order, at TD2 (V2 − V1)(−1/TAU2)^order (the other term is continuous), SIN
  /// at TD its right derivative (0 before); σ itself (order 0) does not jump.  nullopt for the piecewise-linear
  /// kinds, whose slopes read off either side are exact.
  std::optional<double> corner_jump(double tb, int order) const;
  /// A time by which the waveform has shown every feature (delay, two periods, last PWL point).
  double horizon() const;
  static constexpr long kMaxPeriods = 1000000;
  /// SIN: −θ and ω (rad/s) of the exosystem block.
  double decay() const;
  double omega() const;
  /// EXP: the rates −1/TAU1 and −1/TAU2 of its exosystem's states e1, e2.
  double rate1() const;
  double rate2() const;
};

/// gnucap's signal generator (apps/c_genrat.cc), set by `.gen[erator] KEY=VALUE …` and read by a
/// `generator(SCALE)` source as SCALE times its value; gnucap's defaults (a 1 ps rise from 0 to 1).
struct Generator {
  Rational freq = 0, ampl = 1, phase = 0, max = 1, min = 0, offset = 0, init = 0, rise = Rational(1, 1000000000000LL),
           fall = Rational(1, 1000000000000LL), delay = 0, width = 0, period = 0;
  /// Its value as PWL points t1 v1 t2 v2 … (gen() of c_genrat.cc with freq = 0: init up to delay, a ramp to
  /// max·ampl + offset over rise, held for width (0: for ever), a fall to min·ampl + offset, repeated from
  /// delay + period with `*repeat` set to that time).  std::invalid_argument where gnucap's value has no
  /// continuous piecewise-linear form (freq != 0: a sine times the pulse; a zero rise or fall; a period that
  /// cuts the pulse).
  std::vector<Rational> pwl(std::optional<Rational>* repeat) const;
  /// Sets KEY=VALUE with gnucap's abbreviations (f{requency} a{mplitude} p{hase} ma{x} mi{n} o{ffset}
  /// i{nitial} r{ise} f{all} d{elay} w{idth} pe{riod}); false for a key it does not have.
  bool set(const std::string& key, const Rational& value);
};

/// Parses the source specification after the nodes as ngspice does for a transient: "[DC] v", "DC=v",
/// "SIN(...)", "PULSE(...)", "PWL(...)" — with or without parentheses (SPICE3) — in any order with an AC
/// specification ("AC mag [phase]", "AC=mag"), DISTOF1/DISTOF2 and a port's "portnum N z0 Z pwr P freq F",
/// which the transient does not use (recorded in `ignored`); a DC value before a function is the operating
/// point's and is ignored as ngspice ignores it for .tran.  PULSE's and SIN's missing values wait for
/// complete().  `number` converts one token exactly.  Throws std::invalid_argument naming what is not read
/// (AM, TRNOISE, PAT …) and what to write instead.  EXP and PWL's TD= and R= are read as ngspice reads them;
/// gnucap's `generator(SCALE)` as the PWL of `generator` times SCALE.  `gnucap`: SIN, EXP and PULSE with values
/// by position take gnucap's order and defaults (PULSE's rise and fall 0, width and period forever: bm_pulse.cc),
/// as gnucap's keyword form always does, not SPICE's TSTEP and TSTOP.
Waveform parse_waveform(const std::string& spec, const std::function<Rational(const std::string&)>& number,
                        const Generator& generator = Generator{}, bool gnucap = false);

/// The first source the exact flows do not take, for simulate, check and the enclosures to refuse by name and
/// cause: "V1 (SFFM …), frequency modulated: no finite exosystem" or "V1 (pulse (0 1)), a step at t = 0";
/// nullopt when every source is continuous with a finite exosystem.
std::optional<std::string> without_exact_flow(const std::vector<Waveform>& waveforms);

}  // namespace dcad::io
