// The certified tier's ball helpers (Arb): RAII for arb_t and arb_mat_t, exact rationals into balls, a
// ball as a double enclosure.  Shared by enclosure.cpp and zero_enclosure.cpp.
#pragma once

#include "dcad/certified/enclosure.hpp"
#include "dcad/reference/arb_ball.hpp"

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpq.h>

#include <cmath>

namespace dcad::certified {

namespace detail {

/// RAII for arb_t (dcad/reference/arb_ball.hpp) and arb_mat_t (the C types are arrays: not copyable).
using reference::arb::Ball;
using reference::arb::set_q;
struct BallMat {
  arb_mat_t m;
  BallMat(slong r, slong c) { arb_mat_init(m, r, c); }
  ~BallMat() { arb_mat_clear(m); }
  BallMat(const BallMat&) = delete;
  BallMat& operator=(const BallMat&) = delete;
  slong rows() const { return arb_mat_nrows(m); }
  slong cols() const { return arb_mat_ncols(m); }
  arb_ptr at(slong i, slong j) { return arb_mat_entry(m, i, j); }
};

inline Enclosure enclosure_of(const arb_t x) {
  Enclosure e;
  e.mid = arf_get_d(arb_midref(x), ARF_RND_NEAR);
  Ball d;
  arb_set_d(d.v, e.mid);
  arb_sub(d.v, x, d.v, ARF_PREC_EXACT);  // x − mid, exactly (mid is a double)
  arf_t u;
  arf_init(u);
  arb_get_abs_ubound_arf(u, d.v, 64);
  e.rad = arf_get_d(u, ARF_RND_UP);
  arf_clear(u);
  if (!arb_is_finite(x)) e.mid = std::nan(""), e.rad = HUGE_VAL;
  return e;
}

}  // namespace detail

}  // namespace dcad::certified
