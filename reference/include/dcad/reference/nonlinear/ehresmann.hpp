// YM §5 on formulas: the Ehresmann connection of linear constraints a(q)·v = 0, its curvature, the
// constrained Lagrangian L_c, and the implicit Lagrange–d'Alembert equations (5.6) of the implicit
// constrained Lagrangian system (L_c, Δ, X_P) — YM Thm 5.6 (a).  Everything is a formula
// (expression.hpp); nothing is decided here but the choice of the fibre coordinates at a point.
#pragma once

#include "dcad/reference/matrix.hpp"
#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/reference/nonlinear/lagrangian_system.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::reference {

/// q = (r, s): base coordinates r (n − m) and fibre coordinates s (m), with the constraints written
/// ω^a = ds^a + A^a_α(q) dr^α, i.e. v_s = −A v_r on Δ  [YM §5, "Ehresmann connections"].
struct EhresmannConnection {
  std::vector<std::size_t> r, s;           ///< coordinate indices
  std::vector<std::vector<expr::Expr>> a;  ///< A[a][α]
};

/// The value of a formula of q at a point (exact: no sin/cos/exp except at values where rational).
inline Rational value_at(const expr::Expr& e, const std::vector<Rational>& vars) {
  auto none = std::make_shared<const JetSpace>(0, 0);
  std::vector<Jet<Rational>> x;
  for (const Rational& v : vars) x.emplace_back(none, v);
  return expr::evaluate<Jet<Rational>>(e, x, [&](const Rational& c) { return Jet<Rational>(none, c); }).value();
}

/// The connection with fibre coordinates s = the first coordinates, in order, on which the constraints'
/// velocity coefficients a(q0) are independent (YM's choice in both of its §6 examples: (x, y) for
/// the disk, (q_L, q_C1) for the L-C circuit), A = a_s⁻¹ a_r by Gauss–Jordan on formulas with pivots
/// nonzero at q0.  std::invalid_argument unless the constraints are linear and homogeneous in v and
/// independent of t, with a(q0) of full rank.
inline EhresmannConnection ehresmann_connection(const LagrangianSystem& sys, const std::vector<Rational>& q0) {
  const LagrangianDerivatives d = derivatives(sys);
  const std::size_t n = sys.n, m = sys.m();
  for (std::size_t c = 0; c < m; ++c) {
    if (!expr::is_number(d.b[c], 0) || expr::depends_on(sys.constraints[c], sys.t()))
      throw std::invalid_argument(
          "ehresmann_connection: expected constraints linear and homogeneous in v, free of t (YM §5), found "
          "constraint " +
          std::to_string(c + 1));
  }
  std::vector<Rational> at(2 * n + 1, Rational(0));
  for (std::size_t i = 0; i < n; ++i) at[i] = q0[i];
  std::vector<std::vector<expr::Expr>> a = d.a;  // m × n, reduced in place (formulas)
  EhresmannConnection conn;
  std::vector<char> fibre(n, 0);
  std::size_t row = 0;
  for (std::size_t col = 0; col < n && row < m; ++col) {
    std::size_t p = row;
    while (p < m && value_at(a[p][col], at) == 0) ++p;
    if (p == m) continue;
    std::swap(a[p], a[row]);
    const expr::Expr pivot = a[row][col];
    for (std::size_t j = 0; j < n; ++j) a[row][j] = expr::div(a[row][j], pivot);
    for (std::size_t i = 0; i < m; ++i) {
      if (i == row || expr::is_number(a[i][col], 0)) continue;
      const expr::Expr f = a[i][col];
      for (std::size_t j = 0; j < n; ++j) a[i][j] = expr::sub(a[i][j], expr::mul(f, a[row][j]));
    }
    conn.s.push_back(col);
    fibre[col] = 1;
    ++row;
  }
  if (row < m)
    throw std::invalid_argument("ehresmann_connection: expected independent constraints at the point, found rank " +
                                std::to_string(row));
  for (std::size_t i = 0; i < n; ++i)
    if (!fibre[i]) conn.r.push_back(i);
  conn.a.assign(m, {});
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t alpha : conn.r) conn.a[b].push_back(a[b][alpha]);  // row b: v_s^b + Σ A^b_α v_r^α = 0
  return conn;
}

