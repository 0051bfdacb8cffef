// Linear Dirac systems with external forces and sources, literally:
//   (ẋ − Z σ(t), dE(x) − F x − B σ(t)) ∈ D,      E(x) = ½ xᵀ H x + gᵀ x,
// with F x a linear force one-form (YM §4, (4.3): a resistor is −R v on its branch), B σ(t) the
// time-dependent forces (a voltage source is +V(t) on its branch), and Z σ(t) the affine shift of
// D by affine constraints (YM §4 with ω^a(q)·v = b^a(t); a current source is v = I(t)).
//
// The CAD then runs on time-dependent affine submanifolds M_k(t) (V §3).  Each constraint is kept
// as a jet row  a·x + b + Σ_d c_d·σ^{(d)}(t) = 0, columns [x (N) | 1 | σ⁽⁰⁾ (m) | σ⁽¹⁾ (m) | …].
// x ∈ M_{k+1}(t) iff some ẋ solves (ẋ − Zσ, α(t, x)) ∈ D and is tangent to the moving M_k(t):
// a_j·ẋ + Σ_d c_{j,d}·σ^{(d+1)} = 0 for every row j.  With D = row space of [G_v | G_α]
// (ẋ − Zσ = G_vᵀ λ, α = G_αᵀ λ) that is a linear system for λ, solvable iff y·rhs = 0 for every y in
// the left kernel (Fredholm) — each such y is a candidate equation.  A candidate that is 0 on x
// but not on the sources is a *source condition*: M_{k+1}(t) is empty unless the sources satisfy
// it for all t (a loop of voltage sources, a cutset of current sources).
#pragma once

#include "dcad/reference/cad.hpp"

