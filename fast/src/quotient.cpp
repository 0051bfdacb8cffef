#include "dcad/fast/quotient.hpp"

#include <Eigen/LU>

#include <stdexcept>

namespace dcad::fast {

GaugeQuotient gauge_quotient(const ConstrainedSystem& s, const DiracBergmannResult& r, const Options& opt_in) {
  if (!r.consistent || r.tower.empty() || r.tower.back().empty)
    throw std::invalid_argument("gauge_quotient: expected a consistent tower (M_c nonempty), found an empty M_c");
  const Options opt = assessed(opt_in, {s.omega, s.hessian, s.gradient, s.primary});
  const MatrixXd& w = s.omega;
  const int n = static_cast<int>(w.rows());
  GaugeQuotient q;
  q.certain = r.certain;
  q.tangent = r.tower.back().direction;
  const MatrixXd& t = q.tangent.columns();
  // the Gram matrix of Ω on TM_c's orthonormal basis: its null space is K_c, its row space a complement
  const MatrixXd gt = t.transpose() * w * t;
  q.certain &= q.tangent.certain();
  MatrixXd v = MatrixXd::Identity(gt.cols(), gt.cols());  // right singular vectors, nonzero σ first
  int rank = 0;
  if (gt.cols() > 0) {
    const Svd sv = full_svd(gt);
    const RankDecision d = decide_rank(gt, sv.sigma, std::max(norm2(w), 1e-300), opt);
    q.certain &= d.certain;
    v = sv.v;
    rank = d.rank;
  }
  q.gauge = Subspace::from_orthonormal_columns(t * v.rightCols(gt.cols() - rank), q.certain);
  q.complement = (t * v.leftCols(rank)).transpose();
  // K̃_c = {y = T c : Ω(y, m) = 0 for every m ∈ TM}: c in the kernel of Mᵀ Wᵀ T
  const Subspace tm = kernel(s.primary.leftCols(n), opt);
  // (a product that may vanish exactly: decided at Ω's scale, not at its own norm)
  const Subspace c = Subspace::solutions(tm.columns().transpose() * w.transpose() * t, std::max(norm2(w), 1e-300), opt);
  q.physical_gauge = Subspace::from_orthonormal_columns(t * c.columns(), c.certain() & tm.certain() & q.certain);
  q.certain &= q.physical_gauge.certain();
  q.coordinates = q.complement * w;
  const MatrixXd g = q.coordinates * q.complement.transpose();  // [Ω(b_i, b_j)]
  const MatrixXd g_inv = rank > 0 ? MatrixXd(g.fullPivLu().inverse()) : MatrixXd(0, 0);
  q.form = g_inv.transpose();
  q.point = r.tower.back().point;
  q.section = q.complement.transpose() * g_inv;
  // z' = −B (H x(z) + g), x(z) = (x₀ − S C x₀) + S z
  const VectorXd base = q.point - q.section * (q.coordinates * q.point);
  q.field = -(q.complement * s.hessian * q.section);
  q.offset = -(q.complement * (s.hessian * base + s.gradient));
  q.tilde_coordinates = (t * orthogonal_complement(c.columns())).transpose();
  q.fibration = q.coordinates * q.tilde_coordinates.transpose();
  return q;
}

Subspace first_class_covectors(const MatrixXd& w, const Subspace& tmc, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  Truth nondegenerate = yes;
  const MatrixXd j = poisson_tensor(w, opt, nondegenerate);
  return preimage(j, tmc, opt, std::max(norm2(j), 1e-300)).and_certain(nondegenerate);
}

}  // namespace dcad::fast
