// Rigorous enclosures of the exact motion of a linear forced system — a circuit's (CEF §5 with sources,
// reference/forced.hpp) — at any times, in ball arithmetic (Arb, LGPL): the certified tier of
// `simulate --certified` and of `check WAVEFORM DECK` (CONTRACT "Checking a simulator's waveform").
//
// The data are exact: on M_c(t) the state is x = X0 u(t) + Bᵀ y with ẏ = A_y y + A_u u_ext(t) and
// ẋ = V_y y + V_u u_ext(t), u_ext = (1, σ, σ', …, σ^{(orders)}) the sources' jets (u: the first
// 1 + m·orders entries).  Between the sources' corners every source is the output of a 3-state linear
// exosystem (a ramp (σ, σ', 0), or a damped sine (VO, Re z, Im z), z = VA e^{(−θ+iω)(t−TD)+iφ}), so that
// z = [y; 1; w] obeys ż = G z and z(t) = exp(G (t − s)) z(s) — no truncation: the only errors are the
// balls' own, which Arb bounds.  The corners are exact rationals (TD + k·PER + …, PWL's times), the
// exosystem is reset from the waveform's exact formula at every corner (π, exp, sin and cos as balls),
// and at a corner σ' jumps: σ'' carries a Dirac delta of that weight, so y jumps by A_u,(σ'') Δσ'.
//
// Wrapping (a ball vector stepped through a rotation-like matrix widens geometrically): each evaluation
// steps from the previous one (a cached exp(G δ) for a repeated δ, else the Taylor series of exp(G δ) z
// with a rigorous remainder, else arb_mat_exp), and when the radius has grown beyond 2^(−precision/2)
// of the state it restarts from the piece's start with one exponential exp(G (t − s)).
#pragma once

#include "dcad/io/waveform.hpp"
#include "dcad/reference/matrix.hpp"
#include "dcad/reference/rational.hpp"

#include <memory>
#include <vector>

namespace dcad::certified {

using Q = reference::Rational;
using QM = reference::Matrix<Q>;

/// The exact value lies in [mid − rad, mid + rad]; rad (rounded up) covers mid's own rounding to double.
struct Enclosure {
  double mid = 0, rad = 0;
};

/// Exact data of the motion (see the header comment).  `balance`: powers of two D, the state carried
/// as D⁻¹ z (the similarity is exact; it keeps the balls' widening near that of the dimensionless twin);
/// empty: none.  Its size is that of z = [y; 1; w]: dm + 1 + 3·(sources).
struct ForcedMotionData {
  QM x0, basis, ay, au, vy, vu;
  long orders = 1;
  std::vector<io::Waveform> waveforms;
  std::vector<double> balance;
};

/// A linear functional of the motion at one time: Σ c·x_i + Σ c·ẋ_i + Σ c·u_ext_k.
struct Functional {
  enum class Of { x, xdot, u };
  struct Term {
    Of of;
    std::size_t index;
    Q coef;
  };
  std::vector<Term> terms;
};

class MotionEnclosure {
 public:
  /// From y(0) = y0 (exact, right after t = 0).  Throws std::invalid_argument when a corner of a source
  /// needs a derivative of a Dirac delta (as simulate refuses), or on inconsistent shapes.
  MotionEnclosure(const ForcedMotionData& data, const std::vector<Q>& y0, long precision = 256);
  ~MotionEnclosure();
  MotionEnclosure(const MotionEnclosure&) = delete;
  MotionEnclosure& operator=(const MotionEnclosure&) = delete;

  /// Moves to the exact time t ≥ time().
  void advance_to(const Q& t);
  const Q& time() const;
  /// Whether time() is a corner of some source, or 0 (then left values may differ; at 0 the left limit
  /// has the sources held at their values at 0, as before a transient).
  bool at_corner() const;
  /// The sources' corners in (0, until], exact, sorted; at most `limit` of them.
  std::vector<Q> corners(const Q& until, std::size_t limit = static_cast<std::size_t>(-1)) const;

  /// The functionals at time(): right values, or limits from the left (`left`; equal away from corners).
  std::vector<Enclosure> evaluate(const std::vector<Functional>& f, bool left = false) const;
  /// x (every variable) at time().
  std::vector<Enclosure> state(bool left = false) const;

  long restarts() const;      ///< evaluations recomputed from their piece's start (wrapping)
  long exponentials() const;  ///< arb_mat_exp calls

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The exact rational value of a double (every double is a dyadic rational).
Q rational_of(double t);

}  // namespace dcad::certified
