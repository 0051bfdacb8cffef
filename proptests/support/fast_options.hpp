// Options for the fast backend in properties: each case takes one of the two decision routes.
#pragma once

#include "dcad/fast/rank.hpp"

#include <rapidcheck.h>

namespace dcad::test {

/// qr_from = 0 puts every rank decision through pivoted QR first (the route of matrices above 48
/// rows and columns, issue 14); 48 is the default, where the small matrices of a property go by SVD.
inline fast::Options any_route_options() {
  fast::Options opt;
  opt.qr_from = *rc::gen::element(0, 48);
  RC_CLASSIFY(opt.qr_from == 0, "pivoted-QR route");
  return opt;
}

}  // namespace dcad::test
