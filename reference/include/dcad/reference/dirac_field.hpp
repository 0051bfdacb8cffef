// Dirac structures that depend on the point (CEF §4, "Dirac structures on manifolds"), literally, on M = Q^n:
//   D ⊆ TM ⊕ T*M given by sections s = (X, α) affine in x, X(x) = a + A x, α(x) = b + B x, spanning D(x) at
//   every x — the graph of a 2-form field ω(x) (sections (e_i, ω(x)(e_i, ·))) or of a bivector field P(x)
//   (sections (P(x) e_i, e_i)), both affine in x;
//   D is integrable when ⟨L_{X1}α2, X3⟩ + ⟨L_{X2}α3, X1⟩ + ⟨L_{X3}α1, X2⟩ = 0 for sections of D (CEF §4,
//   before Thm 4.7), with ⟨L_X α, Y⟩ = X(α(Y)) − α([X, Y]) and [X, Y] = DY·X − DX·Y: a polynomial of degree
//   ≤ 2 in x here, held by its coefficients and decided identically zero;
//   "this definition encompasses the notion of closedness for presymplectic forms and Jacobi identity for
//   brackets": dω = 0 and [P, P] = 0 are computed by their own formulas (exterior derivative, Schouten
//   bracket) for the properties to hold against the definition;
//   Thm 4.7: for integrable D, E_D is involutive — [X_i, X_j](x) ∈ E_D(x) = span{X_k(x)}, decided at a point.
#pragma once

#include "dcad/affine_skew_field.hpp"
#include "dcad/reference/dirac_bergmann.hpp"