/// K^b_{αβ} = ∂A^b_α/∂r^β − ∂A^b_β/∂r^α + A^a_α ∂A^b_β/∂s^a − A^a_β ∂A^b_α/∂s^a  [YM, after (5.6)].
inline std::vector<std::vector<std::vector<expr::Expr>>> curvature(const EhresmannConnection& c) {
  const std::size_t m = c.s.size(), k = c.r.size();
  std::vector<std::vector<std::vector<expr::Expr>>> out(
      m, std::vector<std::vector<expr::Expr>>(k, std::vector<expr::Expr>(k)));
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < k; ++al)
      for (std::size_t be = 0; be < k; ++be) {
        expr::Expr e = expr::sub(expr::diff(c.a[b][al], c.r[be]), expr::diff(c.a[b][be], c.r[al]));
        for (std::size_t a = 0; a < m; ++a)
          e = expr::add(e, expr::sub(expr::mul(c.a[a][al], expr::diff(c.a[b][be], c.s[a])),
                                     expr::mul(c.a[a][be], expr::diff(c.a[b][al], c.s[a]))));
        out[b][al][be] = e;
      }
  return out;
}

/// YM (5.9), literally: B_P^♯ at a point y = (q, p̃) of P = FL(Δ_Q), the (2n − m) × (2n − m) matrix in the
/// coordinates (r^α, s^a, p̃_α) of P —
///   [[0, 0, δ], [0, 0, −A^a_β], [−δ, (A^b_α)ᵀ, −p_b K^b_{αβ}]],
/// from the connection's A^b_α(q) (`a`: m × (n − m)), its curvature K^b_{αβ}(q) (`k[b]`: (n − m) × (n − m),
/// skew) and p_b = ∂L/∂w^b at y (`p_s`), all evaluated at q.  YM's own disk (§6) prints the (p̃_1, p̃_2) entry
/// as +p_b K^b_12; (5.9) and the bracket {p̃_1, p̃_2} of B = the canonical Poisson tensor say −p_b K^b_12
/// (ERRATA).  std::invalid_argument on sizes or a K that is not skew.
inline Matrix<Rational> constrained_poisson_tensor(const Matrix<Rational>& a, const std::vector<Matrix<Rational>>& k,
                                                   const std::vector<Rational>& p_s) {
  const Index m = a.rows(), d = a.cols(), n = 2 * d + m;
  if (k.size() != m || p_s.size() != m)
    throw std::invalid_argument("constrained_poisson_tensor: expected K and p_s with one entry per fibre coordinate (" +
                                std::to_string(m) + "), found " + std::to_string(k.size()) + " and " +
                                std::to_string(p_s.size()));
  Matrix<Rational> b(n, n);
  for (Index al = 0; al < d; ++al) {
    b(al, d + m + al) = 1;  // {r^α, p̃_β} = δ^α_β
    b(d + m + al, al) = -1;
  }
  for (Index s = 0; s < m; ++s) {
    if (k[s].rows() != d || k[s].cols() != d)
      throw std::invalid_argument("constrained_poisson_tensor: expected K^" + std::to_string(s + 1) + " of " +
                                  std::to_string(d) + " × " + std::to_string(d) + ", found " +
                                  std::to_string(k[s].rows()) + " × " + std::to_string(k[s].cols()));
    for (Index be = 0; be < d; ++be) {
      b(d + s, d + m + be) = -a(s, be);  // {s^a, p̃_β} = −A^a_β
      b(d + m + be, d + s) = a(s, be);   // (A^b_α)ᵀ
    }
  }
  for (Index al = 0; al < d; ++al)
    for (Index be = 0; be < d; ++be) {
      Rational pk = 0;
      for (Index s = 0; s < m; ++s) {
        if (k[s](al, be) != -k[s](be, al))
          throw std::invalid_argument("constrained_poisson_tensor: expected a skew curvature K^" +
                                      std::to_string(s + 1) + ", found K(" + std::to_string(al + 1) + ", " +
                                      std::to_string(be + 1) + ") = " + k[s](al, be).str() + " against " +
                                      k[s](be, al).str());
        pk += p_s[s] * k[s](al, be);
      }
      b(d + m + al, d + m + be) = -pk;  // −p_b K^b_{αβ}
    }
  return b;
}

/// YM (5.10): {F_P, G_P}_P = dF_P · B_P^♯ dG_P, with dF, dG in P's coordinates (r, s, p̃).
inline Rational constrained_bracket(const Matrix<Rational>& bp, const std::vector<Rational>& df,
                                    const std::vector<Rational>& dg) {
  if (df.size() != bp.rows() || dg.size() != bp.cols())
    throw std::invalid_argument("constrained_bracket: expected differentials of " + std::to_string(bp.rows()) +
                                " entries, found " + std::to_string(df.size()) + " and " + std::to_string(dg.size()));
  Rational out = 0;
  for (Index i = 0; i < bp.rows(); ++i)
    for (Index j = 0; j < bp.cols(); ++j) out += df[i] * bp(i, j) * dg[j];
  return out;
}

