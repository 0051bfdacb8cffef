// Nonlinear Lagrangian systems with planted answers (issue 13): a linear Pontryagin system (CEF §6),
// whose tower the linear reference computes, written as formulas and pulled back by a polynomial
// change of coordinates q = Φ(Q), Φ = L₂∘T∘L₁ with L₁, L₂ unimodular and T(y)_i = y_i + Σ_{j<i} c_ij y_j²
// (triangular, so Φ⁻¹ is polynomial and rational points map to rational points).  A point
// transformation lifts to TQ ⊕ T*Q (v = DΦ V, p = DΦ⁻ᵀ P) preserving D̄_Δ and E, and the CAD is
// intrinsic (CEF §5), so dims, steps, consistency and solution rank are the linear system's, and
// the motion is the linear one in the new coordinates.
#pragma once

#include "dcad/reference/nonlinear/lagrangian_system.hpp"
#include "dcad/reference/system.hpp"
#include "gen.hpp"

#include <vector>

namespace dcad::test {

namespace ex = reference::expr;

/// Σ_i c_i x_i.
inline ex::Expr linear_combination(const std::vector<Q>& c, const std::vector<ex::Expr>& x) {
  ex::Expr s = ex::number(0);
  for (Index i = 0; i < c.size(); ++i) s = ex::add(s, ex::mul(ex::number(c[i]), x[i]));
  return s;
}

/// M x for a matrix of numbers and a vector of expressions.
inline std::vector<ex::Expr> times(const QM& m, const std::vector<ex::Expr>& x) {
  std::vector<ex::Expr> out;
  for (Index i = 0; i < m.rows(); ++i) out.push_back(linear_combination(m.row(i), x));
  return out;
}

/// L(q, v) = ½ vᵀ A v + qᵀ B v + ½ qᵀ C q + aᵀ q + bᵀ v for expressions q, v  [CONTRACT `pontryagin`].
inline ex::Expr lagrangian_formula(const reference::PontryaginInput<Q>& in, const std::vector<ex::Expr>& q,
                                   const std::vector<ex::Expr>& v) {
  const auto half = ex::number(Q(1, 2));
  ex::Expr l = ex::number(0);
  const std::vector<ex::Expr> av = times(in.vv, v), bv = times(in.qv, v), cq = times(in.qq, q);
  for (Index i = 0; i < in.n; ++i) {
    l = ex::add(l, ex::mul(half, ex::mul(v[i], av[i])));
    l = ex::add(l, ex::mul(q[i], bv[i]));
    l = ex::add(l, ex::mul(half, ex::mul(q[i], cq[i])));
  }
  l = ex::add(l, linear_combination(in.q, q));
  l = ex::add(l, linear_combination(in.v, v));
  return l;
}

/// The system with coordinates Q: L(Φ(Q), DΦ(Q)V), constraints K DΦ(Q) V = 0 (Φ = identity if `phi`
/// is null).
struct PointMap {
  QM l1, l2;                      ///< unimodular
  std::vector<std::vector<Q>> c;  ///< c[i][j], j < i
  Index n() const { return l1.rows(); }

  /// q = Φ(Q) and v = DΦ(Q) V as formulas in the variables Q_i = i, V_i = n + i.
  void formulas(std::vector<ex::Expr>& q, std::vector<ex::Expr>& v) const {
    std::vector<ex::Expr> qs, vs;
    for (Index i = 0; i < n(); ++i) {
      qs.push_back(ex::variable(i));
      vs.push_back(ex::variable(n() + i));
    }
    const std::vector<ex::Expr> y = times(l1, qs), w = times(l1, vs);
    std::vector<ex::Expr> ty = y, tw = w;  // T(y), DT(y) w
    for (Index i = 0; i < n(); ++i)
      for (Index j = 0; j < i; ++j) {
        if (c[i][j] == 0) continue;
        ty[i] = ex::add(ty[i], ex::mul(ex::number(c[i][j]), ex::pow(y[j], 2)));
        tw[i] = ex::add(tw[i], ex::mul(ex::number(2 * c[i][j]), ex::mul(y[j], w[j])));
      }
    q = times(l2, ty);
    v = times(l2, tw);
  }
  /// Φ⁻¹(q) exactly: y = L₁ Q solves T(y) = L₂⁻¹ q row by row.
  std::vector<Q> inverse(const std::vector<Q>& q) const {
    const std::vector<Q> z = (reference::inverse(l2) * QM::column(q)).col(0);
    std::vector<Q> y(n());
    for (Index i = 0; i < n(); ++i) {
      y[i] = z[i];
      for (Index j = 0; j < i; ++j) y[i] -= c[i][j] * y[j] * y[j];
    }
    return (reference::inverse(l1) * QM::column(y)).col(0);
  }
  /// DΦ(Q) exactly.
  QM jacobian(const std::vector<Q>& big_q) const {
    const std::vector<Q> y = (l1 * QM::column(big_q)).col(0);
    QM dt = QM::identity(n());
    for (Index i = 0; i < n(); ++i)
      for (Index j = 0; j < i; ++j) dt(i, j) = 2 * c[i][j] * y[j];
    return l2 * dt * l1;
  }
};

inline PointMap identity_map(Index n) {
  return {QM::identity(n), QM::identity(n), std::vector<std::vector<Q>>(n, std::vector<Q>(n, Q(0)))};
}

/// A random Φ (RapidCheck choices; shrinks toward the identity).
inline PointMap random_map(Index n) {
  PointMap m{unimodular(n), unimodular(n), std::vector<std::vector<Q>>(n, std::vector<Q>(n, Q(0)))};
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < i; ++j) m.c[i][j] = *rc::gen::inRange(-1, 2);
  return m;
}

