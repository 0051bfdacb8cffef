// The CAD of a Lagrangian system given by formulas (CEF §5–6, YM §4, V §3 with the time) as formulas
// on a chart: the constraints of every M_k and the equations of motion on M_c, written in the case's
// names, with the conditions (`valid_where`) under which the chart and its pivots hold.  The
// CONTRACT's section "Formulas for nonlinear results".
//
// The route: in the coordinates (q, v) of M_1 ≅ {p = ∂L/∂v} (t a parameter), M_k = {Φ = 0} with Φ the
// constraints found so far, the first ones a(t, q)·v + b.  A curve on M_k solves the CAD's condition
// (pointwise/system.hpp) iff q̇ = v and, for u = (v̇, λ),
//     Σ_j ∂²L/∂v_i∂v_j v̇_j − Σ_a a_ai λ_a = ∂L/∂q_i + F_i − Σ_j ∂²L/∂v_i∂q_j v_j − ∂²L/∂v_i∂t   (ṗ − ∂L/∂q − F ∈ Δ°)
//     Σ_j ∂φ/∂v_j v̇_j = −Σ_j ∂φ/∂q_j v_j − ∂φ/∂t   for every φ in Φ                          (ẋ ∈ T M_k)
// (the tangency of p = ∂L/∂v is the first row; q̇ ∈ Δ_aff is a·v + b = 0 itself).  Gaussian elimination
// of this system on the expression DAG leaves rows 0 = h: the h independent of Φ at the point cut
// M_{k+1} out of M_k (CEF (5.2)); when none does, M_c = M_k and back substitution gives v̇ (the free
// unknowns, solution_rank many, set to 0).
//
// Decisions (which pivot, which entry vanishes on M_k, which candidate is new) are made in double at a
// generic point of M_c — a perturbed point moved onto M_c level by level (or by the caller's completion) — never at the
// user's point, where sin φ may vanish by accident.  The formulas themselves are exact: every number
// in them is a rational of the case.  The caller compares the dims found here with its backend's tower;
// a property (prop_chart) holds the formulas equal to the pointwise routes at points of M_c, exactly
// where the point is rational.  This is a fast route: the reference is the pointwise CAD.
#pragma once

