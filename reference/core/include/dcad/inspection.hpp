// What a linear Dirac structure is (CEF §4): `dcad inspect` by either twin.
#pragma once

#include "dcad/backend.hpp"
#include "dcad/truth.hpp"

#include <string>
#include <vector>

namespace dcad {

struct Inspection {
  Backend backend = Backend::reference;  ///< which twin answered (each twin's inspect sets it)
  Truth certified = unknown;  ///< yes: every decision exact, or certain in the fast sense (each route sets it)
  /// The answers.  Where fast could not decide one, it is the likely answer, named in `uncertain` with
  /// its evidence, and `certified` is unknown.
  bool valid = false;  ///< a Dirac structure (CEF Lemma 4.1)
  std::string why;     ///< why D is not a Dirac structure
  std::string file, name;
  std::size_t n = 0;
  std::string form;                                      ///< the case's `dirac` form
  long dim_e = -1, rank_omega = -1, dim_ker_omega = -1;  ///< dim E_D, rank ω_D, dim ker ω_D (Prop. 4.3)
  bool presymplectic = false, poisson = false;           ///< E_D = V; D ∩ (V ⊕ 0) = 0
  std::vector<std::string> uncertain;                    ///< outputs whose decision was uncertain (fast)
  std::vector<std::string> evidence;                     ///< the decisions behind them
};

}  // namespace dcad
