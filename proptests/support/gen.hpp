// Exact random data with planted answers, for RapidCheck properties.  Call inside a property:
// every choice is a RapidCheck pick (`*gen`), so failures shrink toward small n and few shears.
#pragma once

#include "dcad/reference/dirac_bergmann.hpp"
#include "dcad/reference/rational.hpp"
#include "families.hpp"

#include <rapidcheck.h>

namespace dcad::test {

using Q = reference::Rational;
using QM = reference::Matrix<Q>;
using QSub = reference::Subspace<Q>;
using reference::Index;

/// Size knob: n in [lo, hi] (RapidCheck shrinks toward lo).
inline Index pick_size(Index lo, Index hi) { return *rc::gen::inRange<Index>(lo, hi + 1); }

/// A product of integer shears I + c E_ij (unimodular, integer inverse).
inline QM unimodular(Index n) {
  QM a = QM::identity(n);
  if (n < 2) return a;
  const int shears = *rc::gen::inRange<int>(0, static_cast<int>(2 * n + 1));
  for (int s = 0; s < shears; ++s) {
    const Index i = *rc::gen::inRange<Index>(0, n), j = *rc::gen::inRange<Index>(0, n);
    const int c = *rc::gen::element(-2, -1, 1, 2);
    if (i == j) continue;
    for (Index k = 0; k < n; ++k) a(i, k) += Q(c) * a(j, k);
  }
  return a;
}

/// Small random integer matrix.
inline QM integer_matrix(Index rows, Index cols, int bound = 3) {
  QM m(rows, cols);
  for (Index i = 0; i < rows; ++i)
    for (Index j = 0; j < cols; ++j) m(i, j) = Q(*rc::gen::inRange(-bound, bound + 1));
  return m;
}

/// A random covector/vector with small integer entries.
inline std::vector<Q> integer_vector(Index n, int bound = 3) { return integer_matrix(1, n, bound).row(0); }

/// The canonical form of rank 2h on Q^n: Ω(e_i, e_{h+i}) = 1 for i < h, zero elsewhere.
inline QM canonical_form(Index n, Index h) {
  QM j(n, n);
  for (Index i = 0; i < h; ++i) {
    j(i, h + i) = Q(1);
    j(h + i, i) = Q(-1);
  }
  return j;
}

/// Aᵀ J A: the form J in the coordinates x = A y (so it has the rank of J).
inline QM pull_back(const QM& j, const QM& a) { return a.transpose() * j * a; }

/// A random skew integer matrix.
inline QM skew_matrix(Index n, int bound = 2) {
  QM w(n, n);
  for (Index i = 0; i < n; ++i)
    for (Index k = i + 1; k < n; ++k) {
      w(i, k) = Q(*rc::gen::inRange(-bound, bound + 1));
      w(k, i) = -w(i, k);
    }
  return w;
}

/// Span of coordinate vectors e_i, i ∈ idx, mapped by A^{-1} (A unimodular): the subspace that A
/// sends to span{e_i}.
inline QSub coordinate_subspace(const QM& a_inverse, const std::vector<Index>& idx) {
  QM rows(idx.size(), a_inverse.rows());
  for (Index r = 0; r < idx.size(); ++r)
    for (Index k = 0; k < a_inverse.rows(); ++k) rows(r, k) = a_inverse(k, idx[r]);
  return QSub::span(rows);
}

/// A symplectic form W = Aᵀ J A on Q^{2m} with a subspace V of planted dim V = 2a + t and planted
/// dim V ∩ V^Ω = t (in J-coordinates V = span{e_1..e_a, f_1..f_a, e_{a+1}..e_{a+t}}).
struct PlantedSymplectic {
  Index m = 0, a = 0, t = 0;
  QM w, a_map;
  QSub v = QSub::zero(0);
  QSub kernel = QSub::zero(0);  ///< V ∩ V^Ω as planted: span{e_{a+1}..e_{a+t}} in J-coordinates
};

inline PlantedSymplectic planted_symplectic(Index max_m = 6) {
  PlantedSymplectic p;
  p.m = pick_size(1, max_m);
  p.a = *rc::gen::inRange<Index>(0, p.m + 1);
  p.t = *rc::gen::inRange<Index>(0, p.m - p.a + 1);
  p.a_map = unimodular(2 * p.m);
  p.w = pull_back(canonical_form(2 * p.m, p.m), p.a_map);
  std::vector<Index> idx;
  for (Index i = 0; i < p.a; ++i) {
    idx.push_back(i);
    idx.push_back(p.m + i);
  }
  for (Index i = p.a; i < p.a + p.t; ++i) idx.push_back(i);
  p.v = coordinate_subspace(reference::inverse(p.a_map), idx);
  std::vector<Index> isotropic;
  for (Index i = p.a; i < p.a + p.t; ++i) isotropic.push_back(i);
  p.kernel = coordinate_subspace(reference::inverse(p.a_map), isotropic);
  return p;
}

/// A presymplectic form of planted rank 2h on Q^n.
struct PlantedPresymplectic {
  Index n = 0, h = 0;
  QM w;
};

inline PlantedPresymplectic planted_presymplectic(Index max_n = 12) {
  PlantedPresymplectic p;
  p.n = pick_size(1, max_n);
  p.h = *rc::gen::inRange<Index>(0, p.n / 2 + 1);
  p.w = pull_back(canonical_form(p.n, p.h), unimodular(p.n));
  return p;
}

/// A Dirac structure from (E, ω_E) with planted dim E = k and rank ω_E = 2h (CEF Prop. 4.3).
struct PlantedDirac {
  Index n = 0, k = 0, h = 0;
  QSub e = QSub::zero(0);
  QM w;      ///< the form (distribution) or the bivector (Poisson)
  QM a_map;  ///< the unimodular change of coordinates that planted it
  reference::DiracStructure<Q> d;
};

inline PlantedDirac planted_dirac_from_distribution(Index max_n = 12) {
  PlantedDirac p;
  p.n = pick_size(1, max_n);
  p.k = *rc::gen::inRange<Index>(0, p.n + 1);
  p.h = *rc::gen::inRange<Index>(0, p.k / 2 + 1);
  const QM a = unimodular(p.n), ainv = reference::inverse(a);
  p.a_map = a;
  std::vector<Index> idx(p.k);
  for (Index i = 0; i < p.k; ++i) idx[i] = i;
  p.e = coordinate_subspace(ainv, idx);
  // In y = A x coordinates: canonical rank-2h block on the first k coordinates; arbitrary skew
  // entries that touch a coordinate ≥ k (invisible on E).
  QM z = canonical_form(p.n, 0);
  const QM junk = skew_matrix(p.n);
  for (Index i = 0; i < p.n; ++i)
    for (Index j = 0; j < p.n; ++j)
      if (i >= p.k || j >= p.k) z(i, j) = junk(i, j);
  for (Index i = 0; i < p.h; ++i) {
    z(i, p.h + i) = Q(1);
    z(p.h + i, i) = Q(-1);
  }
  p.w = pull_back(z, a);
  p.d = reference::dirac_from_distribution(p.e, p.w);
  return p;
}

/// The graph of a Poisson bivector P = B J Bᵀ of planted rank 2h.
inline PlantedDirac planted_dirac_from_poisson(Index max_n = 12) {
  PlantedDirac p;
  p.n = pick_size(1, max_n);
  p.h = *rc::gen::inRange<Index>(0, p.n / 2 + 1);
  p.k = 2 * p.h;
  const QM b = unimodular(p.n);
  p.a_map = b;
  p.w = b * canonical_form(p.n, p.h) * b.transpose();  // the bivector
  p.d = reference::dirac_from_poisson(p.w);
  return p;
}

/// A coordinate Lagrangian {v_i = 0 for i ∈ S, α_i = 0 for i ∉ S}, moved by pairing-preserving
/// maps: (v, α) ↦ (A v, A^{-T} α), B-fields (v, α + B v) and bivectors (v + β α, α), B, β skew.
inline reference::DiracStructure<Q> moved_lagrangian(Index max_n = 12) {
  const Index n = pick_size(1, max_n);
  QM g(n, 2 * n);
  for (Index i = 0; i < n; ++i) g(i, *rc::gen::arbitrary<bool>() ? i : n + i) = Q(1);
  const int moves = *rc::gen::inRange(0, 4);
  for (int s = 0; s < moves; ++s) {
    QM t = QM::identity(2 * n);
    switch (*rc::gen::inRange(0, 3)) {
      case 0: {
        const QM a = unimodular(n), ait = reference::inverse(a).transpose();
        for (Index i = 0; i < n; ++i)
          for (Index j = 0; j < n; ++j) {
            t(i, j) = a(i, j);
            t(n + i, n + j) = ait(i, j);
          }
        break;
      }
      case 1: {
        const QM b = skew_matrix(n);
        for (Index i = 0; i < n; ++i)
          for (Index j = 0; j < n; ++j) t(n + i, j) = b(i, j);
        break;
      }
      default: {
        const QM beta = skew_matrix(n);
        for (Index i = 0; i < n; ++i)
          for (Index j = 0; j < n; ++j) t(i, n + j) = beta(i, j);
      }
    }
    g = g * t.transpose();  // rows are elements (v, α): apply t to each
  }
  return reference::dirac_from_basis(g);
}

/// One of the three Dirac generators, chosen by RapidCheck.
inline reference::DiracStructure<Q> any_dirac(Index max_n = 12) {
  switch (*rc::gen::inRange(0, 3)) {
    case 0: return planted_dirac_from_distribution(max_n).d;
    case 1: return planted_dirac_from_poisson(max_n).d;
    default: return moved_lagrangian(max_n);
  }
}

/// A symmetric integer matrix of planted rank ≤ r: Aᵀ diag(±1, …, 0) A.
inline QM symmetric_matrix(Index n, Index r) {
  QM d(n, n);
  for (Index i = 0; i < r && i < n; ++i) d(i, i) = Q(*rc::gen::element(-2, -1, 1, 2));
  const QM a = unimodular(n);
  return a.transpose() * d * a;
}

/// A linear Dirac dynamical system in one of the input forms: a random Dirac structure with a
/// quadratic energy of random rank (g often in the range of H, so both consistent and
/// inconsistent systems occur), or a Lagrangian system on the Pontryagin bundle (CEF §6).
inline reference::LinearSystem<Q> long_tower_system(Index max_m);
inline reference::LinearSystem<Q> any_system(Index max_n = 8) {
  if (*rc::gen::inRange(0, 5) == 0) return long_tower_system(std::max<Index>(1, (max_n - 1) / 2));
  if (*rc::gen::arbitrary<bool>()) {
    const Index n = pick_size(1, std::max<Index>(1, max_n / 3));
    reference::PontryaginInput<Q> in;
    in.n = n;
    in.k = integer_matrix(*rc::gen::inRange<Index>(0, n + 1), n, 1);
    in.vv = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
    in.qq = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
    in.qv = *rc::gen::arbitrary<bool>() ? integer_matrix(n, n, 1) : QM(n, n);
    in.q = *rc::gen::arbitrary<bool>() ? integer_vector(n, 2) : std::vector<Q>(n, Q(0));
    in.v = *rc::gen::arbitrary<bool>() ? integer_vector(n, 2) : std::vector<Q>(n, Q(0));
    return reference::pontryagin_system(in);
  }
  reference::LinearSystem<Q> s;
  s.d = any_dirac(max_n);
  const Index n = s.d.n;
  s.hessian = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  s.gradient =
      *rc::gen::arbitrary<bool>() ? (s.hessian * QM::column(integer_vector(n, 2))).col(0) : integer_vector(n, 2);
  return s;
}

/// Pulls a system back by x = A y (A unimodular): D ↦ {(A^{-1} v, Aᵀ α)}, H ↦ Aᵀ H A, g ↦ Aᵀ g.
inline reference::LinearSystem<Q> change_coordinates(const reference::LinearSystem<Q>& s, const QM& a) {
  const Index n = s.d.n;
  const QM ainv = reference::inverse(a);
  QM t(2 * n, 2 * n);
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      t(i, j) = ainv(i, j);
      t(n + i, n + j) = a(j, i);
    }
  return {{n, QSub::span(s.d.d.basis() * t.transpose())},
          a.transpose() * s.hessian * a,
          (a.transpose() * QM::column(s.gradient)).col(0),
          s.constant};
}

