// Linear and affine subspaces of Q^n, held by a canonical basis: the nonzero rows of the RREF of
// any spanning set.  Two subspaces are equal iff their canonical bases are equal.
// Covectors use the same coordinates (dual basis), so the annihilator U° ⊂ (Q^n)* is again a
// Subspace of Q^n.
#pragma once

#include "dcad/reference/matrix.hpp"

namespace dcad::reference {

template <class T>
class Subspace {
 public:
  /// span of the rows of `rows` in Q^n, n = rows.cols().
  static Subspace span(const Matrix<T>& rows) { return Subspace(rref(rows).r); }
  /// {x ∈ Q^n : equations · x = 0}, n = equations.cols().
  static Subspace solutions(const Matrix<T>& equations) { return span(nullspace(equations)); }
  static Subspace zero(Index n) { return Subspace(Matrix<T>(0, n)); }
  static Subspace whole(Index n) { return Subspace(Matrix<T>::identity(n)); }

  Index ambient() const { return basis_.cols(); }
  Index dim() const { return basis_.rows(); }
  /// Canonical basis, one vector per row (RREF).
  const Matrix<T>& basis() const { return basis_; }
  bool operator==(const Subspace& o) const { return basis_ == o.basis_; }
  bool operator!=(const Subspace& o) const { return !(*this == o); }

 private:
  explicit Subspace(Matrix<T> b) : basis_(std::move(b)) {}
  Matrix<T> basis_;
};

template <class T>
void require_same_ambient(const Subspace<T>& u, const Subspace<T>& w, const std::string& fn) {
  require(u.ambient() == w.ambient(), fn, "subspaces of the same space",
          "Q^" + std::to_string(u.ambient()) + " and Q^" + std::to_string(w.ambient()));
}

/// U + W.
template <class T>
Subspace<T> sum(const Subspace<T>& u, const Subspace<T>& w) {
  require_same_ambient(u, w, "sum");
  return Subspace<T>::span(vstack(u.basis(), w.basis()));
}

/// U° = {α : α(u) = 0 ∀ u ∈ U}.
template <class T>
Subspace<T> annihilator(const Subspace<T>& u) {
  return Subspace<T>::solutions(u.basis());
}

/// U ∩ W = {x : α(x) = 0 ∀ α ∈ U° + W°}.
template <class T>
Subspace<T> intersection(const Subspace<T>& u, const Subspace<T>& w) {
  require_same_ambient(u, w, "intersection");
  return Subspace<T>::solutions(vstack(annihilator(u).basis(), annihilator(w).basis()));
}

/// ker A = {x : A x = 0}.
template <class T>
Subspace<T> kernel(const Matrix<T>& a) {
  return Subspace<T>::solutions(a);
}

/// im A = span of the columns of A.
template <class T>
Subspace<T> image(const Matrix<T>& a) {
  return Subspace<T>::span(a.transpose());
}

/// A^{-1}(W) = {x : A x ∈ W} = {x : α(A x) = 0 ∀ α ∈ W°}.
template <class T>
Subspace<T> preimage(const Matrix<T>& a, const Subspace<T>& w) {
  require(a.rows() == w.ambient(), "preimage", "a map into Q^" + std::to_string(w.ambient()),
          "a " + shape(a) + " matrix");
  return Subspace<T>::solutions(annihilator(w).basis() * a);
}

/// W ⊆ U.
template <class T>
bool contains(const Subspace<T>& u, const Subspace<T>& w) {
  return sum(u, w).dim() == u.dim();
}

/// x ∈ U.
template <class T>
bool contains(const Subspace<T>& u, const std::vector<T>& x) {
  return contains(u, Subspace<T>::span(Matrix<T>::from_rows({x}, u.ambient())));
}

/// The image of U under x ↦ A x.
template <class T>
Subspace<T> map(const Matrix<T>& a, const Subspace<T>& u) {
  require(a.cols() == u.ambient(), "map", "a map from Q^" + std::to_string(u.ambient()), "a " + shape(a) + " matrix");
  return Subspace<T>::span(u.basis() * a.transpose());
}

/// An affine subspace p + U, or the empty set.
template <class T>
struct AffineSubspace {
  bool empty = true;
  std::vector<T> point;  ///< any point (empty when `empty`)
  Subspace<T> direction = Subspace<T>::zero(0);

  bool contains_point(const std::vector<T>& x) const {
    if (empty) return false;
    std::vector<T> d(x.size());
    for (Index i = 0; i < x.size(); ++i) d[i] = x[i] - point[i];
    return contains(direction, d);
  }
  /// Same set (points may differ).
  bool operator==(const AffineSubspace& o) const {
    if (empty || o.empty) return empty == o.empty;
    return direction == o.direction && contains_point(o.point);
  }
};

/// {x : A x = b}.
template <class T>
AffineSubspace<T> solve(const Matrix<T>& a, const std::vector<T>& b) {
  AffineSubspace<T> s;
  s.direction = kernel(a);
  s.empty = !solve_particular(a, b, s.point);
  return s;
}

}  // namespace dcad::reference
