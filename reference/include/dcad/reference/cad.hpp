// The constraint algorithm for Dirac dynamical systems (CAD) on linear systems, literally:
//   M_0 = M,  W_k = T M_k ∩ E_D,  M_{k+1} = {x ∈ M_k : ⟨dE(x), W_k^D⟩ = 0}   [CEF (5.5)–(5.6),
// Lemma 5.1 (vii)], stopping at the first c with M_{c+1} = M_c.  Every M_k is affine.
#pragma once

#include "dcad/reference/system.hpp"

#include <optional>

namespace dcad::reference {

template <class T>
struct CadStep {
  AffineSubspace<T> m;                   ///< M_k (empty = inconsistent)
  Matrix<T> equations;                   ///< the equations a x = b added to reach M_k (independent), as rows [a | b]
  Subspace<T> w = Subspace<T>::zero(0);  ///< W_k = T M_k ∩ E_D (zero space if M_k is empty)
  long dim() const { return m.empty ? -1 : static_cast<long>(m.direction.dim()); }
};

template <class T>
struct CadResult {
  std::vector<CadStep<T>> tower;  ///< M_0 … M_c, or M_0 … M_k with M_k = ∅
  bool consistent = true;
  Index steps = 0;          ///< c (or k of the empty M_k)
  Index solution_rank = 0;  ///< dim(ker ω_D ∩ T M_c)  [Thm 5.4(b)]; meaningless if inconsistent
  bool unique() const { return consistent && solution_rank == 0; }
  const CadStep<T>& final_step() const { return tower.back(); }
};

/// The rows of `candidates` (as [a | b]) that raise the rank of [accumulated; row]: a basis of the
/// new constraints modulo the old.
/// Greedy in order: row i is kept iff it is independent of the rows before it — exactly the pivot
/// columns of RREF([accumulated; candidates]ᵀ) (the accumulated rows are independent).
template <class T>
Matrix<T> independent_new_rows(const Matrix<T>& accumulated, const Matrix<T>& candidates) {
  const std::vector<Index> piv = rref(vstack(accumulated, candidates).transpose()).pivots;
  Matrix<T> fresh(0, candidates.cols());
  for (Index p : piv)
    if (p >= accumulated.rows())
      fresh = vstack(fresh, candidates.block(p - accumulated.rows(), p - accumulated.rows() + 1, 0, candidates.cols()));
  return fresh;
}

template <class T>
AffineSubspace<T> affine_from_augmented(const Matrix<T>& aug) {
  const Index n = aug.cols() - 1;
  return solve(aug.block(0, aug.rows(), 0, n), aug.col(n));
}

/// The CAD tower with its trace.  [CEF §5]  `initial` ([a | b] rows) restricts M_0 to {a x = b}:
/// with D = D_{(T M_0, Ω)} that is the Gotay–Nester algorithm for (N, Ω, E, M_0)  [CEF §2.2, (2.5)].
template <class T>
CadResult<T> constraint_tower(const LinearSystem<T>& s, const Matrix<T>& initial = Matrix<T>()) {
  require_system(s, "constraint_tower");
  const Index n = s.d.n;
  const Subspace<T> e = dirac_distribution(s.d);
  CadResult<T> out;
  require(initial.rows() == 0 || initial.cols() == n + 1, "constraint_tower",
          "initial equations [a | b] of width " + std::to_string(n + 1), shape(initial));
  Matrix<T> aug = initial.rows() ? initial : Matrix<T>(0, n + 1);  // all equations so far, [a | b]
  CadStep<T> step{affine_from_augmented(aug), aug, Subspace<T>::zero(n)};
  if (step.m.empty) {  // the primary constraints themselves are inconsistent
    out.tower.push_back(step);
    out.consistent = false;
    return out;
  }
  for (;;) {
    step.w = intersection(step.m.direction, e);
    out.tower.push_back(step);
    const Matrix<T> u = dirac_orthogonal(s.d, step.w).basis();  // ⟨H x + g, u⟩ = 0 for u ∈ W_k^D
    Matrix<T> cand = hstack(u * s.hessian, -(u * Matrix<T>::column(s.gradient)));
    const Matrix<T> fresh = independent_new_rows(aug, cand);
    if (fresh.rows() == 0) break;  // M_{k+1} = M_k
    aug = vstack(aug, fresh);
    step = CadStep<T>{affine_from_augmented(aug), fresh, Subspace<T>::zero(n)};
    if (step.m.empty) {
      out.tower.push_back(step);
      out.consistent = false;
      break;
    }
  }
  out.steps = out.tower.size() - 1;
  if (out.consistent)
    out.solution_rank = intersection(form_kernel(dirac_form(s.d)), out.final_step().m.direction).dim();
  return out;
}

/// {ẋ ∈ T M_c ∩ E_D : (ẋ, dE(x)) ∈ D} at a point x ∈ M_c: the solutions of (5.7)–(5.8).
template <class T>
AffineSubspace<T> velocities(const LinearSystem<T>& s, const CadResult<T>& r, const std::vector<T>& x) {
  const Index n = s.d.n;
  // ẋ = Bᵀ w (B = basis of T M_c); (Bᵀ w, dE) ∈ D ⇔ Γ_v Bᵀ w = −Γ_α dE for the equations Γ of D.
  const Matrix<T>& b = r.final_step().m.direction.basis();
  const Matrix<T> g = annihilator(s.d.d).basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, n), ga = g.block(0, g.rows(), n, 2 * n);
  std::vector<T> rhs = (ga * Matrix<T>::column(energy_differential(s, x))).col(0);
  for (T& c : rhs) c = -c;
  const AffineSubspace<T> w = solve(gv * b.transpose(), rhs);
  AffineSubspace<T> out;
  out.empty = w.empty;
  out.direction = map(b.transpose(), w.direction);
  if (!w.empty) out.point = (b.transpose() * Matrix<T>::column(w.point)).col(0);
  return out;
}

