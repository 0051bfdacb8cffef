// Exact → double conversion for fast-vs-reference properties: dcad::fast_exact's, the one the CLI uses.
#pragma once

#include "dcad/fast/dirac.hpp"
#include "dcad/fast/exact.hpp"
#include "gen.hpp"

namespace dcad::test {

/// Rounds to double (fast::to_double); with `opt`, records as the CLI does whether the input's
/// heights and span leave fast's rank deficiencies certain.
inline Eigen::MatrixXd to_double(const QM& m, fast::Options* opt = nullptr) {
  fast::Options ignored;
  return fast::to_double(m, opt ? *opt : ignored);
}

inline Eigen::VectorXd to_double(const std::vector<Q>& v, fast::Options* opt = nullptr) {
  fast::Options ignored;
  return fast::to_double(v, opt ? *opt : ignored);
}

/// The exact subspace as a fast one (for angles; small exact bases are well conditioned).
inline fast::Subspace to_fast(const QSub& s) {
  if (s.dim() == 0) return fast::Subspace::zero(static_cast<int>(s.ambient()));
  return fast::Subspace::span(to_double(s.basis()));  // both twins: rows
}

/// 2-norm condition number of an exact square matrix, in double.
inline double condition(const QM& a) {
  const Eigen::MatrixXd d = to_double(a);
  const auto s = fast::full_svd(d).sigma;
  return s.size() ? s(0) / s(s.size() - 1) : 1.0;
}

/// Bound on sin θ(fast, exact): a backward-stable computation on data of condition κ
/// perturbs a well-separated subspace by O(n ε κ) (Wedin); 1e3 covers the chain of steps.
inline double angle_bound(Index n, double kappa) { return 1e3 * static_cast<double>(n + 1) * 2.2e-16 * kappa; }

}  // namespace dcad::test
