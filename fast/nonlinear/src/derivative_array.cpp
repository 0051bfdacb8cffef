// Campbell's derivative array for the implicit form (derivative_array.hpp: the definitions).
#include "dcad/fast/derivative_array.hpp"

#include "dcad/fast/tracked.hpp"
#include "dcad/symbolic/calculus.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace dcad::fast {

namespace {

namespace ex = symbolic::expr;

/// One equation of the array with its partial derivatives in the x^(j) (not t), symbolically.
struct ArrayEquation {
  ex::Expr e;
  std::vector<std::pair<std::size_t, ex::Expr>> grad;
  ex::Expr dt;  ///< ∂e/∂t
};

void variables_of(const ex::Expr& e, std::set<std::size_t>& out, std::unordered_set<const ex::ExprNode*>& seen) {
  if (!seen.insert(e.get()).second) return;
  if (e->op == ex::ExprOp::Variable) out.insert(e->var);
  if (e->a) variables_of(e->a, out, seen);
  if (e->b) variables_of(e->b, out, seen);
}

using symbolic::expr::tree_size;

ArrayEquation equation(const ex::Expr& e, std::size_t time) {
  ArrayEquation q{e, {}, ex::diff(e, time)};
  std::set<std::size_t> vars;
  std::unordered_set<const ex::ExprNode*> seen;
  variables_of(e, vars, seen);
  for (std::size_t v : vars)
    if (v != time) {
      ex::Expr g = ex::diff(e, v);
      if (!ex::is_number(g, 0)) q.grad.emplace_back(v, g);
    }
  return q;
}

/// d/dt e = ∂_t e + Σ_v ∂e/∂v · (v's next derivative), v's next derivative n indices on.
ex::Expr total_derivative(const ArrayEquation& q, std::size_t n, std::size_t time) {
  ex::Expr d = q.dt;
  for (const auto& [v, g] : q.grad) d = ex::add(d, ex::mul(g, ex::variable(v + n)));
  return d;
}

/// e at z in double; `memo` shares subexpressions across the array's equations and derivatives (they
/// share operands).  std::domain_error where a value is not finite (a division by 0, a root of a negative).
double value(const ex::Expr& e, const std::vector<double>& z, std::unordered_map<const ex::ExprNode*, double>& memo) {
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  const auto sub = [&](const ex::Expr& x) { return value(x, z, memo); };
  double r = 0;
  switch (e->op) {
    case ex::ExprOp::Number: r = e->value.convert_to<double>(); break;
    case ex::ExprOp::Variable: r = z.at(e->var); break;
    case ex::ExprOp::Add: r = sub(e->a) + sub(e->b); break;
    case ex::ExprOp::Sub: r = sub(e->a) - sub(e->b); break;
    case ex::ExprOp::Neg: r = -sub(e->a); break;
    case ex::ExprOp::Mul: r = sub(e->a) * sub(e->b); break;
    case ex::ExprOp::Div: r = sub(e->a) / sub(e->b); break;
    case ex::ExprOp::Pow: r = std::pow(sub(e->a), static_cast<double>(e->exponent)); break;
    case ex::ExprOp::Sin: r = std::sin(sub(e->a)); break;
    case ex::ExprOp::Cos: r = std::cos(sub(e->a)); break;
    case ex::ExprOp::Exp: r = std::exp(sub(e->a)); break;
    case ex::ExprOp::Sqrt: r = std::sqrt(sub(e->a)); break;
  }
  if (!std::isfinite(r))
    throw std::domain_error(
        "a value that is not finite in double (a division by 0, a root of a negative number, an overflow) at the "
        "point");
  memo.emplace(e.get(), r);
  return r;
}

/// e at z with a bound on the rounding of its evaluation in double (fast/tracked.hpp's forward error analysis; z's
/// coordinates are the point itself, exact): an identically zero bracket of terms of 10^16 rounds to about 2 in double
/// — its bound says so, where the bare value says "2".
Tracked rounded(const ex::Expr& e, const std::vector<double>& z,
                std::unordered_map<const ex::ExprNode*, Tracked>& memo) {
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  using F = symbolic::JetFunctions<Tracked>;
  const auto sub = [&](const ex::Expr& x) { return rounded(x, z, memo); };
  Tracked r;
  switch (e->op) {
    case ex::ExprOp::Number: r = Tracked::input(e->value.convert_to<double>()); break;
    case ex::ExprOp::Variable: r = Tracked(z.at(e->var), 0.0); break;
    case ex::ExprOp::Add: r = sub(e->a) + sub(e->b); break;
    case ex::ExprOp::Sub: r = sub(e->a) - sub(e->b); break;
    case ex::ExprOp::Neg: r = -sub(e->a); break;
    case ex::ExprOp::Mul: r = sub(e->a) * sub(e->b); break;
    case ex::ExprOp::Div: r = sub(e->a) / sub(e->b); break;
    case ex::ExprOp::Pow: {  // as the chart's Values evaluate it (repeated products)
      const Tracked a = sub(e->a);
      r = Tracked(1);
      for (long k = 0; k < std::abs(e->exponent); ++k) r = r * a;
      if (e->exponent < 0) r = Tracked(1) / r;
      break;
    }
    case ex::ExprOp::Sin: r = F::sin(sub(e->a)); break;
    case ex::ExprOp::Cos: r = F::cos(sub(e->a)); break;
    case ex::ExprOp::Exp: r = F::exp(sub(e->a)); break;
    case ex::ExprOp::Sqrt: r = F::sqrt(sub(e->a)); break;
  }
  if (!std::isfinite(r.v) || std::isnan(r.e)) r.e = HUGE_VAL;
  memo.emplace(e.get(), r);
  return r;
}

struct Values {
  Eigen::VectorXd f;
  Eigen::MatrixXd j;  ///< over the first `cols` variables
};

Values evaluate_array(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z, std::size_t cols) {
  Values v{Eigen::VectorXd::Zero(static_cast<Eigen::Index>(eqs.size())),
           Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(eqs.size()), static_cast<Eigen::Index>(cols))};
  std::unordered_map<const ex::ExprNode*, double> memo;
  for (std::size_t i = 0; i < eqs.size(); ++i) {
    v.f(static_cast<Eigen::Index>(i)) = value(eqs[i].e, z, memo);
    for (const auto& [var, g] : eqs[i].grad)
      if (var < cols) v.j(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(var)) = value(g, z, memo);
  }
  return v;
}