/// A consistent initial point: solutions of (1.1) pass exactly through the points of M_c (CEF §5), so an
/// initial condition that prescribes some variables (`given[i]`, the rest free) is consistent iff the
/// prescribed values meet every equation of the tower.  `levels[k]`: the equations M_k adds, rows [a | b]
/// (the `equations` of a CadResult's steps, or a circuit route's levels).
template <class T>
struct InitialPoint {
  bool consistent = false;
  std::vector<T> point;  ///< consistent: a point of M_c with the given values, the free ones 0 where M_c allows
  Index level = 0;       ///< inconsistent: the first M_k whose equations the given values cannot meet …
  Matrix<T> violated;    ///< … and the first such equation, a row [a | b]
};

template <class T>
InitialPoint<T> consistent_initial_point(const std::vector<Matrix<T>>& levels,
                                         const std::vector<std::optional<T>>& given) {
  const Index n = given.size();
  Matrix<T> fixed(0, n + 1), defaults(0, n + 1), constraints(0, n + 1);
  for (Index i = 0; i < n; ++i) {
    Matrix<T> row(1, n + 1);
    row(0, i) = T(1);
    row(0, n) = given[i] ? *given[i] : T(0);
    if (given[i])
      fixed = vstack(fixed, row);
    else
      defaults = vstack(defaults, row);
  }
  for (const Matrix<T>& rows : levels) constraints = vstack(constraints, rows);
  // consistency of the given values with rows 0 … k of the tower is monotone in k: one solve when all
  // is well, a bisection for the first violated row when not
  const auto meets = [&](Index rows) {
    return !affine_from_augmented(vstack(fixed, constraints.block(0, rows, 0, n + 1))).empty;
  };
  InitialPoint<T> out;
  if (!meets(constraints.rows())) {
    Index lo = 0, hi = constraints.rows();  // meets(lo), !meets(hi)
    while (hi - lo > 1) {
      const Index mid = (lo + hi) / 2;
      (meets(mid) ? lo : hi) = mid;
    }
    out.violated = constraints.block(hi - 1, hi, 0, n + 1);
    for (Index k = 0, seen = 0; k < levels.size(); seen += levels[k].rows(), ++k)
      if (hi - 1 < seen + levels[k].rows()) {
        out.level = k;
        break;
      }
    return out;
  }
  const Matrix<T> acc = vstack(fixed, constraints);
  const AffineSubspace<T> with_defaults = affine_from_augmented(vstack(acc, defaults));
  out.consistent = true;
  out.point = (with_defaults.empty ? affine_from_augmented(acc) : with_defaults).point;
  return out;
}