/// L_c(r, s, u) = L(r, s, u, −A(r, s) u): the Lagrangian restricted to Δ, with u = v_r  [YM §5].
inline expr::Expr constrained_lagrangian(const LagrangianSystem& sys, const EhresmannConnection& c) {
  expr::Expr l = sys.lagrangian;
  for (std::size_t b = 0; b < c.s.size(); ++b) {
    expr::Expr w = expr::number(0);
    for (std::size_t al = 0; al < c.r.size(); ++al)
      w = expr::sub(w, expr::mul(c.a[b][al], expr::variable(sys.v(c.r[al]))));
    l = expr::substitute(l, sys.v(c.s[b]), w);
  }
  return l;
}

/// The residuals of YM (5.6) at x = (q, v, p) with v ∈ Δ, for a motion with d/dt (q, v) = (q̇, v̇):
///   ṡ + A ṙ,   ṙ − u,   d/dt p̃_α − (∂L_c/∂r^α − A^b_α ∂L_c/∂s^b − p_b K^b_{αβ} u^β),
/// with p̃_α = ∂L_c/∂u^α along the motion and p_b = ∂L/∂w^b (w = v_s) at (q, v).  All zero on a
/// solution of the implicit constrained Lagrangian system (YM Thm 5.6 (a) ⇔ (c)).
inline std::vector<Rational> implicit_lagrange_dalembert_residual(const LagrangianSystem& sys,
                                                                  const EhresmannConnection& c,
                                                                  const std::vector<Rational>& qv,
                                                                  const std::vector<Rational>& qv_dot) {
  const std::size_t n = sys.n, m = c.s.size(), k = c.r.size();
  auto sp = std::make_shared<const JetSpace>(1, 1);  // first-order jets along the motion: value + ε d/dt
  std::vector<Jet<Rational>> x;
  for (std::size_t i = 0; i < 2 * n; ++i) {
    Jet<Rational> j = Jet<Rational>::variable(sp, 0, qv[i]);
    j.set_coefficient(1, qv_dot[i]);
    x.push_back(j);
  }
  x.emplace_back(sp, Rational(0));
  const auto ev = [&](const expr::Expr& e) {
    return expr::evaluate<Jet<Rational>>(e, x, [&](const Rational& q) { return Jet<Rational>(sp, q); });
  };
  const expr::Expr lc = constrained_lagrangian(sys, c);
  const auto kk = curvature(c);
  std::vector<Rational> res;
  for (std::size_t b = 0; b < m; ++b) {  // ṡ^b = −A^b_α ṙ^α
    Rational r = qv_dot[c.s[b]];
    for (std::size_t al = 0; al < k; ++al) r += ev(c.a[b][al]).value() * qv_dot[c.r[al]];
    res.push_back(r);
  }
  for (std::size_t al = 0; al < k; ++al) res.push_back(qv_dot[c.r[al]] - qv[sys.v(c.r[al])]);  // ṙ = u
  std::vector<Rational> pb;
  for (std::size_t b = 0; b < m; ++b) pb.push_back(ev(expr::diff(sys.lagrangian, sys.v(c.s[b]))).value());
  for (std::size_t al = 0; al < k; ++al) {
    Rational rhs = ev(expr::diff(lc, c.r[al])).value();
    for (std::size_t b = 0; b < m; ++b) rhs -= ev(c.a[b][al]).value() * ev(expr::diff(lc, c.s[b])).value();
    for (std::size_t b = 0; b < m; ++b)
      for (std::size_t be = 0; be < k; ++be) rhs -= pb[b] * ev(kk[b][al][be]).value() * qv[sys.v(c.r[be])];
    res.push_back(ev(expr::diff(lc, sys.v(c.r[al]))).gradient(0) - rhs);  // d/dt p̃_α − rhs
  }
  return res;
}

