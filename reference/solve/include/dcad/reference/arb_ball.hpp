// Arb's balls for the exact tiers where a value is transcendental (the reference's source conditions,
// src/source_balls.hpp; the certified tier's enclosures, certified/src/balls.hpp): RAII for Arb's types and
// an exact rational into a ball.  Include only from .cpp files that link FLINT::ARB.
#pragma once

#include "dcad/reference/rational.hpp"

#include <arb.h>
#include <flint/fmpq.h>

namespace dcad::reference::arb {

/// RAII for one of Arb's C types (arb_t, acb_t, arb_poly_t: arrays of one struct, not copyable); `v` is used as
/// the C type.
template <class S, void (*Init)(S*), void (*Clear)(S*)>
struct Owned {
  S v[1];
  Owned() { Init(v); }
  ~Owned() { Clear(v); }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
};
using Ball = Owned<arb_struct, arb_init, arb_clear>;

/// out = q, rounded to prec bits (exact where q's numerator and denominator fit).
inline void set_q(arb_t out, const Rational& q, slong prec) {
  fmpq_t f;
  fmpq_init(f);
  fmpq_set_mpq(f, q.backend().data());
  arb_set_fmpq(out, f, prec);
  fmpq_clear(f);
}

}  // namespace dcad::reference::arb
