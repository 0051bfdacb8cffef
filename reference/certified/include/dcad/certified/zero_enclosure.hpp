// A zero of formulas enclosed in balls (Arb): the certified values of the expression form at the
// user's own point where it is irrational (sin 0.7, rounded decimals of a point on a sphere), issue 29.
//
// Krawczyk's test (Krawczyk 1969; Moore, Kearfott & Cloud, "Introduction to Interval Analysis" §8.2):
// for F: Rᵐ → Rᴷ restricted to K unknowns s (the others held at exact values), a box X ∋ s̃ and any
// matrix Y,  K(X) = s̃ − Y F(s̃) + (I − Y F'(X)) (X − s̃)  contains every zero of F in X, and K(X) ⊂ int X
// proves that X holds exactly one zero (F'(X) evaluated in interval arithmetic).  Arb's balls are
// rigorous at every operation (sin, cos, exp, sqrt included), so the proof is a proof.  The outputs
// (the equations of motion, the momenta) are then formulas evaluated on the proved box; the
// conditions `nonzero` are proved nonzero there (a ball that excludes 0).
#pragma once

#include "dcad/certified/enclosure.hpp"
#include "dcad/reference/nonlinear/expression.hpp"

#include <optional>
#include <string>
#include <vector>

namespace dcad::certified {

/// F = 0 over variables 0…m−1 (m = approx.size()).
struct ZeroProblem {
  std::vector<reference::expr::Expr> equations;               ///< F, K of them
  std::vector<std::vector<reference::expr::Expr>> gradients;  ///< ∂F_k/∂x_j for every variable j < m
  std::vector<std::optional<Q>> given;                        ///< exact values to hold where possible (size m)
  std::vector<double> approx;                                 ///< a point near the zero (every variable)
  std::vector<reference::expr::Expr> nonzero;                 ///< must not vanish at the zero
  std::vector<reference::expr::Expr> outputs;                 ///< enclosed at the zero
};

struct ZeroEnclosure {
  bool proved = false;  ///< a unique zero in the box, every `nonzero` proved nonzero there
  std::string why;      ///< not proved: which test failed
  std::vector<std::size_t>
      solved;  ///< the K unknowns (the rest held: given values exactly, others at `approx` as exact doubles)
  bool given_moved = false;       ///< the given values alone admit no zero near approx: some of them are among `solved`
  std::vector<Enclosure> values;  ///< every variable
  std::vector<Enclosure> outputs;
};

/// The zero of p near p.approx, in balls of `precision` bits; never throws on non-finite values (not proved).
ZeroEnclosure enclose_zero(const ZeroProblem& p, long precision = 192);

}  // namespace dcad::certified
