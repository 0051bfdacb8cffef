#include "source_balls.hpp"

#include "dcad/reference/arb_ball.hpp"

#include <acb.h>
#include <arb.h>
#include <arb_poly.h>
#include <flint/fmpq.h>

#include <algorithm>
#include <cmath>

namespace dcad::reference::pipeline {

namespace {

using io::Waveform;

using Arb = reference::arb::Ball;
using reference::arb::set_q;

using Acb = reference::arb::Owned<acb_struct, acb_init, acb_clear>;
using ArbPoly = reference::arb::Owned<arb_poly_struct, arb_poly_init, arb_poly_clear>;

/// ngspice's SIN (Waveform::value): VO + VA sin(φ) before TD; after it Im(VA s^order e^{s (t − TD) + iφ}) plus VO
/// at order 0, s = −θ + iω, ω = 2π FREQ, φ = PHASE·π/180.
void sin_ball(arb_t out, const Waveform& w, const Rational& t, long order, slong prec) {
  Arb va, phi, pi;
  set_q(va.v, w.p[1], prec);
  arb_const_pi(pi.v, prec);
  set_q(phi.v, Rational(w.p[5] / 180), prec);
  arb_mul(phi.v, phi.v, pi.v, prec);
  if (t < w.p[3]) {
    arb_zero(out);
    if (order > 0) return;
    arb_sin(out, phi.v, prec);
    arb_mul(out, out, va.v, prec);
  } else {
    Acb s, z, e;
    set_q(acb_realref(s.v), Rational(-w.p[4]), prec);
    set_q(acb_imagref(s.v), Rational(2 * w.p[2]), prec);
    arb_mul(acb_imagref(s.v), acb_imagref(s.v), pi.v, prec);
    Arb lag;
    set_q(lag.v, Rational(t - w.p[3]), prec);
    acb_mul_arb(e.v, s.v, lag.v, prec);
    arb_add(acb_imagref(e.v), acb_imagref(e.v), phi.v, prec);
    acb_exp(e.v, e.v, prec);
    acb_pow_ui(z.v, s.v, static_cast<ulong>(order), prec);
    acb_mul(z.v, z.v, e.v, prec);
    arb_mul(out, acb_imagref(z.v), va.v, prec);
  }
  if (order == 0) {
    Arb vo;
    set_q(vo.v, w.p[0], prec);
    arb_add(out, out, vo.v, prec);
  }
}

/// ngspice's EXP (Waveform::value, exp_state): the states (c, e1, e2) at t, σ^{(order)} = c [order = 0] +
/// e1 (−1/TAU1)^order + e2 (−1/TAU2)^order.  False for TAU 0.
bool exp_ball(arb_t out, const Waveform& w, const Rational& t, long order, slong prec) {
  if (w.p[3] == 0 || w.p[5] == 0) return false;
  arb_zero(out);
  Rational constant = w.p[0];
  const auto decayed = [&](const Rational& amplitude, const Rational& from, const Rational& tau) {
    Arb x, rate;
    set_q(x.v, Rational(-(t - from) / tau), prec);
    arb_exp(x.v, x.v, prec);
    set_q(rate.v, Rational(-1 / tau), prec);
    arb_pow_ui(rate.v, rate.v, static_cast<ulong>(order), prec);
    arb_mul(x.v, x.v, rate.v, prec);
    set_q(rate.v, amplitude, prec);
    arb_addmul(out, x.v, rate.v, prec);
  };
  if (!(t < w.p[2])) {
    decayed(Rational(w.p[0] - w.p[1]), w.p[2], w.p[3]);
    if (t < w.p[4])
      constant = w.p[1];
    else
      decayed(Rational(w.p[1] - w.p[0]), w.p[4], w.p[5]);
  }
  if (order == 0) {
    Arb c;
    set_q(c.v, constant, prec);
    arb_add(out, out, c.v, prec);
  }
  return true;
}

/// SFFM (Waveform::value): VO + VA sin(2π FC t + MDI sin(2π FS t)); σ^{(order)}(t) = order! · VA · [h^order] of
/// the series of sin(φ(t + h)), by Arb's power series (arb_poly_sin_series).
void sffm_ball(arb_t out, const Waveform& w, const Rational& t, long order, slong prec) {
  const slong n = order + 1;
  Arb pi, a, b;
  arb_const_pi(pi.v, prec);
  ArbPoly inner, outer;
  for (int which = 0; which < 2; ++which) {  // 2π F (t + h) for F = FS, then FC
    set_q(b.v, Rational(2 * w.p[which == 0 ? 4 : 2]), prec);
    arb_mul(b.v, b.v, pi.v, prec);
    set_q(a.v, t, prec);
    arb_mul(a.v, a.v, b.v, prec);
    arb_poly_fit_length(which == 0 ? inner.v : outer.v, 2);
    arb_poly_set_coeff_arb(which == 0 ? inner.v : outer.v, 0, a.v);
    arb_poly_set_coeff_arb(which == 0 ? inner.v : outer.v, 1, b.v);
  }
  arb_poly_sin_series(inner.v, inner.v, n, prec);
  set_q(a.v, w.p[3], prec);
  arb_poly_scalar_mul(inner.v, inner.v, a.v, prec);
  arb_poly_add(outer.v, outer.v, inner.v, prec);
  arb_poly_sin_series(outer.v, outer.v, n, prec);
  arb_poly_get_coeff_arb(out, outer.v, order);
  arb_fac_ui(a.v, static_cast<ulong>(order), prec);
  arb_mul(out, out, a.v, prec);
  set_q(a.v, w.p[1], prec);
  arb_mul(out, out, a.v, prec);
  if (order == 0) {
    set_q(a.v, w.p[0], prec);
    arb_add(out, out, a.v, prec);
  }
}

/// σ^{(order)}(t) as a ball; false where there is none here.
bool waveform_ball(arb_t out, const Waveform& w, const Rational& t, long order, slong prec) {
  switch (w.kind) {
    case Waveform::Kind::sin: sin_ball(out, w, t, order, prec); return true;
    case Waveform::Kind::sffm: sffm_ball(out, w, t, order, prec); return true;
    case Waveform::Kind::exp:
      if (w.period == 0) return exp_ball(out, w, t, order, prec);
      if (!(t < std::min(w.p[2], w.p[4]))) return false;  // gnucap's periodic EXP: its closed-form sum has no ball here
      set_q(out, order == 0 ? w.p[0] : Rational(0), prec);  // before TD1 and TD2 no period has started: IV (bm_exp.cc)
      return true;
    default: {  // DC, PULSE, PWL: exact
      Rational v, slope;
      w.exact_piece(t, v, slope);
      set_q(out, order == 0 ? v : order == 1 ? slope : Rational(0), prec);
      return true;
    }
  }
}

}  // namespace

std::optional<ConditionBall> condition_ball(const Matrix<Rational>& row, const std::vector<io::Waveform>& waveforms,
                                            long orders, const Rational& t, long bits) {
  const std::size_t m = waveforms.size();
  const auto prec = static_cast<slong>(bits);
  Arb sum, term, c;
  set_q(sum.v, row(0, 0), prec);
  for (std::size_t j = 0; j < m; ++j)
    for (long d = 0; d < orders; ++d) {
      const Rational& coefficient = row(0, 1 + static_cast<std::size_t>(d) * m + j);
      if (coefficient == 0) continue;
      if (!waveform_ball(term.v, waveforms[j], t, d, prec)) return std::nullopt;
      set_q(c.v, coefficient, prec);
      arb_addmul(sum.v, term.v, c.v, prec);
    }
  ConditionBall out;
  out.excludes_zero = arb_is_finite(sum.v) && !arb_contains_zero(sum.v);
  char* s = arb_get_str(sum.v, 15, 0);
  out.text = s;
  flint_free(s);
  return out;
}

}  // namespace dcad::reference::pipeline