/// The structural rank of the array's Jacobian in the columns [from, cols): a maximum matching of equations to
/// variables through the partial derivatives that are not identically 0 (ArrayEquation::grad; an algebraic
/// equation has none in x'), by augmenting paths (Kuhn).  It bounds the rank at every point (rank.hpp,
/// proved_by_structure).
/// `skip`: columns left out as well (the given values, held).
int structural_rank(const std::vector<ArrayEquation>& eqs, std::size_t from, std::size_t cols,
                    const std::vector<bool>* skip = nullptr) {
  std::vector<long> owner(cols, -1);  // the equation matched to each column
  std::vector<std::size_t> seen(cols, 0);
  std::size_t round = 0;
  const auto augment = [&](auto&& self, std::size_t i) -> bool {
    for (const auto& [var, g] : eqs[i].grad) {
      if (var < from || var >= cols || seen[var] == round || (skip && (*skip)[var])) continue;
      seen[var] = round;
      if (owner[var] < 0 || self(self, static_cast<std::size_t>(owner[var]))) {
        owner[var] = static_cast<long>(i);
        return true;
      }
    }
    return false;
  };
  int rank = 0;
  for (std::size_t i = 0; i < eqs.size(); ++i) {
    ++round;
    if (augment(augment, i)) ++rank;
  }
  return rank;
}

/// Whether every gradient of the array is a constant (F_k affine with constant coefficients): Gauss–Newton's least
/// residual is then the least-squares residual of one linear system.
bool constant_gradients(const std::vector<ArrayEquation>& eqs) {
  for (const ArrayEquation& q : eqs)
    for (const auto& [v, g] : q.grad)
      if (!ex::is_number(g)) return false;
  return true;
}

/// Equation i of the array at z, alone (a probe of one row need not evaluate the array and its Jacobian).
double row_value(const std::vector<ArrayEquation>& eqs, std::size_t i, const std::vector<double>& z) {
  std::unordered_map<const ex::ExprNode*, double> memo;
  return value(eqs[i].e, z, memo);
}

/// The array's values at z, without its Jacobian.
Eigen::VectorXd array_values(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z) {
  Eigen::VectorXd f(static_cast<Eigen::Index>(eqs.size()));
  std::unordered_map<const ex::ExprNode*, double> memo;
  for (std::size_t i = 0; i < eqs.size(); ++i) f(static_cast<Eigen::Index>(i)) = value(eqs[i].e, z, memo);
  return f;
}

/// Rows, then columns, scaled by powers of two to a largest entry in [1, 2): exact in binary, and no
/// rank, left null space of the derivative columns or rank of the x-gradients on it changes (row scaling
/// D maps Z to D⁻¹Z; column scaling multiplies columns), while the array's graded rows (higher
/// derivatives carry products of the multipliers and the data) no longer set one scale for all.
/// Returns the column factors C (J becomes D J C: a kernel vector y of it is C y of J's).
/// `rs` gets the row factors D.
Eigen::VectorXd equilibrate(Eigen::MatrixXd& j, Eigen::VectorXd& rs) {
  Eigen::VectorXd cs = Eigen::VectorXd::Ones(j.cols());
  rs = Eigen::VectorXd::Ones(j.rows());
  for (Eigen::Index r = 0; r < j.rows(); ++r) {
    const double m = j.row(r).cwiseAbs().maxCoeff();
    if (m > 0 && std::isfinite(m)) {
      rs(r) = std::ldexp(1.0, -std::ilogb(m));
      j.row(r) *= rs(r);
    }
  }
  for (Eigen::Index c = 0; c < j.cols(); ++c) {
    const double m = j.col(c).cwiseAbs().maxCoeff();
    if (m > 0 && std::isfinite(m)) {
      cs(c) = std::ldexp(1.0, -std::ilogb(m));
      j.col(c) *= cs(c);
    }
  }
  return cs;
}

