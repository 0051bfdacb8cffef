// Linear symplectic and presymplectic algebra, literally as in CEF §3.1 and Lemma 4.2.
// A bilinear form on Q^n is a matrix W with Ω(u, w) = uᵀ W w.  X^♭ = i_X Ω = Ω(X, ·), whose
// coordinates are Wᵀ X; ♯ is its inverse.  (With W = [[0, I], [-I, 0]] this gives Ω = dq ∧ dp,
// X_f = (∂f/∂p, -∂f/∂q) and {q_i, p_j} = δ_ij, the convention of ../shared/ERRATA.md.)
#pragma once

#include "dcad/reference/subspace.hpp"

namespace dcad::reference {

/// Ω(u, w) = uᵀ W w.
template <class T>
T form_value(const Matrix<T>& w, const std::vector<T>& u, const std::vector<T>& v) {
  return (Matrix<T>::from_rows({u}, w.rows()) * w * Matrix<T>::column(v))(0, 0);
}

template <class T>
void require_skew(const Matrix<T>& w, const std::string& fn) {
  require(is_square(w), fn, "a square matrix", shape(w));
  require(is_skew(w), fn, "a skew matrix (W = -Wᵀ)", "a matrix that is not skew");
}

template <class T>
bool is_symplectic(const Matrix<T>& w) {
  return is_skew(w) && rank(w) == w.rows();
}

template <class T>
void require_symplectic(const Matrix<T>& w, const std::string& fn) {
  require_skew(w, fn);
  require(rank(w) == w.rows(), fn, "a nondegenerate form (rank " + std::to_string(w.rows()) + ")",
          "rank " + std::to_string(rank(w)));
}

/// X^♭ = i_X Ω, coordinates Wᵀ X.  [CEF §3.1]
template <class T>
std::vector<T> flat(const Matrix<T>& w, const std::vector<T>& x) {
  return (w.transpose() * Matrix<T>::column(x)).col(0);
}

/// α^♯: the unique X with X^♭ = α; Ω must be symplectic.  [CEF §3.1]
template <class T>
std::vector<T> sharp(const Matrix<T>& w, const std::vector<T>& alpha) {
  require_symplectic(w, "sharp");
  std::vector<T> x;
  solve_particular(w.transpose(), alpha, x);
  return x;
}

/// V^Ω = {x : Ω(x, v) = 0 ∀ v ∈ V}.  [CEF Lemma 3.1]
template <class T>
Subspace<T> symplectic_complement(const Matrix<T>& w, const Subspace<T>& v) {
  require_skew(w, "symplectic_complement");
  return Subspace<T>::solutions(v.basis() * w.transpose());  // row i: x ↦ xᵀ W v_i
}

/// A presymplectic form on a subspace: ω(u, w) = uᵀ M w for u, w ∈ `space`.  M is any skew
/// extension; only its values on `space` matter.
template <class T>
struct PresymplecticForm {
  Subspace<T> space;
  Matrix<T> matrix;
};

/// ω = Ω|_V, the pullback to V.  [CEF §3.1, before Lemma 3.4]
template <class T>
PresymplecticForm<T> restrict_form(const Matrix<T>& w, const Subspace<T>& v) {
  require_skew(w, "restrict_form");
  require(w.rows() == v.ambient(), "restrict_form", "a form on Q^" + std::to_string(v.ambient()),
          "a " + shape(w) + " matrix");
  return {v, w};
}

/// ω restricted further to U ⊆ V.
template <class T>
PresymplecticForm<T> restrict_form(const PresymplecticForm<T>& f, const Subspace<T>& u) {
  require(contains(f.space, u), "restrict_form", "a subspace of the form's domain", "a subspace not contained in it");
  return {u, f.matrix};
}

/// [ω(b_i, b_j)] in the canonical basis b of the form's domain.
template <class T>
Matrix<T> gram(const PresymplecticForm<T>& f) {
  return f.space.basis() * f.matrix * f.space.basis().transpose();
}

/// rank ω (even).
template <class T>
Index form_rank(const PresymplecticForm<T>& f) {
  return rank(gram(f));
}

/// W^ω = {v ∈ V : ω(v, w) = 0 ∀ w ∈ W}.  [CEF §4, before Lemma 4.2]
template <class T>
Subspace<T> orthogonal(const PresymplecticForm<T>& f, const Subspace<T>& w) {
  require_same_ambient(f.space, w, "orthogonal");
  return intersection(f.space, Subspace<T>::solutions(w.basis() * f.matrix.transpose()));
}

/// ker ω = V^ω = {v ∈ V : ω(v, y) = 0 ∀ y ∈ V}.
template <class T>
Subspace<T> form_kernel(const PresymplecticForm<T>& f) {
  return orthogonal(f, f.space);
}

/// ω^♭(W) ⊆ V*, returned as the subspace {α ∈ (Q^n)* : α|_V ∈ ω^♭(W)} (it contains V°).  [Lemma 4.2]
template <class T>
Subspace<T> flat(const PresymplecticForm<T>& f, const Subspace<T>& w) {
  require(contains(f.space, w), "flat", "a subspace of the form's domain", "a subspace not contained in it");
  return sum(Subspace<T>::span(w.basis() * f.matrix), annihilator(f.space));  // row: y ↦ wᵀ M y
}

/// The basis of Lemma 3.1: α_i = X_i^♭ with X_i a basis of V^Ω such that
/// Ω(X_i, X_{i+s}) = 1 = -Ω(X_{i+s}, X_i) for i ≤ s and all other Ω(X_i, X_j) = 0.
template <class T>
struct NormalFormBasis {
  Index s = 0;
  Matrix<T> x;      ///< rows X_1 … X_r
  Matrix<T> alpha;  ///< rows α_1 … α_r
};

/// Symplectic Gram–Schmidt on V^Ω: take a pair with Ω(e, f) ≠ 0, scale so Ω(e, f) = 1, make every
/// other vector Ω-orthogonal to both, repeat; what is left spans V ∩ V^Ω.  [CEF Lemma 3.1 proof]
template <class T>
NormalFormBasis<T> normal_form_basis(const Matrix<T>& w, const Subspace<T>& v) {
  require_symplectic(w, "normal_form_basis");
  std::vector<std::vector<T>> rest;
  const Matrix<T> b = symplectic_complement(w, v).basis();
  for (Index i = 0; i < b.rows(); ++i) rest.push_back(b.row(i));
  std::vector<std::vector<T>> es, fs;
  for (bool found = true; found;) {
    found = false;
    for (Index i = 0; i < rest.size() && !found; ++i)
      for (Index j = i + 1; j < rest.size() && !found; ++j) {
        const T om = form_value(w, rest[i], rest[j]);
        if (om == 0) continue;
        std::vector<T> e = rest[i], f = rest[j];
        for (T& c : f) c /= om;
        rest.erase(rest.begin() + j);
        rest.erase(rest.begin() + i);
        for (auto& y : rest) {  // y ← y − Ω(y, f) e + Ω(y, e) f
          const T yf = form_value(w, y, f), ye = form_value(w, y, e);
          for (Index k = 0; k < y.size(); ++k) y[k] += -yf * e[k] + ye * f[k];
        }
        es.push_back(e);
        fs.push_back(f);
        found = true;
      }
  }
  NormalFormBasis<T> out;
  out.s = es.size();
  std::vector<std::vector<T>> xs = es;
  xs.insert(xs.end(), fs.begin(), fs.end());
  xs.insert(xs.end(), rest.begin(), rest.end());
  out.x = Matrix<T>::from_rows(xs, w.rows());
  out.alpha = Matrix<T>(xs.size(), w.rows());
  for (Index i = 0; i < xs.size(); ++i) {
    const std::vector<T> a = flat(w, xs[i]);
    for (Index k = 0; k < a.size(); ++k) out.alpha(i, k) = a[k];
  }
  return out;
}

/// [α_i(X_j)] for covectors α (rows) and vectors X (rows).
template <class T>
Matrix<T> pairing_matrix(const Matrix<T>& alpha, const Matrix<T>& x) {
  return alpha * x.transpose();
}

/// The solutions of i_X ω = β|_V, ω = Ω|_V, by Lemmas 3.5–3.6: with γ_i the canonical basis of V°
/// and Y_i = γ_i^♯, solve (3.1) β(Y_i) + λ^j γ_j(Y_i) = 0 for λ; then X = β^♯ + λ^j Y_j.
template <class T>
struct RestrictedSolution {
  AffineSubspace<T> lambda;  ///< solutions λ of (3.1), in Q^r
  AffineSubspace<T> x;       ///< solutions X of (3.3), in Q^n
};

template <class T>
RestrictedSolution<T> solve_restricted(const Matrix<T>& w, const Subspace<T>& v, const std::vector<T>& beta) {
  require_symplectic(w, "solve_restricted");
  require(beta.size() == w.rows(), "solve_restricted", "β of length " + std::to_string(w.rows()),
          "length " + std::to_string(beta.size()));
  const Matrix<T> gamma = annihilator(v).basis();
  const Index r = gamma.rows(), n = w.rows();
  Matrix<T> y(r, n);  // rows Y_i = γ_i^♯
  for (Index i = 0; i < r; ++i) {
    const std::vector<T> yi = sharp(w, gamma.row(i));
    for (Index k = 0; k < n; ++k) y(i, k) = yi[k];
  }
  // (3.1) as a linear system in λ: Σ_j λ^j γ_j(Y_i) = −β(Y_i), coefficient (i, j) = γ_j(Y_i).
  const Matrix<T> coeff = pairing_matrix(gamma, y).transpose();
  std::vector<T> rhs(r);
  for (Index i = 0; i < r; ++i) rhs[i] = -dot(beta, y.row(i));
  RestrictedSolution<T> out;
  out.lambda = solve(coeff, rhs);
  out.x.empty = out.lambda.empty;
  out.x.direction = map(y.transpose(), out.lambda.direction);
  if (!out.x.empty) {
    out.x.point = sharp(w, beta);
    for (Index j = 0; j < r; ++j)
      for (Index k = 0; k < n; ++k) out.x.point[k] += out.lambda.point[j] * y(j, k);
  }
  return out;
}

/// The same set straight from the definition: {X ∈ V : ω(X, v) = β(v) ∀ v ∈ V}.
template <class T>
AffineSubspace<T> solve_on_subspace(const PresymplecticForm<T>& f, const std::vector<T>& beta) {
  const Matrix<T>& b = f.space.basis();
  // X = cᵀ b;  ω(X, b_j) = Σ_i c_i G_ij = β(b_j)  ⇔  Gᵀ c = (β(b_j))_j.
  std::vector<T> rhs(b.rows());
  for (Index j = 0; j < b.rows(); ++j) rhs[j] = dot(beta, b.row(j));
  const AffineSubspace<T> c = solve(gram(f).transpose(), rhs);
  AffineSubspace<T> out;
  out.empty = c.empty;
  out.direction = map(b.transpose(), c.direction);
  if (!c.empty) out.point = (b.transpose() * Matrix<T>::column(c.point)).col(0);
  return out;
}

}  // namespace dcad::reference