namespace dcad::reference {

template <class T>
struct ForcedSystem {
  LinearSystem<T> s;       ///< D and E (H symmetric, g)
  Matrix<T> force;         ///< F, N×N (empty = 0)
  Index sources = 0;       ///< m
  Matrix<T> source_force;  ///< B, N×m
  Matrix<T> shift;         ///< Z, N×m
  /// Rows of source conditions known before the CAD (e.g. KCL on current sources), columns [1 | σ⁽⁰⁾].
  Matrix<T> given_conditions;
};

template <class T>
struct ForcedResult {
  std::vector<long> dims;  ///< dim M_k(t), k = 0…c (−1: empty)
  Index steps = 0;
  bool consistent = true;   ///< false: M_k = ∅ whatever the sources are (0 = 1)
  Index orders = 1;         ///< jet columns hold σ⁽⁰⁾ … σ^{(orders−1)}
  Matrix<T> equations;      ///< M_c(t) as jet rows, x-parts in RREF (independent)
  Matrix<T> conditions;     ///< source conditions, columns [1 | σ⁽⁰⁾ | …] (x-part dropped)
  Index solution_rank = 0;  ///< dim{ẋ : (ẋ, 0) ∈ D, ẋ ∈ T M_c}  [CEF Thm 5.4(b)]
  /// per step k, the equations that raised the rank (jet rows of that step's width): for reports
  std::vector<Matrix<T>> added;
  /// per step k, the source conditions known at M_k (columns [1 | σ⁽⁰⁾ | …] of that step's width);
  /// one entry past the dims when the step that found M_{c+1} = M_c found new conditions: where the
  /// sources fail them, M_{c+1} is empty
  std::vector<Matrix<T>> conditions_at;
};

/// The rows of `cand` whose x-parts raise the rank of the x-parts of `eq`, greedily in order.
template <class T>
Matrix<T> rank_raising_rows(const Matrix<T>& eq, const Matrix<T>& cand, Index n) {
  Matrix<T> x = eq.block(0, eq.rows(), 0, n), out(0, cand.cols());
  for (Index i = 0; i < cand.rows(); ++i) {
    const Matrix<T> more = vstack(x, cand.block(i, i + 1, 0, n));
    if (rank(more) > x.rows()) {  // the rows kept in x are independent
      x = more;
      out = vstack(out, cand.block(i, i + 1, 0, cand.cols()));
    }
  }
  return out;
}

/// M with `more` zero columns appended (jets of one more order).
template <class T>
Matrix<T> widen(const Matrix<T>& m, Index more) {
  return hstack(m, Matrix<T>(m.rows(), more));
}

/// −d/dt of the source part: c_d·σ^{(d)} becomes c_d·σ^{(d+1)} (one order up; the constant drops).
template <class T>
Matrix<T> time_derivative_of_sources(const Matrix<T>& rows, Index n, Index m) {
  Matrix<T> out(rows.rows(), rows.cols() + m);
  for (Index i = 0; i < rows.rows(); ++i)
    for (Index j = n + 1; j < rows.cols(); ++j) out(i, j + m) = rows(i, j);
  return out;
}

template <class T>
void require_forced(const ForcedSystem<T>& f, const std::string& fn) {
  require_system(f.s, fn);
  const Index n = f.s.d.n, m = f.sources;
  require(f.force.rows() == 0 || (f.force.rows() == n && f.force.cols() == n), fn, "an N×N force matrix",
          shape(f.force));
  require(f.source_force.rows() == n && f.source_force.cols() == m, fn, "B of shape N×m", shape(f.source_force));
  require(f.shift.rows() == n && f.shift.cols() == m, fn, "Z of shape N×m", shape(f.shift));
  require(f.given_conditions.rows() == 0 || f.given_conditions.cols() == 1 + m, fn, "conditions [1 | σ]",
          shape(f.given_conditions));
}

/// A = H − F: α(t, x) = A x + g − B σ(t).
template <class T>
Matrix<T> one_form_matrix(const ForcedSystem<T>& f) {
  return f.force.rows() ? f.s.hessian - f.force : f.s.hessian;
}

/// The linear system for λ at the current tower: [G_αᵀ; A_x G_vᵀ] λ = rhs, rhs as jet rows.
template <class T>
struct LambdaSystem {
  Matrix<T> lhs, rhs;
};

template <class T>
LambdaSystem<T> lambda_system(const ForcedSystem<T>& f, const Matrix<T>& eq, Index orders) {
  const Index n = f.s.d.n, m = f.sources, w = n + 1 + m * orders;
  const Matrix<T>& g = f.s.d.d.basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, n), ga = g.block(0, g.rows(), n, 2 * n);
  const Matrix<T> ax = eq.block(0, eq.rows(), 0, n);
  LambdaSystem<T> out{vstack(ga.transpose(), ax * gv.transpose()), Matrix<T>(n + eq.rows(), w + m)};
  const Matrix<T> a = one_form_matrix(f);
  for (Index i = 0; i < n; ++i) {  // A x + g − B σ
    for (Index j = 0; j < n; ++j) out.rhs(i, j) = a(i, j);
    out.rhs(i, n) = f.s.gradient[i];
    for (Index j = 0; j < m; ++j) out.rhs(i, n + 1 + j) = -f.source_force(i, j);
  }
  // a_j·(G_vᵀλ + Zσ) + Σ c_{j,d} σ^{(d+1)} = 0
  const Matrix<T> az = ax * f.shift, dc = time_derivative_of_sources(eq, n, m);
  for (Index r = 0; r < eq.rows(); ++r) {
    for (Index j = 0; j < m; ++j) out.rhs(n + r, n + 1 + j) = -az(r, j);
    for (Index j = n + 1; j < w + m; ++j) out.rhs(n + r, j) -= dc(r, j);
  }
  return out;
}

/// Splits RREF rows into those with an x-pivot (equations) and the rest (conditions on sources);
/// false if some row reads 1 = 0.
template <class T>
bool split_rows(const Matrix<T>& pool, Index n, Matrix<T>& eq, Matrix<T>& cond) {
  const Rref<T> e = rref(pool);
  eq = Matrix<T>(0, pool.cols());
  cond = Matrix<T>(0, pool.cols() - n);
  bool ok = true;
  for (Index i = 0; i < e.pivots.size(); ++i) {
    const Matrix<T> row = e.r.block(i, i + 1, 0, pool.cols());
    if (e.pivots[i] < n) {
      eq = vstack(eq, row);
    } else {
      const Matrix<T> c = row.block(0, 1, n, pool.cols());
      cond = vstack(cond, c);
      if (e.pivots[i] == n && rank(c.block(0, 1, 1, c.cols())) == 0) ok = false;  // 1 = 0
    }
  }
  return ok;
}