/// The Lagrangian system of `in` in the coordinates Q of `phi`.
inline reference::LagrangianSystem pulled_back(const reference::PontryaginInput<Q>& in, const PointMap& phi) {
  reference::LagrangianSystem s;
  s.n = in.n;
  for (Index i = 0; i < in.n; ++i) s.names.push_back("Q" + std::to_string(i + 1));
  std::vector<ex::Expr> q, v;
  phi.formulas(q, v);
  s.lagrangian = lagrangian_formula(in, q, v);
  for (Index a = 0; a < in.k.rows(); ++a) s.constraints.push_back(linear_combination(in.k.row(a), v));
  return s;
}

/// A random linear Pontryagin system on Q^n (CEF §6): degenerate A of random rank, B, C, a, b, and
/// m < n independent constraints (at least min_m).
inline reference::PontryaginInput<Q> random_pontryagin(Index n, Index min_m = 0) {
  reference::PontryaginInput<Q> in;
  in.n = n;
  in.vv = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  in.qv = *rc::gen::element(0, 1) ? integer_matrix(n, n, 1) : QM(n, n);
  in.qq = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  const bool affine = *rc::gen::inRange(0, 4) == 0;  // with a, b = 0 the system is consistent (x = 0 ∈ M_c)
  in.q = affine ? integer_vector(n, 1) : std::vector<Q>(n, Q(0));
  in.v = affine ? integer_vector(n, 1) : std::vector<Q>(n, Q(0));
  const Index m = *rc::gen::inRange<Index>(std::min(min_m, n - 1), n);
  in.k = (integer_matrix(m, n, 1) + QM::identity(n).block(0, m, 0, n)) * unimodular(n);  // rank m: [B + (I 0)] U, B
  if (reference::rank(in.k) < m)
    in.k = QM::identity(n).block(0, m, 0, n) * unimodular(n);  // small, else the identity rows
  return in;
}

/// A Heisenberg-type constraint z' = x y' − y x' (nonholonomic, polynomial) with L = ½|v|² − ½ qᵀ K q
/// (K random symmetric): coordinates x, y, z at the indices ix, iy, iz.
struct Heisenberg {
  reference::LagrangianSystem s;
  Index ix, iy, iz;
};
inline Heisenberg heisenberg_system(Index ix, Index iy, Index iz) {
  Heisenberg h{{}, ix, iy, iz};
  h.s.n = 3;
  h.s.names.assign(3, "");
  h.s.names[ix] = "x";
  h.s.names[iy] = "y";
  h.s.names[iz] = "z";
  const std::vector<ex::Expr> q{ex::variable(0), ex::variable(1), ex::variable(2)},
      v{ex::variable(3), ex::variable(4), ex::variable(5)};
  const QM k = symmetric_matrix(3, pick_size(0, 3));
  ex::Expr l = ex::number(0);
  for (Index i = 0; i < 3; ++i) l = ex::add(l, ex::mul(ex::number(Q(1, 2)), ex::pow(v[i], 2)));
  const std::vector<ex::Expr> kq = times(k, q);
  for (Index i = 0; i < 3; ++i) l = ex::sub(l, ex::mul(ex::number(Q(1, 2)), ex::mul(q[i], kq[i])));
  h.s.lagrangian = l;
  h.s.constraints = {ex::add(ex::sub(v[iz], ex::mul(q[ix], v[iy])), ex::mul(q[iy], v[ix]))};
  return h;
}
/// A random rational point (q, v, t = 0) on the constraint.
inline std::vector<Q> heisenberg_point(const Heisenberg& h) {
  std::vector<Q> x;
  for (int i = 0; i < 6; ++i) x.push_back(Q(*rc::gen::inRange(-6, 7), *rc::gen::inRange(1, 5)));
  x[3 + h.iz] = x[h.ix] * x[3 + h.iy] - x[h.iy] * x[3 + h.ix];
  x.push_back(0);
  return x;
}

}  // namespace dcad::test
