// Dirac's theory of constraints for linear constrained Hamiltonian systems (N, Ω, E, M), literally:
// N = Q^{2n} with symplectic Ω (matrix W), E = ½ xᵀ H x + gᵀ x, primary constraints
// φ_i(x) = a_i·x − b_i with M = {φ = 0}.  Brackets: {f, g} = df ᵀ J dg with J = (Wᵀ)^{-1}, so that
// X_f = J df solves i_{X_f} Ω = df and {q, p} = 1 for Ω = dq ∧ dp (ERRATA conventions).
#pragma once

#include "dcad/reference/cad.hpp"

#include <algorithm>

namespace dcad::reference {

template <class T>
struct ConstrainedSystem {
  Matrix<T> omega;          ///< W, symplectic
  Matrix<T> hessian;        ///< H
  std::vector<T> gradient;  ///< g
  Matrix<T> primary;        ///< rows [a_i | b_i]: φ_i = a_i·x − b_i
};

/// J = (Wᵀ)^{-1}: the Poisson tensor of Ω.
template <class T>
Matrix<T> poisson_tensor(const Matrix<T>& w) {
  require_symplectic(w, "poisson_tensor");
  return inverse(w.transpose());
}

/// Gradient rows a_i of constraint rows [a_i | b_i].
template <class T>
Matrix<T> gradients(const Matrix<T>& constraints) {
  return constraints.block(0, constraints.rows(), 0, constraints.cols() - 1);
}

/// The Dirac–Bergmann tower: E_T = E + λ^i φ_i (i over primary constraints); at step k every known
/// constraint φ_j must be preserved, {φ_j, E}(x) + λ^i {φ_j, φ_i} = 0 on M_k (CEF (2.1)–(2.2)); the
/// combinations μ with μ^j {φ_j, φ_i} = 0 give the next (secondary) constraints μ^j {φ_j, E} = 0.
template <class T>
struct DiracBergmannResult {
  std::vector<AffineSubspace<T>> tower;  ///< M_0 = M, M_1, …
  Matrix<T> constraints;                 ///< all constraints of M_c (independent rows [a | b])
  bool consistent = true;
};

/// M must be defined regularly (CEF §2.1): independent gradients of the primary constraints.
template <class T>
void require_regular_primary(const ConstrainedSystem<T>& s, const std::string& fn) {
  require(s.primary.cols() == s.omega.rows() + 1, fn,
          "primary constraint rows [a | b] of width " + std::to_string(s.omega.rows() + 1), shape(s.primary));
  require(rank(gradients(s.primary)) == s.primary.rows(), fn,
          "primary constraints with independent gradients (M defined regularly)",
          std::to_string(s.primary.rows()) + " constraints with gradients of rank " +
              std::to_string(rank(gradients(s.primary))));
}

template <class T>
DiracBergmannResult<T> dirac_bergmann(const ConstrainedSystem<T>& s) {
  require_regular_primary(s, "dirac_bergmann");
  const Matrix<T> j = poisson_tensor(s.omega);
  const Index n = s.omega.rows();
  DiracBergmannResult<T> out;
  Matrix<T> all = independent_new_rows(Matrix<T>(0, n + 1), s.primary);
  const Matrix<T> prim = gradients(s.primary);
  out.tower.push_back(affine_from_augmented(all));
  if (out.tower.back().empty) {
    out.consistent = false;
    return out;
  }
  for (;;) {
    const Matrix<T> a = gradients(all);
    const Matrix<T> c = a * j * prim.transpose();   // {φ_j, φ_i}, j all, i primary
    const Matrix<T> mu = nullspace(c.transpose());  // rows μ with μ C = 0
    const Matrix<T> lhs = mu * a * j * s.hessian;   // μ^j {φ_j, E}(x) = μ A J (H x + g)
    const Matrix<T> rhs = -(mu * a * j * Matrix<T>::column(s.gradient));
    const Matrix<T> fresh = independent_new_rows(all, hstack(lhs, rhs));
    if (fresh.rows() == 0) break;
    all = vstack(all, fresh);
    out.tower.push_back(affine_from_augmented(all));
    if (out.tower.back().empty) {
      out.consistent = false;
      break;
    }
  }
  out.constraints = all;
  return out;
}

/// Λ^(c)_x = {λ : {φ_j, E}(x) + λ^i {φ_j, φ_i} = 0 for all constraints φ_j of M_c}.  [CEF §2.1]
template <class T>
AffineSubspace<T> multipliers(const ConstrainedSystem<T>& s, const DiracBergmannResult<T>& r, const std::vector<T>& x) {
  const Matrix<T> j = poisson_tensor(s.omega), a = gradients(r.constraints);
  std::vector<T> de = (s.hessian * Matrix<T>::column(x)).col(0);
  for (Index i = 0; i < de.size(); ++i) de[i] += s.gradient[i];
  std::vector<T> rhs = (a * j * Matrix<T>::column(de)).col(0);
  for (T& v : rhs) v = -v;
  return solve(a * j * gradients(s.primary).transpose(), rhs);
}

/// X_{E_T}(x) = J (dE(x) + λ^i a_i).
template <class T>
std::vector<T> total_energy_field(const ConstrainedSystem<T>& s, const std::vector<T>& x,
                                  const std::vector<T>& lambda) {
  std::vector<T> d = (s.hessian * Matrix<T>::column(x)).col(0);
  const Matrix<T> prim = gradients(s.primary);
  for (Index i = 0; i < d.size(); ++i) {
    d[i] += s.gradient[i];
    for (Index k = 0; k < lambda.size(); ++k) d[i] += lambda[k] * prim(k, i);
  }
  return (poisson_tensor(s.omega) * Matrix<T>::column(d)).col(0);
}

/// First and second class constraints of a constraint set (CEF §2.1, Lemma 3.23): χ are 2s of the
/// given constraints with det {χ_i, χ_j} ≠ 0 (2s = rank of the bracket matrix); ψ are the
/// combinations λ^j φ_j with λ^j {φ_j, φ_k} = 0 for all k.
/// Gotay–Nester's setting for (N, Ω, E, M): the Dirac structure D_{(T M, Ω)} (E_D = T M, ω_D = Ω|) with
/// the energy E  [CEF §2.2; §5: "the Gotay–Nester algorithm corresponds to E_D = TM"].
template <class T>
LinearSystem<T> gotay_nester_system(const ConstrainedSystem<T>& s) {
  return {dirac_from_distribution(kernel(gradients(s.primary)), s.omega), s.hessian, s.gradient, T(0)};
}

/// The Gotay–Nester algorithm: the CAD of gotay_nester_system(s) from M_0 = M  [CEF §2.2].
template <class T>
CadResult<T> gotay_nester(const ConstrainedSystem<T>& s) {
  return constraint_tower(gotay_nester_system(s), s.primary);
}

/// The secondary constraints of a tower: the equations it added after M_0, rows [a | b], in order.
template <class T>
Matrix<T> secondary_constraints(const CadResult<T>& r) {
  Matrix<T> out(0, r.tower.front().equations.cols());
  for (Index k = 1; k < r.tower.size(); ++k) out = vstack(out, r.tower[k].equations);
  return out;
}

template <class T>
struct ConstraintClasses {
  Index s = 0;
  std::vector<Index> second;  ///< indices of χ among the constraint rows
  Matrix<T> first;            ///< rows [a | b] of ψ
  Matrix<T> sigma;            ///< Σ = [{χ_i, χ_j}]
  Matrix<T> dirac_tensor;     ///< J* = J − J Gᵀ Σ⁻¹ G J, G = gradients of χ  [Lemma 3.23 (e)]
  Subspace<T> second_class_subbundle = Subspace<T>::zero(0);  ///< V^Ω = {X : dχ(X) = 0} = T S^V  [Thm 3.24]
};

template <class T>
ConstraintClasses<T> classify_constraints(const Matrix<T>& w, const Matrix<T>& constraints) {
  const Matrix<T> j = poisson_tensor(w), a = gradients(constraints);
  const Matrix<T> c = a * j * a.transpose();
  ConstraintClasses<T> out;
  out.s = rank(c) / 2;
  const auto principal = [&](const std::vector<Index>& idx) {
    Matrix<T> m(idx.size(), idx.size());
    for (Index p = 0; p < idx.size(); ++p)
      for (Index q = 0; q < idx.size(); ++q) m(p, q) = c(idx[p], idx[q]);
    return m;
  };
  // Grow a nonsingular principal submatrix by pairs.  While |S| < rank, the Schur complement of C_S
  // is a nonzero skew matrix, so some pair (p, q) outside S extends it.
  const auto chosen = [&](Index i) { return std::find(out.second.begin(), out.second.end(), i) != out.second.end(); };
  while (out.second.size() < 2 * out.s) {
    bool grown = false;
    for (Index p = 0; p < c.rows() && !grown; ++p)
      for (Index q = p + 1; q < c.rows() && !grown; ++q) {
        if (chosen(p) || chosen(q)) continue;
        std::vector<Index> more = out.second;
        more.push_back(p);
        more.push_back(q);
        if (rank(principal(more)) == more.size()) {
          out.second = more;
          grown = true;
        }
      }
    require(grown, "classify_constraints", "a nonsingular principal extension (Schur complement argument)", "none");
  }
  out.first = nullspace(c) * constraints;
  Matrix<T> g(out.second.size(), a.cols());
  for (Index p = 0; p < out.second.size(); ++p)
    for (Index k = 0; k < a.cols(); ++k) g(p, k) = a(out.second[p], k);
  out.sigma = g * j * g.transpose();
  out.second_class_subbundle = kernel(g);  // V = span{X_χ}; V^Ω = {X : Ω(X_χ, X) = dχ(X) = 0}
  out.dirac_tensor = out.second.empty() ? j : j - j * g.transpose() * inverse(out.sigma) * g * j;
  return out;
}

/// A second class submanifold through S chosen by V (CEF Lemma 3.23 (d)): its tangent V^Ω, the
/// constraints χ′ defining it and their bracket matrix, and the Dirac tensor of χ′.
template <class T>
struct SecondClassChoice {
  Subspace<T> tangent = Subspace<T>::zero(0);  ///< V^Ω = T S^V
  Matrix<T> chi;                               ///< rows [a | b]: the a span V^♭ = (V^Ω)°, b = a·x₀
  Matrix<T> sigma;                             ///< [{χ′_i, χ′_j}]
  Matrix<T> dirac_tensor;                      ///< J − J Aᵀ Σ⁻¹ A J  [Lemma 3.23 (e)]
};

/// Lemma 3.23 (d) for S = x₀ + TS: any V with V ⊕ ker ω = (TS)^Ω (3.12), ω = Ω|_{TS}, gives S^V = x₀ + V^Ω
/// ⊇ S, defined by χ′ with dχ′ spanning V^♭ (Ω(v, ·), v ∈ V: they vanish exactly on V^Ω).  Literal:
/// (3.12) is checked (std::invalid_argument where V is no such complement), nothing else is.
template <class T>
SecondClassChoice<T> second_class_choice(const Matrix<T>& w, const AffineSubspace<T>& s, const Subspace<T>& v) {
  require(!s.empty, "second_class_choice", "a nonempty S", "the empty set");
  const Subspace<T> kerw = form_kernel(restrict_form(w, s.direction));
  require(intersection(v, kerw).dim() == 0 && sum(v, kerw) == symplectic_complement(w, s.direction),
          "second_class_choice", "V with V ⊕ ker ω = (TS)^Ω (CEF (3.12))", "another subspace");
  SecondClassChoice<T> out;
  out.tangent = symplectic_complement(w, v);
  const Matrix<T> a = v.basis() * w;  // row i: y ↦ v_iᵀ W y = Ω(v_i, y)
  out.chi = hstack(a, a * Matrix<T>::column(s.point));
  const Matrix<T> j = poisson_tensor(w);
  out.sigma = a * j * a.transpose();
  out.dirac_tensor = v.dim() == 0 ? j : j - j * a.transpose() * inverse(out.sigma) * a * j;
  return out;
}

/// Def 3.22: S (direction TS) is a first class constraint submanifold of (P, Ω) when every function that
/// vanishes on S is first class — X_f = J df ∈ TS for every df ∈ (TS)° — literally, over a basis of (TS)°.
template <class T>
bool is_first_class_submanifold(const Matrix<T>& w, const Subspace<T>& ts) {
  const Matrix<T> j = poisson_tensor(w), a = annihilator(ts).basis();
  for (Index i = 0; i < a.rows(); ++i)
    if (!contains(ts, (j * Matrix<T>::column(a.row(i))).col(0))) return false;
  return true;
}

/// f(x) = ½ xᵀ A x + bᵀ x + c on N (A symmetric).
template <class T>
struct QuadraticFunction {
  Matrix<T> a;
  std::vector<T> b;
  T c = T(0);
};

/// Remark 2.2's weak equality f ≈ 0, literally: f|_{M_c} = 0.  On x = x₀ + Σ t_k d_k (M_c's point and basis)
/// f is a polynomial in t, zero exactly when D A Dᵀ = 0, D (A x₀ + b) = 0 and f(x₀) = 0.  (Remark 2.2's other
/// side, f = ν^i φ_i^(c), is fast's route: fast::weakly_zero.)
template <class T>
bool weakly_zero(const AffineSubspace<T>& mc, const QuadraticFunction<T>& f) {
  require(!mc.empty, "weakly_zero", "a nonempty M_c", "the empty set");
  const Matrix<T>& d = mc.direction.basis();
  const Matrix<T> x0 = Matrix<T>::column(mc.point);
  const Matrix<T> slope = f.a * x0 + Matrix<T>::column(f.b);
  const T value = (x0.transpose() * f.a * x0)(0, 0) / T(2) + (Matrix<T>::column(f.b).transpose() * x0)(0, 0) + f.c;
  return (d * f.a * d.transpose()).is_zero() && (d * slope).is_zero() && value == T(0);
}

}  // namespace dcad::reference
