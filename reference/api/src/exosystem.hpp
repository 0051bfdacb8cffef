// The sources' exosystem, shared by simulate's routes (internal to dcad::api): between breakpoints every
// SPICE source is an output of a linear system of 3 states — a ramp (σ, σ', 0), a sine (VO, Re z, Im z)
// with z = VA e^{(−θ+iω)(t−TD) + iφ}, or EXP's (c, e1, e2) decaying at −1/TAU1, −1/TAU2 — so sources and
// circuit together are one autonomous linear system.
#pragma once

#include "dcad/io/waveform.hpp"

#include <cmath>
#include <complex>
#include <vector>

namespace dcad::api {

/// The 3 exosystem states of `wf` for the substep (t, stop), read at the substep's midpoint and carried
/// back to t along its piece, so that a time that rounds onto the wrong side of a breakpoint (k·PER
/// computed as 0.99999…) cannot pick the neighbouring piece.
inline void exo_state_for(const io::Waveform& wf, double t, double stop, long double* w) {
  const double mid = stop > t ? (t + stop) / 2 : t;
  if (wf.is_sine()) {
    const double td = wf.p[3].convert_to<double>();
    wf.exo_state(t >= td || mid < td ? t : mid, w);
    if (mid >= td && t < td) {  // started within: back along the sine
      const std::complex<long double> z =
          std::complex<long double>(w[1], w[2]) *
          std::exp(std::complex<long double>(wf.decay(), wf.omega()) * static_cast<long double>(t - mid));
      w[1] = z.real();
      w[2] = z.imag();
    }
  } else if (wf.is_exp()) {  // read on the piece at mid, carried back along it: e_k(t) = e_k(mid) e^{rate_k (t − mid)}
    wf.exo_state(mid, w);
    w[1] *= std::exp(static_cast<long double>(wf.rate1()) * static_cast<long double>(t - mid));
    w[2] *= std::exp(static_cast<long double>(wf.rate2()) * static_cast<long double>(t - mid));
  } else {
    const double slope = wf.value(mid, 1);
    w[0] = wf.value(mid, 0) - slope * (mid - t);
    w[1] = slope;
    w[2] = 0;
  }
}

/// A sine's angular frequency and decay in long double from its exact FREQ and THETA (the double ones
/// are rounded: over 5 ns at 1 GHz ω's rounding moves the phase by 3e-15, which a long-double shadow
/// built on the same double ω cannot see).
inline long double omega_ld(const io::Waveform& wf) {
  return wf.is_sine() ? 2 * 3.14159265358979323846264338327950288L * wf.p[2].convert_to<long double>() : 0.0L;
}
inline long double decay_ld(const io::Waveform& wf) { return wf.is_sine() ? -wf.p[4].convert_to<long double>() : 0.0L; }

/// exo_state_for with a sine's state from omega_ld and decay_ld (the long-double shadow's exosystem).
inline void exo_state_for_ld(const io::Waveform& wf, double t, double stop, long double* w) {
  const double mid = stop > t ? (t + stop) / 2 : t;
  if (!wf.is_sine() || (t < wf.p[3].convert_to<double>() && mid < wf.p[3].convert_to<double>())) {
    exo_state_for(wf, t, stop, w);
    return;
  }
  const long double td = wf.p[3].convert_to<long double>(), pi = 3.14159265358979323846264338327950288L;
  const long double phi = wf.p[5].convert_to<long double>() * pi / 180;
  // started within the substep (t < TD <= mid): the state the sine would have at t, carried back from TD
  const std::complex<long double> z =
      wf.p[1].convert_to<long double>() *
      std::exp(std::complex<long double>(decay_ld(wf), omega_ld(wf)) * (static_cast<long double>(t) - td) +
               std::complex<long double>(0, phi));
  w[0] = wf.p[0].convert_to<long double>();
  w[1] = z.real();
  w[2] = z.imag();
}

/// σ and σ' from the 3 exosystem states of a source.
inline void exo_output(const io::Waveform& wf, const double* w, double& sigma, double& dsigma) {
  if (wf.is_exp()) {
    sigma = w[0] + w[1] + w[2];
    dsigma = wf.rate1() * w[1] + wf.rate2() * w[2];
  } else if (wf.is_sine()) {
    sigma = w[0] + w[2];
    dsigma = wf.omega() * w[1] + wf.decay() * w[2];
  } else {
    sigma = w[0];
    dsigma = w[1];
  }
}

/// d/dt of the 3 exosystem states of a source.
inline void exo_rate(const io::Waveform& wf, const double* w, double* dw) {
  if (wf.is_exp()) {
    dw[0] = 0;
    dw[1] = wf.rate1() * w[1];
    dw[2] = wf.rate2() * w[2];
  } else if (wf.is_sine()) {
    dw[0] = 0;
    dw[1] = wf.decay() * w[1] - wf.omega() * w[2];
    dw[2] = wf.omega() * w[1] + wf.decay() * w[2];
  } else {
    dw[0] = w[1];
    dw[1] = 0;
    dw[2] = 0;
  }
}

}  // namespace dcad::api
