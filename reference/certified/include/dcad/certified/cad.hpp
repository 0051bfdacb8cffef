// dcad::certified::constraint_tower — the CAD with certified decisions as a library call (issue 15; the
// route of `dcad solve --backend certified`, issue 14).  Every route runs the reference's own algorithm
// (reference::constraint_tower, CEF Remark 5.2) on another scalar, cheapest first:
//   1. SmallRational, then WideRational: the same exact arithmetic in 64-bit, then 128-bit words, or
//      reference::Overflow when a number does not fit;
//   2. Fmpq: the same exact arithmetic in FLINT's rationals (fmpq.hpp).
// Every route is the exact arithmetic of mpq_rational, so the discrete answers — dims of the M_k, c,
// consistency, solution rank — are the exact ones whichever route gave them (cascade.hpp).
#pragma once

#include "dcad/certified/cascade.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/small_rational.hpp"

#include <string>
#include <vector>

namespace dcad::certified {

using reference::Index;
using reference::Matrix;
using reference::Rational;

struct CertifiedTower {
  Tier tier = Tier::fmpq;
  int word_bits = 0;       ///< machine_words: 64, or 128 when a number outgrew 64 bits
  std::vector<long> dims;  ///< dim M_0 … M_c (−1 for an empty M_k)
  Index steps = 0;         ///< c
  bool consistent = true;
  Index solution_rank = 0;  ///< dim(ker ω_D ∩ T M_c)  [Thm 5.4(b)]
  std::string why;          ///< why the cheaper routes gave up ("" on the first)
};

namespace detail {

template <class S, class Lift>
Matrix<S> lift(const Matrix<Rational>& m, Lift f) {
  Matrix<S> out(m.rows(), m.cols());
  for (Index i = 0; i < m.rows(); ++i)
    for (Index j = 0; j < m.cols(); ++j) out(i, j) = f(m(i, j));
  return out;
}

/// The system and the initial equations over S, entry by entry (the Dirac structure by its canonical basis).
template <class S, class Lift>
CertifiedTower run(const reference::LinearSystem<Rational>& s, const Matrix<Rational>& initial, Tier tier, Lift f) {
  reference::LinearSystem<S> t;
  t.d.n = s.d.n;
  t.d.d = reference::Subspace<S>::span(lift<S>(s.d.d.basis(), f));
  t.hessian = lift<S>(s.hessian, f);
  for (const Rational& g : s.gradient) t.gradient.push_back(f(g));
  t.constant = f(s.constant);
  const reference::CadResult<S> r = reference::constraint_tower(t, lift<S>(initial, f));
  CertifiedTower out;
  out.tier = tier;
  for (const auto& st : r.tower) out.dims.push_back(st.dim());
  out.steps = r.steps;
  out.consistent = r.consistent;
  out.solution_rank = r.solution_rank;
  return out;
}

}  // namespace detail

/// The constraint tower of an exact linear system (CEF §5), decided by the cheapest route that can
/// (cascade.hpp).
inline CertifiedTower constraint_tower(const reference::LinearSystem<Rational>& s,
                                       const Matrix<Rational>& initial = Matrix<Rational>()) {
  std::string narrow;  // why 64-bit words gave up, if they did
  const Cascaded<CertifiedTower> c = cascade<CertifiedTower>(
      [&](int& bits) {
        try {
          bits = 64;
          return detail::run<reference::SmallRational>(
              s, initial, Tier::machine_words, [](const Rational& q) { return reference::SmallRational::from(q); });
        } catch (const reference::Overflow& e) {
          narrow = std::string("64-bit words: ") + e.what() + "; ";
          bits = 128;
          return detail::run<reference::WideRational>(
              s, initial, Tier::machine_words, [](const Rational& q) { return reference::WideRational::from(q); });
        }
      },
      [&] {
        return detail::run<reference::Fmpq>(s, initial, Tier::fmpq,
                                            [](const Rational& q) { return reference::Fmpq::from(q); });
      });
  CertifiedTower out = c.result;
  out.tier = c.tier;
  out.word_bits = c.word_bits;
  out.why = narrow;
  if (!c.overflow.empty()) out.why += "128-bit words: " + c.overflow;
  return out;
}

}  // namespace dcad::certified