/// The same for a tower: its steps' equations are the levels.
template <class T>
InitialPoint<T> consistent_initial_point(const CadResult<T>& r, const std::vector<std::optional<T>>& given) {
  std::vector<Matrix<T>> levels;
  for (const CadStep<T>& st : r.tower) levels.push_back(st.equations);
  return consistent_initial_point(levels, given);
}

/// ż = F z + f + G λ on M_c in coordinates z = S x (S selects variables `coords`), [CEF (5.12)].
template <class T>
struct ReducedEquations {
  std::vector<Index> coords;  ///< indices of the variables used as coordinates on M_c
  Matrix<T> f_matrix;         ///< F
  std::vector<T> f;           ///< f
  Matrix<T> g;                ///< G (columns span the non-uniqueness directions; 0 columns if unique)
};

/// Default coordinates: the pivot variables of the RREF basis of T M_c (then S Bᵀ = I).
template <class T>
std::vector<Index> default_coordinates(const CadResult<T>& r) {
  return rref(r.final_step().m.direction.basis()).pivots;
}

template <class T>
ReducedEquations<T> reduced_equations(const LinearSystem<T>& s, const CadResult<T>& r, std::vector<Index> coords = {}) {
  require(r.consistent, "reduced_equations", "a consistent system", "M_c empty");
  if (coords.empty()) coords = default_coordinates(r);
  const Index n = s.d.n, m = r.final_step().m.direction.dim();
  const Matrix<T>& b = r.final_step().m.direction.basis();  // m × n
  require(coords.size() == m, "reduced_equations", std::to_string(m) + " coordinates (dim M_c)",
          std::to_string(coords.size()));
  Matrix<T> sel(m, n);
  for (Index i = 0; i < m; ++i) sel(i, coords[i]) = T(1);
  const Matrix<T> t = sel * b.transpose();  // dz = T dy for x = x0 + Bᵀ y
  require(rank(t) == m, "reduced_equations", "coordinates that parametrize M_c", "variables that do not");
  const Matrix<T> tinv = inverse(t);
  const std::vector<T>& x0 = r.final_step().m.point;
  // velocity at x = x0 + Bᵀ y is Bᵀ w, w = P y + p0 + K λ: solve Γ_v Bᵀ w = −Γ_α (H x + g).
  const Matrix<T> g = annihilator(s.d.d).basis();
  const Matrix<T> gv = g.block(0, g.rows(), 0, n), ga = g.block(0, g.rows(), n, 2 * n);
  const Matrix<T> lhs = gv * b.transpose(), dh = -(ga * s.hessian * b.transpose());
  std::vector<T> rhs0 = (ga * Matrix<T>::column(energy_differential(s, x0))).col(0);
  for (T& c : rhs0) c = -c;
  Matrix<T> p;
  solve_particular(lhs, dh, p);  // every column solvable: M_c is invariant (CEF Thm 5.4)
  std::vector<T> p0;
  solve_particular(lhs, rhs0, p0);
  // z = S x0 + T y  ⇒  ż = T w = T P T⁻¹ (z − S x0) + T p0 + T K λ.
  ReducedEquations<T> red;
  red.coords = coords;
  red.f_matrix = t * p * tinv;
  const std::vector<T> sx0 = (sel * Matrix<T>::column(x0)).col(0);
  red.f = (t * Matrix<T>::column(p0)).col(0);
  const std::vector<T> shift = (red.f_matrix * Matrix<T>::column(sx0)).col(0);
  for (Index i = 0; i < m; ++i) red.f[i] -= shift[i];
  red.g = t * kernel(lhs).basis().transpose();
  return red;
}

}  // namespace dcad::reference
