// Linear algebra at a point for the pointwise CAD: Gaussian elimination of constant rows and of jet
// rows with pivots that the decision object finds nonzero at the point (the rank there), and square
// solves whose rank was decided already.
#pragma once

#include "dcad/reference/nonlinear/pointwise/result.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dcad::reference {

namespace pointwise_detail {

/// Gaussian elimination on constant rows, pivots taken group by group: within a group the decision
/// object picks among all (row, column) candidates in column order — the exact route the first
/// nonzero, the double route the first that is at least 1/8 of the largest (threshold pivoting, so
/// that a chart is never built on a small pivot, like v_theta = v_x/(R cos phi) near phi = pi/2,
/// and is otherwise the preferred one) — and only when a group has no pivot left does the next come.  Returns the
/// pivots (row, column); rows and rhs are reduced.
template <class T, class Decide>
std::vector<std::pair<std::size_t, std::size_t>> eliminate_constants(
    std::vector<std::vector<T>>& rows, std::vector<T>& rhs, const std::vector<std::vector<std::size_t>>& groups,
    Decide& decide) {
  std::vector<std::pair<std::size_t, std::size_t>> piv;
  std::vector<char> used(rows.size(), 0);
  std::vector<std::size_t> used_cols;
  for (const auto& group : groups)
    for (;;) {
      std::vector<std::pair<std::size_t, std::size_t>> cand;
      std::vector<T> vals;
      for (std::size_t c : group) {
        if (std::find(used_cols.begin(), used_cols.end(), c) != used_cols.end()) continue;
        for (std::size_t i = 0; i < rows.size(); ++i)
          if (!used[i]) {
            cand.emplace_back(i, c);
            vals.push_back(rows[i][c]);
          }
      }
      const std::size_t k = decide.pivot(vals);
      if (k == vals.size()) break;
      const auto [p, c] = cand[k];
      used[p] = 1;
      used_cols.push_back(c);
      piv.emplace_back(p, c);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        if (i == p || rows[i][c] == 0) continue;
        const T f = rows[i][c] / rows[p][c];
        for (std::size_t j = 0; j < rows[i].size(); ++j) rows[i][j] -= f * rows[p][j];
        rhs[i] -= f * rhs[p];
        rows[i][c] = T(0);
      }
    }
  return piv;
}

/// The same with one group: columns in `col_order`.
template <class T, class Decide>
std::vector<std::pair<std::size_t, std::size_t>> eliminate_constants(std::vector<std::vector<T>>& rows,
                                                                     std::vector<T>& rhs,
                                                                     const std::vector<std::size_t>& col_order,
                                                                     Decide& decide) {
  return eliminate_constants(rows, rhs, std::vector<std::vector<std::size_t>>{col_order}, decide);
}

/// Elimination of jet rows R (with right-hand sides h) by pivots nonzero at the point.  The rows
/// left without a pivot must vanish identically (else the rank drops at the point: `singular`);
/// their right-hand sides are the Fredholm candidates.
template <class T>
struct JetElimination {
  std::vector<std::pair<std::size_t, std::size_t>> pivots;
  std::vector<T> pivot_values;  ///< each pivot's value at the point, after the eliminations before it (nonzero)
  std::vector<std::size_t> free_rows;
  std::vector<Jet<T>> candidates;
  std::string singular;  ///< empty if regular
};