/// A planted tower of full length c = N = 2m+1: coordinates (q_1..q_m, p_1..p_m, z), ω = Σ dq_i∧dp_i
/// (z spans ker ω), E = z q_1 + Σ_{i<m} p_i q_{i+1} + ½ p_m².  Then M_1 = {q_1 = 0} and each
/// tangency condition adds the next: q_2, …, q_m, p_m, …, p_1, z — dims N, N−1, …, 0.  Moved by a
/// random unimodular change of coordinates.
inline reference::LinearSystem<Q> long_tower_system(Index max_m = 4) {
  const Index m = pick_size(1, max_m), n = 2 * m + 1;
  const families::Instance t = families::tower_instance(m, unimodular(n), "tower", static_cast<double>(n));
  return {reference::dirac_from_presymplectic(t.omega), t.hessian, t.gradient, Q(0)};
}

/// Symplectic Ω = Aᵀ J A on Q^{2m}, quadratic E of random rank, k primary constraints (often
/// through a common point, so the system is often consistent).
inline reference::ConstrainedSystem<Q> any_constrained_system() {
  const Index m = pick_size(1, 4), n = 2 * m;
  reference::ConstrainedSystem<Q> s;
  const QM change = unimodular(n);
  s.omega = pull_back(canonical_form(n, m), change);
  s.hessian = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  s.gradient = integer_vector(n, 2);
  const Index k = *rc::gen::inRange<Index>(1, n);
  QM a = integer_matrix(k, n, 2);
  if (*rc::gen::arbitrary<bool>()) {  // isotropic primary constraints (on p only, before the change
    QM iso(k, n);                     // of basis): mutually first class, as for p_i = 0 in T*Q
    for (Index i = 0; i < k; ++i)
      for (Index c = 0; c < m; ++c) iso(i, m + c) = Q(*rc::gen::inRange(-2, 3));
    a = iso * change;
  }
  const std::vector<Q> x0 = integer_vector(n, 2);
  const QM rows = hstack(a, *rc::gen::arbitrary<bool>() ? a * QM::column(x0) : integer_matrix(k, 1, 2));
  // keep the rows whose gradients are independent: M is defined regularly (CEF §2.1)
  s.primary = QM(0, n + 1);
  for (Index i = 0; i < rows.rows(); ++i) {
    const QM more = vstack(s.primary, rows.block(i, i + 1, 0, n + 1));
    if (reference::rank(reference::gradients(more)) == more.rows()) s.primary = more;
  }
  return s;
}

