// A Lagrangian system given by formulas (the CONTRACT's expression form): L(t, q, v) on TQ, affine
// constraints a(t, q)·v + b(t, q) = 0 defining Δ(t, q) (ideal, reactions in Δ°), and an external
// force F(t, q, v) (YM §4).  On M = TQ ⊕ T*Q, x = (q, v, p), E = p·v − L and the Dirac structure
// D̄_Δ of CEF §6 (YM §3): (ẋ, dE − F) ∈ D̄_Δ  ⟺  q̇ ∈ Δ_aff, p = ∂L/∂v, q̇ = v, ṗ − ∂L/∂q − F ∈ Δ°.
//
// Variable indices in every expression: q_0…q_{n−1} are 0…n−1, v_0…v_{n−1} are n…2n−1, and the
// time t (if the system has one) is 2n.
#pragma once

#include "dcad/symbolic/expression.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::symbolic {

/// Thrown when a point cannot be completed to a point of M_c (the exact route at a point with
/// irrational coordinates, or given values that conflict with a constraint), by every route that completes one.
struct PointwiseNoPoint : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct LagrangianSystem {
  std::size_t n = 0;
  bool has_time = false;
  /// The CONTRACT's `implicit` form instead: the implicit differential equation φ(t, q, q̇) = 0 on Q
  /// itself (CEF (1.6), M_0 = Q), each φ_a affine in q̇ — `constraints` are the φ_a (any number),
  /// there is no L, no force, no momentum and no multiplier λ: the state is q alone.
  bool implicit = false;
  std::vector<std::string> names;  ///< the n coordinate names
  std::string time_name = "t";
  expr::Expr lagrangian;
  std::vector<expr::Expr> constraints;  ///< m expressions, each affine in v
  std::vector<expr::Expr> forces;       ///< n expressions (empty: no force)

  std::size_t m() const { return constraints.size(); }
  std::size_t q(std::size_t i) const { return i; }
  std::size_t v(std::size_t i) const { return n + i; }
  std::size_t t() const { return 2 * n; }
  /// Names of the expression variables: q names, v_<name>, then the time.
  std::vector<std::string> variable_names() const {
    std::vector<std::string> out = names;
    for (const std::string& s : names) out.push_back("v_" + s);
    out.push_back(time_name);
    return out;
  }
  /// Names of M's coordinates x = (q, v, p) (the implicit form: q).
  std::vector<std::string> state_names() const {
    if (implicit) return names;
    std::vector<std::string> out = variable_names();
    out.pop_back();
    for (const std::string& s : names) out.push_back("p_" + s);
    return out;
  }
};

/// The derived objects every route uses, by symbolic differentiation of the formulas:
/// ∂L/∂q_i, ∂L/∂v_i, and the constraints as a(t, q)·v + b(t, q): a_{ai} = ∂c_a/∂v_i, b_a = c_a(v = 0).
struct LagrangianDerivatives {
  std::vector<expr::Expr> dl_dq, dl_dv;
  std::vector<std::vector<expr::Expr>> a;
  std::vector<expr::Expr> b;
};

/// The index of the first constraint that is not affine in the velocities, or m if all are
/// (CONTRACT: such a constraint is bad input).
inline std::size_t first_non_affine_constraint(const LagrangianSystem& s) {
  const auto is_velocity = [&](std::size_t i) { return i >= s.n && i < 2 * s.n; };
  for (std::size_t a = 0; a < s.m(); ++a) {
    const long d = expr::degree_in(s.constraints[a], is_velocity);
    if (d < 0 || d > 1) return a;
  }
  return s.m();
}

inline LagrangianDerivatives derivatives(const LagrangianSystem& s) {
  LagrangianDerivatives d;
  for (std::size_t i = 0; i < s.n; ++i) {
    d.dl_dq.push_back(expr::diff(s.lagrangian, s.q(i)));
    d.dl_dv.push_back(expr::diff(s.lagrangian, s.v(i)));
  }
  for (const expr::Expr& c : s.constraints) {
    std::vector<expr::Expr> row;
    expr::Expr b = c;
    for (std::size_t i = 0; i < s.n; ++i) {
      row.push_back(expr::diff(c, s.v(i)));
      b = expr::substitute(b, s.v(i), expr::number(0));
    }
    d.a.push_back(row);
    d.b.push_back(b);
  }
  return d;
}

}  // namespace dcad::symbolic
