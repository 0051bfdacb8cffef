// V's objects at a point z of the constraint submanifold 𝒜 ⊂ j₁(𝒱_{n+1}), literally, in exact arithmetic
// (the data: dcad/vignolo_data.hpp; coordinates (t, q, q̇) on j₁ and (t, q, q̇, u̇) on the Lagrangian bundle):
//   the contact forms ω^i = dq^i − q̇^i dt and the dynamical flows (SODEs) j₂ at z  [V §2.1, (2.1)–(2.3)];
//   the contact bundle C(j₁) as the annihilator of the distribution j₂ generates  [V §2.1];
//   (2.7b)'s velocities q̇ = ψ_A z^A + ψ_0 of 𝒜 over π(z), τ(𝒜) (2.9) and V(𝒜)  [V (2.7b)–(2.10)];
//   the Chetaev bundle χ(𝒜) = {ν_i ω̃^i : ν_i ψ^i_A = 0}  [V (2.11)];
//   the Poincaré–Cartan form Ω_l by V §3.4's coordinate expression, the Lagrangian bundle's Ω̃_l (2.19), the
//   section l: u̇ = L, its trivialization φ_l = u̇ − L and horizontal lift (2.17), J̃ (2.18)  [V §2.2];
//   the non-holonomic problems (2.13) on 𝒜 and (3.3) on 𝓛(𝒜), each with or without (3.9)  [V §2.1, §3.1–3.2];
//   the unconstrained problem (2.20) and the decomposition (3.7) with its projector 𝒫  [V Prop 3.1, Thm 3.1];
//   the algorithm's first step at z ∈ M_0: M_1 by (3.12) and (3.15)'s directions  [V §3.3];
//   𝒪_l = ker Ω_l ∩ V(D^v) and its lift 𝒪̃_l = l_*(𝒪_l)  [V §3.4, (3.17), (3.21)].
// Covectors are rows in the same coordinates; Ω(X, Y) = Xᵀ W Y and X ⌟ Ω = Wᵀ X (symplectic.hpp's flat).
#pragma once

#include "dcad/reference/symplectic.hpp"
#include "dcad/vignolo_data.hpp"

