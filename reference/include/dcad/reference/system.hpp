// Linear Dirac dynamical systems (x, ẋ) ⊕ dE(x) ∈ D on Q^N with constant D and
// E(x) = ½ xᵀ H x + gᵀ x + c  [CEF (1.1), §5 "constant Dirac structure"], and the Lagrangian
// systems on the Pontryagin bundle TQ ⊕ T*Q of CEF §6.
#pragma once

#include "dcad/reference/dirac.hpp"
#include "dcad/types.hpp"

namespace dcad::reference {

template <class T>
struct LinearSystem {
  DiracStructure<T> d;
  Matrix<T> hessian;        ///< H, symmetric N×N
  std::vector<T> gradient;  ///< g
  T constant = T(0);        ///< c
};

template <class T>
void require_system(const LinearSystem<T>& s, const std::string& fn) {
  require_dirac(s.d, fn);
  const Index n = s.d.n;
  require(s.hessian.rows() == n && s.hessian.cols() == n, fn,
          "an " + std::to_string(n) + "x" + std::to_string(n) + " Hessian", shape(s.hessian));
  require(is_symmetric(s.hessian), fn, "a symmetric Hessian", "an asymmetric one");
  require(s.gradient.size() == n, fn, "a gradient of length " + std::to_string(n),
          "length " + std::to_string(s.gradient.size()));
}

/// dE(x) = H x + g.
template <class T>
std::vector<T> energy_differential(const LinearSystem<T>& s, const std::vector<T>& x) {
  std::vector<T> de = (s.hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < de.size(); ++i) de[i] += s.gradient[i];
  return de;
}

/// L(q, v) = ½ vᵀ A v + qᵀ B v + ½ qᵀ C q + aᵀ q + bᵀ v on Q^n, with Δ = ker K  [CONTRACT `pontryagin`].
template <class T>
using PontryaginInput = PontryaginData<Matrix<T>, std::vector<T>>;  // dcad/types.hpp

/// M = TQ ⊕ T*Q = Q^{3n}, x = (q, v, p); D̄_Δ = {(ẋ, (α, γ, β)) : q̇ ∈ Δ, α + ṗ ∈ Δ°, β = q̇, γ = 0},
/// i.e. E_D = Δ ⊕ Q^n ⊕ Q^n with ω_D = dq ∧ dp (CEF (6.10)–(6.13), ERRATA conventions);
/// E = p·v − L, so dE = (−C q − B v − a, p − Bᵀ q − A v − b, v).
template <class T>
LinearSystem<T> pontryagin_system(const PontryaginInput<T>& in) {
  const Index n = in.n;
  require(is_symmetric(in.vv) && is_symmetric(in.qq), "pontryagin_system", "symmetric vv and qq", "an asymmetric one");
  const Subspace<T> delta = kernel(in.k);
  Matrix<T> e_rows(delta.dim() + 2 * n, 3 * n), w(3 * n, 3 * n), h(3 * n, 3 * n);
  for (Index i = 0; i < delta.dim(); ++i)
    for (Index j = 0; j < n; ++j) e_rows(i, j) = delta.basis()(i, j);
  for (Index i = 0; i < 2 * n; ++i) e_rows(delta.dim() + i, n + i) = T(1);
  for (Index i = 0; i < n; ++i) {
    w(i, 2 * n + i) = T(1);
    w(2 * n + i, i) = T(-1);
    h(n + i, 2 * n + i) = h(2 * n + i, n + i) = T(1);
    for (Index j = 0; j < n; ++j) {
      h(i, j) = -in.qq(i, j);
      h(i, n + j) = -in.qv(i, j);
      h(n + j, i) = -in.qv(i, j);
      h(n + i, n + j) = -in.vv(i, j);
    }
  }
  std::vector<T> g(3 * n, T(0));
  for (Index i = 0; i < n; ++i) {
    g[i] = -in.q[i];
    g[n + i] = -in.v[i];
  }
  return {dirac_from_distribution(Subspace<T>::span(e_rows), w), h, g, T(0)};
}

}  // namespace dcad::reference
