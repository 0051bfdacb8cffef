#include "dcad/fast/symplectic.hpp"

#include <Eigen/LU>

#include <cmath>
#include <stdexcept>
#include <string>

namespace dcad::fast {

void require_skew(const MatrixXd& w, const std::string& fn) {
  require_finite(w, fn);
  if (w.rows() != w.cols())
    throw std::invalid_argument(fn + ": expected a square matrix, found " + std::to_string(w.rows()) + "x" +
                                std::to_string(w.cols()));
  if (w != -w.transpose())
    throw std::invalid_argument(fn + ": expected a skew matrix (W = -Wᵀ), found one that is not");
}

Truth is_symplectic(const MatrixXd& w, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  require_skew(w, "is_symplectic");
  const RankDecision d = decide_rank(w, -1, opt);
  return Truth::decided(d.rank == w.rows(), d.certain);
}

Truth require_symplectic(const MatrixXd& w, const std::string& fn, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  const Truth nondegenerate = is_symplectic(w, opt);
  if (nondegenerate.no())
    throw std::invalid_argument(fn + ": expected a nondegenerate form, found " +
                                decide_rank(w, -1, Options()).describe());
  return nondegenerate;
}

VectorXd flat(const MatrixXd& w, const VectorXd& x) { return w.transpose() * x; }

VectorXd sharp(const MatrixXd& w, const VectorXd& alpha) {
  if (!require_symplectic(w, "sharp").yes())
    throw std::invalid_argument("sharp: expected a certainly nondegenerate form, found " +
                                decide_rank(w, -1, Options()).describe());
  return w.transpose().fullPivLu().solve(alpha);
}

Subspace symplectic_complement(const MatrixXd& w, const Subspace& v, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  require_skew(w, "symplectic_complement");
  return Subspace::solutions((w * v.columns()).transpose(), norm2(w), opt).and_certain(v.certain());
}

PresymplecticForm restrict_form(const MatrixXd& w, const Subspace& v) {
  require_skew(w, "restrict_form");
  if (w.rows() != v.ambient())
    throw std::invalid_argument("restrict_form: expected a form on R^" + std::to_string(v.ambient()) + ", found " +
                                std::to_string(w.rows()) + "x" + std::to_string(w.cols()));
  return {v, w, norm2(w)};
}

PresymplecticForm restrict_form(const PresymplecticForm& f, const Subspace& u, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.matrix});
  const Truth in = contains(f.space, u, opt);
  if (in.no())
    throw std::invalid_argument("restrict_form: expected a subspace of the form's domain, found one outside it");
  PresymplecticForm g{u, f.matrix, f.scale};
  g.space.and_certain(in);
  return g;
}

MatrixXd gram(const PresymplecticForm& f) { return f.space.columns().transpose() * f.matrix * f.space.columns(); }

RankDecision form_rank(const PresymplecticForm& f, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.matrix});
  RankDecision d = decide_rank(gram(f), f.scale, opt);
  d.certain &= f.space.certain();
  return d;
}

Subspace orthogonal(const PresymplecticForm& f, const Subspace& w, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.matrix});
  // v = Q c with ω(Q c, w_j) = cᵀ Qᵀ M w_j = 0 for all j.
  const MatrixXd& q = f.space.columns();
  const Subspace c = Subspace::solutions((q.transpose() * f.matrix * w.columns()).transpose(), f.scale, opt);
  return Subspace::from_orthonormal_columns(q * c.columns(), c.certain() & f.space.certain() & w.certain());
}

Subspace form_kernel(const PresymplecticForm& f, const Options& opt) { return orthogonal(f, f.space, opt); }

Subspace flat(const PresymplecticForm& f, const Subspace& w, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.matrix});
  const MatrixXd images = f.matrix.transpose() * w.columns();  // columns: y ↦ wᵀ M y
  return sum(Subspace::span_columns(images, f.scale, opt), annihilator(f.space), opt).and_certain(w.certain());
}