template <class T, class Decide>
JetElimination<T> eliminate_jets(std::vector<std::vector<Jet<T>>> r, std::vector<Jet<T>> h, Decide& decide,
                                 const std::vector<std::string>& row_names, const std::vector<std::string>& col_names) {
  JetElimination<T> out;
  const std::size_t rows = r.size(), cols = rows ? r[0].size() : 0;
  std::vector<char> used(rows, 0);
  for (std::size_t c = 0; c < cols; ++c) {
    std::vector<std::size_t> cand;
    std::vector<T> vals;
    for (std::size_t i = 0; i < rows; ++i)
      if (!used[i]) {
        cand.push_back(i);
        vals.push_back(r[i][c].value());
      }
    const std::size_t k = decide.pivot(vals);
    if (k == vals.size()) continue;
    const std::size_t p = cand[k];
    used[p] = 1;
    out.pivots.emplace_back(p, c);
    out.pivot_values.push_back(vals[k]);
    const Jet<T> inv = r[p][c].reciprocal();
    for (std::size_t i = 0; i < rows; ++i) {
      if (used[i] || r[i][c].is_zero()) continue;
      const Jet<T> f = r[i][c] * inv;
      // every column: one skipped for want of a pivot is 0 at the point but not as a series
      for (std::size_t j = 0; j < cols; ++j) r[i][j] -= f * r[p][j];
      h[i] -= f * h[p];
    }
  }
  for (std::size_t i = 0; i < rows; ++i) {
    if (used[i]) continue;
    for (std::size_t c = 0; c < cols && out.singular.empty(); ++c)
      if (!decide.zero(r[i][c]))
        out.singular = "the rank of the system for (d/dt s, lambda) drops at the point: after the pivots, row " +
                       row_names[i] + " keeps a nonzero series in column " + col_names[c] +
                       " that vanishes at the point";
    out.free_rows.push_back(i);
    out.candidates.push_back(h[i]);
  }
  return out;
}

/// The largest value (no decision: for square systems whose rank was decided already), or
/// values.size() if all are exactly 0.
template <class T>
std::size_t largest(const std::vector<T>& v) {
  std::size_t best = v.size();
  for (std::size_t i = 0; i < v.size(); ++i)
    if (JetFunctions<T>::magnitude(v[i]) > 0 &&
        (best == v.size() || JetFunctions<T>::magnitude(v[i]) > JetFunctions<T>::magnitude(v[best])))
      best = i;
  return best;
}

/// Pivots by largest magnitude, decided nonzero (any nonzero pivot is exact; this one is the best conditioned).
template <class T, class Decide>
struct Largest {
  Decide& d;
  std::size_t pivot(const std::vector<T>& v) {
    const std::size_t best = largest(v);
    return best == v.size() || d.zero(v[best]) ? v.size() : best;
  }
};

/// The inverse of a square matrix whose rank was decided already (Gauss–Jordan, largest pivots).
template <class T>
std::vector<std::vector<T>> inverse(std::vector<std::vector<T>> a) {
  const std::size_t n = a.size();
  std::vector<std::vector<T>> inv(n, std::vector<T>(n, T(0)));
  for (std::size_t i = 0; i < n; ++i) inv[i][i] = T(1);
  for (std::size_t c = 0; c < n; ++c) {
    std::vector<T> vals;
    for (std::size_t i = c; i < n; ++i) vals.push_back(a[i][c]);
    const std::size_t p = c + largest(vals);
    if (p >= n) throw std::logic_error("pointwise_cad: singular Jacobian after a rank check");
    std::swap(a[p], a[c]);
    std::swap(inv[p], inv[c]);
    const T d = a[c][c];
    for (std::size_t j = 0; j < n; ++j) {
      a[c][j] /= d;
      inv[c][j] /= d;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (i == c || a[i][c] == 0) continue;
      const T f = a[i][c];
      for (std::size_t j = 0; j < n; ++j) {
        a[i][j] -= f * a[c][j];
        inv[i][j] -= f * inv[c][j];
      }
    }
  }
  return inv;
}

/// r·z = h for square jet rows whose rank was decided already (Gauss–Jordan on jets, largest pivots at the point).
template <class T>
std::vector<Jet<T>> solve_square(std::vector<std::vector<Jet<T>>> r, std::vector<Jet<T>> h) {
  const std::size_t n = r.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::vector<T> vals;
    for (std::size_t i = c; i < n; ++i) vals.push_back(r[i][c].value());
    const std::size_t p = c + largest(vals);
    if (p >= n) throw std::logic_error("pointwise_cad: singular square system after a rank check");
    std::swap(r[p], r[c]);
    std::swap(h[p], h[c]);
    const Jet<T> inv = r[c][c].reciprocal();
    for (std::size_t j = c; j < n; ++j) r[c][j] = r[c][j] * inv;
    h[c] = h[c] * inv;
    for (std::size_t i = 0; i < n; ++i) {
      if (i == c || r[i][c].is_zero()) continue;
      const Jet<T> f = r[i][c];
      for (std::size_t j = c; j < n; ++j) r[i][j] -= f * r[c][j];
      h[i] -= f * h[c];
    }
  }
  return h;
}

}  // namespace pointwise_detail

}  // namespace dcad::reference
