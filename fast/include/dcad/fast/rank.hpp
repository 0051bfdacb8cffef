// The one place where dcad::fast decides a rank.  Every discrete answer of the fast backend
// (dimensions, solvability, containment, validity) is derived from a RankDecision, which carries
// its evidence and a verdict: certain or uncertain.
#pragma once

#include "dcad/trace.hpp"
#include "dcad/truth.hpp"

#include <Eigen/Core>

#include <initializer_list>
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
/// inequality an exact zero shows up below τ0.  zero_factor is 64, not the 8 of a single SVD: the
/// matrices decided here are computed through several orthogonal steps, whose rounding adds up
/// (at 8, the sweep's planted towers came out uncertain on 84 % of instances with residues of
/// 40–70 ε; at 64, 22 %, and no answer claimed certain changed — `bash bench/run.sh`).
/// τ1 = √ε·scale (≈1.5e-8) keeps a margin of three or more orders of magnitude above τ0 (for
/// max(m, n) ≤ 10^3), so that a value reported nonzero is far from anything rounding produces.
/// A dropped σ ≤ τ0 is *assumed* to be an exact zero: that is sound only under the separation
/// hypothesis that the exact data's nonzero singular values exceed τ1 — true for most small-height
/// rational data, not all: an integer matrix's smallest nonzero σ can be 1/(σ₁σ₂⋯) (Cauchy–Binet), and a 3×3 one of
/// height 1.3e7 with determinant 6 has σ₃ = 3.9e-10 (cases/regression-pointwise-height.json).  So fast::solve
/// confirms a certain answer by the certified tier (Options::confirm_exactly, below) before it says certified.
/// Two properties of the *input* void that hypothesis, and then no rank deficiency is ever certain:
///  * `input_exact` false — some input value was rounded to double in a digit that may decide the
///    answer, so rounding the input may have destroyed the very degeneracy being decided (1 + 2^-60
///    reads as 1).  The one exact → double conversion (dcad/fast/exact.hpp) clears it for a rounded value of height
///    above 1/nonzero_factor (x = 2^e p/q, p, q odd: max(|p|, q)); a rounded 1/3 moves by 2^-53
///    relative, as the first step of any computation does, and leaves the hypothesis as it was;
///  * `input_well_scaled` false — the binary digits of the nonzero input entries span more than 1/τ1
///    in magnitude: graded data (entries 1 and 2^-30), or an entry 1 + 2^-40, which carries 2^-40 as
///    much as an entry 2^-40 does; so a singular value below τ0 may be a true one, not rounding.
/// `assess_input` sets the second from each input matrix.  The scale passed to a decision must be
/// that of the *data* (never the norm of a computed matrix that is zero in exact arithmetic).
///
/// `probe` (testing only): counts the decisions made with these options, in order, and reports the
/// one numbered `uncertain_at` uncertain whatever its evidence.  Every result built on a decision
/// must then say uncertain (prop_uncertainty: a verdict dropped at any place that combines them fails).
struct DecisionProbe {
  long made = 0;           ///< decisions made so far
  long uncertain_at = -1;  ///< the decision (0-based) to report uncertain; −1: none
};

struct Options {
  double zero_factor = 64.0;
  double nonzero_factor = 1.4901161193847656e-08;  // √ε
  bool input_exact = true;
  bool input_well_scaled = true;
  /// Whether the two flags above describe this computation's data.  False (the default): the data are a
  /// caller's doubles nobody has looked at, and every public entry point assesses the raw matrices it is
  /// given (`assessed`, below) before deciding anything, then passes options with this set to what it
  /// calls; a decision made with it still false (on data no entry point assessed) is never certain about
  /// a rank deficiency.  dcad/fast/exact.hpp's conversions set it (they assess the exact values).  Set
  /// it yourself only after assess_input on all of your data, or to vouch that your doubles are exact
  /// data of small height (the separation hypothesis above).
  bool input_assessed = false;
  /// Decisions on matrices with more than this many rows and columns go by pivoted QR first (see
  /// RankDecision); the properties set it to 0 to put every decision through that route.
  int qr_from = 48;
  /// The dae form goes by the sparse route (reference/fast_backend/src/dae_sparse.cpp) from this many variables on,
  /// and always where E and A are too large to hold densely: only where the dense routes cannot run, as
  /// its answers are less sure (see there); the tests set it to 0 to compare it with the reference.
  int dae_sparse_from = 2001;
  /// On that route, the part of C_k outside E's row space is factored by sparse QR (not a dense SVD) from
  /// this many constraints on, where it is at most 5 % filled; 0: always (the tests, to compare both).
  int dae_sparse_qr_from = 201;
  DecisionProbe* probe = nullptr;  ///< testing: see DecisionProbe (shared by copies of these options)
  /// The fast backend (fast::solve, `--backend fast`) confirms a certain answer that rests on a rank decided in
  /// double by the certified tier (exact), up to 2000 variables, before it says certified
  /// (reference/fast_backend/src/solve.cpp: the separation hypothesis above fails on integer data of height 10^6).
  /// False: the answer's certainty is fast's own decisions' — for the properties that hold those decisions to the
  /// reference, never for a user.
  bool confirm_exactly = true;
};