#include "dcad/symbolic/calculus.hpp"
#include "dcad/symbolic/lagrangian_system.hpp"

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::fast {

/// The CAD as formulas over the variables of LagrangianSystem (q: 0…n−1, v: n…2n−1, t: 2n).
struct Chart {
  /// levels[k]: the constraints (formulas = 0) that cut M_{k+1} out of M_k; levels[0] are the given
  /// a·v + b (those independent at the point).  M_c = {every levels[k] formula = 0}, with p = ∂L/∂v.
  std::vector<std::vector<symbolic::expr::Expr>> levels;
  std::vector<long> dims;  ///< dim M_k, k = 0…c: 3n, then 2n − (the constraints so far)
  /// d/dt of q_i (= v_i) and of v_i, i = 0…n−1: the equations of motion on M_c.
  std::vector<symbolic::expr::Expr> rates;
  std::vector<std::size_t> free;  ///< velocities whose rate is free on M_c (solution_rank many): set to 0
  struct Condition {
    std::string what;              ///< "pivot of M_k's system: row …, column …" or "chart: solve for …"
    symbolic::expr::Expr formula;  ///< must not vanish
  };
  std::vector<Condition> valid_where;
  std::vector<std::size_t> kept, solved;  ///< M_c's chart: (q, v) coordinates kept and those the constraints solve for
  std::vector<double> point;              ///< the generic point of M_c (q, v, t) where the decisions were made
  std::vector<symbolic::expr::Expr> constraints;             ///< every level's, in order
  std::vector<std::vector<symbolic::expr::Expr>> gradients;  ///< ∂/∂(q, v) of each constraint
  std::vector<symbolic::expr::Expr> momenta;                 ///< p_i = ∂L/∂v_i
  /// What the elimination took as zero on M_k (entries, implied candidates): each must vanish at any
  /// point where the chart is used (chart_near checks the given point).
  std::vector<symbolic::expr::Expr> vanishing;
};

/// The chart could not be built here (the decisions at the generic point disagree, a value is not finite).
struct ChartFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// chart_at's point is not on a level: the constraints so far and the candidates that do not vanish there.
struct NotOnLevel : ChartFailure {
  using ChartFailure::ChartFailure;
  std::vector<symbolic::expr::Expr> constraints;
  std::vector<std::vector<symbolic::expr::Expr>> gradients;  ///< ∂/∂(q, v)
};

/// y (q, v) moved onto {constraints = 0} at time t by Gauss–Newton steps of least norm; false if 30
/// steps do not bring each |constraint_i| below tol × Σ_j |∂_j constraint_i · y_j| (its own terms), or, where Newton
/// stalls, within the rounding bound of its evaluation.
bool project_onto(const std::vector<symbolic::expr::Expr>& constraints,
                  const std::vector<std::vector<symbolic::expr::Expr>>& gradients, std::vector<double>& y, double t,
                  double tol, const std::vector<bool>* held = nullptr);

/// `start` ((q, v, t)) completed onto M_c with the coordinates `held` kept (the user's given values):
/// a chart of the formulas' tower decided at a generic point near `start` (its dims unchecked: the
/// caller's pointwise CAD recomputes the tower at the completed point), then least-norm Gauss–Newton on
/// its constraints over the other coordinates.  Empty where no chart or no such point is reached.  For
/// given values the pointwise CAD's own Newton moves do not settle (multiplier coordinates, index 3).
std::vector<double> complete_on_chart(const symbolic::LagrangianSystem& s, const std::vector<double>& start,
                                      const std::vector<bool>& held);

/// The CAD as formulas, decided at `generic` ((q, v, t), a point of M_c that is not special).
Chart chart_at(const symbolic::LagrangianSystem& s, const std::vector<double>& generic);

/// The chart near `near`, decided at a generic point of M_c: `near` perturbed (by a relative 1/10, then
/// less) and moved onto M_c level by level (NotOnLevel, project_onto); the chart's dims must be `dims`
/// (the backend's tower).  Never decided at `near` itself, where a coefficient may vanish by accident.
/// With `velocity` (d/dt of (q, v) at `near` by another route — the pointwise CAD in double — when the
/// solution is unique), the chart's rates at `near` must equal it to 1e-7 relative: two routes to one
/// motion, and a chart whose decisions do not hold at `near` is refused.
/// `complete`, if given, is one more way onto M_c tried last: a perturbed (q, v, t) in, a generic point of M_c
/// ((q, v, t)) out, or nothing (the caller's other route, e.g. the pointwise CAD's Newton on jets; fast does not
/// link the reference's).
using Completion = std::function<std::optional<std::vector<double>>(const std::vector<double>& start)>;
Chart chart_near(const symbolic::LagrangianSystem& s, const std::vector<double>& near, const std::vector<long>& dims,
                 const std::vector<double>* velocity = nullptr, const Completion& complete = {});

/// Compiled formulas: the DAG flattened once (shared subexpressions evaluated once), evaluated in double.
class Tape {
 public:
  explicit Tape(const std::vector<symbolic::expr::Expr>& outputs);
  /// out[k] = outputs[k] at vars (indices of the expressions' variables).
  void evaluate(const double* vars, double* out) const;
  /// The same, with jac[k·width + j] = ∂outputs[k]/∂vars[j] for j < width, by forward differentiation of the tape (no
  /// derivative formulas are built: their trees, one per column, cost more than the formula itself).
  void jacobian(const double* vars, std::size_t width, double* out, double* jac) const;
  std::size_t size() const { return ops_.size(); }

 private:
  struct Op {
    symbolic::expr::ExprOp op;
    std::size_t a = 0, b = 0;
    long k = 0;
    double c = 0;
  };
  std::vector<Op> ops_;
  std::vector<std::size_t> out_;
  mutable std::vector<double> val_;
};

/// The chart compiled: its formulas evaluated in double, and the projection onto M_c.
class ChartField {
 public:
  explicit ChartField(const Chart& c);
  std::size_t n() const { return n_; }
  /// d/dt (q, v) at (q, v) (2n values) and time t.
  void rates(const double* y, double t, double* dy) const;
  /// The largest |constraint| at (y, t), relative to the magnitude of y (at least 1); HUGE_VAL where one is not finite.
  double drift(const std::vector<double>& y, double t) const;
  /// y moved onto M_c by Gauss–Newton steps of least norm (the constraints' Jacobian has full row rank on
  /// a regular M_c); false if 20 steps do not bring the drift below `tol`.
  bool project(std::vector<double>& y, double t, double tol) const;
  /// p = ∂L/∂v at (y, t).
  std::vector<double> momenta(const std::vector<double>& y, double t) const;
  /// min over valid_where of |formula| relative to its value where the chart was built (1: as there);
  /// `which` (if given) gets the index of that condition.
  double margin(const std::vector<double>& y, double t, std::size_t* which = nullptr) const;

 private:
  std::size_t n_;
  Tape rates_, constraints_, jacobian_, momenta_, valid_;
  std::vector<double> valid0_;
  std::size_t k_;  ///< number of constraints
  mutable std::vector<double> buf_;
};

/// ∂e/∂x_i with shared subexpressions differentiated once (symbolic/calculus.hpp).
using Differentiator = symbolic::expr::Differentiator;

}  // namespace dcad::fast
