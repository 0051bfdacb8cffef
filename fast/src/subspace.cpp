#include "dcad/fast/subspace.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {
void require_same_ambient(const Subspace& u, const Subspace& w, const char* fn) {
  if (u.ambient() != w.ambient())
    throw std::invalid_argument(std::string(fn) + ": expected subspaces of the same space, found R^" +
                                std::to_string(u.ambient()) + " and R^" + std::to_string(w.ambient()));
}
}  // namespace

Subspace Subspace::span(const MatrixXd& cols, double scale, const Options& opt) {
  require_finite(cols, "Subspace::span");
  const Svd s = full_svd(cols);
  RankDecision d = decide_rank(cols, s.sigma, scale, opt);
  Subspace out(s.u.leftCols(d.rank), d.certain);
  out.evidence_ = std::move(d);
  return out;
}

Subspace Subspace::solutions(const MatrixXd& equations, double scale, const Options& opt) {
  require_finite(equations, "Subspace::solutions");
  const Svd s = full_svd(equations);
  RankDecision d = decide_rank(equations, s.sigma, scale, opt);
  Subspace out(s.v.rightCols(equations.cols() - d.rank), d.certain);
  out.evidence_ = std::move(d);
  return out;
}

Subspace sum(const Subspace& u, const Subspace& w, const Options& opt) {
  require_same_ambient(u, w, "sum");
  MatrixXd both(u.ambient(), u.dim() + w.dim());
  both << u.basis(), w.basis();
  return Subspace::span(both, 1.0, opt).and_certain(u.certain() && w.certain());
}

Subspace annihilator(const Subspace& u) {
  return Subspace::from_orthonormal(orthogonal_complement(u.basis()), u.certain());
}

Subspace intersection(const Subspace& u, const Subspace& w, const Options& opt) {
  require_same_ambient(u, w, "intersection");
  return annihilator(sum(annihilator(u), annihilator(w), opt));
}

Subspace kernel(const MatrixXd& a, const Options& opt) { return Subspace::solutions(a, -1, opt); }

Subspace image(const MatrixXd& a, const Options& opt) { return Subspace::span(a, -1, opt); }

Subspace preimage(const MatrixXd& a, const Subspace& w, const Options& opt, double scale) {
  if (a.rows() != w.ambient())
    throw std::invalid_argument("preimage: expected a map into R^" + std::to_string(w.ambient()) + ", found a " +
                                std::to_string(a.rows()) + "x" + std::to_string(a.cols()) + " matrix");
  return Subspace::solutions(annihilator(w).basis().transpose() * a, scale >= 0 ? scale : norm2(a), opt)
      .and_certain(w.certain());
}

Subspace map(const MatrixXd& a, const Subspace& u, const Options& opt) {
  if (a.cols() != u.ambient())
    throw std::invalid_argument("map: expected a map from R^" + std::to_string(u.ambient()) + ", found a " +
                                std::to_string(a.rows()) + "x" + std::to_string(a.cols()) + " matrix");
  return Subspace::span(a * u.basis(), norm2(a), opt).and_certain(u.certain());
}

Answer contains(const Subspace& u, const Subspace& w, const Options& opt) {
  require_same_ambient(u, w, "contains");
  const Subspace s = sum(u, w, opt);
  return {s.dim() == u.dim(), s.certain()};
}

Answer contains(const Subspace& u, const VectorXd& x, const Options& opt) {
  if (x.size() != u.ambient())
    throw std::invalid_argument("contains: expected a vector of R^" + std::to_string(u.ambient()) +
                                ", found length " + std::to_string(x.size()));
  const double nx = x.norm();
  if (nx == 0) return {true, u.certain()};
  return contains(u, Subspace::from_orthonormal(x / nx, true), opt);
}

Answer equal(const Subspace& u, const Subspace& w, const Options& opt) {
  const Answer a = contains(u, w, opt), b = contains(w, u, opt);
  return {a.value && b.value, a.certain && b.certain};
}

double largest_principal_angle_sin(const Subspace& u, const Subspace& w) {
  if (u.ambient() != w.ambient() || u.dim() != w.dim()) return 1.0;
  if (u.dim() == 0) return 0.0;
  return norm2(w.basis() - u.basis() * (u.basis().transpose() * w.basis()));
}

AffineSubspace solve(const MatrixXd& a, const VectorXd& b, const Options& opt, double scale) {
  require_finite(a, "solve");
  require_finite(b, "solve");
  AffineSubspace out;
  const Svd s = full_svd(a);
  if (scale < 0) scale = s.sigma.size() ? s.sigma(0) : 0.0;
  const RankDecision ra = decide_rank(a, s.sigma, scale, opt);
  MatrixXd ab(a.rows(), a.cols() + 1);
  ab << a, b;
  const RankDecision rab = decide_rank(ab, std::max(scale, b.norm()), opt);
  out.certain = ra.certain && rab.certain;
  out.direction = Subspace::from_orthonormal(s.v.rightCols(a.cols() - ra.rank), ra.certain);
  out.empty = rab.rank > ra.rank;
  if (!out.empty) {  // minimum-norm solution through the truncated SVD
    out.point = VectorXd::Zero(a.cols());
    for (int i = 0; i < ra.rank; ++i) out.point += s.v.col(i) * (s.u.col(i).dot(b) / s.sigma(i));
  }
  return out;
}

}  // namespace dcad::fast
