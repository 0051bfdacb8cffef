#include "dcad/fast/forced.hpp"

#include <algorithm>
#include <stdexcept>

namespace dcad::fast {

namespace {

MatrixXd widen(const MatrixXd& m, int more) {
  MatrixXd out = MatrixXd::Zero(m.rows(), m.cols() + more);
  out.leftCols(m.cols()) = m;
  return out;
}

MatrixXd vcat(const MatrixXd& a, const MatrixXd& b) {
  MatrixXd out(a.rows() + b.rows(), std::max(a.cols(), b.cols()));
  out.setZero();
  out.topLeftCorner(a.rows(), a.cols()) = a;
  out.bottomLeftCorner(b.rows(), b.cols()) = b;
  return out;
}

struct Absorbed {
  bool consistent = true;
  int added = 0;
};

/// Adds candidate jet rows to (eq, cond): x-parts projected off eq's orthonormal x-parts; the new
/// directions join eq (orthonormal); what vanishes on x is a source condition (or 0 = 1).
Absorbed absorb(MatrixXd& eq, MatrixXd& cond, const MatrixXd& cand, int n, double scale, const Options& opt,
                ForcedResult& r) {
  Absorbed out;
  const MatrixXd ex = eq.leftCols(n);
  const MatrixXd coef = cand.leftCols(n) * ex.transpose();
  const MatrixXd res = cand - coef * eq;
  const Svd sv = full_svd(res.leftCols(n));
  // How many rows are new: on the projected residual (whose cancelled digits, graded up by the
  // equilibration cross-check of decide_rank, can make a clear gap look uncertain) and on
  // [old; candidates] minus the old rows (no cancellation, but computed rows near the old span).
  // Both routes are decided; a verdict that either one certifies and both agree on is certain.
  RankDecision d = decide_rank_either(vcat(ex, cand.leftCols(n)), static_cast<int>(eq.rows()), std::max(scale, 1.0),
                                      res.leftCols(n), sv.sigma, scale, opt);
  const int room = n - static_cast<int>(eq.rows());
  if (d.rank < 0 || d.rank > room) {
    d.rank = std::clamp(d.rank, 0, room);
    d.certain = unknown;
  }
  r.decisions.push_back(d);
  r.certain &= d.certain;
  const MatrixXd rest = sv.u.rightCols(res.rows() - d.rank).transpose() * res;  // x-part ≈ 0
  if (d.rank > 0) {
    MatrixXd rows = sv.u.leftCols(d.rank).transpose() * res;  // x-part = Σ Vᵀ
    for (int i = 0; i < d.rank; ++i) rows.row(i) /= sv.sigma(i);
    rows.leftCols(n) = sv.v.leftCols(d.rank).transpose();
    eq = vcat(eq, rows);
    out.added = d.rank;
  }
  if (rest.rows() > 0) {
    MatrixXd c = vcat(cond, rest.rightCols(rest.cols() - n));
    const Svd cs = full_svd(c);
    const RankDecision dc = decide_rank(c, cs.sigma, scale, opt);
    r.decisions.push_back(dc);
    r.certain &= dc.certain;
    cond = cs.v.leftCols(dc.rank).transpose();
    // 0 = 1: a condition with a constant and no source part
    if (dc.rank > 0) {
      const MatrixXd src = cond.rightCols(cond.cols() - 1);
      const RankDecision ds = decide_rank(src, 1.0, opt);
      r.decisions.push_back(ds);
      r.certain &= ds.certain;
      if (ds.rank < dc.rank) out.consistent = false;
    }
  }
  return out;
}

}  // namespace

ForcedResult forced_tower(const ForcedSystem& f, const Options& opt_in) {
  const Options opt = assessed(
      opt_in, {dirac_data(f.s.d), f.s.hessian, f.s.gradient, f.force, f.source_force, f.shift, f.given_conditions});
  const int n = f.s.d.n, m = f.sources;
  if (f.source_force.rows() != n || f.source_force.cols() != m || f.shift.rows() != n || f.shift.cols() != m)
    throw std::invalid_argument("forced_tower: expected B and Z of shape N×m, found other shapes");
  ForcedResult r;
  const MatrixXd a = f.force.size() ? MatrixXd(f.s.hessian - f.force) : f.s.hessian;
  const MatrixXd gv = f.s.d.v_part(), ga = f.s.d.alpha_part();  // D = span of the columns [G_v; G_α]
  const double scale = std::max({norm2(a), f.s.gradient.norm(), f.source_force.size() ? norm2(f.source_force) : 0.0,
                                 f.shift.size() ? norm2(f.shift) : 0.0, 1e-300});
  MatrixXd eq(0, n + 1 + m), cond(0, 1 + m);
  r.dims.push_back(n);  // M_0 = M
  // the given conditions (KCL through current sources) are primary: they bound M_1, never M_0
  if (f.given_conditions.rows()) {
    MatrixXd c(f.given_conditions.rows(), n + 1 + m);
    c << MatrixXd::Zero(f.given_conditions.rows(), n), f.given_conditions;
    if (!absorb(eq, cond, c, n, 1.0, opt, r).consistent) {
      r.consistent = false;
      r.dims.push_back(-1);
    }
  }
  while (r.consistent) {
    const int w = static_cast<int>(eq.cols()), rows = static_cast<int>(eq.rows());
    MatrixXd lhs(n + rows, gv.cols());
    lhs << ga, eq.leftCols(n) * gv;  // ẋ − Zσ = G_v λ, α = G_α λ
    MatrixXd rhs = MatrixXd::Zero(n + rows, w + m);
    rhs.block(0, 0, n, n) = a;
    rhs.col(n).head(n) = f.s.gradient;
    rhs.block(0, n + 1, n, m) = -f.source_force;
    rhs.block(n, n + 1, rows, m) = -(eq.leftCols(n) * f.shift);
    rhs.block(n, n + 1 + m, rows, w - n - 1) -= eq.rightCols(w - n - 1);  // d/dt of the source part
    const Svd sv = full_svd(lhs);
    RankDecision d = decide_rank(lhs, sv.sigma, -1, opt);
    r.decisions.push_back(d);
    r.certain &= d.certain;
    const MatrixXd cand = sv.u.rightCols(lhs.rows() - d.rank).transpose() * rhs;
    ++r.orders;
    eq = widen(eq, m);
    cond = widen(cond, m);
    const Absorbed ab = absorb(eq, cond, cand, n, scale, opt, r);
    if (!ab.consistent) {
      r.consistent = false;
      r.dims.push_back(-1);
      break;
    }
    if (ab.added == 0) break;
    r.dims.push_back(n - static_cast<long>(eq.rows()));
  }
  r.steps = static_cast<int>(r.dims.size()) - 1;
  r.equations = eq;
  r.conditions = cond;
  if (r.consistent) {  // dim{G_v λ : lhs λ = 0}
    MatrixXd lhs(n + eq.rows(), gv.cols());
    lhs << ga, eq.leftCols(n) * gv;
    const Svd sv = full_svd(lhs);
    const RankDecision d = decide_rank(lhs, sv.sigma, -1, opt);
    const MatrixXd ker = gv * sv.v.rightCols(lhs.cols() - d.rank);
    const RankDecision dk = decide_rank(ker, 1.0, opt);
    r.decisions.push_back(d);
    r.decisions.push_back(dk);
    r.certain &= d.certain & dk.certain;
    r.solution_rank = dk.rank;
  }
  return r;
}

}  // namespace dcad::fast