namespace dcad::reference {

template <class T>
using VignoloPoint = VignoloData<T, Matrix<T>, std::vector<T>>;  // dcad/vignolo_data.hpp

template <class T>
void require_vignolo(const VignoloPoint<T>& d, const std::string& fn) {
  const Index n = d.n, m = d.g.rows();
  const auto vec = [&](const std::vector<T>& v, Index len, const char* name) {
    require(v.size() == len, fn, std::string(name) + " of length " + std::to_string(len),
            "length " + std::to_string(v.size()));
  };
  vec(d.qdot, n, "qdot");
  vec(d.lq, n, "lq");
  vec(d.lv, n, "lv");
  vec(d.ltv, n, "ltv");
  const std::string sq = std::to_string(n) + "x" + std::to_string(n);
  require(d.lqv.rows() == n && d.lqv.cols() == n, fn, "lqv " + sq, shape(d.lqv));
  require(d.lvv.rows() == n && d.lvv.cols() == n, fn, "lvv " + sq, shape(d.lvv));
  require(is_symmetric(d.lvv), fn, "a symmetric lvv (second derivatives)", "an asymmetric one");
  require(m == 0 || d.g.cols() == n, fn, "g with " + std::to_string(n) + " columns", shape(d.g));
  require(m == 0 || rank(d.g) == m, fn, "independent constraints (rank g = rows, V (2.6))",
          "rank " + std::to_string(m ? rank(d.g) : 0) + " of " + std::to_string(m) + " rows");
  vec(d.g0, m, "g0");
  vec(d.phi_t, m, "phi_t");
  require(m == 0 ? d.phi_q.rows() == 0 : (d.phi_q.rows() == m && d.phi_q.cols() == n), fn,
          "phi_q " + std::to_string(m) + "x" + std::to_string(n), shape(d.phi_q));
  for (Index s = 0; s < m; ++s) {
    T phi = d.g0[s];
    for (Index i = 0; i < n; ++i) phi += d.g(s, i) * d.qdot[i];
    require(phi == 0, fn, "z on the constraint submanifold (g q̇ + g0 = 0, V (2.7a))",
            "constraint " + std::to_string(s) + " = " + phi.str());
  }
}

namespace vignolo_detail {

/// The covector a bᵀ − b aᵀ: (α ∧ β)(X, Y) = α(X) β(Y) − β(X) α(Y) as Xᵀ W Y.
template <class T>
Matrix<T> wedge(const std::vector<T>& a, const std::vector<T>& b) {
  Matrix<T> w(a.size(), a.size());
  for (Index i = 0; i < a.size(); ++i)
    for (Index j = 0; j < a.size(); ++j) w(i, j) = a[i] * b[j] - b[i] * a[j];
  return w;
}
template <class T>
void add(Matrix<T>& w, const Matrix<T>& x, const T& c = T(1)) {
  for (Index i = 0; i < w.rows(); ++i)
    for (Index j = 0; j < w.cols(); ++j) w(i, j) += c * x(i, j);
}
template <class T>
std::vector<T> unit(Index dim, Index i) {
  std::vector<T> e(dim);
  e[i] = T(1);
  return e;
}
/// ω^i = dq^i − q̇^i dt on a space of dimension `dim` ≥ 2n + 1 (coordinates t, q, q̇, …).
template <class T>
std::vector<T> omega(const VignoloPoint<T>& d, Index i, Index dim) {
  std::vector<T> w = unit<T>(dim, 1 + i);
  w[0] = -d.qdot[i];
  return w;
}
/// The covector a dt + b_j dq^j + c_j dq̇^j on a space of dimension `dim`.
template <class T>
std::vector<T> covector(Index dim, const T& a, const std::vector<T>& b, const std::vector<T>& c) {
  std::vector<T> w(dim);
  w[0] = a;
  for (Index j = 0; j < b.size(); ++j) {
    w[1 + j] = b[j];
    w[1 + b.size() + j] = c[j];
  }
  return w;
}
/// dp_i = ∂²L/∂t∂q̇^i dt + ∂²L/∂q^j∂q̇^i dq^j + ∂²L/∂q̇^j∂q̇^i dq̇^j.
template <class T>
std::vector<T> dp(const VignoloPoint<T>& d, Index i, Index dim) {
  return covector(dim, d.ltv[i], d.lqv.row(i), d.lvv.row(i));
}
/// dφ^σ = ∂φ^σ/∂t dt + ∂φ^σ/∂q^j dq^j + g^σ_i dq̇^i.
template <class T>
std::vector<T> dphi(const VignoloPoint<T>& d, Index s, Index dim) {
  return covector(dim, d.phi_t[s], d.phi_q.row(s), d.g.row(s));
}
/// The dφ^σ as rows.
template <class T>
Matrix<T> dphi_rows(const VignoloPoint<T>& d, Index dim) {
  Matrix<T> a(d.g.rows(), dim);
  for (Index s = 0; s < a.rows(); ++s) {
    const std::vector<T> w = dphi(d, s, dim);
    for (Index j = 0; j < dim; ++j) a(s, j) = w[j];
  }
  return a;
}
/// The first `k` coordinates of an affine subspace (a projection π_*).
template <class T>
AffineSubspace<T> head(const AffineSubspace<T>& a, Index k) {
  AffineSubspace<T> out;
  Matrix<T> p(k, a.direction.ambient());
  for (Index i = 0; i < k; ++i) p(i, i) = T(1);
  out.empty = a.empty;
  out.direction = map(p, a.direction);
  if (!a.empty) out.point.assign(a.point.begin(), a.point.begin() + static_cast<std::ptrdiff_t>(k));
  return out;
}
/// {X : X ⌟ W + β ∈ span(rows) on the whole space, and eq X = rhs}: unknowns (X, multipliers).
template <class T>
AffineSubspace<T> flat_modulo(const Matrix<T>& w, const std::vector<T>& beta, const Matrix<T>& rows,
                              const Matrix<T>& eq, const std::vector<T>& rhs) {
  const Index dim = w.rows(), k = rows.rows();
  Matrix<T> a(dim + eq.rows(), dim + k);
  std::vector<T> b(dim + eq.rows());
  for (Index i = 0; i < dim; ++i) {  // Wᵀ X − Σ c_s rows_s = −β
    for (Index j = 0; j < dim; ++j) a(i, j) = w(j, i);
    for (Index s = 0; s < k; ++s) a(i, dim + s) = -rows(s, i);
    b[i] = -beta[i];
  }
  for (Index r = 0; r < eq.rows(); ++r) {
    for (Index j = 0; j < dim; ++j) a(dim + r, j) = eq(r, j);
    b[dim + r] = rhs[r];
  }
  return head(solve(a, b), dim);
}

}  // namespace vignolo_detail

/// The contact forms ω^i = dq^i − q̇^i dt at z, one per row (n × (2n+1))  [V §2.1].
template <class T>
Matrix<T> contact_forms(const VignoloPoint<T>& d) {
  require_vignolo(d, "contact_forms");
  Matrix<T> c(d.n, 2 * d.n + 1);
  for (Index i = 0; i < d.n; ++i) {
    const std::vector<T> w = vignolo_detail::omega(d, i, 2 * d.n + 1);
    for (Index j = 0; j < w.size(); ++j) c(i, j) = w[j];
  }
  return c;
}

/// j₂ at z, the dynamical flows' values: {X : ⟨X, dt⟩ = 1, ⟨X, ω^i⟩ = 0}  [V (2.2)–(2.3), (2.9) without 𝒜].
template <class T>
AffineSubspace<T> dynamical_flows(const VignoloPoint<T>& d) {
  const Matrix<T> eq =
      vstack(Matrix<T>::from_rows({vignolo_detail::unit<T>(2 * d.n + 1, 0)}, 2 * d.n + 1), contact_forms(d));
  std::vector<T> rhs(eq.rows());
  rhs[0] = T(1);
  return solve(eq, rhs);
}

/// The contact bundle C_z(j₁): the annihilator of the (n+1)-dimensional distribution j₂ generates  [V §2.1].
template <class T>
Subspace<T> contact_bundle(const VignoloPoint<T>& d) {
  const AffineSubspace<T> j2 = dynamical_flows(d);
  return annihilator(Subspace<T>::span(vstack(Matrix<T>::from_rows({j2.point}, 2 * d.n + 1), j2.direction.basis())));
}

/// 𝒜's velocities over π(z), q̇ = ψ_A z^A + ψ_0 with g ψ_A = 0 (2.8): {v : g v + g0 = 0}  [V (2.7b)].
template <class T>
AffineSubspace<T> constraint_velocities(const VignoloPoint<T>& d) {
  require_vignolo(d, "constraint_velocities");
  std::vector<T> rhs(d.g.rows());
  for (Index s = 0; s < rhs.size(); ++s) rhs[s] = -d.g0[s];
  return d.g.rows() ? solve(d.g, rhs) : solve(Matrix<T>(0, d.n), rhs);
}

/// T_z𝒜 = ker dφ, the differentials of (2.7a) at z (j₁ coordinates).
template <class T>
Subspace<T> constraint_tangent(const VignoloPoint<T>& d) {
  require_vignolo(d, "constraint_tangent");
  return kernel(vignolo_detail::dphi_rows(d, 2 * d.n + 1));
}

/// τ_z(𝒜) = {X ∈ T_z𝒜 : ⟨X, dt⟩ = 1, ⟨X, ω̃^i⟩ = 0}  [V (2.9)]; its direction is V_z(𝒜)  [V §2.1].
template <class T>
AffineSubspace<T> tau_constraint(const VignoloPoint<T>& d) {
  const Matrix<T> eq =
      vstack(annihilator(constraint_tangent(d)).basis(),
             vstack(Matrix<T>::from_rows({vignolo_detail::unit<T>(2 * d.n + 1, 0)}, 2 * d.n + 1), contact_forms(d)));
  std::vector<T> rhs(eq.rows());
  rhs[eq.rows() - d.n - 1] = T(1);
  return solve(eq, rhs);
}

/// χ_z(𝒜) = {ν_i ω̃^i : ν_i ψ^i_A = 0 ∀A}, the Chetaev bundle as covectors on j₁  [V (2.11)].
template <class T>
Subspace<T> chetaev_bundle(const VignoloPoint<T>& d) {
  const Subspace<T> psi = constraint_velocities(d).direction;  // the ψ_A
  const Subspace<T> nu = annihilator(psi);                     // the ν with ν·ψ_A = 0
  return map(contact_forms(d).transpose(), nu);                // ν ↦ ν_i ω^i
}

/// Ω_l by V §3.4's coordinate expression: ∂L/∂q^i dq^i∧dt + ∂²L/∂t∂q̇^i dt∧ω^i + ∂²L/∂q^j∂q̇^i dq^j∧ω^i
/// + ∂²L/∂q̇^j∂q̇^i dq̇^j∧ω^i  [V §3.4; Ω_l = d(L dt + ∂L/∂q̇^i ω^i), §2.1].
template <class T>
Matrix<T> poincare_cartan(const VignoloPoint<T>& d) {
  require_vignolo(d, "poincare_cartan");
  using namespace vignolo_detail;
  const Index n = d.n, dim = 2 * n + 1;
  Matrix<T> w(dim, dim);
  const std::vector<T> dt = unit<T>(dim, 0);
  for (Index i = 0; i < n; ++i) {
    const std::vector<T> om = omega(d, i, dim);
    add(w, wedge(unit<T>(dim, 1 + i), dt), d.lq[i]);
    add(w, wedge(dt, om), d.ltv[i]);
    for (Index j = 0; j < n; ++j) {
      add(w, wedge(unit<T>(dim, 1 + j), om), d.lqv(i, j));
      add(w, wedge(unit<T>(dim, 1 + n + j), om), d.lvv(j, i));
    }
  }
  return w;
}

/// Ω̃_l = du̇ ∧ dt + d(∂L/∂q̇^i) ∧ ω^i − ∂L/∂q̇^i dq̇^i ∧ dt on 𝓛(𝒱_{n+1})  [V (2.19)].
template <class T>
Matrix<T> lagrangian_bundle_form(const VignoloPoint<T>& d) {
  require_vignolo(d, "lagrangian_bundle_form");
  using namespace vignolo_detail;
  const Index n = d.n, dim = 2 * n + 2;
  const std::vector<T> dt = unit<T>(dim, 0);
  Matrix<T> w = wedge(unit<T>(dim, dim - 1), dt);
  for (Index i = 0; i < n; ++i) {
    add(w, wedge(dp(d, i, dim), omega(d, i, dim)));
    add(w, wedge(unit<T>(dim, 1 + n + i), dt), T(-d.lv[i]));
  }
  return w;
}

/// dL at z over (t, q, q̇).
template <class T>
std::vector<T> lagrangian_differential(const VignoloPoint<T>& d) {
  require_vignolo(d, "lagrangian_differential");
  std::vector<T> dl(2 * d.n + 1);
  dl[0] = d.lt;
  for (Index i = 0; i < d.n; ++i) {
    dl[1 + i] = d.lq[i];
    dl[1 + d.n + i] = d.lv[i];
  }
  return dl;
}

/// l_*: T_z j₁ → T 𝓛 for the section l: u̇ = L  [V §2.2]; ((2n+2) × (2n+1)).
template <class T>
Matrix<T> section_tangent(const VignoloPoint<T>& d) {
  require_vignolo(d, "section_tangent");
  const Index dim = 2 * d.n + 1;
  Matrix<T> s(dim + 1, dim);
  for (Index i = 0; i < dim; ++i) s(i, i) = T(1);
  const std::vector<T> dl = lagrangian_differential(d);
  for (Index j = 0; j < dim; ++j) s(dim, j) = dl[j];
  return s;
}

/// dφ_l = du̇ − dL, the differential of the trivialization φ_l = u̇ − L  [V §2.2].
template <class T>
std::vector<T> trivialization_differential(const VignoloPoint<T>& d) {
  std::vector<T> w(2 * d.n + 2);
  const std::vector<T> dl = lagrangian_differential(d);
  for (Index j = 0; j < dl.size(); ++j) w[j] = -dl[j];
  w[2 * d.n + 1] = T(1);
  return w;
}

/// The horizontal lift X_l = X + X(L) ∂/∂u̇ of X ∈ T_z j₁  [V (2.17)].
template <class T>
std::vector<T> bundle_horizontal_lift(const VignoloPoint<T>& d, const std::vector<T>& x) {
  require(x.size() == 2 * d.n + 1, "bundle_horizontal_lift", "X of length 2n + 1",
          "length " + std::to_string(x.size()));
  return (section_tangent(d) * Matrix<T>::column(x)).col(0);
}

/// J̃(X) = ⟨X, ω^i⟩ (∂L/∂q̇^i ∂/∂u̇ + ∂/∂q̇^i) for X ∈ T𝓛  [V (2.18)].
template <class T>
std::vector<T> vertical_endomorphism(const VignoloPoint<T>& d, const std::vector<T>& x) {
  require_vignolo(d, "vertical_endomorphism");
  require(x.size() == 2 * d.n + 2, "vertical_endomorphism", "X of length 2n + 2", "length " + std::to_string(x.size()));
  std::vector<T> out(x.size());
  for (Index i = 0; i < d.n; ++i) {
    T c(0);
    const std::vector<T> om = vignolo_detail::omega(d, i, x.size());
    for (Index j = 0; j < x.size(); ++j) c += om[j] * x[j];
    out[1 + d.n + i] += c;
    out[2 * d.n + 1] += c * d.lv[i];
  }
  return out;
}

/// The differentials dφ^σ on 𝓛 (rows; T𝓛(𝒜) is their kernel) and the Chetaev forms ν^σ = −g^σ_i ω^i,
/// a basis of χ̂(𝒜) (V §3.1, before (3.6)); each m × (2n+2).
template <class T>
Matrix<T> bundle_constraint_differentials(const VignoloPoint<T>& d) {
  require_vignolo(d, "bundle_constraint_differentials");
  return vignolo_detail::dphi_rows(d, 2 * d.n + 2);
}
template <class T>
Matrix<T> chetaev_forms(const VignoloPoint<T>& d) {
  require_vignolo(d, "chetaev_forms");
  Matrix<T> a(d.g.rows(), 2 * d.n + 2);
  for (Index s = 0; s < a.rows(); ++s)
    for (Index i = 0; i < d.n; ++i) {
      const std::vector<T> om = vignolo_detail::omega(d, i, 2 * d.n + 2);
      for (Index j = 0; j < om.size(); ++j) a(s, j) -= d.g(s, i) * om[j];
    }
  return a;
}

/// The solutions at z of (2.13): Z ⌟ Ω_l at z in χ(𝒜), ⟨Z, dt⟩ = 1, Z(φ^σ) = 0, and with `chetaev_condition`
/// also (3.9): ⟨Z, ν⟩ = 0 for ν ∈ χ(𝒜)  [V (2.13), (3.9)].  "|_𝒜" is the form along 𝒜, a section of T*j₁
/// over 𝒜 (χ(𝒜) = D^v|_𝒜, V's footnote 1), not its pull-back to T𝒜: read as pull-backs, (2.13) would leave
/// more solutions where V proves them unique (Γ definite: one more for (2.13) at n = 3 with two constraints, one
/// more for (3.3) at n = 2 with one; Vignolo.Eq3_4_… asserts the uniqueness).  V's "L regular" needs C = g Γ⁻¹ gᵀ
/// invertible too: with Γ = diag(1, −1) and ẋ + ẏ = 0 the solutions are a line, or none (Vignolo.IndefiniteGamma…).
template <class T>
AffineSubspace<T> lagrange_chetaev_fields(const VignoloPoint<T>& d, bool chetaev_condition) {
  const Index dim = 2 * d.n + 1;
  const Matrix<T> chi = chetaev_bundle(d).basis(), tan_ann = annihilator(constraint_tangent(d)).basis();
  Matrix<T> eq = vstack(Matrix<T>::from_rows({vignolo_detail::unit<T>(dim, 0)}, dim), tan_ann);
  if (chetaev_condition) eq = vstack(eq, chi);
  std::vector<T> rhs(eq.rows());
  rhs[0] = T(1);
  return vignolo_detail::flat_modulo(poincare_cartan(d), std::vector<T>(dim), chi, eq, rhs);
}

/// The solutions at z ∈ 𝓛(𝒜) of (3.3): Ẑ ⌟ Ω̃_l + dφ_l at z in χ̂(𝒜) (along 𝓛(𝒜), as in (2.13)), Ẑ(φ^σ) = 0,
/// and with `chetaev_condition` also (3.9)  [V (3.2)–(3.3), (3.9)].  (Ω̃_l and dφ_l do not depend on u̇:
/// the answer is one for the whole fibre, V Prop 3.4.)
template <class T>
AffineSubspace<T> nonholonomic_fields(const VignoloPoint<T>& d, bool chetaev_condition) {
  const Matrix<T> nu = chetaev_forms(d), dphi = bundle_constraint_differentials(d);
  const Matrix<T> eq = chetaev_condition ? vstack(dphi, nu) : dphi;
  return vignolo_detail::flat_modulo(lagrangian_bundle_form(d), trivialization_differential(d), nu, eq,
                                     std::vector<T>(eq.rows()));
}

/// The solutions of the unconstrained problem (2.20) Z̃ ⌟ Ω̃_l = −dφ_l at z  [V (2.20)].
template <class T>
AffineSubspace<T> unconstrained_fields(const VignoloPoint<T>& d) {
  return vignolo_detail::flat_modulo(lagrangian_bundle_form(d), trivialization_differential(d),
                                     Matrix<T>(0, 2 * d.n + 2), Matrix<T>(0, 2 * d.n + 2), std::vector<T>{});
}

/// (3.7)'s two summands: (χ̂(𝒜)°)^⊥ ⊕ T(𝓛(𝒜))^⊥ and χ̂(𝒜)° ∩ T(𝓛(𝒜)), Ω̃_l's complements  [V Prop 3.1, (3.7)].
template <class T>
struct ConstrainedSplitting {
  Subspace<T> chetaev_complement = Subspace<T>::zero(0);  ///< (χ̂°)^⊥
  Subspace<T> tangent_complement = Subspace<T>::zero(0);  ///< T(𝓛(𝒜))^⊥
  Subspace<T> constrained = Subspace<T>::zero(0);         ///< χ̂° ∩ T(𝓛(𝒜)), 𝒫's image
};
template <class T>
ConstrainedSplitting<T> constrained_splitting(const VignoloPoint<T>& d) {
  const Matrix<T> w = lagrangian_bundle_form(d);
  const Subspace<T> chi0 = Subspace<T>::solutions(chetaev_forms(d)),
                    tan = Subspace<T>::solutions(bundle_constraint_differentials(d));
  return {symplectic_complement(w, chi0), symplectic_complement(w, tan), intersection(chi0, tan)};
}

/// 𝒫(X): X's part in χ̂° ∩ T(𝓛(𝒜)) along (3.7)'s other summand.  (3.7) is a direct sum where Γ and
/// C = g Γ⁻¹ gᵀ are invertible (Γ definite suffices); V's proof of Prop 3.1 takes C's invertibility from det Γ ≠ 0
/// and rank g, which an indefinite Γ breaks (Γ = diag(1, −1), g = (1, 1): C = 0; Vignolo.IndefiniteGamma…).
template <class T>
std::vector<T> constrained_projection(const VignoloPoint<T>& d, const std::vector<T>& x) {
  require(x.size() == 2 * d.n + 2, "constrained_projection", "X of length 2n + 2",
          "length " + std::to_string(x.size()));
  const ConstrainedSplitting<T> s = constrained_splitting(d);
  const Matrix<T> basis =
      vstack(s.constrained.basis(), vstack(s.chetaev_complement.basis(), s.tangent_complement.basis()));
  require(basis.rows() == x.size() && rank(basis) == x.size(), "constrained_projection",
          "the direct sum (3.7) (Γ and C = g Γ⁻¹ gᵀ invertible, V Prop 3.1)",
          "summands spanning dimension " + std::to_string(rank(basis)) + " of " + std::to_string(x.size()));
  std::vector<T> c;
  solve_particular(basis.transpose(), x, c);
  std::vector<T> p(x.size());
  for (Index k = 0; k < s.constrained.dim(); ++k)
    for (Index j = 0; j < x.size(); ++j) p[j] += c[k] * s.constrained.basis()(k, j);
  return p;
}

/// TM_0 ∩ χ̂(𝒜)° at z ∈ M_0 = l(𝒜) (3.10): ker dφ_l ∩ ker dφ^σ ∩ ker ν^σ on 𝓛.
template <class T>
Subspace<T> first_level_directions(const VignoloPoint<T>& d) {
  require_vignolo(d, "first_level_directions");
  const Matrix<T> rows = vstack(Matrix<T>::from_rows({trivialization_differential(d)}, 2 * d.n + 2),
                                vstack(bundle_constraint_differentials(d), chetaev_forms(d)));
  return Subspace<T>::solutions(rows);
}

/// z ∈ M_1 by (3.12): dφ_l(z) ∈ (TM_0 ∩ χ̂(𝒜)°)^♭ + χ̂(𝒜)  [V (3.12)].
template <class T>
bool in_first_constraint_manifold(const VignoloPoint<T>& d) {
  const Subspace<T> s = first_level_directions(d);
  const Subspace<T> flats = Subspace<T>::span(s.basis() * lagrangian_bundle_form(d));  // rows sᵀ Ω̃: s ⌟ Ω̃
  return contains(sum(flats, Subspace<T>::span(chetaev_forms(d))), trivialization_differential(d));
}

/// (TM_0 ∩ χ̂(𝒜)°)^⊥ ∩ χ̂(𝒜)°, whose pairings with dφ_l are M_1's constraints at z  [V (3.15), k = 0].
template <class T>
Subspace<T> first_constraint_directions(const VignoloPoint<T>& d) {
  return intersection(symplectic_complement(lagrangian_bundle_form(d), first_level_directions(d)),
                      Subspace<T>::solutions(chetaev_forms(d)));
}

/// 𝒪_l at z = ker Ω_l ∩ V_z(D^v): vertical vectors V^i ∂/∂q̇^i with ⟨V ‖ g^σ⟩ = V^i g^σ_i = 0 (2.5) in Ω_l's
/// kernel, on j₁  [V §3.4].
template <class T>
Subspace<T> sode_obstruction(const VignoloPoint<T>& d) {
  const Index n = d.n, dim = 2 * n + 1;
  const Matrix<T> w = poincare_cartan(d);
  Matrix<T> vertical_dg(1 + n + d.g.rows(), dim);  // dt, dq^i and the pairing with D^v
  vertical_dg(0, 0) = T(1);
  for (Index i = 0; i < n; ++i) vertical_dg(1 + i, 1 + i) = T(1);
  for (Index s = 0; s < d.g.rows(); ++s)
    for (Index i = 0; i < n; ++i) vertical_dg(1 + n + s, 1 + n + i) = d.g(s, i);
  return intersection(kernel(w.transpose()), kernel(vertical_dg));
}

/// 𝒪̃_l = l_*(𝒪_l), 𝒪_l lifted to 𝓛 by the section's tangent map (= the horizontal lift on vertical vectors)  [V
/// (3.21)].
template <class T>
Subspace<T> lifted_sode_obstruction(const VignoloPoint<T>& d) {
  return map(section_tangent(d), sode_obstruction(d));
}

}  // namespace dcad::reference