/// dω^b(v, w) for each fibre index b, by the definition of the exterior derivative of the connection's
/// one-forms ω^b = ds^b + A^b_α(q) dr^α: dω^b = Σ_{α,i} ∂A^b_α/∂q^i dq^i ∧ dr^α, so
///   dω^b(v, w) = Σ_{α,i} ∂A^b_α/∂q^i (q) (v^i w^{r_α} − w^i v^{r_α})   [YM Prop 5.1, the right side of (5.7)].
/// `q` the point (its first n entries are read), v and w tangent vectors at q (n each, the system's order).
/// The proof of Prop 5.1 says dω^b(v, ·) = K^b_{αβ} u^β dr^α on Δ (u = v_r): prop_ehresmann holds it.
inline std::vector<Rational> connection_form_differential(const EhresmannConnection& c, const std::vector<Rational>& q,
                                                          const std::vector<Rational>& v,
                                                          const std::vector<Rational>& w) {
  const std::size_t m = c.s.size(), k = c.r.size(), n = m + k;
  if (v.size() != n || w.size() != n || q.size() < n)
    throw std::invalid_argument("connection_form_differential: expected q of at least " + std::to_string(n) +
                                " and v, w of " + std::to_string(n) + " entries, found " + std::to_string(q.size()) +
                                ", " + std::to_string(v.size()) + ", " + std::to_string(w.size()));
  std::vector<Rational> out(m, Rational(0));
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < k; ++al)
      for (std::size_t i = 0; i < n; ++i)
        out[b] += value_at(expr::diff(c.a[b][al], i), q) * (v[i] * w[c.r[al]] - w[i] * v[c.r[al]]);
  return out;
}

/// The horizontal lift hor y = (y on r, −A(q) y on s) of y ∈ R^{n − m} at q: the vector of Δ over y  [YM §5].
inline std::vector<Rational> horizontal_lift(const EhresmannConnection& c, const std::vector<Rational>& q,
                                             const std::vector<Rational>& y) {
  const std::size_t m = c.s.size(), k = c.r.size();
  if (y.size() != k)
    throw std::invalid_argument("horizontal_lift: expected " + std::to_string(k) + " base components, found " +
                                std::to_string(y.size()));
  std::vector<Rational> out(m + k, Rational(0));
  for (std::size_t al = 0; al < k; ++al) out[c.r[al]] = y[al];
  for (std::size_t b = 0; b < m; ++b)
    for (std::size_t al = 0; al < k; ++al) out[c.s[b]] -= value_at(c.a[b][al], q) * y[al];
  return out;
}

/// YM Prop 5.1, (5.7), literally: with F(r, s, u, ṙ, p̃) = L_c(r, s, u) + p̃_α (ṙ^α − u^α), the first variation
/// δ∫F dt over variations tangent to Δ (δs = −A δr; δṙ integrated by parts) less its right side
/// p_b dω^b(v, δq), as coefficients of δr^α, δu^α and δp̃_α:
///   dr_α = ∂F/∂r^α − A^a_α ∂F/∂s^a − d/dt ∂F/∂ṙ^α − p_b dω^b(v, hor e_α),   du_α = ∂F/∂u^α,   dp_α = ∂F/∂p̃_α,
/// at x = (q, v), v ∈ Δ (u = v_r), with p̃ = `p_tilde`, d/dt p̃ = `p_tilde_dot`, ṙ from `q_dot`, p_b = ∂L/∂w^b
/// (w = v_s) at (q, v), dω by connection_form_differential.  (5.7) holds for all variations iff all vanish.
struct LdapVariation {
  std::vector<Rational> dr, du, dp;
};
inline LdapVariation ldap_variation(const LagrangianSystem& sys, const EhresmannConnection& c,
                                    const std::vector<Rational>& qv, const std::vector<Rational>& q_dot,
                                    const std::vector<Rational>& p_tilde, const std::vector<Rational>& p_tilde_dot) {
  const std::size_t m = c.s.size(), k = c.r.size(), n = sys.n;
  if (qv.size() != 2 * n || q_dot.size() != n || p_tilde.size() != k || p_tilde_dot.size() != k)
    throw std::invalid_argument("ldap_variation: expected (q, v) of " + std::to_string(2 * n) + ", q̇ of " +
                                std::to_string(n) + ", p̃ and its rate of " + std::to_string(k) + " entries");
  std::vector<Rational> at(qv);
  at.push_back(Rational(0));  // t
  const expr::Expr lc = constrained_lagrangian(sys, c);
  const std::vector<Rational> vel(qv.begin() + static_cast<long>(n), qv.end());
  std::vector<Rational> pb;
  for (std::size_t b = 0; b < m; ++b) pb.push_back(value_at(expr::diff(sys.lagrangian, sys.v(c.s[b])), at));
  LdapVariation out;
  for (std::size_t al = 0; al < k; ++al) {
    Rational d = value_at(expr::diff(lc, c.r[al]), at) - p_tilde_dot[al];
    for (std::size_t a = 0; a < m; ++a) d -= value_at(c.a[a][al], at) * value_at(expr::diff(lc, c.s[a]), at);
    std::vector<Rational> e(k, Rational(0));
    e[al] = 1;
    const std::vector<Rational> dw = connection_form_differential(c, at, vel, horizontal_lift(c, at, e));
    for (std::size_t b = 0; b < m; ++b) d -= pb[b] * dw[b];
    out.dr.push_back(d);
    out.du.push_back(value_at(expr::diff(lc, sys.v(c.r[al])), at) - p_tilde[al]);
    out.dp.push_back(q_dot[c.r[al]] - qv[sys.v(c.r[al])]);
  }
  return out;
}

