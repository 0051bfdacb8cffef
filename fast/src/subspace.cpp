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

Subspace Subspace::span_columns(const MatrixXd& cols, double scale, const Options& opt_in) {
  const Options opt = assessed(opt_in, {cols});
  require_finite(cols, "Subspace::span");
  const RankRevealing f(cols, scale, opt);
  Subspace out(f.range(), f.decision().certain);
  out.evidence_ = f.decision();
  return out;
}

Subspace Subspace::span(const MatrixXd& rows, double scale, const Options& opt_in) {
  const Options opt = assessed(opt_in, {rows});
  require_finite(rows, "Subspace::span");
  return span_columns(rows.transpose(), scale, opt);
}

Subspace Subspace::solutions(const MatrixXd& equations, double scale, const Options& opt_in) {
  const Options opt = assessed(opt_in, {equations});
  require_finite(equations, "Subspace::solutions");
  const RankRevealing f(equations.transpose(), scale, opt);  // ker A = (im Aᵀ)^⊥
  Subspace out(f.corange(), f.decision().certain);
  out.evidence_ = f.decision();
  return out;
}

Subspace sum(const Subspace& u, const Subspace& w, const Options& opt_in) {
  Options opt = opt_in;  // subspaces carry their own certainty (their spans were assessed)
  opt.input_assessed = true;
  require_same_ambient(u, w, "sum");
  MatrixXd both(u.ambient(), u.dim() + w.dim());
  both << u.columns(), w.columns();
  return Subspace::span_columns(both, 1.0, opt).and_certain(u.certain() & w.certain());
}

Subspace annihilator(const Subspace& u) {
  return Subspace::from_orthonormal_columns(orthogonal_complement(u.columns()), u.certain());
}

Subspace intersection(const Subspace& u, const Subspace& w, const Options& opt_in) {
  Options opt = opt_in;  // subspaces carry their own certainty (their spans were assessed)
  opt.input_assessed = true;
  require_same_ambient(u, w, "intersection");
  return annihilator(sum(annihilator(u), annihilator(w), opt));
}

Subspace kernel(const MatrixXd& a, const Options& opt) { return Subspace::solutions(a, -1, opt); }

Subspace image(const MatrixXd& a, const Options& opt) { return Subspace::span_columns(a, -1, opt); }

Subspace preimage(const MatrixXd& a, const Subspace& w, const Options& opt_in, double scale) {
  const Options opt = assessed(opt_in, {a});
  if (a.rows() != w.ambient())
    throw std::invalid_argument("preimage: expected a map into R^" + std::to_string(w.ambient()) + ", found a " +
                                std::to_string(a.rows()) + "x" + std::to_string(a.cols()) + " matrix");
  return Subspace::solutions(annihilator(w).columns().transpose() * a, scale >= 0 ? scale : norm2(a), opt)
      .and_certain(w.certain());
}

Subspace map(const MatrixXd& a, const Subspace& u, const Options& opt_in) {
  const Options opt = assessed(opt_in, {a});
  if (a.cols() != u.ambient())
    throw std::invalid_argument("map: expected a map from R^" + std::to_string(u.ambient()) + ", found a " +
                                std::to_string(a.rows()) + "x" + std::to_string(a.cols()) + " matrix");
  return Subspace::span_columns(a * u.columns(), norm2(a), opt).and_certain(u.certain());
}

Truth contains(const Subspace& u, const Subspace& w, const Options& opt_in) {
  Options opt = opt_in;  // subspaces carry their own certainty (their spans were assessed)
  opt.input_assessed = true;
  require_same_ambient(u, w, "contains");
  const Subspace s = sum(u, w, opt);
  return Truth::decided(s.dim() == u.dim(), s.certain());
}

Truth contains(const Subspace& u, const VectorXd& x, const Options& opt_in) {
  const Options opt = assessed(opt_in, {x});
  if (x.size() != u.ambient())
    throw std::invalid_argument("contains: expected a vector of R^" + std::to_string(u.ambient()) + ", found length " +
                                std::to_string(x.size()));
  const double nx = x.norm();
  if (nx == 0) return Truth::decided(true, u.certain());
  return contains(u, Subspace::from_orthonormal_columns(x / nx, yes), opt);
}

Truth equal(const Subspace& u, const Subspace& w, const Options& opt) {
  return contains(u, w, opt) & contains(w, u, opt);
}

double largest_principal_angle_sin(const Subspace& u, const Subspace& w) {
  if (u.ambient() != w.ambient() || u.dim() != w.dim()) return 1.0;
  if (u.dim() == 0) return 0.0;
  return norm2(w.columns() - u.columns() * (u.columns().transpose() * w.columns()));
}

AffineSubspace solve(const MatrixXd& a, const VectorXd& b, const Options& opt_in, double scale, double rhs_scale) {
  const Options opt = assessed(opt_in, {a, b});
  require_finite(a, "solve");
  require_finite(b, "solve");
  AffineSubspace out;
  if (scale < 0) scale = norm2(a);
  const double rhs = rhs_scale < 0 ? b.norm() : rhs_scale;
  const RankRevealing f(a.transpose(), scale, opt);  // rows of A: ker A = (im Aᵀ)^⊥
  const RankDecision& ra = f.decision();
  out.direction = Subspace::from_orthonormal_columns(f.corange(), ra.certain);
  if (rhs <= scale) {  // b's rounding is within A's: rank [A | b] at A's scale
    MatrixXd ab(a.rows(), a.cols() + 1);
    ab << a, b;
    const RankDecision rab = decide_rank(ab, scale, opt);
    out.certain = ra.certain & rab.certain;
    out.empty = rab.rank > ra.rank;
  } else {
    // b's rounding is rhs's, far above A's: its part off im A is decided by itself at rhs.  Deciding
    // [A | b] at rhs put A's singular values in the band or below τ0 (fast::multipliers at ‖x‖ = 10^12
    // along M_c: uncertain on 45 %); b scaled down to A's scale is a column 2^28 below the others, which
    // the equilibration cross-check calls graded (uncertain on 15 %).
    const RankRevealing g(a, scale, opt);  // im A, and (im A)^⊥ = corange
    const MatrixXd off = g.corange().transpose() * b;
    const RankDecision rb = off.rows() ? decide_rank(off, rhs, opt) : RankDecision{};
    out.certain = ra.certain & g.decision().certain & rb.certain;
    if (g.rank() != ra.rank) out.certain = unknown;  // A's rank decided twice, differently
    out.empty = rb.rank > 0;
  }
  if (!out.empty) out.point = f.min_norm_transposed(b);  // minimum-norm solution on the decided rank
  return out;
}

}  // namespace dcad::fast
