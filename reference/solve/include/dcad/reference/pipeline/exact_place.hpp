// Where the exact route runs when it cannot run at the case's own values (issue 29: exact at generic
// points).  dim M_k, the number of steps and the solution rank are generic (CEF §5: constant on the
// regular part of a component), so they can be computed exactly at a rational regular point of the
// same component near the given one.  Two kinds of such points:
//   - angles: a coordinate that occurs only in the arguments of sin and cos, integer-linearly
//     (sin φ, cos 2φ, sin(φ₁ − φ₂)), is translated, φ = φ₀ + φ', to an angle φ₀ = 2·atan(t) with t
//     rational, where cos φ₀ = (1 − t²)/(1 + t²) and sin φ₀ = 2t/(1 + t²) are rational; the
//     addition formulas rewrite sin(kφ + r) as sin(kφ₀)·cos(kφ' + r) + cos(kφ₀)·sin(kφ' + r).  A
//     translation of Q is a change of coordinates: the CAD in φ' at φ' = 0 is the CAD at φ₀.
//   - holonomic constraints h(t, q) = 0 (∂L/∂μ for a multiplier coordinate μ, CEF §6; constraints
//     without velocities) hold on M_c: the positions are put on them exactly — an h affine in a
//     coordinate is solved for it; on a quadric, from a rational point R of it (a small search) the
//     line through R and the given point meets the quadric again at a rational point near the given
//     one.  Everything else (velocities, multipliers, momenta) is the exact CAD's own completion.
// Nothing here is trusted: the exact CAD runs at the place and decides everything there.
#pragma once

#include "dcad/io/lagrangian_case.hpp"
#include "dcad/reference/nonlinear/lagrangian_system.hpp"

#include <optional>
#include <string>
#include <vector>

namespace dcad::reference::pipeline {

/// φ_q = 2·atan(tan_half) + 2π·turns + φ' (φ' the coordinate the exact route uses, 0 at the place;
/// whole turns change no sin or cos of an angle).
struct PlacedAngle {
  std::size_t q = 0;
  Rational tan_half, cos, sin;
  long turns = 0;
};

/// A rational place for the exact route.
struct ExactPlace {
  LagrangianSystem system;      ///< the case's system, its angles translated
  std::vector<Rational> start;  ///< (q, v, t) to start from (angles: 0 = the translated angle)
  std::vector<bool> fixed;      ///< values the CAD may not change (angles, landed positions, the time)
  std::vector<PlacedAngle> angles;
  std::vector<std::string> landed;  ///< the holonomic constraints the positions were put on, as text
  std::vector<std::size_t> loosen;  ///< given values typed short, fixed: freed if M_c has no point with them fixed
  std::string not_exact;            ///< a given value no rational place can move (why the exact route may still fail)
};

/// Coordinates that occur only integer-linearly inside arguments of sin and cos (angles).
std::vector<std::size_t> angle_coordinates(const LagrangianSystem& s);

/// The system with φ_j = φ₀_j + φ'_j for the given angles (φ'_j keeps φ_j's index and name).
LagrangianSystem translate_angles(const LagrangianSystem& s, const std::vector<PlacedAngle>& angles);

/// h(t, q) that vanish on M_c: ∂L/∂μ for coordinates μ without v_μ in L, the constraints or the
/// forces (the Euler–Lagrange equation of μ reads 0 = ∂L/∂μ), and constraints without velocities.
std::vector<expr::Expr> holonomic_constraints(const LagrangianSystem& s);

/// The exact value of e at x (variables as in LagrangianSystem: q, v, t); NotExactHere where a
/// function's value is irrational there.
Rational exact_value(const expr::Expr& e, const std::vector<Rational>& x);
/// ∂e/∂x_j at x for j < width, exactly, in one pass (jets of order 1 in the first `width` variables: a formula of 10⁶
/// characters is not differentiated symbolically once per column); NotExactHere where a value is irrational there.
/// `value`, if given, gets e's exact value at x (the same pass).
std::vector<Rational> exact_gradient(const expr::Expr& e, const std::vector<Rational>& x, std::size_t width,
                                     Rational* value = nullptr);

/// The best rational approximation of x with denominator ≤ max_den (continued fractions).
Rational simplest_near(const Rational& x, long max_den);

/// A place near `start` (the case's given values when `given`, else dcad's default point):
/// angles translated to rational points of the circle near their values (2·atan(value) for a default
/// point), other coordinates inside sin/cos/exp at a default point set to 0, positions put on the
/// holonomic constraints (coordinates not given move first).  Given values typed short (6 decimals
/// or fewer) stay fixed, freed only if M_c has no point with them (`loosen`); long ones (rounded
/// irrational values) become starting values (the caller bounds how far the CAD moves them).
/// nullopt (and `why`) where no such place is found.
std::optional<ExactPlace> exact_place(const io::LagrangianCase& c, const std::vector<Rational>& start, bool given,
                                      std::string& why);

}  // namespace dcad::reference::pipeline
