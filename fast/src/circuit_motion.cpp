#include "dcad/fast/circuit_motion.hpp"

#include "dcad/fast/subspace.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <algorithm>

#include <stdexcept>

namespace dcad::fast {

namespace {

/// The rows of the tower's equations on one block (0 = q, 1 = v) as a dense matrix in R^n.
MatrixXd block_rows(const CircuitTower& t, std::size_t n, std::size_t block) {
  std::vector<const SparseRow*> rows;
  for (const auto& step : t.equations)
    for (const SparseRow& r : step)
      if (!r.empty() && r.front().var / n == block) rows.push_back(&r);
  MatrixXd m = MatrixXd::Zero(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (const Term& term : *rows[i])
      m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(term.var - block * n)) += term.coeff;
  return m;
}

void record(CircuitMotion& out, const RankDecision& d) {
  out.certain &= d.certain;
  out.decisions.push_back(d);
}

}  // namespace

CircuitMotion circuit_motion(const CircuitGraph& g, const CircuitTower& t, std::vector<int> coords,
                             const Options& opt_in) {
  const Options opt = assessed_values(opt_in, g);
  const std::size_t n = g.branches.size();
  const Eigen::Index ni = static_cast<Eigen::Index>(n);
  CircuitMotion out;
  MatrixXd k = MatrixXd::Zero(static_cast<Eigen::Index>(g.nodes), ni), phi = MatrixXd::Zero(ni, ni),
           psi = MatrixXd::Zero(ni, ni);
  for (std::size_t b = 0; b < n; ++b) {
    const CircuitBranch& br = g.branches[b];
    const Eigen::Index bi = static_cast<Eigen::Index>(b);
    if (br.from >= 0) k(br.from, bi) += 1;
    if (br.to >= 0) k(br.to, bi) -= 1;
    if (br.kind == BranchKind::inductor) phi(bi, bi) = br.value;
    if (br.kind == BranchKind::capacitor) psi(bi, bi) = 1 / br.value;
  }
  const Subspace s = Subspace::solutions(block_rows(t, n, 0), -1, opt),
                 v = Subspace::solutions(block_rows(t, n, 1), -1, opt);
  const Subspace delta = kernel(k, opt);
  for (const Subspace* sub : {&s, &v, &delta}) record(out, sub->evidence());
  const MatrixXd &bs = s.columns(), &bv = v.columns(), &bd = delta.columns();
  const Eigen::Index ds = bs.cols(), dv = bv.cols(), m = ds + dv;
  // ȧ = R b with B_S R = B_V (V ⊂ S, B_S orthonormal); A ḃ = −B_Δᵀ ψ B_S a, A = B_Δᵀ φ B_V
  const MatrixXd r = bs.transpose() * bv, a = bd.transpose() * phi * bv, rhs = -(bd.transpose() * psi * bs);
  const double scale = std::max(norm2(phi), 1e-300);
  const Svd sv = full_svd(a);
  const RankDecision da = decide_rank(a, sv.sigma, scale, opt);
  record(out, da);
  MatrixXd p = MatrixXd::Zero(dv, ds);
  for (int i = 0; i < da.rank; ++i) p += sv.v.col(i) * (sv.u.col(i).transpose() * rhs) / sv.sigma(i);
  const MatrixXd gauge = sv.v.rightCols(dv - da.rank);
  MatrixXd fy = MatrixXd::Zero(m, m), gy = MatrixXd::Zero(m, gauge.cols());
  fy.topRightCorner(ds, dv) = r;
  fy.bottomLeftCorner(dv, ds) = p;
  gy.bottomRows(dv) = gauge;
  // x = B y with B = [[B_S, 0], [0, B_V], [0, φ B_V]]
  MatrixXd b = MatrixXd::Zero(3 * ni, m);
  b.topLeftCorner(ni, ds) = bs;
  b.block(ni, ds, ni, dv) = bv;
  b.bottomRightCorner(ni, dv) = phi * bv;
  if (coords.empty()) {
    // m variables whose rows of B are best conditioned (column-pivoted QR of Bᵀ; B has full column
    // rank m by construction), in variable order.  Not the reference's "first independent ones": on
    // a ladder those make T = B[coords] ill-conditioned exponentially in its length, and any
    // coordinates on M_c describe the same equations (dcad check compares in the result's).
    const Eigen::ColPivHouseholderQR<MatrixXd> qr(b.transpose());
    for (Eigen::Index i = 0; i < m; ++i) coords.push_back(qr.colsPermutation().indices()(i));
    std::sort(coords.begin(), coords.end());
  }
  if (static_cast<Eigen::Index>(coords.size()) != m)
    throw std::invalid_argument("circuit_motion: expected " + std::to_string(m) + " coordinates (dim M_c), found " +
                                std::to_string(coords.size()));
  MatrixXd tm(m, m);
  for (Eigen::Index i = 0; i < m; ++i) {
    if (coords[i] < 0 || coords[i] >= 3 * ni)
      throw std::invalid_argument("circuit_motion: expected variable indices below 3n");
    tm.row(i) = b.row(coords[i]);
  }
  const RankDecision dt = decide_rank(tm, 1.0, opt);
  record(out, dt);
  if (dt.rank < m)
    throw std::invalid_argument(
        "circuit_motion: expected coordinates that parametrize M_c, found variables that do not");
  out.coords = coords;
  out.f_matrix = m ? MatrixXd(tm * fy * tm.fullPivLu().inverse()) : MatrixXd(0, 0);
  out.g = tm * gy;
  return out;
}

}  // namespace dcad::fast
