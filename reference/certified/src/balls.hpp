// The certified tier's ball helpers (Arb): RAII for arb_t and arb_mat_t, exact rationals into balls, a
// ball as a double enclosure.  Shared by enclosure.cpp and zero_enclosure.cpp.
#pragma once

#include "dcad/certified/enclosure.hpp"

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpq.h>

#include <cmath>

namespace dcad::certified {

namespace detail {

/// RAII for arb_t and arb_mat_t (the C types are arrays: not copyable).
struct Ball {
  arb_t v;
  Ball() { arb_init(v); }
  ~Ball() { arb_clear(v); }
  Ball(const Ball&) = delete;
  Ball& operator=(const Ball&) = delete;
};
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

inline void set_q(arb_t out, const Q& q, slong prec) {
  fmpq_t f;
  fmpq_init(f);
  fmpq_set_mpq(f, q.backend().data());
  arb_set_fmpq(out, f, prec);
  fmpq_clear(f);
}

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
