#include "dcad/fast/adapted.hpp"

#include <Eigen/LU>

#include <stdexcept>

namespace dcad::fast {

AdaptedConstraints adapted_constraints(const MatrixXd& w, const MatrixXd& constraints, const std::vector<bool>& primary,
                                       const Options& opt_in) {
  const Options opt = assessed(opt_in, {w, constraints});
  const int n = static_cast<int>(w.rows());
  if (static_cast<Eigen::Index>(primary.size()) != constraints.rows())
    throw std::invalid_argument("adapted_constraints: expected one primary flag per constraint, found " +
                                std::to_string(primary.size()) + " for " + std::to_string(constraints.rows()));
  AdaptedConstraints out;
  const MatrixXd j = poisson_tensor(w, opt, out.certain), a = constraints.leftCols(n);
  const MatrixXd phi = a * j * a.transpose();
  const double scale = norm2(j) * std::max(1.0, norm2(a) * norm2(a));
  const RankDecision full = decide_rank(phi, scale, opt);
  out.certain &= full.certain;
  out.s = full.rank / 2;
  MatrixXd chosen(0, phi.cols());
  const auto take = [&](bool want_primary) {
    for (int i = 0; i < phi.rows(); ++i) {
      if (primary[i] != want_primary) continue;
      MatrixXd more(chosen.rows() + 1, phi.cols());
      more << chosen, phi.row(i);
      const RankDecision d = decide_rank(more, scale, opt);
      out.certain &= d.certain;
      if (d.rank > chosen.rows()) {
        chosen = more;
        out.chi.push_back(i);
      } else if (want_primary) {
        out.abridged.push_back(i);
      }
    }
  };
  take(true);
  out.s_prime = static_cast<int>(out.chi.size());
  take(false);
  if (static_cast<int>(out.chi.size()) != 2 * out.s) out.certain = unknown;
  MatrixXd g(out.chi.size(), n);
  for (std::size_t p = 0; p < out.chi.size(); ++p) g.row(p) = a.row(out.chi[p]);
  out.dirac_tensor =
      g.rows() ? MatrixXd(j - j * g.transpose() * (g * j * g.transpose()).fullPivLu().inverse() * g * j) : j;
  return out;
}

VectorXd abridged_field(const AdaptedConstraints& ad, const MatrixXd& constraints, const MatrixXd& hessian,
                        const VectorXd& gradient, const VectorXd& x, const VectorXd& lambda) {
  VectorXd d = hessian * x + gradient;
  for (std::size_t k = 0; k < ad.abridged.size(); ++k)
    d += lambda(k) * constraints.row(ad.abridged[k]).head(d.size()).transpose();
  return ad.dirac_tensor * d;
}

FoliatedEmbedding tangent_cotangent_embedding(const PontryaginInput& in, const Options& /*opt: nothing is decided*/) {
  const LinearSystem s =
      pontryagin_energy(in);  // as the reference: E on TQ ⊕ T*Q (Δ is not needed: K gives the leaves)
  const MatrixXd& k = in.k;
  const int n = static_cast<int>(s.hessian.rows() / 3), m = 4 * n;
  FoliatedEmbedding f;
  f.omega = MatrixXd::Zero(m, m);
  f.omega.block(0, 2 * n, n, n).setIdentity();
  f.omega.block(2 * n, 0, n, n) = -MatrixXd::Identity(n, n);
  f.omega.block(n, 3 * n, n, n).setIdentity();
  f.omega.block(3 * n, n, n, n) = -MatrixXd::Identity(n, n);
  f.hessian = MatrixXd::Zero(m, m);
  f.hessian.topLeftCorner(3 * n, 3 * n) = s.hessian;
  f.gradient = VectorXd::Zero(m);
  f.gradient.head(3 * n) = s.gradient;
  f.primary = MatrixXd::Zero(n, m + 1);
  f.primary.block(0, 3 * n, n, n).setIdentity();
  f.leaf = MatrixXd::Zero(k.rows(), m + 1);
  f.leaf.leftCols(n) = k;
  return f;
}

LinearSystem foliated_system(const FoliatedEmbedding& f, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.omega, f.hessian, f.primary, f.leaf, f.gradient});
  MatrixXd both(f.primary.rows() + f.leaf.rows(), f.primary.cols());
  both << f.primary, f.leaf;
  return {dirac_from_distribution(kernel(both.leftCols(f.omega.rows()), opt), f.omega), f.hessian, f.gradient, 0.0};
}

CadResult foliated_tower(const FoliatedEmbedding& f, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.omega, f.hessian, f.primary, f.leaf, f.gradient});
  return constraint_tower(foliated_system(f, opt), opt, f.primary);
}

AdaptedToPrimary adapted_to_primary(const MatrixXd& w, const MatrixXd& primary, const MatrixXd& secondary,
                                    const MatrixXd& leaf, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w, primary, secondary, leaf});
  AdaptedToPrimary out;
  out.constraints.resize(primary.rows() + secondary.rows() + leaf.rows(), primary.cols());
  out.constraints << primary, secondary, leaf;
  std::vector<bool> is_primary(out.constraints.rows(), false);
  for (Eigen::Index i = 0; i < out.constraints.rows(); ++i)
    is_primary[i] = i < primary.rows() || i >= primary.rows() + secondary.rows();
  out.adapted = adapted_constraints(w, out.constraints, is_primary, opt);
  return out;
}

AffineSubspace foliated_multipliers(const FoliatedEmbedding& f, const CadResult& r, const MatrixXd& secondary,
                                    const VectorXd& x, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.omega, f.hessian, f.primary, f.leaf, f.gradient});
  const int n = static_cast<int>(f.omega.rows());
  MatrixXd mult(f.primary.rows() + f.leaf.rows(), n), all(mult.rows() + secondary.rows(), n);
  mult << f.primary.leftCols(n), f.leaf.leftCols(n);
  all << f.primary.leftCols(n), secondary.leftCols(n), f.leaf.leftCols(n);
  AffineSubspace out;
  Truth certain = yes;
  const MatrixXd j = poisson_tensor(f.omega, opt, certain);
  const AffineSubspace xdot = velocities(foliated_system(f, opt), r, x, opt);
  out.certain = certain & xdot.certain;
  if (xdot.empty) return out;
  const VectorXd de = f.hessian * x + f.gradient;
  const MatrixXd ja = j * mult.transpose();  // X − J dE = J Aᵀ λ
  const double scale = std::max(norm2(ja), 1e-300);
  // X and J dE carry the rounding of the velocities' solve: the right-hand side's scale is theirs
  const double rhs_scale = xdot.point.norm() + norm2(j) * de.norm() + scale * x.norm();
  const AffineSubspace lam = solve(ja, xdot.point - j * de, opt, scale, rhs_scale);
  out.certain &= lam.certain;
  if (lam.empty) return out;
  out.empty = false;
  out.point = lam.point;
  out.direction = Subspace::solutions(all * ja, std::max(norm2(all) * scale, 1e-300), opt);  // J λ·a ∈ T S
  out.certain &= out.direction.certain();
  return out;
}

VectorXd foliated_field(const FoliatedEmbedding& f, const VectorXd& x, const VectorXd& lambda) {
  const int n = static_cast<int>(f.omega.rows());
  MatrixXd mult(f.primary.rows() + f.leaf.rows(), n);
  mult << f.primary.leftCols(n), f.leaf.leftCols(n);
  Truth ignored = yes;
  return poisson_tensor(f.omega, {}, ignored) * (f.hessian * x + f.gradient + mult.transpose() * lambda);
}

}  // namespace dcad::fast
