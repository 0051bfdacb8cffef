// Second class constraints adapted to the primary ones, the abridged total energy and the Dirac
// bracket of Theorem 3.28 (CEF §3.4), and its foliated form, Theorem 7.4 (§7), for linear
// constraints φ_i(x) = a_i·x − b_i on a symplectic Q^N.
#pragma once

#include "dcad/reference/dirac_bergmann.hpp"

namespace dcad::reference {

template <class T>
struct AdaptedConstraints {
  Index s_prime = 0;            ///< s' = rank Φ', Φ' = ({φ_i, φ_j}), i primary, j all
  Index s = 0;                  ///< 2s = rank Φ, Φ = ({φ_i, φ_j}), i, j all
  std::vector<Index> chi;       ///< χ'_1 … χ'_{s'} (primary), then χ''_{s'+1} … χ''_{2s} (not primary)
  std::vector<Index> abridged;  ///< the primary φ_k of E_AT = E + λ^k φ_k: those not chosen as χ'
  Matrix<T> dirac_tensor;       ///< J*_(χ) = J − J Gᵀ Σ⁻¹ G J
};

/// Rows are chosen greedily, in order, while they raise the rank of the chosen rows of Φ: χ' among
/// the primary constraints (rank s'), then χ'' among the others (up to 2s).  `primary[i]` marks the
/// primary constraints (in §7 also the leaf constraints φ_{a+1} … φ_b).  [CEF Thm 3.28, Thm 7.4]
template <class T>
AdaptedConstraints<T> adapted_constraints(const Matrix<T>& w, const Matrix<T>& constraints,
                                          const std::vector<bool>& primary) {
  require(primary.size() == constraints.rows(), "adapted_constraints", "one primary flag per constraint",
          std::to_string(primary.size()) + " flags for " + std::to_string(constraints.rows()) + " constraints");
  const Matrix<T> j = poisson_tensor(w), a = gradients(constraints);
  const Matrix<T> phi = a * j * a.transpose();
  AdaptedConstraints<T> out;
  out.s = rank(phi) / 2;
  Matrix<T> chosen(0, phi.cols());
  const auto take = [&](bool want_primary) {
    for (Index i = 0; i < phi.rows(); ++i) {
      if (primary[i] != want_primary) continue;
      const Matrix<T> more = vstack(chosen, phi.block(i, i + 1, 0, phi.cols()));
      if (rank(more) > chosen.rows()) {
        chosen = more;
        out.chi.push_back(i);
      } else if (want_primary) {
        out.abridged.push_back(i);
      }
    }
  };
  take(true);
  out.s_prime = out.chi.size();
  take(false);
  require(out.chi.size() == 2 * out.s, "adapted_constraints", std::to_string(2 * out.s) + " second class constraints",
          std::to_string(out.chi.size()));
  Matrix<T> g(out.chi.size(), a.cols());
  for (Index p = 0; p < out.chi.size(); ++p)
    for (Index k = 0; k < a.cols(); ++k) g(p, k) = a(out.chi[p], k);
  // independent rows of a skew Φ, as many as its rank, have a nonsingular principal submatrix
  out.dirac_tensor = out.chi.empty() ? j : j - j * g.transpose() * inverse(g * j * g.transpose()) * g * j;
  return out;
}

/// X_(χ),E_AT(x) = J* (dE(x) + λ^k a_k), k over `abridged`.  [CEF (3.24), (7.11)]
template <class T>
std::vector<T> abridged_field(const AdaptedConstraints<T>& ad, const Matrix<T>& constraints, const Matrix<T>& hessian,
                              const std::vector<T>& gradient, const std::vector<T>& x, const std::vector<T>& lambda) {
  require(lambda.size() == ad.abridged.size(), "abridged_field", std::to_string(ad.abridged.size()) + " multipliers",
          std::to_string(lambda.size()));
  std::vector<T> d = (hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < d.size(); ++i) {
    d[i] += gradient[i];
    for (Index k = 0; k < lambda.size(); ++k) d[i] += lambda[k] * constraints(ad.abridged[k], i);
  }
  return (ad.dirac_tensor * Matrix<T>::column(d)).col(0);
}

/// A Pontryagin-bundle system embedded in P = T*TQ = Q^{4n}, y = (q, v, p, ν), with
/// Ω = dq ∧ dp + dv ∧ dν (CEF Appendix A, ERRATA): primary constraints ν = 0 (S' = TQ ⊕ T*Q), leaf
/// constraints κ_j·q = C_j for the rows κ_j of K (KCL integrated: the leaves of D̄_Δ), and E(q, v, p)
/// extended to P independently of ν.  This is the foliated setting of §7 (7.2)–(7.6).
template <class T>
struct FoliatedEmbedding {
  Matrix<T> omega;          ///< 4n × 4n
  Matrix<T> hessian;        ///< 4n × 4n
  std::vector<T> gradient;  ///< 4n
  Matrix<T> primary;        ///< [0 0 0 I | 0]: ν = 0
  Matrix<T> leaf;           ///< [K 0 0 0 | 0]: κ·q = C
};

template <class T>
FoliatedEmbedding<T> tangent_cotangent_embedding(const PontryaginInput<T>& in) {
  const LinearSystem<T> s = pontryagin_system(in);
  const Index n = in.n, m = 4 * n;
  FoliatedEmbedding<T> f;
  f.omega = Matrix<T>(m, m);
  f.hessian = Matrix<T>(m, m);
  f.gradient.assign(m, T(0));
  for (Index i = 0; i < n; ++i) {
    f.omega(i, 2 * n + i) = T(1);  // dq ∧ dp
    f.omega(2 * n + i, i) = T(-1);
    f.omega(n + i, 3 * n + i) = T(1);  // dv ∧ dν
    f.omega(3 * n + i, n + i) = T(-1);
  }
  for (Index i = 0; i < 3 * n; ++i) {
    f.gradient[i] = s.gradient[i];
    for (Index j = 0; j < 3 * n; ++j) f.hessian(i, j) = s.hessian(i, j);
  }
  f.primary = Matrix<T>(n, m + 1);
  for (Index i = 0; i < n; ++i) f.primary(i, 3 * n + i) = T(1);
  f.leaf = Matrix<T>(in.k.rows(), m + 1);
  for (Index i = 0; i < in.k.rows(); ++i)
    for (Index j = 0; j < n; ++j) f.leaf(i, j) = in.k(i, j);
  return f;
}

/// §7 (7.1): the Dirac structure on S' = {primary = 0} whose presymplectic leaves are the
/// S'_C = S' ∩ {leaf = C} with the pullback of Ω, and the energy E.  Any FoliatedEmbedding is such a
/// setting (tangent_cotangent_embedding gives the one of CEF App. A for a Pontryagin system).
template <class T>
LinearSystem<T> foliated_system(const FoliatedEmbedding<T>& f) {
  return {dirac_from_distribution(kernel(gradients(vstack(f.primary, f.leaf))), f.omega), f.hessian, f.gradient, T(0)};
}

/// The CAD of (7.1) from M_0 = S': its M_c is the final foliated constraint submanifold S of §7.
template <class T>
CadResult<T> foliated_tower(const FoliatedEmbedding<T>& f) {
  return constraint_tower(foliated_system(f), f.primary);
}

/// The constraints of S_0 in the paper's order — primary, secondary, leaf — and Theorem 3.28 / 7.4 on
/// them with the primary and the leaf rows counted as primary (χ adapted to S'_0, E_AT for S_0).
template <class T>
struct AdaptedToPrimary {
  Matrix<T> constraints;          ///< [primary; secondary; leaf], rows [a | b]
  AdaptedConstraints<T> adapted;  ///< indices into `constraints`
};

template <class T>
AdaptedToPrimary<T> adapted_to_primary(const Matrix<T>& w, const Matrix<T>& primary, const Matrix<T>& secondary,
                                       const Matrix<T>& leaf) {
  AdaptedToPrimary<T> out;
  out.constraints = vstack(vstack(primary, secondary), leaf);
  std::vector<bool> is_primary(out.constraints.rows(), false);
  for (Index i = 0; i < out.constraints.rows(); ++i)
    is_primary[i] = i < primary.rows() || i >= primary.rows() + secondary.rows();
  out.adapted = adapted_constraints(w, out.constraints, is_primary);
  return out;
}

/// CEF §7 after (7.7): the multipliers of E_{C,T} = E + λ^i (φ_i − C_i), i over the primary then the leaf
/// functions, at x ∈ S: {E, φ_j}(x) + λ^i {φ_i, φ_j}(x) = 0 for every constraint φ_j of S (primary,
/// `secondary`, leaf).  C enters neither side: Λ_x depends on x, not on the leaf through it.
template <class T>
AffineSubspace<T> foliated_multipliers(const FoliatedEmbedding<T>& f, const Matrix<T>& secondary,
                                       const std::vector<T>& x) {
  const Matrix<T> j = poisson_tensor(f.omega);
  const Matrix<T> mult = gradients(vstack(f.primary, f.leaf));
  const Matrix<T> all = gradients(vstack(vstack(f.primary, secondary), f.leaf));
  std::vector<T> de = (f.hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < de.size(); ++i) de[i] += f.gradient[i];
  // {E, φ_j} = dEᵀ J a_jᵀ and {φ_i, φ_j} = a_i J a_jᵀ: row j of both is a_j Jᵀ (·)
  std::vector<T> rhs = (all * j.transpose() * Matrix<T>::column(de)).col(0);
  for (T& v : rhs) v = -v;
  return solve(all * j.transpose() * mult.transpose(), rhs);
}

/// (7.8) at x₀, C₀ = φ(x₀) held fixed: X = dE^♯(x₀) + λ^i dφ_i^♯(x₀) = J (dE(x₀) + λ^i a_i), λ over the primary
/// then the leaf functions.
template <class T>
std::vector<T> foliated_field(const FoliatedEmbedding<T>& f, const std::vector<T>& x, const std::vector<T>& lambda) {
  const Matrix<T> mult = gradients(vstack(f.primary, f.leaf));
  require(lambda.size() == mult.rows(), "foliated_field", std::to_string(mult.rows()) + " multipliers",
          std::to_string(lambda.size()));
  std::vector<T> d = (f.hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < d.size(); ++i) {
    d[i] += f.gradient[i];
    for (Index k = 0; k < lambda.size(); ++k) d[i] += lambda[k] * mult(k, i);
  }
  return (poisson_tensor(f.omega) * Matrix<T>::column(d)).col(0);
}

/// CEF §7's extended Poisson manifold U × R^{b−a} (the bracket Ω⁻¹ on U, 0 on the leaf values C): the
/// Hamiltonian field at (x, c) of E_{λ̃,T}(x, C) = E(x) + λ̃^i(x) (φ_i(x) − C_i) (C_i = 0 for the primary φ_i),
/// for a section λ̃ with value `lambda` and derivative `dlambda` (row i: dλ̃^i) at x: (J ∂_x E_{λ̃,T}, 0) — the
/// C-part vanishes with the bracket there.
template <class T>
std::vector<T> extended_hamiltonian_field(const FoliatedEmbedding<T>& f, const std::vector<T>& x,
                                          const std::vector<T>& c, const std::vector<T>& lambda,
                                          const Matrix<T>& dlambda) {
  const Matrix<T> rows = vstack(f.primary, f.leaf);
  const Index n = x.size(), p = f.primary.rows();
  require(c.size() == f.leaf.rows(), "extended_hamiltonian_field", std::to_string(f.leaf.rows()) + " leaf values",
          std::to_string(c.size()));
  std::vector<T> grad = (f.hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < n; ++i) grad[i] += f.gradient[i];
  for (Index k = 0; k < rows.rows(); ++k) {
    T level = -rows(k, n) - (k < p ? T(0) : c[k - p]);  // φ_k(x) − C_k, φ_k = a_k·x − b_k
    for (Index i = 0; i < n; ++i) level += rows(k, i) * x[i];
    for (Index i = 0; i < n; ++i) grad[i] += lambda[k] * rows(k, i) + level * dlambda(k, i);
  }
  std::vector<T> out = (poisson_tensor(f.omega) * Matrix<T>::column(grad)).col(0);
  out.resize(n + c.size(), T(0));
  return out;
}

}  // namespace dcad::reference