NormalFormBasis normal_form_basis(const MatrixXd& w, const Subspace& v, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  const Truth nondegenerate = require_symplectic(w, "normal_form_basis", opt);
  const Subspace comp = symplectic_complement(w, v, opt);
  MatrixXd rest = comp.columns();                                   // columns
  const double scale = norm2(w), tol = opt.nonzero_factor * scale;  // pairs below τ1 are not split off
  NormalFormBasis out;
  out.certain = comp.certain() & nondegenerate;
  std::vector<VectorXd> es, fs;
  while (rest.cols() >= 2) {
    const MatrixXd g = rest.transpose() * w * rest;
    Eigen::Index i = 0, j = 0;
    const double big = g.cwiseAbs().maxCoeff(&i, &j);
    if (big <= tol) {
      if (big > zero_threshold(static_cast<int>(g.rows()), static_cast<int>(g.cols()), scale, opt))
        out.certain = unknown;  // neither zero nor clearly not
      break;
    }
    const VectorXd e = rest.col(i), f = rest.col(j) / g(i, j);
    MatrixXd next(rest.rows(), rest.cols() - 2);
    for (Eigen::Index k = 0, o = 0; k < rest.cols(); ++k) {
      if (k == i || k == j) continue;
      const VectorXd y = rest.col(k);
      next.col(o++) = y - (y.dot(w * f)) * e + (y.dot(w * e)) * f;
    }
    rest = next;
    es.push_back(e);
    fs.push_back(f);
  }
  out.s = static_cast<int>(es.size());
  out.x.resize(es.size() * 2 + rest.cols(), w.rows());
  for (size_t k = 0; k < es.size(); ++k) {
    out.x.row(k) = es[k].transpose();
    out.x.row(es.size() + k) = fs[k].transpose();
  }
  for (Eigen::Index k = 0; k < rest.cols(); ++k) out.x.row(2 * es.size() + k) = rest.col(k).transpose();
  out.alpha = out.x * w;  // row i: (Wᵀ X_i)ᵀ = X_iᵀ W
  return out;
}

RestrictedSolution solve_restricted(const MatrixXd& w, const Subspace& v, const VectorXd& beta, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w, beta});
  const Truth nondegenerate = require_symplectic(w, "solve_restricted", opt);
  require_finite(beta, "solve_restricted");
  const MatrixXd gamma = annihilator(v).columns();             // columns γ_i
  const MatrixXd y = w.transpose().fullPivLu().solve(gamma);   // columns Y_i = γ_i^♯
  const MatrixXd coeff = (gamma.transpose() * y).transpose();  // (i, j) = γ_j(Y_i)
  RestrictedSolution out;
  out.lambda = solve(coeff, -(y.transpose() * beta), opt, norm2(y));  // coeff may vanish exactly
  out.lambda.certain &= v.certain() & nondegenerate;
  out.x.empty = out.lambda.empty;
  out.x.certain = out.lambda.certain;
  out.x.direction = map(y, out.lambda.direction, opt);
  if (!out.x.empty) out.x.point = w.transpose().fullPivLu().solve(beta) + y * out.lambda.point;  // β^♯ + λ^j Y_j
  return out;
}

AffineSubspace solve_on_subspace(const PresymplecticForm& f, const VectorXd& beta, const Options& opt_in) {
  const Options opt = assessed(opt_in, {f.matrix, beta});
  const MatrixXd& q = f.space.columns();
  const AffineSubspace c = solve(gram(f).transpose(), q.transpose() * beta, opt, f.scale);
  AffineSubspace out;
  out.empty = c.empty;
  out.certain = c.certain & f.space.certain();
  out.direction =
      Subspace::from_orthonormal_columns(q * c.direction.columns(), c.direction.certain() & f.space.certain());
  if (!c.empty) out.point = q * c.point;
  return out;
}

}  // namespace dcad::fast
