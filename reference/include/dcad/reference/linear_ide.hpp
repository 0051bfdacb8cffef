// CEF (1.6), the constraint algorithm of an implicit differential equation, for a linear DAE with
// constant coefficients and sources:  E ẋ = A x + f(t),  E, A m×N,
//     M_0 = R^N,   M_{k+1}(t) = {x ∈ M_k(t) : ∃ v ∈ T M_k(t), E v = A x + f(t)}.
// M_k(t) = {x : C_k x = G_k u(t)} is affine, u(t) = (f(t), f'(t), f''(t), …) the sources' jets
// (u[d·m + i] = f_i^{(d)}), and a curve stays in it iff C_k ẋ = Ġ_k u (Ġ: G shifted one derivative
// up — "tangency includes ∂_t", V §3).  So v exists iff the stacked system
//     [E; C_k] v = [A x + F u; Ġ_k u]      (F u = f)
// is solvable, iff y·rhs = 0 for every y = (y_E, y_C) with y [E; C_k] = 0 (a left null vector):
//     (y_E A) x = −(y_E F + y_C Ġ_k) u.
// These rows, reduced together with C_k (RREF over the columns (x, u)), give C_{k+1}: rows with a
// pivot in x; rows left with x-part 0 are conditions 0 = c·u(t) on the sources alone — M_{k+1}(t) is
// empty where one fails (decided by the caller, who knows f).  The algorithm stops when the rank in x
// stops growing (M_{k+1} = M_k).  On M_c the velocities are the solutions of the stacked system: a
// particular one (free unknowns 0, rows implied by M_c dropped) plus ker [E; C_c], solution_rank =
// dim ker [E; C_c].  Exact arithmetic only (RREF, nullspace of matrix.hpp); no tolerance.
#pragma once

#include "dcad/reference/matrix.hpp"

#include <vector>