namespace dcad::reference {

template <class T>
using AffineSkewField = AffineSkewData<Matrix<T>>;  // dcad/affine_skew_field.hpp

/// A section (X, α) of TM ⊕ T*M affine in x: X(x) = a + A x, α(x) = b + B x.
template <class T>
struct AffineSection {
  std::vector<T> a;
  Matrix<T> a_slope;
  std::vector<T> b;
  Matrix<T> b_slope;
};

/// A QuadraticFunction (dirac_bergmann.hpp: ½ xᵀ A x + b·x + c) that is the zero polynomial.
template <class T>
bool identically_zero(const QuadraticFunction<T>& f) {
  for (const T& c : f.b)
    if (c != T(0)) return false;
  for (Index i = 0; i < f.a.rows(); ++i)
    for (Index j = 0; j < f.a.cols(); ++j)
      if (f.a(i, j) != T(0)) return false;
  return f.c == T(0);
}

template <class T>
void require_skew_field(const AffineSkewField<T>& f, const std::string& fn) {
  require_skew(f.constant, fn);
  const Index n = f.constant.rows();
  require(f.slopes.size() == static_cast<std::size_t>(n), fn, std::to_string(n) + " slopes (one per coordinate)",
          std::to_string(f.slopes.size()));
  for (const Matrix<T>& s : f.slopes) {
    require(s.rows() == n && s.cols() == n, fn, "slopes " + std::to_string(n) + "x" + std::to_string(n), shape(s));
    require_skew(s, fn);
  }
}

/// (u₀ + U x)·(w₀ + W x) = u₀·w₀ + (Uᵀ w₀ + Wᵀ u₀)·x + ½ xᵀ (UᵀW + WᵀU) x.
template <class T>
QuadraticFunction<T> pair_affine(const std::vector<T>& u0, const Matrix<T>& u, const std::vector<T>& w0,
                                 const Matrix<T>& w) {
  const Index n = u.cols();
  QuadraticFunction<T> out{Matrix<T>(n, n), std::vector<T>(n), T(0)};
  for (Index i = 0; i < u0.size(); ++i) out.c += u0[i] * w0[i];
  const std::vector<T> g1 = (u.transpose() * Matrix<T>::column(w0)).col(0),
                       g2 = (w.transpose() * Matrix<T>::column(u0)).col(0);
  for (Index i = 0; i < n; ++i) out.b[i] = g1[i] + g2[i];
  const Matrix<T> uw = u.transpose() * w;
  out.a = uw + uw.transpose();
  return out;
}

template <class T>
QuadraticFunction<T> operator+(QuadraticFunction<T> f, const QuadraticFunction<T>& g) {
  f.c += g.c;
  for (Index i = 0; i < f.b.size(); ++i) f.b[i] += g.b[i];
  f.a = f.a + g.a;
  return f;
}

template <class T>
QuadraticFunction<T> operator-(QuadraticFunction<T> f, const QuadraticFunction<T>& g) {
  f.c -= g.c;
  for (Index i = 0; i < f.b.size(); ++i) f.b[i] -= g.b[i];
  f.a = f.a - g.a;
  return f;
}

/// X(f) = df·X for f = ½ xᵀ A x + b·x + c and X = a + A_X x: (b + A x)·(a + A_X x).
template <class T>
QuadraticFunction<T> derivative_along(const QuadraticFunction<T>& f, const std::vector<T>& a,
                                      const Matrix<T>& a_slope) {
  return pair_affine(f.b, f.a, a, a_slope);
}

/// [X, Y] = DY·X − DX·Y for affine X = a + A x, Y = c + C x: (C a − A c) + (C A − A C) x.
template <class T>
std::pair<std::vector<T>, Matrix<T>> lie_bracket(const AffineSection<T>& x, const AffineSection<T>& y) {
  const std::vector<T> ca = (y.a_slope * Matrix<T>::column(x.a)).col(0),
                       ac = (x.a_slope * Matrix<T>::column(y.a)).col(0);
  std::vector<T> c(ca.size());
  for (Index i = 0; i < c.size(); ++i) c[i] = ca[i] - ac[i];
  return {c, y.a_slope * x.a_slope - x.a_slope * y.a_slope};
}

/// ⟨L_X α, Y⟩ = X(α(Y)) − α([X, Y]), for X from s, α from t, Y from u.
template <class T>
QuadraticFunction<T> lie_derivative_pairing(const AffineSection<T>& s, const AffineSection<T>& t,
                                            const AffineSection<T>& u) {
  const QuadraticFunction<T> alpha_y = pair_affine(t.b, t.b_slope, u.a, u.a_slope);
  const auto [c, cs] = lie_bracket(s, u);
  return derivative_along(alpha_y, s.a, s.a_slope) - pair_affine(t.b, t.b_slope, c, cs);
}

/// The integrability expression of CEF §4 on three sections.
template <class T>
QuadraticFunction<T> courant_tensor(const AffineSection<T>& s1, const AffineSection<T>& s2,
                                    const AffineSection<T>& s3) {
  return lie_derivative_pairing(s1, s2, s3) + lie_derivative_pairing(s2, s3, s1) + lie_derivative_pairing(s3, s1, s2);
}

/// The sections of a graph: of ω(x), (e_i, ω(x)(e_i, ·)) — row i of ω(x), as dirac_from_presymplectic takes
/// it; of P(x), (P(x) e_i, e_i) — v = P α, as dirac_from_poisson takes it.
template <class T>
std::vector<AffineSection<T>> graph_sections(const AffineSkewField<T>& f, bool bivector, const std::string& fn) {
  require_skew_field(f, fn);
  const Index n = f.constant.rows();
  std::vector<AffineSection<T>> out;
  for (Index i = 0; i < n; ++i) {
    std::vector<T> e(n);
    e[i] = T(1);
    Matrix<T> slope(n, n);  // column k: ∂_k of the varying part
    for (Index k = 0; k < n; ++k)
      for (Index j = 0; j < n; ++j) slope(j, k) = bivector ? f.slopes[k](j, i) : f.slopes[k](i, j);
    out.push_back(bivector ? AffineSection<T>{f.constant.col(i), slope, e, Matrix<T>(n, n)}
                           : AffineSection<T>{e, Matrix<T>(n, n), f.constant.row(i), slope});
  }
  return out;
}

template <class T>
std::vector<AffineSection<T>> presymplectic_sections(const AffineSkewField<T>& w) {
  return graph_sections(w, false, "presymplectic_sections");
}

template <class T>
std::vector<AffineSection<T>> poisson_sections(const AffineSkewField<T>& p) {
  return graph_sections(p, true, "poisson_sections");
}

/// ⟨⟨s_i, s_j⟩⟩ = α_i(X_j) + α_j(X_i) vanishes identically for all pairs: D(x) isotropic at every x (Lemma 4.1).
template <class T>
bool is_isotropic_everywhere(const std::vector<AffineSection<T>>& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i; j < s.size(); ++j)
      if (!identically_zero(pair_affine(s[i].b, s[i].b_slope, s[j].a, s[j].a_slope) +
                            pair_affine(s[j].b, s[j].b_slope, s[i].a, s[i].a_slope)))
        return false;
  return true;
}