std::string text(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

/// The first entry of the array's Jacobian in the columns [from, cols) whose nonzero value at z is not resolved from
/// its own rounding (|value| ≤ 64 × its forward error bound, fast/tracked.hpp) although it is not identically 0 — ((t +
/// 10^6)² − t² − 2·10^6 t − 10^12 + t − r) v_x at t = r is exactly 0 there and 1/8192 in double — as "entry (i, j)", or
/// "". The structural rank (proved_by_structure) assumes computed entries that are their values up to rounding of the
/// data; a cancellation within one entry voids that, and any rank decided on it.
std::string cancelled_entry(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z, std::size_t from,
                            std::size_t cols) {
  std::unordered_map<const ex::ExprNode*, Tracked> memo;
  for (std::size_t i = 0; i < eqs.size(); ++i)
    for (const auto& [var, g] : eqs[i].grad) {
      if (var < from || var >= cols || ex::is_number(g)) continue;
      const Tracked t = rounded(g, z, memo);
      if (t.v != 0 && std::abs(t.v) <= 64 * t.e)  // a nonzero that may be rounding alone (a computed 0 is a zero)
        return "entry (" + std::to_string(i) + ", " + std::to_string(var) + ") = " + text(t.v) + " ± " + text(64 * t.e);
    }
  return "";
}

/// Gauss–Newton with minimum-norm steps on the free columns: the residual it ends at, and its scale.
struct Newton {
  double residual = 0, scale = 1;
  double relative =
      HUGE_VAL;  ///< at the best iterate: max_i |F_i| / Σ_j |∂F_i/∂z_j · z_j| (each row against its own terms)
  bool zero() const { return residual <= 1e-12 * scale || relative <= 1e-10; }
};
/// `ceiling`: the largest scale a residual may be judged against (2^10 × the problem's own, at the case's
/// point): a diverging iterate, or a start that is an earlier level's wild zero, never excuses one.
Newton gauss_newton(const std::vector<ArrayEquation>& eqs, std::vector<double>& z, std::size_t cols,
                    const std::vector<bool>& held, double ceiling) {
  Newton out;
  std::vector<Eigen::Index> free;
  for (std::size_t c = 0; c < cols; ++c)
    if (!held[c]) free.push_back(static_cast<Eigen::Index>(c));
  double best = HUGE_VAL, best_scale = 1;
  std::vector<double> best_z = z;
  for (int it = 0; it < 60; ++it) {
    const Values v = evaluate_array(eqs, z, cols);
    double zmax = 1;
    for (std::size_t c = 0; c < cols; ++c) zmax = std::max(zmax, std::abs(z[c]));
    // the scale a residual is judged against: the iterate's, but never above the ceiling — a diverging
    // iterate (z ~ 1e12, |J| ~ 1e13) excused a residual of 1.6e13 against 2.6e26, and a pulled-back
    // index-3 system's M_c = {0} became a curve of free velocities, certified (prop_dae's
    // Implicit.PulledBackLinearDaeHasThePlantedTower)
    out.scale = std::min(std::max(1.0, v.j.size() ? v.j.cwiseAbs().maxCoeff() : 0.0) * zmax, ceiling);
    const double r = v.f.size() ? v.f.cwiseAbs().maxCoeff() : 0.0;
    if (r < best) best = r, best_z = z, best_scale = out.scale;
    if (r <= 1e-15 * out.scale || free.empty()) break;
    Eigen::MatrixXd jf(v.j.rows(), static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) jf.col(static_cast<Eigen::Index>(k)) = v.j.col(free[k]);
    // columns scaled by powers of two first: a pF coefficient beside a 1000 is not a rank deficiency; a
    // column at rounding level (2 x1 at x1 = 2e-16) is noise, not data: scaled up it took steps of 1e12
    Eigen::VectorXd colscale = Eigen::VectorXd::Ones(jf.cols());
    const double jmax = jf.size() ? jf.cwiseAbs().maxCoeff() : 0.0;
    for (Eigen::Index c = 0; c < jf.cols(); ++c) {
      const double m = jf.col(c).cwiseAbs().maxCoeff();
      if (m > 1e-13 * jmax && std::isfinite(m)) {
        colscale(c) = std::ldexp(1.0, -std::ilogb(m));
        jf.col(c) *= colscale(c);
      }
    }
    const Eigen::VectorXd step = colscale.asDiagonal() * jf.completeOrthogonalDecomposition().solve(-v.f);
    if (!step.allFinite()) break;
    for (std::size_t k = 0; k < free.size(); ++k)
      z[static_cast<std::size_t>(free[k])] += step(static_cast<Eigen::Index>(k));
    if ((step.size() ? step.cwiseAbs().maxCoeff() : 0.0) <= 1e-16 * zmax &&
        r > 0) {  // a stationary point of the residual
      const Values w = evaluate_array(eqs, z, cols);
      const double r2 = w.f.size() ? w.f.cwiseAbs().maxCoeff() : 0.0;
      if (r2 < best) best = r2, best_z = z, best_scale = out.scale;
      break;
    }
  }
  z = best_z;  // with the scale where it was reached (a diverged iterate's huge scale would excuse any residual)
  out.residual = best;
  out.scale = best_scale;
  {  // graded rows (2.2 pF · e'' beside 1000 cos 1000 t): rounding there is relative to the row's own terms
    const Values v = evaluate_array(eqs, z, cols);
    out.relative = 0;
    for (Eigen::Index i = 0; i < v.f.size(); ++i) {
      double terms = 0;
      for (std::size_t c = 0; c < cols; ++c) terms += std::abs(v.j(i, static_cast<Eigen::Index>(c)) * z[c]);
      out.relative = std::max(out.relative, terms > 0 ? std::abs(v.f(i)) / terms : (v.f(i) == 0 ? 0.0 : HUGE_VAL));
    }
  }
  return out;
}

/// F_k affine with constant coefficients, F(z) = A z + b(t), with the columns `held` fixed, decided on A's free
/// columns scaled by powers of two (a column of 2^-60 beside 1 is data, which Gauss–Newton's noise cut drops): a zero
/// by a least-squares step on the decided rank or on every column (v_x + v_y/2^60 beside v_x: a zero at v_y = −2^120
/// that the decided rank truncates), taken by Gauss–Newton's test; "empty" where a combination of the rows that no
/// free column moves stays off 0 by more than the rounding bound of its terms (`rounded`) — also against a zero that
/// Gauss–Newton's relative test took (x = 2^40 beside x = 2^40 + 1/16) — certain only with A's rank certain;
/// undecided otherwise, with the reason.
struct AffineVerdict {
  enum Kind { zero, empty, undecided } kind = undecided;
  Newton newton;          ///< zero: at the zero
  std::string evidence;   ///< undecided (or a zero in double that a combination contradicts): why
  double off = 0;         ///< empty: the largest combination's value beyond its bound (their ratio)
  bool unproved = false;  ///< a combination within its rounding bound but not 0: a zero in double, not proved one
};

/// The largest ratio of a combination's value (the columns of `n`, over rows scaled by `rs`) to the rounding bound of
/// its terms at w: beyond 1, F_k has no zero (A's rank being what `n` says).  `nonzero`: whether a value is not 0.
double off_by(const std::vector<ArrayEquation>& eqs, const std::vector<double>& w, std::size_t cols,
              const Eigen::MatrixXd& n, const Eigen::VectorXd& rs, double nonzero_factor, bool& nonzero) {
  const Values at = evaluate_array(eqs, w, cols);
  std::unordered_map<const ex::ExprNode*, Tracked> memo;
  Eigen::VectorXd bound(at.f.size());
  for (Eigen::Index i = 0; i < at.f.size(); ++i) {
    double terms = 0;  // the coefficients' own rounding (numbers of the formulas), at w
    for (std::size_t c = 0; c < cols; ++c) terms += std::abs(at.j(i, static_cast<Eigen::Index>(c)) * w[c]);
    const double err = rounded(eqs[static_cast<std::size_t>(i)].e, w, memo).e;
    bound(i) = rs(i) * (4 * err + 0x1p-48 * (terms + std::abs(at.f(i))));
  }
  // (and the combinations' own rounding: a coefficient of 5.6e-17 in place of 0 times a row's 2e-47 was "off" by
  // 1.3e14 times the rows' bounds, on a consistent linear system whose zero Gauss–Newton left at 1e-47 — Dae.
  // LinearFormEqualsImplicitFormOnLinearData; √ε of the rows' values, as for a rank decided certain)
  const Eigen::VectorXd scaled = rs.asDiagonal() * at.f, value = n.transpose() * scaled,
                        slack = (n.cwiseAbs().transpose() * bound).array() + nonzero_factor * scaled.cwiseAbs().sum();
  double off = 0;
  for (Eigen::Index k = 0; k < value.size(); ++k)
    if (std::abs(value(k)) > slack(k)) off = std::max(off, std::abs(value(k)) / slack(k));
  // not 0: beyond the combinations' own rounding (a consistent system's zero left at 1e-47 is no contradiction)
  nonzero = value.size() > 0 && value.cwiseAbs().maxCoeff() > nonzero_factor * scaled.cwiseAbs().sum();
  return off;
}

AffineVerdict affine_verdict(const std::vector<ArrayEquation>& eqs, std::vector<double>& z, std::size_t cols,
                             const std::vector<bool>& held, double ceiling, const Options& opt) {
  AffineVerdict out;
  std::vector<Eigen::Index> free;
  for (std::size_t c = 0; c < cols; ++c)
    if (!held[c]) free.push_back(static_cast<Eigen::Index>(c));
  const Values v = evaluate_array(eqs, z, cols);
  Eigen::MatrixXd a(v.j.rows(), static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k) a.col(static_cast<Eigen::Index>(k)) = v.j.col(free[k]);
  Eigen::VectorXd rs;
  const Eigen::VectorXd cs = equilibrate(a, rs);
  const RankRevealing rr(a, -1, opt, false);  // the steps' factorization; the decision is counted where it decides
  const Eigen::VectorXd rhs = -(rs.asDiagonal() * v.f);
  // Gaussian elimination on every column besides: its row operations on exact binary data are exact (v_x + v_y/2^60
  // less v_x leaves v_y/2^60, which a Householder reflection drowns in its rounding of 1e-16)
  Eigen::FullPivLU<Eigen::MatrixXd> full(a);
  full.setThreshold(0.0);
  // the least-residual point (the decided rank's step: its part in A's range at rounding level, so the combinations
  // are not sums of large cancelling parts), then a zero if a step reaches one
  std::vector<double> least = z;
  bool first = true;
  for (const Eigen::VectorXd& step :
       {Eigen::VectorXd(cs.asDiagonal() * rr.solve_range(rhs)), Eigen::VectorXd(cs.asDiagonal() * full.solve(rhs))}) {
    std::vector<double> w = z;
    if (step.allFinite())
      for (std::size_t k = 0; k < free.size(); ++k)
        w[static_cast<std::size_t>(free[k])] += step(static_cast<Eigen::Index>(k));
    const Newton nw = gauss_newton(eqs, w, cols, held, ceiling);
    if (first || nw.zero()) least = w, first = false;
    if (nw.zero()) {
      out.kind = AffineVerdict::zero;
      out.newton = nw;
      break;
    }
  }
  bool nonzero = false;
  const double off =
      rr.rank() < a.rows() ? off_by(eqs, least, cols, rr.corange(), rs, opt.nonzero_factor, nonzero) : 0.0;
  if (off == 0) {
    if (out.kind == AffineVerdict::zero) z = least;
    // within the rounding of its terms but not 0: x − 1 beside x − 1 − y/2^60 and y = 1 (off by 2^-60) is no zero
    out.unproved = nonzero;
    out.evidence = "each combination of its rows that no free coordinate moves is within the rounding of its terms" +
                   std::string(nonzero ? ", but not 0: a contradiction below double's resolution is not excluded" : "");
    return out;
  }
  // a combination off 0 beyond its rounding: no zero, if A's rank is what the combinations assume
  const RankDecision d = proved_by_structure(decide_rank(a, -1, opt), structural_rank(eqs, 0, cols, &held));
  if (d.certain.yes() && d.rank == rr.rank()) {
    out.kind = AffineVerdict::empty;
    out.off = off;
    return out;
  }
  out.off = off;  // (kind zero or undecided: a contradiction the rank does not settle)
  out.evidence = "a combination of its rows that no free coordinate moves is " + text(off) +
                 " times its rounding bound off 0, but the rank of its Jacobian in the free coordinates is not "
                 "certain: " +
                 d.describe();
  if (out.kind == AffineVerdict::zero) z = least;
  return out;
}

void withdraw(DerivativeArrayResult& out, const std::string& why) {
  if (out.certain.yes()) out.evidence = why;
  out.certain = unknown;
}

/// The array's level: F_k over its first `cols` columns, and gauss_newton's ceiling.
struct Level {
  std::size_t k, cols;
  double ceiling;
};

/// Gauss–Newton found no zero of F_k near the point (`nw`), or F_k is affine and its zero has a residual: a zero after
/// all (true: `z` and `nw` at it), given values that F_k has a zero without (symbolic::PointwiseNoPoint), or M_{k+1}
/// empty in `out` — certain only where F_k is affine and affine_verdict proves it with and without the given values
/// (Gauss–Newton from one start proves no emptiness, and its least residual none where it dropped a column or the
/// t-only terms round; its relative test no zero where 2^40 beside 2^40 + 1/16 is a contradiction).
bool zero_after_all(const symbolic::LagrangianSystem& sys, const std::vector<ArrayEquation>& eqs,
                    std::vector<double>& z, const std::vector<double>& before, const Level& at,
                    const std::vector<bool>& held, Newton& nw, const Options& opt, DerivativeArrayResult& out) {
  const std::string fk = "F_" + std::to_string(at.k);
  const bool affine = constant_gradients(eqs);
  AffineVerdict av;
  if (affine) {
    av = affine_verdict(eqs, z, at.cols, held, at.ceiling, opt);
    if (av.kind != AffineVerdict::empty && (av.off > 0 || av.unproved)) withdraw(out, fk + ": " + av.evidence);
    if (av.kind == AffineVerdict::zero) nw = av.newton;
    if (av.kind == AffineVerdict::zero || (av.kind == AffineVerdict::undecided && nw.zero())) return true;
  }
  if (std::find(held.begin(), held.end(), true) != held.end()) {  // without the given values: then they are what is off
    std::vector<double> loose = before;
    const std::vector<bool> none(held.size(), false);
    Newton lw = gauss_newton(eqs, loose, at.cols, none, at.ceiling);
    bool off = false;  // the loose zero proved not one
    if (affine) {
      const AffineVerdict lv = affine_verdict(eqs, loose, at.cols, none, at.ceiling, opt);
      if (lv.kind == AffineVerdict::zero) lw = lv.newton;
      off = lv.kind == AffineVerdict::empty;
      if (lv.kind == AffineVerdict::undecided && av.kind == AffineVerdict::empty)
        av.kind = AffineVerdict::undecided, av.evidence = "without the given values, " + lv.evidence;
    }
    if (lw.zero() && !off) {
      std::string given;
      for (std::size_t i = 0; i < sys.n; ++i)
        if (held[i]) given += (given.empty() ? "" : ", ") + sys.names[i];
      throw symbolic::PointwiseNoPoint("the given values (" + given + ") violate a constraint of M_" +
                                       std::to_string(at.k + 1) + " (the derivative array " + fk +
                                       " has a zero without them, none with them: residual " + text(nw.residual) + ")");
    }
  }
  out.consistent = false;
  out.dims.push_back(-1);
  out.steps = static_cast<long>(at.k + 1);
  const std::string empty = ": M_" + std::to_string(at.k + 1) + " is empty";
  if (av.kind == AffineVerdict::empty)
    out.why = "the derivative array " + fk + " is affine and a combination of its equations that no coordinate moves " +
              "stays off 0 by " + text(av.off) + " times its rounding bound" + empty;
  else
    out.why = "the derivative array " + fk + " has no zero near the point (Gauss–Newton's least residual " +
              text(nw.residual) + ")" + empty;
  if (!affine)
    withdraw(out, fk + "'s gradients are not constant (nonlinear, or coefficients that vary with t): Gauss–Newton "
                       "from one start proves no emptiness");
  else if (av.kind != AffineVerdict::empty)
    withdraw(out, fk + " is affine, but its emptiness is not proved: " + av.evidence);
  return false;
}

/// Whether M_{k+1}'s constraints fix the time: a combination of them that no coordinate moves but t does (t³ x = 1
/// and y = −3 with x' = y: step 1 asks 3 t² x + t³ y = 0, which with the others fixes t = 1), so M_{k+1}(t) is empty
/// at generic times — the reference's "condition on the time alone" (pointwise/run.hpp), which a derivative array at
/// one fixed t never sees by its zeros.  `corange` combines F_k's rows scaled by `rs` (those no derivative moves),
/// `g` is their gradient in x.  Sets `out` (empty, with its certainty) where it does.
bool time_alone(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z, const Eigen::MatrixXd& corange,
                const Eigen::VectorXd& rs, const Eigen::MatrixXd& g, int rg, double scale, std::size_t k,
                const Options& opt, DerivativeArrayResult& out) {
  Eigen::VectorXd jt(static_cast<Eigen::Index>(eqs.size())), err(jt.size());
  std::unordered_map<const ex::ExprNode*, Tracked> memo;
  for (std::size_t i = 0; i < eqs.size(); ++i) {
    const Tracked r = rounded(eqs[i].dt, z, memo);
    const Eigen::Index ii = static_cast<Eigen::Index>(i);
    jt(ii) = rs(ii) * r.v, err(ii) = rs(ii) * r.e;
  }
  Eigen::MatrixXd aug(g.rows(), g.cols() + 1);
  aug << g, corange.transpose() * jt;
  // a combination's t-derivative that cancels to rounding level is 0 (x' = t, y' = t, x = y: the rows' ∂t cancel to
  // 1e-16, which scaled up was a time condition), as is one within the evaluation's bound (2^60 (1/(1/t) − t))
  const Eigen::VectorXd terms = corange.cwiseAbs().transpose() * jt.cwiseAbs(),
                        bound = corange.cwiseAbs().transpose() * err;
  // (and against the whole column: a combination's coefficient at rounding level on a row with ∂t ≠ 0 is noise of the
  // factorization, 5.6e-17 on the doubled circle x² + y² = 25 + t²)
  const double largest = jt.size() ? jt.cwiseAbs().maxCoeff() : 0.0;
  for (Eigen::Index w = 0; w < aug.rows(); ++w)
    if (!(std::abs(aug(w, g.cols())) > opt.nonzero_factor * std::max(terms(w), largest) + 4 * bound(w)))
      aug(w, g.cols()) = 0;
  const double m = aug.col(g.cols()).cwiseAbs().maxCoeff();
  if (!(m > 0)) return false;
  aug.col(g.cols()) *= std::ldexp(1.0, -std::ilogb(m));  // a power of two: no rank changes
  const RankDecision d = decide_rank(aug, scale, opt);
  if (d.rank <= rg) return false;
  out.consistent = false;
  out.dims.push_back(-1);
  out.steps = static_cast<long>(k + 1);
  out.why = "step " + std::to_string(k) + " gives a condition on the time alone: M_" + std::to_string(k + 1) +
            "(t) is empty at generic times";
  // the rank beyond rg is what is claimed: σ_{rg+1} beyond τ1
  if (!(d.singular_values[static_cast<std::size_t>(rg)] > d.nonzero_threshold) || d.probed)
    withdraw(out, "the condition on the time alone at step " + std::to_string(k) + ": " + d.describe());
  return true;
}

/// A zero whose coordinates span more than 1/√ε in magnitude (x1 = 4.3 beside x5 = 1.8e13 for a pencil pulled back
/// by x_i = y_i + c y_{i-1}², completed from dcad's default point): its Jacobian's entries carry rounding at the large
/// ones' scale into the small ones, which no equilibration undoes — the rank of M_3's constraints came out one short,
/// certified (Implicit.PulledBackLinearDaeHasThePlantedTower); no rank deficiency is certain there (rank.hpp's
/// separation hypothesis, as for graded input).  Their ratio where they do, else 0.
double graded_zero(const std::vector<double>& z, std::size_t cols, const Options& opt) {
  double lo = HUGE_VAL, hi = 0;
  for (std::size_t c = 0; c < cols; ++c)
    if (std::isfinite(z[c])) hi = std::max(hi, std::abs(z[c]));
  for (std::size_t c = 0; c < cols; ++c) {
    // values at rounding level beside the largest (and 1) are zeros, not grading — unless they are 1 or more
    // (y = 2^60 beside v_y = −2^120 is data: below 1e-12 of the largest it was not counted)
    const double x = std::abs(z[c]);
    if ((x > 1e-12 * std::max(1.0, hi) || x >= 1) && std::isfinite(x)) lo = std::min(lo, x);
  }
  // (only where the largest is itself beyond 1/√ε: small values beside unit ones — a chain's derivatives of 1e-10
  // beside multipliers of 30, pF currents beside volts — are the data's own grading, which the equilibration handles)
  return hi > 1 / opt.nonzero_factor && lo < hi * opt.nonzero_factor ? hi / lo : 0.0;
}

/// Whether equation i of the array vanishes with its differential at z (a constraint that is not reduced, x² = 0, or
/// a singular point), as far as double tells:
///  * its gradient is within the rounding bound of its evaluation (`rounded`; an exact 0 too: y·(eˣ − Σ_{j<8} xʲ/j!) at
///    x = 0 is flat to order 8; (x² − 1/100)² eᵗ at x = 0.1 has a gradient of 7e-19, all rounding);
///  * or it is small beside the array's largest entry `jmax` (1e-6: 2.2 pF beside 1000 is not zero) and the row grows
///    faster than linearly away from z, moving one of the first `cols` columns or t (`time`: t⁶⁴ = 0 at t = 0 is a
///    zero of every order there, a constraint nowhere else), while its gradient is not resolved by its value and
///    curvature: Newton stops near x = 1e-9 on x² = 0, where |∇f|² ≈ 2 |f| f''; ROBER's y2' = … − 3·10⁷ y2² at
///    y2 = 0 has |∇f|² = 1 against |f| f'' ≈ 0, small only beside 3·10⁷.
bool flat_here(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z, std::size_t i, std::size_t cols,
               std::size_t time, double jmax, std::unordered_map<const ex::ExprNode*, Tracked>& memo) {
  if (ex::is_number(eqs[i].e)) return false;
  double g2 = 0, gmax = 0;
  bool resolved = false;
  for (const auto& [var, g] : eqs[i].grad) {
    if (var >= cols) continue;
    const Tracked r = rounded(g, z, memo);
    g2 += r.v * r.v;
    gmax = std::max(gmax, std::abs(r.v));
    resolved = resolved || std::abs(r.v) > 64 * r.e;
  }
  if (!resolved) return true;
  if (gmax > 1e-6 * jmax) return false;
  const double f0 = row_value(eqs, i, z);
  std::vector<std::size_t> moved(cols);
  for (std::size_t c = 0; c < cols; ++c) moved[c] = c;
  moved.push_back(time);
  bool super = false;
  double curvature = 0;
  for (std::size_t c : moved) {
    const double h = 1e-2 * std::max(1.0, std::abs(z[c]));
    std::vector<double> a = z, b = z;
    a[c] += h;
    b[c] += 2 * h;
    const double fa = row_value(eqs, i, a), fb = row_value(eqs, i, b);
    const double da = std::abs(fa - f0), db = std::abs(fb - f0);
    super = super || (db > 3 * da && db > 0);
    curvature = std::max(curvature, std::abs(fb - 2 * fa + f0) / (h * h));
  }
  return super && !(g2 > 100 * std::abs(f0) * curvature);
}

}  // namespace