/// The CAD tower of a forced system with sources.  [CEF §5 with YM §4 forces; V §3 moving M_k]
template <class T>
ForcedResult<T> forced_tower(const ForcedSystem<T>& f, const Matrix<T>& initial = Matrix<T>()) {
  require_forced(f, "forced_tower");
  const Index n = f.s.d.n, m = f.sources;
  ForcedResult<T> out;
  Matrix<T> eq = initial.rows() ? initial : Matrix<T>(0, n + 1 + m);
  require(eq.cols() == n + 1 + m, "forced_tower", "initial jet rows of width N+1+m", shape(eq));
  Matrix<T> cond(0, 1 + m);
  out.consistent = split_rows(eq, n, eq, cond);
  out.dims.push_back(out.consistent ? long(n - eq.rows()) : -1L);
  out.added.push_back(eq);
  out.conditions_at.push_back(cond);
  // The given conditions (KCL through current sources: the affine part of D) are primary: they bound
  // M_1, never M_0 = M — two current sources in series that disagree leave M_1 empty.
  if (f.given_conditions.rows()) cond = vstack(cond, f.given_conditions);
  while (out.consistent) {
    const LambdaSystem<T> ls = lambda_system(f, eq, out.orders);
    const Matrix<T> cand = nullspace(ls.lhs.transpose()) * ls.rhs;  // y·rhs for y in the left kernel
    ++out.orders;
    const Index before = eq.rows();
    const Matrix<T> fresh = rank_raising_rows(widen(eq, m), cand, n);
    const Matrix<T> pool = vstack(vstack(widen(eq, m), hstack(Matrix<T>(cond.rows(), n), widen(cond, m))), cand);
    out.consistent = split_rows(pool, n, eq, cond);
    if (!out.consistent) {
      out.dims.push_back(-1);
      out.added.push_back(fresh);
      out.conditions_at.push_back(cond);
      break;
    }
    // M_{k+1} = M_k where the sources meet the conditions found here, empty where they do not: the new
    // conditions get an entry of their own, one past the dims (the given ones belong to M_1, see above)
    if (eq.rows() == before && (out.dims.size() > 1 || f.given_conditions.rows() == 0)) {
      if (cond.rows() > out.conditions_at.back().rows()) out.conditions_at.push_back(cond);
      break;
    }
    out.dims.push_back(long(n - eq.rows()));
    out.added.push_back(fresh);
    out.conditions_at.push_back(cond);
  }
  out.steps = out.dims.size() - 1;
  out.equations = eq;
  out.conditions = cond;
  if (out.consistent) {
    const LambdaSystem<T> ls = lambda_system(f, eq, out.orders);
    const Matrix<T>& g = f.s.d.d.basis();
    out.solution_rank = rank(nullspace(ls.lhs) * g.block(0, g.rows(), 0, n));  // {G_vᵀλ : lhs λ = 0}
  }
  return out;
}

/// Evaluates jet rows at (x, u) with u = (1, σ⁽⁰⁾, σ⁽¹⁾, …) (missing orders are 0).
template <class T>
std::vector<T> evaluate_rows(const Matrix<T>& rows, const std::vector<T>& x, const std::vector<T>& u) {
  std::vector<T> out(rows.rows(), T(0));
  const Index n = x.size();
  for (Index i = 0; i < rows.rows(); ++i) {
    for (Index j = 0; j < n; ++j) out[i] += rows(i, j) * x[j];
    for (Index j = n; j < rows.cols() && j - n < u.size(); ++j) out[i] += rows(i, j) * u[j - n];
  }
  return out;
}

/// {ẋ : (ẋ − Zσ, α(t, x)) ∈ D, ẋ tangent to M_c(t)} at x ∈ M_c(t), u = (1, σ⁽⁰⁾, …, σ^{(orders)}).
template <class T>
AffineSubspace<T> forced_velocities(const ForcedSystem<T>& f, const ForcedResult<T>& r, const std::vector<T>& x,
                                    const std::vector<T>& u) {
  const Index n = f.s.d.n;
  const LambdaSystem<T> ls = lambda_system(f, r.equations, r.orders);
  std::vector<T> rhs = evaluate_rows(ls.rhs, x, u);
  const AffineSubspace<T> lam = solve(ls.lhs, rhs);
  AffineSubspace<T> out;
  out.empty = lam.empty;
  if (lam.empty) return out;
  const Matrix<T>& g = f.s.d.d.basis();
  const Matrix<T> gvt = g.block(0, g.rows(), 0, n).transpose();
  out.direction = map(gvt, lam.direction);
  out.point = (gvt * Matrix<T>::column(lam.point)).col(0);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < f.sources; ++j) out.point[i] += f.shift(i, j) * u[1 + j];
  return out;
}

