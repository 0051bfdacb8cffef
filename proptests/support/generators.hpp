// The generators of gen.hpp as rc::Gen<T> (issue 47), each value shown as the case file it is: a failing property
// prints its counterexample as one line "dcad case: {…}" (case_json.hpp) — the case, not the draws behind it — which
// `dcad cases freeze LOG NAME` turns into a golden case.  Shrinking works on the draws inside (rc::gen::exec).
//
//   const LinearSystem<Q> s = *systems();   // in a property: a random linear Dirac system (CEF §5)
#pragma once

#include "case_json.hpp"
#include "gen.hpp"

#include <rapidcheck.h>

#include <ostream>

namespace dcad::test {

/// any_system(max_n) as a generator: a linear Dirac system (D, E) with a planted structure (CEF §5).
inline rc::Gen<reference::LinearSystem<Q>> systems(Index max_n = 8) {
  return rc::gen::exec([max_n] { return any_system(max_n); });
}

/// any_constrained_system() as a generator: (N, Ω, E, M) with M = {a·x = b} (CEF §2).
inline rc::Gen<reference::ConstrainedSystem<Q>> constrained_systems() {
  return rc::gen::exec([] { return any_constrained_system(); });
}

}  // namespace dcad::test

namespace dcad::reference {

// RapidCheck shows a value by showValue, found by argument-dependent lookup in the value's namespace.
inline void showValue(const LinearSystem<test::Q>& s, std::ostream& os) { os << test::case_json(s); }
inline void showValue(const ConstrainedSystem<test::Q>& s, std::ostream& os) { os << test::case_json(s); }
inline void showValue(const PontryaginInput<test::Q>& p, std::ostream& os) { os << test::case_json(p); }

}  // namespace dcad::reference