/// Why no rank of F_k's Jacobian at its zero z is certain, or "": a row vanishing with its differential there (x² = 0;
/// singular), or an entry of dF_k/d(x', ...) that its own rounding may have made nonzero (cancelled_entry).
std::string unresolved_at_zero(const std::vector<ArrayEquation>& eqs, const std::vector<double>& z,
                               const Eigen::MatrixXd& j, std::size_t cols, std::size_t time, std::size_t n,
                               std::size_t k) {
  const double jmax = std::max(1.0, j.cwiseAbs().maxCoeff());
  std::unordered_map<const ex::ExprNode*, Tracked> memo;
  for (Eigen::Index i = 0; i < j.rows(); ++i)
    if (flat_here(eqs, z, static_cast<std::size_t>(i), cols, time, jmax, memo))
      return "equation " + std::to_string(i) + " of the derivative array F_" + std::to_string(k) + " vanishes " +
             "with its differential at the point (a constraint that is not reduced, x² = 0, or a singular point)";
  if (const std::string c = cancelled_entry(eqs, z, n, cols); !c.empty())
    return c + " of dF_" + std::to_string(k) +
           "/d(x', ...) is within its evaluation's rounding bound (a cancellation): no rank of it is certain";
  return "";
}

DerivativeArrayResult derivative_array(const symbolic::LagrangianSystem& sys, const std::vector<double>& start,
                                       const std::vector<bool>& fixed, const Options& opt) {
  const std::size_t n = sys.n, kcap = std::min<std::size_t>(n + 1, 12);
  const std::size_t time = (kcap + 2) * n;  // x^(j)_l at j n + l (so x = q, x' = v of the system), then t
  DerivativeArrayResult out;
  out.time = start[sys.t()];
  out.dims.push_back(static_cast<long>(n));
  std::vector<double> z(time + 1, 0.0);
  for (std::size_t i = 0; i < n; ++i) z[i] = start[sys.q(i)];
  z[time] = out.time;
  std::vector<bool> held(time, false);
  bool any_held = false;
  for (std::size_t i = 0; i < n; ++i) held[i] = fixed[sys.q(i)], any_held = any_held || held[i];
  std::vector<ArrayEquation> eqs;
  for (const ex::Expr& c : sys.constraints)
    eqs.push_back(equation(ex::substitute(c, sys.t(), ex::variable(time)), time));
  const auto uncertain = [&](const std::string& why) { withdraw(out, why); };
  const auto decided = [&](const RankDecision& d, const std::string& what) {
    if (!d.certain.yes()) uncertain(what + ": " + d.describe());
  };
  std::size_t block = 0;      // eqs[block…] are the last derivatives added
  double ceiling = HUGE_VAL;  // 2^10 × the scale of F_0 at the case's point (gauss_newton)
  for (std::size_t k = 0; k <= kcap; ++k) {
    if (k > 0) {
      const std::size_t end = eqs.size();
      constexpr double kTree = 2e5;  // a bound on the work of differentiating once more (never a hang on user input)
      std::unordered_map<const ex::ExprNode*, double> memo;
      for (std::size_t i = block; i < end; ++i)
        if (tree_size(eqs[i].e, memo, kTree) >= kTree) {
          uncertain("the derivative array F_" + std::to_string(k - 1) + " has an equation of more than " + text(kTree) +
                    " operations (as a tree): not differentiated further");
          return out;
        }
      for (std::size_t i = block; i < end; ++i) eqs.push_back(equation(total_derivative(eqs[i], n, time), time));
      block = end;
    }
    out.order = static_cast<long>(k);
    const std::size_t cols = (k + 2) * n;
    std::vector<double> before = z;
    if (k == 0) {
      const Values v0 = evaluate_array(eqs, z, cols);
      double zmax = 1;
      for (std::size_t c = 0; c < cols; ++c) zmax = std::max(zmax, std::abs(z[c]));
      ceiling = 1024 * std::max(1.0, v0.j.size() ? v0.j.cwiseAbs().maxCoeff() : 0.0) * zmax;
    }
    Newton nw = gauss_newton(eqs, z, cols, held, ceiling);
    if (!nw.zero()) {  // no zero of F_k found near the point
      if (any_held) {  // first from a nudged start (x² + y² = 1 with x given, y at 0: ∂/∂y = 0 there)
        std::vector<double> nudged = before;
        for (std::size_t c = 0; c < cols; ++c)
          if (!held[c]) nudged[c] += 0.1 + 0.01 * static_cast<double>(c % 7);
        const Newton again = gauss_newton(eqs, nudged, cols, held, ceiling);
        if (again.zero()) {
          z = nudged;
          nw = again;
        }
      }
    }
    if ((!nw.zero() || (nw.residual > 0 && constant_gradients(eqs))) &&
        !zero_after_all(sys, eqs, z, before, Level{k, cols, ceiling}, held, nw, opt, out))
      break;
    if (eqs.empty()) {  // no equation: every velocity is free
      out.steps = 0;
      out.solution_rank = static_cast<long>(n);
      out.point.assign(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(n));
      out.velocity.assign(n, 0.0);
      for (std::size_t i = 0; i < n; ++i) {
        out.gauge.emplace_back(n, 0.0);
        out.gauge.back()[i] = 1;
      }
      return out;
    }
    Values v = evaluate_array(eqs, z, cols);
    if (const std::string why = unresolved_at_zero(eqs, z, v.j, cols, time, n, k); !why.empty()) uncertain(why);
    Eigen::VectorXd rs;
    const Eigen::VectorXd cs = equilibrate(v.j, rs);
    if (const double span = graded_zero(z, cols, opt); span > 0)
      uncertain("the derivative array F_" + std::to_string(k) + "'s zero spans " + text(span) +
                " in magnitude (its coordinates and derivatives): graded beyond a certain rank decision in double");
    const double scale = v.j.norm();
    const Eigen::Index nn = static_cast<Eigen::Index>(n);
    const Eigen::MatrixXd jd = v.j.rightCols(static_cast<Eigen::Index>(cols) - nn), jx = v.j.leftCols(nn),
                          jr = v.j.rightCols(static_cast<Eigen::Index>(cols) - 2 * nn);
    const RankRevealing rd(jd, scale, opt);
    decided(proved_by_structure(rd.decision(), structural_rank(eqs, n, cols)),
            "rank of dF_" + std::to_string(k) + "/d(x', ...)");
    if (out.certain.yes()) {  // the rank here is the rank near it (x v_x = u at x = 0 drops it: a singular point)
      std::vector<double> near = z;
      for (std::size_t i = 0; i < n; ++i)
        near[i] += 1e-3 * std::max(1.0, std::abs(z[i])) * (1 + 0.37 * static_cast<double>(i % 5));
      Values w = evaluate_array(eqs, near, cols);
      Eigen::VectorXd rs2;
      equilibrate(w.j, rs2);
      Options quiet = opt;  // a probe of the neighbourhood, not one of the result's decisions (their uncertainty is
                            // tested, prop_uncertainty.cpp)
      quiet.probe = nullptr;
      const RankRevealing rn(w.j.rightCols(static_cast<Eigen::Index>(cols) - nn), w.j.norm(), quiet);
      if (rn.rank() != rd.rank())
        uncertain("the rank of dF_" + std::to_string(k) + "/d(x', ...) is " + std::to_string(rd.rank()) +
                  " at the point and " + std::to_string(rn.rank()) +
                  " beside it (x moved by 1e-3 relative): a point where it drops, singular");
    }
    const Eigen::MatrixXd g = rd.corange().transpose() * jx;  // the constraints' gradients in x
    const int rg = g.rows() == 0 ? 0 : [&] {
      const RankDecision d = decide_rank(g, scale, opt);
      decided(d, "rank of the constraints of M_" + std::to_string(k + 1));
      return d.rank;
    }();
    if (g.rows() > rg && out.certain.yes()) {
      // a combination of the constraints whose differential vanishes here but which does not vanish
      // nearby (y − (x − 1/5)⁴ and v_y = 0 at x = 1/5 combine to 4 (x − 1/5)³ x' = 0): M_{k+1} is smaller
      // here than its rank says.  Probed at x ± h e_j (the derivatives held), second order and up.
      const RankRevealing gw(g, scale, opt, false);
      const Eigen::MatrixXd y = rs.asDiagonal() * (rd.corange() * gw.corange());  // rows of F_k combined
      double zmax = 1;
      for (std::size_t c = 0; c < cols; ++c) zmax = std::max(zmax, std::abs(z[c]));
      const double fscale = std::max(1.0, evaluate_array(eqs, z, cols).j.cwiseAbs().maxCoeff()) * zmax;
      for (Eigen::Index w = 0; w < y.cols() && out.certain.yes(); ++w)
        for (std::size_t j = 0; j < n && out.certain.yes(); ++j) {
          std::vector<double> moved = z;
          moved[j] += 1e-2 * std::max(1.0, std::abs(z[j]));
          const double val = y.col(w).dot(array_values(eqs, moved));
          if (std::abs(val) > 1e-9 * y.col(w).cwiseAbs().sum() * fscale)
            uncertain("a combination of the constraints of M_" + std::to_string(k + 1) +
                      " vanishes with its differential at the point but is " + text(val) + " at " + sys.names[j] +
                      " + " + text(1e-2 * std::max(1.0, std::abs(z[j]))) + " (not a generic point: M_" +
                      std::to_string(k + 1) + " may be smaller here than its rank says)");
        }
    }
    if (g.rows() > rg && time_alone(eqs, z, rd.corange(), rs, g, rg, scale, k, opt, out)) return out;
    const long dim = static_cast<long>(n) - rg;
    if (dim != out.dims.back()) {
      out.dims.push_back(dim);
      continue;
    }
    // M_{k+1} = M_k: the tower ends; the velocities that F_k leaves
    int rr = 0;
    if (jr.cols() > 0) {
      const RankDecision dr = proved_by_structure(decide_rank(jr, scale, opt), structural_rank(eqs, 2 * n, cols));
      decided(dr, "rank of dF_" + std::to_string(k) + "/d(x'', ...)");
      rr = dr.rank;
    }
    out.steps = static_cast<long>(k);
    out.solution_rank = static_cast<long>(n) - rd.rank() + rr;
    out.point.assign(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(n));
    out.velocity.assign(z.begin() + static_cast<std::ptrdiff_t>(n), z.begin() + static_cast<std::ptrdiff_t>(2 * n));
    if (out.solution_rank > 0) {  // ker J_d's x' part, orthonormal
      const RankRevealing kt(jd.transpose(), scale, opt, false);
      const Eigen::MatrixXd kernel = kt.corange();                                       // ker J_d
      const Eigen::MatrixXd top = cs.segment(nn, nn).asDiagonal() * kernel.topRows(nn);  // back to x' (unscaled)
      if (top.cols() > 0) {
        const RankRevealing tr(top, -1, opt, false);
        const Eigen::MatrixXd basis = tr.range();
        if (basis.cols() != out.solution_rank)
          uncertain("the free velocities' directions have rank " + std::to_string(basis.cols()) + ", the ranks say " +
                    std::to_string(out.solution_rank));
        for (Eigen::Index c = 0; c < basis.cols(); ++c)
          out.gauge.emplace_back(basis.col(c).data(), basis.col(c).data() + nn);
      }
    }
    return out;
  }
  if (out.consistent) uncertain("the tower did not end within the derivative array's cap F_" + std::to_string(kcap));
  return out;
}

}  // namespace dcad::fast
