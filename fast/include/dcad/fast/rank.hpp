// The one place where dcad::fast decides a rank.  Every discrete answer of the fast backend
// (dimensions, solvability, containment, validity) is derived from a RankDecision, which carries
// its evidence and a verdict: certain or uncertain.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace dcad::fast {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// Thresholds of a rank decision, relative to `scale` (the 2-norm of the data the matrix came from).
///
/// A singular value σ is
///   * taken as zero  if σ ≤ τ0 = zero_factor · max(m, n) · ε · scale,
///   * taken as nonzero if σ > τ1 = nonzero_factor · scale,
///   * *uncertain* in between.
/// Why: a backward-stable SVD computes the exact singular values of A + E with ‖E‖ ≲ p(m,n) ε ‖A‖
/// (Higham, Accuracy and Stability, §20; the bound behind Eigen's and numpy's default
/// threshold max(m,n)·ε·σ₁), and the same holds for the orthonormal bases fed into it, so by Weyl's
/// inequality an exact zero shows up below τ0.  τ1 = √ε·scale (≈1.5e-8) keeps a margin of seven
/// orders of magnitude, so that a value reported nonzero is far from anything rounding produces.
/// A dropped σ ≤ τ0 is *assumed* to be an exact zero: that is sound only under the separation
/// hypothesis that the exact data's nonzero singular values exceed τ1 — true for the small-height
/// rational data dcad is built for, and exactly what the `certified` backend will check.
/// Two properties of the *input* void that hypothesis, and then no rank deficiency is ever certain:
///  * `input_exact` false — some input value was not representable in double, so rounding the
///    input may have destroyed the very degeneracy being decided (1 + 2^-60 reads as 1);
///  * `input_well_scaled` false — the nonzero input entries span more than 1/τ1 in magnitude
///    (graded data), so a singular value below τ0 may be a true one, not rounding.
/// `assess_input` sets the second from each input matrix.  The scale passed to a decision must be
/// that of the *data* (never the norm of a computed matrix that is zero in exact arithmetic).
struct Options {
  double zero_factor = 8.0;
  double nonzero_factor = 1.4901161193847656e-08;  // √ε
  bool input_exact = true;
  bool input_well_scaled = true;
};

/// Clears opt.input_well_scaled if the nonzero entries of `a`, together with 1, span more than
/// 1/nonzero_factor in magnitude.
void assess_input(const MatrixXd& a, Options& opt);

struct RankDecision {
  int rank = 0;
  int rows = 0, cols = 0;
  std::vector<double> singular_values;  ///< all of them, descending
  double scale = 0;                     ///< what the thresholds are relative to
  double zero_threshold = 0;            ///< τ0
  double nonzero_threshold = 0;         ///< τ1
  double gap = 0;                       ///< σ_rank / σ_{rank+1} (∞ if either side is empty)
  bool certain = true;
  std::string describe() const;  ///< evidence in one line
};

/// rank(A) with evidence.  `scale` < 0 means: the largest singular value of A itself.
/// A claimed deficiency is cross-checked on A equilibrated by exact powers of two (rows and columns
/// scaled to unit max-norm, after entries at rounding level are set to 0): rank is invariant under
/// such scaling, graded data is not, so if the two ranks differ the verdict is uncertain.
RankDecision decide_rank(const MatrixXd& a, double scale = -1, const Options& opt = {});
/// The same decision when the singular values (descending) of A are already computed.
RankDecision decide_rank(const MatrixXd& a, const VectorXd& sigma, double scale, const Options& opt);

/// Singular value decomposition A = U Σ Vᵀ with full U and V (one instantiation, in rank.cpp).
struct Svd {
  MatrixXd u, v;
  VectorXd sigma;
};
Svd full_svd(const MatrixXd& a);

/// An orthonormal basis (columns) of the orthogonal complement of the column span of an
/// orthonormal Q: no decision is needed, Q has full column rank.
MatrixXd orthogonal_complement(const MatrixXd& q);

/// 2-norm (largest singular value).
double norm2(const MatrixXd& a);

/// Throws std::invalid_argument naming `fn` if `a` has a NaN or an infinity.
void require_finite(const MatrixXd& a, const std::string& fn);

}  // namespace dcad::fast