/// τ0 of a decision on a rows × cols matrix at `scale` (no decision is made).
double zero_threshold(int rows, int cols, double scale, const Options& opt);

/// Clears opt.input_well_scaled if the binary digits of the nonzero entries of `a` (each entry's
/// largest and its lowest nonzero digit), together with 1, span more than 1/nonzero_factor in magnitude.
void assess_input(const Eigen::Ref<const MatrixXd>& a, Options& opt);
/// `opt` itself if it is already assessed; else a copy with assess_input applied to each of `data` (a
/// public entry point's raw input: matrices, vectors, a caller's values) and input_assessed set.
Options assessed(const Options& opt, std::initializer_list<Eigen::Ref<const MatrixXd>> data);
/// Whether a rank deficiency may be certain with these options: assessed, exact and well scaled.
inline bool deficiency_provable(const Options& opt) {
  return opt.input_assessed && opt.input_exact && opt.input_well_scaled;
}

/// A decision is made in one of three ways (the evidence says which):
///  * by the norm alone: ‖A‖_F ≤ τ0 bounds every singular value, so rank 0 without a factorization
///    (the last step of every CAD, whose candidates all project to rounding residue);
///  * by an SVD: `singular_values` are all of them, descending;
///  * by a column-pivoted QR, A P = Q R (large matrices, issue 14): `singular_values` are |r_ii|
///    (descending, a rank-revealing estimate, not singular values), and the verdict rests on two
///    bounds that hold for the R of A + E with ‖E‖ ≲ p(m,n) ε ‖A‖ (the same backward error as an
///    SVD's): σ_rank ≥ σ_min(R₁₁) ≥ 1/‖R₁₁⁻¹‖_F (R₁₁ = R[0:r, 0:r], a column subset of A P) and
///    σ_{rank+1} ≤ ‖R₂₂‖₂ ≤ ‖R₂₂‖_F (Weyl: R minus a rank-r matrix; Golub–Van Loan §5.4.2).
///    Where ‖R₂₂‖_F exceeds τ0 by less than √rank(R₂₂) (rounding residue of a large block: N ≳ 1000),
///    twice a 30-step power estimate of ‖R₂₂‖₂ stands in for the bound — a heuristic, like τ0 itself.
///    When σ_rank is provably inside the band (τ0 < 1/‖R₁₁⁻¹‖_F and ‖R[r−1:, r−1:]‖_F ≤ τ1), the QR
///    route answers "uncertain" itself, as the SVD would.
///    The QR route answers only when σ_{rank+1} ≤ τ0 and σ_rank > τ1 follow from those bounds, i.e.
///    when the SVD would give the same rank, certain; otherwise the SVD decides.
struct RankDecision {
  int rank = 0;
  int rows = 0, cols = 0;
  std::vector<double> singular_values;  ///< SVD: all, descending; QR: |r_ii|, descending
  double scale = 0;                     ///< what the thresholds are relative to
  double zero_threshold = 0;            ///< τ0
  double nonzero_threshold = 0;         ///< τ1
  double gap = 0;                       ///< (a lower bound of) σ_rank / σ_{rank+1} (∞ if either side is empty)
  double largest = 0;                   ///< σ₁ (QR: |r_00|, within a factor √n of σ₁)
  double kept_lower = 0;                ///< σ_rank (QR: a lower bound of it); ∞ if rank = 0
  double dropped_upper = 0;             ///< σ_{rank+1} (QR: an upper bound of it); 0 if none
  bool by_qr = false;
  bool by_norm = false;          ///< rank 0 because ‖A‖_F ≤ τ0 (then σ₁ ≤ ‖A‖_F): no factorization
  bool by_two_routes = false;    ///< decide_rank_either: the verdict of two routes
  Truth certain = yes;           ///< yes, or unknown
  bool probed = false;           ///< testing: the DecisionProbe reported this decision uncertain
  int structural = -1;           ///< the rank of A's pattern (proved_by_structure); −1: not used
  std::string describe() const;  ///< evidence in one line
};

/// A deficiency explained by the pattern of A: `structural` is the structural rank of A (a maximum matching of
/// rows to columns through entries that are not identically 0 as functions — the entries' values play no part),
/// which bounds rank(A) at every value, since a nonzero minor needs a perfect matching of nonzero entries.  Where it
/// equals the decided rank and σ_rank is beyond τ1 (so the rank is at least that), the rank is proved whatever
/// the input's rounding or grading: certain (unless the probe reported the decision uncertain).  Else `d` as it was.
RankDecision proved_by_structure(RankDecision d, int structural);

