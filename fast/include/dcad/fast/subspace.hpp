// Subspaces of R^n by orthonormal bases; the twin of dcad/reference/subspace.hpp.  basis() gives the
// vectors as rows, as the reference does (one orientation at every boundary); columns() as columns.
// Each subspace and each yes/no answer says whether every rank decision behind it was certain.
#pragma once

#include "dcad/fast/rank.hpp"

namespace dcad::fast {

class Subspace {
 public:
  /// Row span of `rows` (n = cols), as the reference's Subspace<T>::span; `scale` for the rank
  /// decision (<0: ‖rows‖₂).
  static Subspace span(const MatrixXd& rows, double scale = -1, const Options& opt = {});
  /// Column span of `cols` (n = rows): fast's own products make columns.
  static Subspace span_columns(const MatrixXd& cols, double scale = -1, const Options& opt = {});
  /// {x : equations · x = 0}.
  static Subspace solutions(const MatrixXd& equations, double scale = -1, const Options& opt = {});
  static Subspace zero(int n) { return Subspace(MatrixXd(n, 0), yes); }
  static Subspace whole(int n) { return Subspace(MatrixXd::Identity(n, n), yes); }
  /// Orthonormal columns, trusted as given (no decision).
  static Subspace from_orthonormal_columns(MatrixXd q, Truth certain) { return Subspace(std::move(q), certain); }

  int ambient() const { return static_cast<int>(basis_.rows()); }
  int dim() const { return static_cast<int>(basis_.cols()); }
  /// An orthonormal basis, one vector per row (dim × n): the reference's orientation
  /// (Subspace<T>::basis(), rows of the RREF), so results compare without a transpose.
  MatrixXd basis() const { return basis_.transpose(); }
  /// The same vectors as columns (n × dim), for fast's own products.
  const MatrixXd& columns() const { return basis_; }
  /// yes when every decision behind this basis was certain, else unknown.
  Truth certain() const { return certain_; }
  /// The decision that produced this subspace, if any (its evidence).
  const RankDecision& evidence() const { return evidence_; }
  /// σ₁/σ_r of the spanning set this basis came from (1 for a basis built orthonormal): rounding
  /// moves the subspace by about ε times this (Wedin), the scale of any test on its vectors.
  double conditioning() const { return evidence_.rank > 0 ? evidence_.largest / evidence_.kept_lower : 1.0; }
  Subspace& and_certain(Truth c) {
    certain_ &= c;
    return *this;
  }

 private:
  Subspace(MatrixXd q, Truth certain) : basis_(std::move(q)), certain_(certain) {}
  MatrixXd basis_;  // orthonormal columns
  Truth certain_ = yes;
  RankDecision evidence_;
};

/// The decision that produced `s` as a trace entry (dcad/trace.hpp): certain only where every decision behind `s` was.
inline Decision traced(const Subspace& s, const std::string& what) {
  Decision d = traced(s.evidence(), what);
  if (!s.certain().yes() && d.certain.yes()) {
    d.certain = s.certain();
    d.evidence += "; a decision before it was uncertain";
  }
  return d;
}

Subspace sum(const Subspace& u, const Subspace& w, const Options& opt = {});
Subspace annihilator(const Subspace& u);
Subspace intersection(const Subspace& u, const Subspace& w, const Options& opt = {});
Subspace kernel(const MatrixXd& a, const Options& opt = {});
Subspace image(const MatrixXd& a, const Options& opt = {});
/// `scale` < 0: ‖a‖₂ (pass the data's scale when a is computed and may vanish exactly).
Subspace preimage(const MatrixXd& a, const Subspace& w, const Options& opt = {}, double scale = -1);
Subspace map(const MatrixXd& a, const Subspace& u, const Options& opt = {});
/// W ⊆ U.
Truth contains(const Subspace& u, const Subspace& w, const Options& opt = {});
/// x ∈ U.
Truth contains(const Subspace& u, const VectorXd& x, const Options& opt = {});
Truth equal(const Subspace& u, const Subspace& w, const Options& opt = {});

/// sin of the largest principal angle between equal-dimensional subspaces (1 if dims differ).
double largest_principal_angle_sin(const Subspace& u, const Subspace& w);

/// An affine subspace p + U, or the empty set.
struct AffineSubspace {
  bool empty = true;
  VectorXd point;
  Subspace direction = Subspace::zero(0);
  Truth certain = yes;  ///< whether `empty` and the rank behind `direction` were decided certainly
};

/// {x : A x = b}: solvable iff rank A = rank [A b] (both decided), least-squares point.  `scale`: of
/// A's rounding (<0: ‖A‖₂); `rhs_scale`: of b's (<0: ‖b‖).  A product's own norm is no scale: when
/// the product is all rounding residue, its residue would be decided its rank.  Where rhs_scale
/// exceeds scale, solvability is b's part off im A (an orthonormal complement from A's factorization),
/// decided at rhs_scale: a right-hand side computed from large factors is not held to A's threshold.
AffineSubspace solve(const MatrixXd& a, const VectorXd& b, const Options& opt = {}, double scale = -1,
                     double rhs_scale = -1);

}  // namespace dcad::fast