/// 0–2 leaf functions φ_leaf(x) = c·x (level sets C) for the foliated setting of §7, or a 0×0 matrix where
/// they and the primary constraints are not defined regularly together.
inline QM any_leaf_functions(const reference::ConstrainedSystem<Q>& s) {
  const Index n = s.omega.rows();
  const Index nleaf = *rc::gen::inRange<Index>(0, 3);
  const QM leaf = hstack(integer_matrix(nleaf, n, 2), QM(nleaf, 1));
  return reference::rank(reference::gradients(vstack(s.primary, leaf))) == s.primary.rows() + nleaf ? leaf : QM(0, 0);
}

/// A point of an affine subspace: its point plus an integer combination of its directions.
inline std::vector<Q> some_point(const reference::AffineSubspace<Q>& m) {
  std::vector<Q> x = m.point;
  const QM c = integer_matrix(1, m.direction.dim());
  for (Index i = 0; i < m.direction.dim(); ++i)
    for (Index k = 0; k < x.size(); ++k) x[k] += c(0, i) * m.direction.basis()(i, k);
  return x;
}

/// A random subspace of a given subspace U (random integer combinations of its basis).
inline QSub random_subspace_of(const QSub& u) {
  if (u.dim() == 0) return u;
  const Index k = *rc::gen::inRange<Index>(0, u.dim() + 1);
  return QSub::span(integer_matrix(k, u.dim()) * u.basis());
}

}  // namespace dcad::test