/// The decision as an entry of Solution::trace (dcad/trace.hpp), `what` naming what was decided.
Decision traced(const RankDecision& d, const std::string& what);
/// Each decision of `ds`, in order, appended to `trace` with `what` and its place ("what #i").
void append_traced(std::vector<Decision>& trace, const std::vector<RankDecision>& ds, const std::string& what);

/// rank(A) with evidence.  `scale` < 0 means: the largest singular value of A itself.
/// A claimed deficiency is cross-checked on A equilibrated by exact powers of two (rows and columns
/// scaled to unit max-norm, after entries at rounding level are set to 0): rank is invariant under
/// such scaling, graded data is not, so if the two ranks differ the verdict is uncertain.  The
/// equilibrated matrix is decided with A's zero threshold times the scaling's gain (the rounding
/// residue grows with it), so graded data fails the check and plain computed data passes.
RankDecision decide_rank(const MatrixXd& a, double scale = -1, const Options& opt = {});
/// The same decision when the singular values (descending) of A are already computed.
RankDecision decide_rank(const MatrixXd& a, const VectorXd& sigma, double scale, const Options& opt);
/// One rank reached two ways — rank(A) − offset and rank(B) (B's singular values `sigma_b`), for a rank
/// both describe (fast::forced_tower: the new rows of a step, from [old; candidates] and from the
/// candidates projected off the old rows): certain when the two agree and either is certain (then with
/// B's evidence), else A's, uncertain.  One decision (DecisionProbe counts it once).
RankDecision decide_rank_either(const MatrixXd& a, int offset, double scale_a, const MatrixXd& b,
                                const VectorXd& sigma_b, double scale_b, const Options& opt);

/// Singular value decomposition A = U Σ Vᵀ with full U and V (one instantiation, in rank.cpp).
struct Svd {
  MatrixXd u, v;
  VectorXd sigma;
};
Svd full_svd(const MatrixXd& a);

/// The factorization behind one rank decision, kept for what the callers need next: an orthogonal
/// Q (m×m) whose first `rank` columns span im A, and the minimum-norm solutions of Aᵀ X = B on
/// the decided rank.  Column-pivoted QR when its bounds decide (see RankDecision), else the SVD.
class RankRevealing {
 public:
  /// `count`: the decision is one of the caller's (DecisionProbe); false inside another decision.
  RankRevealing(const MatrixXd& a, double scale, const Options& opt, bool count = true);
  const RankDecision& decision() const { return d_; }
  int rank() const { return d_.rank; }
  MatrixXd range() const;    ///< im A: Q's first `rank` columns
  MatrixXd corange() const;  ///< (im A)^⊥ = ker Aᵀ: Q's other columns
  /// X = Q_r Y with (Aᵀ restricted to the decided rank) X = B: the minimum-norm solution when
  /// Aᵀ X = B is consistent; the caller checks consistency (the residual B − Aᵀ X).
  MatrixXd min_norm_transposed(const MatrixXd& b) const;
  /// X with A X = Y for Y in im A (on the decided rank): the basic solution P [R₁₁⁻¹ (QᵀY)_top; 0]
  /// on the QR route, V_r Σ_r⁻¹ U_rᵀ Y on the SVD route.  For Y off im A it solves for Y's part in
  /// the decided range.
  MatrixXd solve_range(const MatrixXd& y) const;

 private:
  void decide(const MatrixXd& a, double scale, const Options& opt);
  /// Q · [0; I; 0] with the identity in rows [from, from + count): Q's columns, formed only when asked.
  MatrixXd q_columns(Eigen::Index from, Eigen::Index count) const;
  RankDecision d_;
  Eigen::Index m_ = 0;
  MatrixXd qr_;                                                 // QR: Eigen's compact Householder form
  VectorXd tau_;                                                // QR: Householder coefficients
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic> p_;  // QR: A P = Q R
  MatrixXd u_;                                                  // SVD: U (m×m)
  MatrixXd v_;                                                  // SVD: V[:, 0:r]
  Eigen::Index n_ = 0;                                          // columns of A
  VectorXd sigma_;                                              // SVD: σ_1..σ_r
};

/// An orthonormal basis (columns) of the orthogonal complement of the column span of an
/// orthonormal Q: no decision is needed, Q has full column rank.
MatrixXd orthogonal_complement(const MatrixXd& q);

/// 2-norm (largest singular value): by an SVD up to 48 rows or columns, above by power iteration
/// until a step gains less than 1e-7 relative (at most 300 steps).  Above 48 it is a lower bound of
/// ‖A‖₂, never below ‖A‖_F/√min(m,n), and slow only when σ₂ ≈ σ₁, where it is then close to σ₁
/// anyway (seen within 2e-6); a threshold relative to it moves by as little.
double norm2(const MatrixXd& a);

/// Throws std::invalid_argument naming `fn` if `a` has a NaN or an infinity.
void require_finite(const MatrixXd& a, const std::string& fn);

}  // namespace dcad::fast