/// The motion on M_c(t) as linear maps: x = X0 u + Bᵀ y (B the canonical basis of T M_c, u = (1, σ, …,
/// σ^{(orders−1)})) and ẋ = V_y y + V_u u_ext (u_ext one order more), ẏ = A_y y + A_u u_ext.
/// V comes from the λ-system solved by exact normal equations: where it is solvable (every x ∈ M_c
/// with sources that meet the conditions, CEF Thm 5.4) that is an exact solution, and it is linear,
/// so columns solvable only together (sources tied by a condition) still add up to one.
template <class T>
struct ForcedMotion {
  Index orders = 1;
  Matrix<T> basis, x0, vy, vu, ay, au;
  Matrix<T> gauge;  ///< columns: the free directions of ẋ (dim = solution rank)
};

template <class T>
ForcedMotion<T> forced_motion(const ForcedSystem<T>& f, const ForcedResult<T>& r) {
  require(r.consistent, "forced_motion", "a consistent system", "M_c empty");
  const Index n = f.s.d.n, m = f.sources, wu = 1 + m * r.orders, wx = wu + m;
  ForcedMotion<T> fm;
  fm.orders = r.orders;
  const Matrix<T> ex = r.equations.block(0, r.equations.rows(), 0, n),
                  eu = r.equations.block(0, r.equations.rows(), n, n + wu);
  fm.basis = Subspace<T>::solutions(ex).basis();
  solve_particular(ex, -eu, fm.x0);  // independent rows: solvable column by column
  const LambdaSystem<T> ls = lambda_system(f, r.equations, r.orders);
  const Matrix<T> rx = ls.rhs.block(0, ls.rhs.rows(), 0, n), ru = ls.rhs.block(0, ls.rhs.rows(), n, n + wx);
  Matrix<T> x0e(n, wx);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < wu; ++j) x0e(i, j) = fm.x0(i, j);
  const Matrix<T> rhs = hstack(rx * fm.basis.transpose(), rx * x0e + ru);
  Matrix<T> lam;
  solve_particular(ls.lhs.transpose() * ls.lhs, ls.lhs.transpose() * rhs, lam);
  const Matrix<T>& g = f.s.d.d.basis();
  const Matrix<T> gvt = g.block(0, g.rows(), 0, n).transpose();
  Matrix<T> v = gvt * lam;  // ẋ = G_vᵀ λ + Z σ
  const Index dm = fm.basis.rows();
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < m; ++j) v(i, dm + 1 + j) += f.shift(i, j);
  fm.vy = v.block(0, n, 0, dm);
  fm.vu = v.block(0, n, dm, dm + wx);
  // ẏ = P (ẋ − X0 u̇), P = (B Bᵀ)⁻¹ B, u̇ = u's jets one order up
  const Matrix<T> p = inverse(fm.basis * fm.basis.transpose()) * fm.basis;
  Matrix<T> x0dot(n, wx);
  for (Index i = 0; i < n; ++i)
    for (Index j = 1; j < wu; ++j) x0dot(i, j + m) = fm.x0(i, j);
  fm.ay = p * fm.vy;
  fm.au = p * (fm.vu - x0dot);
  fm.gauge = gvt * nullspace(ls.lhs).transpose();
  return fm;
}

/// ż = F z + f + S u_src(t) + G λ in the coordinates z = the pivot variables of T M_c's canonical
/// basis [CEF (5.12) with sources]; u_src = (σ, σ', …, σ^{(orders)}).
template <class T>
struct ForcedReducedEquations {
  std::vector<Index> coords;
  Matrix<T> f_matrix, s, g;
  std::vector<T> f;
};

template <class T>
ForcedReducedEquations<T> forced_reduced_equations(const ForcedMotion<T>& fm, Index m) {
  ForcedReducedEquations<T> out;
  out.coords = rref(fm.basis).pivots;
  const Index dm = out.coords.size(), wx = fm.au.cols();
  // z = x[piv] = (X0 u)[piv] + y; ż = A_y (z − (X0 u)[piv]) + A_u u_ext + (X0 u̇)[piv]
  Matrix<T> cu = fm.au;
  for (Index i = 0; i < dm; ++i)
    for (Index j = 0; j < fm.x0.cols(); ++j) {
      for (Index k = 0; k < dm; ++k) cu(i, j) -= fm.ay(i, k) * fm.x0(out.coords[k], j);
      if (j >= 1) cu(i, j + m) += fm.x0(out.coords[i], j);
    }
  out.f_matrix = fm.ay;
  out.f = cu.col(0);
  out.s = cu.block(0, dm, 1, wx);
  out.g = Matrix<T>(dm, fm.gauge.cols());
  for (Index i = 0; i < dm; ++i)
    for (Index j = 0; j < fm.gauge.cols(); ++j) out.g(i, j) = fm.gauge(out.coords[i], j);
  return out;
}

}  // namespace dcad::reference