/// Integrability (CEF §4) on every ordered triple of the spanning sections.
template <class T>
bool is_integrable(const std::vector<AffineSection<T>>& s) {
  for (const AffineSection<T>& s1 : s)
    for (const AffineSection<T>& s2 : s)
      for (const AffineSection<T>& s3 : s)
        if (!identically_zero(courant_tensor(s1, s2, s3))) return false;
  return true;
}

/// E_D(x) = span{X_i(x)} is closed under the brackets of the sections' vector fields at x  [CEF Thm 4.7].
template <class T>
bool involutive_at(const std::vector<AffineSection<T>>& s, const std::vector<T>& x) {
  if (s.empty()) return true;
  const Index n = x.size();
  Matrix<T> rows(s.size(), n);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const std::vector<T> v = (s[i].a_slope * Matrix<T>::column(x)).col(0);
    for (Index j = 0; j < n; ++j) rows(i, j) = s[i].a[j] + v[j];
  }
  const Subspace<T> e = Subspace<T>::span(rows);
  for (const AffineSection<T>& si : s)
    for (const AffineSection<T>& sj : s) {
      const auto [c, cs] = lie_bracket(si, sj);
      std::vector<T> at = (cs * Matrix<T>::column(x)).col(0);
      for (Index j = 0; j < n; ++j) at[j] += c[j];
      if (!contains(e, at)) return false;
    }
  return true;
}

/// dω = 0: (dω)_{ijk} = ∂_i ω_{jk} + ∂_j ω_{ki} + ∂_k ω_{ij}, ∂_i ω = slopes[i] (constant: ω is affine).
template <class T>
bool is_closed(const AffineSkewField<T>& w) {
  require_skew_field(w, "is_closed");
  const Index n = w.constant.rows();
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j)
      for (Index k = 0; k < n; ++k)
        if (w.slopes[i](j, k) + w.slopes[j](k, i) + w.slopes[k](i, j) != T(0)) return false;
  return true;
}

/// [P, P] = 0: Σ_l (P_il ∂_l P_jk + P_jl ∂_l P_ki + P_kl ∂_l P_ij) = 0 identically (the Jacobi identity of
/// {f, g} = df·P dg); affine in x: its constant part and its part along each x_m vanish.
template <class T>
bool is_jacobi(const AffineSkewField<T>& p) {
  require_skew_field(p, "is_jacobi");
  const Index n = p.constant.rows();
  const auto vanishes = [&](const Matrix<T>& m) {  // Σ_l m_il ∂_l P_jk + cyclic
    for (Index i = 0; i < n; ++i)
      for (Index j = 0; j < n; ++j)
        for (Index k = 0; k < n; ++k) {
          T s(0);
          for (Index l = 0; l < n; ++l)
            s += m(i, l) * p.slopes[l](j, k) + m(j, l) * p.slopes[l](k, i) + m(k, l) * p.slopes[l](i, j);
          if (s != T(0)) return false;
        }
    return true;
  };
  if (!vanishes(p.constant)) return false;
  for (const Matrix<T>& m : p.slopes)
    if (!vanishes(m)) return false;
  return true;
}

}  // namespace dcad::reference