namespace dcad::reference {

/// One step: M_{k+1} = {C x = G u} (every row, RREF) and the conditions 0 = c·u found on the way.
template <class T>
struct IdeLevel {
  Matrix<T> c, g;              ///< C_{k+1} (r × N), G_{k+1} (r × U)
  Matrix<T> fresh_c, fresh_g;  ///< the rows new at this step (the candidates reduced modulo C_k, independent in x)
  Matrix<T> conditions;        ///< rows c (× U): 0 = c·u(t) must hold, else M_{k+1}(t) = ∅
  Index dim() const { return c.cols() - c.rows(); }  ///< N − rank C, where nonempty
};

/// The tower M_1 ⊇ M_2 ⊇ … ⊇ M_c (levels[k] = M_{k+1}) and the velocities on M_c:
///   ẋ = X x + W u + K λ, λ free (K's columns span ker [E; C_c]).
template <class T>
struct IdeTower {
  Index n = 0, sources = 0, orders = 0;  ///< N, s (the sources), and u's blocks f, f', …, f^(orders−1)
  std::vector<IdeLevel<T>> levels;
  Matrix<T> x_rate, u_rate, gauge;  ///< X (N×N), W (N×U), K (N×solution_rank)
  Index solution_rank() const { return gauge.cols(); }
};

/// u's shifted row: the coefficient of f_i^{(d)} moves to f_i^{(d+1)} (orders·m columns, m sources).
template <class T>
Matrix<T> shift_jets(const Matrix<T>& g, Index m) {
  Matrix<T> s(g.rows(), g.cols());
  for (Index i = 0; i < g.rows(); ++i)
    for (Index j = 0; j + m < g.cols(); ++j) s(i, j + m) = g(i, j);
  return s;
}

/// CEF (1.6) on E ẋ = A x + F σ(t): σ the s sources (F m×s; f = F σ), u = (σ, σ', …) in `orders`
/// blocks of s (N + 2 blocks suffice: each step differentiates at most once more, at most N + 1 steps).
template <class T>
IdeTower<T> linear_ide_tower(const Matrix<T>& e, const Matrix<T>& a, const Matrix<T>& sources, Index orders) {
  require(e.rows() == a.rows() && e.cols() == a.cols() && sources.rows() == e.rows(), "linear_ide_tower",
          "E, A and F with one number of rows, E and A of one shape",
          shape(e) + ", " + shape(a) + " and " + shape(sources));
  const Index m = e.rows(), n = e.cols(), s = sources.cols(), u = s * orders;
  IdeTower<T> t;
  t.n = n, t.sources = s, t.orders = orders;
  Matrix<T> f(m, u);  // F u = f: the block of order 0
  for (Index i = 0; i < m; ++i)
    for (Index j = 0; j < s && j < u; ++j) f(i, j) = sources(i, j);
  Matrix<T> c(0, n), g(0, u);  // M_0 = R^N
  for (;;) {
    const Matrix<T> stacked = vstack(e, c);
    const Matrix<T> y = nullspace(stacked.transpose());  // rows y with y [E; C] = 0
    const Matrix<T> ye = y.block(0, y.rows(), 0, m), yc = y.block(0, y.rows(), m, m + c.rows());
    // the new rows [C | −G] (C x − G u = 0): (y_E A) x + (y_E F + y_C Ġ) u = 0
    Matrix<T> fresh = hstack(ye * a, ye * f + yc * shift_jets(g, s));
    for (Index i = 0; i < fresh.rows(); ++i)  // modulo C_k (in RREF over x: its pivot columns cleared)
      for (Index r = 0; r < c.rows(); ++r) {
        Index p = 0;
        while (c(r, p) == 0) ++p;
        const T k = fresh(i, p);
        if (k == 0) continue;
        for (Index j = 0; j < n; ++j) fresh(i, j) -= k * c(r, j);
        for (Index j = 0; j < u; ++j) fresh(i, n + j) += k * g(r, j);
      }
    const Rref<T> nr = rref(fresh);
    Index in_x = 0;
    while (in_x < nr.pivots.size() && nr.pivots[in_x] < n) ++in_x;
    IdeLevel<T> level;
    level.fresh_c = nr.r.block(0, in_x, 0, n);
    level.fresh_g = -nr.r.block(0, in_x, n, n + u);
    level.conditions = nr.r.block(in_x, nr.r.rows(), n, n + u);  // x-part 0: 0 = c·u
    // C_{k+1}: C_k and the fresh rows, in RREF over (x, u)
    const Rref<T> r = rref(vstack(hstack(c, -g), hstack(level.fresh_c, -level.fresh_g)));
    level.c = r.r.block(0, r.r.rows(), 0, n);
    level.g = -r.r.block(0, r.r.rows(), n, n + u);
    const bool same = in_x == 0;  // nothing new in x: M_{k+1} = M_k (where nonempty)
    c = level.c, g = level.g;
    t.levels.push_back(level);
    if (same) break;
  }
  // velocities on M_c: [E; C] v = [A x + F u; Ġ u], read off the RREF of [E; C | A, F; 0, Ġ]
  const Matrix<T> stacked = vstack(e, c);
  const Matrix<T> rhs = vstack(hstack(a, f), hstack(Matrix<T>(c.rows(), n), shift_jets(g, s)));
  const Rref<T> r = rref(hstack(stacked, rhs));
  t.x_rate = Matrix<T>(n, n), t.u_rate = Matrix<T>(n, u);
  for (Index i = 0; i < r.pivots.size(); ++i) {
    if (r.pivots[i] >= n) break;  // a row implied by M_c's constraints (0 = its right-hand side there)
    for (Index j = 0; j < n; ++j) t.x_rate(r.pivots[i], j) = r.r(i, n + j);
    for (Index j = 0; j < u; ++j) t.u_rate(r.pivots[i], j) = r.r(i, 2 * n + j);
  }
  t.gauge = nullspace(stacked).transpose();
  return t;
}

/// det(sE − A) ≢ 0 for square E, A: the determinant is a polynomial of degree ≤ N in s, so it is
/// identically zero iff it vanishes at s = 0, 1, …, N.
template <class T>
bool regular_pencil(const Matrix<T>& e, const Matrix<T>& a) {
  require(is_square(e) && e.rows() == a.rows() && e.cols() == a.cols(), "regular_pencil", "square E and A of one shape",
          shape(e) + " and " + shape(a));
  for (Index s = 0; s <= e.rows(); ++s) {
    Matrix<T> p = a;
    for (Index i = 0; i < e.rows(); ++i)
      for (Index j = 0; j < e.cols(); ++j) p(i, j) = T(static_cast<long>(s)) * e(i, j) - a(i, j);
    if (determinant(p) != 0) return true;
  }
  return false;
}

}  // namespace dcad::reference