/// YM §5, after Prop 5.1: the constrained energy E_c(r, s, u, p̃) = p̃_α u^α − L_c(r, s, u) at (q, v) (u = v_r)
/// and p̃.
inline Rational constrained_energy(const LagrangianSystem& sys, const EhresmannConnection& c,
                                   const std::vector<Rational>& qv, const std::vector<Rational>& p_tilde) {
  if (qv.size() != 2 * sys.n || p_tilde.size() != c.r.size())
    throw std::invalid_argument("constrained_energy: expected (q, v) of " + std::to_string(2 * sys.n) + " and p̃ of " +
                                std::to_string(c.r.size()) + " entries");
  std::vector<Rational> at(qv);
  at.push_back(Rational(0));
  Rational e = -value_at(constrained_lagrangian(sys, c), at);
  for (std::size_t al = 0; al < c.r.size(); ++al) e += p_tilde[al] * qv[sys.v(c.r[al])];
  return e;
}

/// e with sin(x_i) and cos(x_i) of the variables i in `angles` replaced by the variables sin_var[i]
/// and cos_var[i]: formulas in which each angle occurs only under sin and cos can then be evaluated
/// exactly at rational points of the circle (cos, sin) = ((1 − t²)/(1 + t²), 2t/(1 + t²)).
inline expr::Expr angles_as_variables(const expr::Expr& e, const std::vector<std::size_t>& angles,
                                      const std::vector<std::size_t>& sin_var,
                                      const std::vector<std::size_t>& cos_var) {
  using expr::ExprOp;
  for (std::size_t k = 0; k < angles.size(); ++k)
    if ((e->op == ExprOp::Sin || e->op == ExprOp::Cos) && e->a->op == ExprOp::Variable && e->a->var == angles[k])
      return expr::variable(e->op == ExprOp::Sin ? sin_var[k] : cos_var[k]);
  switch (e->op) {
    case ExprOp::Number:
    case ExprOp::Variable: return e;
    case ExprOp::Add:
      return expr::add(angles_as_variables(e->a, angles, sin_var, cos_var),
                       angles_as_variables(e->b, angles, sin_var, cos_var));
    case ExprOp::Sub:
      return expr::sub(angles_as_variables(e->a, angles, sin_var, cos_var),
                       angles_as_variables(e->b, angles, sin_var, cos_var));
    case ExprOp::Mul:
      return expr::mul(angles_as_variables(e->a, angles, sin_var, cos_var),
                       angles_as_variables(e->b, angles, sin_var, cos_var));
    case ExprOp::Div:
      return expr::div(angles_as_variables(e->a, angles, sin_var, cos_var),
                       angles_as_variables(e->b, angles, sin_var, cos_var));
    case ExprOp::Neg: return expr::neg(angles_as_variables(e->a, angles, sin_var, cos_var));
    case ExprOp::Pow: return expr::pow(angles_as_variables(e->a, angles, sin_var, cos_var), e->exponent);
    case ExprOp::Sin: return expr::sin(angles_as_variables(e->a, angles, sin_var, cos_var));
    case ExprOp::Cos: return expr::cos(angles_as_variables(e->a, angles, sin_var, cos_var));
    case ExprOp::Exp: return expr::exp(angles_as_variables(e->a, angles, sin_var, cos_var));
    case ExprOp::Sqrt: return expr::sqrt(angles_as_variables(e->a, angles, sin_var, cos_var));
  }
  throw std::logic_error("angles_as_variables: unknown operation");
}

}  // namespace dcad::reference
