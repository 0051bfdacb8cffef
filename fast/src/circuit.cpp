#include "dcad/fast/circuit.hpp"

#include "dcad/fast/cad.hpp"
#include "dcad/fast/subspace.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

void validate(const CircuitGraph& g) {
  for (std::size_t b = 0; b < g.branches.size(); ++b) {
    const CircuitBranch& br = g.branches[b];
    const long n = static_cast<long>(g.nodes);
    if (br.from < -1 || br.from >= n || br.to < -1 || br.to >= n)
      throw std::invalid_argument("circuit_tower: branch " + std::to_string(b + 1) + ": expected nodes in [-1, " +
                                  std::to_string(n) + "), found " + std::to_string(br.from) + ", " +
                                  std::to_string(br.to));
    if (br.kind != BranchKind::empty && (!std::isfinite(br.value) || br.value == 0))
      throw std::invalid_argument("circuit_tower: branch " + std::to_string(b + 1) +
                                  ": expected a finite nonzero L or C in double, found " + std::to_string(br.value));
  }
}

SparseRow sparse(const Eigen::RowVectorXd& row, std::size_t offset) {
  SparseRow r;
  const double big = row.cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < row.size(); ++j)
    if (std::abs(row(j)) > 1e-13 * big) r.push_back({offset + static_cast<std::size_t>(j), row(j)});
  return r;
}

/// The fundamental-loop currents (rows: a basis of Δ, each loop with its own tree-free branch) and the
/// diagonals of φ (L) and ψ (1/C).
struct LoopData {
  MatrixXd bl;
  VectorXd phi, psi;
};
LoopData loop_data(const CircuitGraph& g) {
  const std::size_t n = g.branches.size();
  const std::vector<Loop> loops =
      graph::fundamental_loops(g.nodes, lc::edges(g.branches), std::vector<bool>(n, true), std::vector<bool>(n, false));
  const Eigen::Index m = static_cast<Eigen::Index>(loops.size()), nn = static_cast<Eigen::Index>(n);
  LoopData d{MatrixXd::Zero(m, nn), VectorXd::Zero(nn), VectorXd::Zero(nn)};
  for (Eigen::Index i = 0; i < m; ++i)
    for (const LoopBranch& lb : loops[i]) d.bl(i, static_cast<Eigen::Index>(lb.branch)) += lb.sign;
  for (std::size_t b = 0; b < n; ++b) {
    if (g.branches[b].kind == BranchKind::inductor) d.phi(b) = g.branches[b].value;
    if (g.branches[b].kind == BranchKind::capacitor) d.psi(b) = 1.0 / g.branches[b].value;
  }
  return d;
}

/// The closed form with each rank decided: q-constraints aq (rows of S^⊥), v-constraints av (Δ_k^⊥).
void signed_route(const CircuitGraph& g, CircuitTower& t, const Options& opt) {
  const std::size_t n = g.branches.size();
  const LoopData ld = loop_data(g);
  const MatrixXd& bl = ld.bl;
  const VectorXd &phi = ld.phi, &psi = ld.psi;
  const Eigen::Index m = bl.rows(), nn = static_cast<Eigen::Index>(n);
  const double nb = m ? norm2(bl) : 1.0;
  const double phi_scale = nb * std::max(phi.cwiseAbs().maxCoeff(), 0.0), psi_scale = nb * psi.cwiseAbs().maxCoeff();
  std::vector<RankDecision>& trace = t.decisions;
  // Δ^⊥: the loop rows have full rank m exactly (each has its own tree-free branch), no decision
  MatrixXd av = m ? MatrixXd(full_svd(bl.transpose()).u.rightCols(nn - m).transpose()) : MatrixXd::Identity(nn, nn);
  MatrixXd aq(0, nn);
  VectorXd bq(0), bv = VectorXd::Zero(av.rows());
  const auto dim = [&] { return static_cast<long>(2 * nn - aq.rows() - av.rows()); };
  const auto add_step = [&](const MatrixXd& a, Eigen::Index before, std::size_t offset) {
    const long d = dim();
    if (d == t.dims.back()) return false;  // M_{k+1} = M_k: stop
    std::vector<SparseRow> rows;
    for (Eigen::Index i = before; i < a.rows(); ++i) rows.push_back(sparse(a.row(i), offset));
    t.dims.push_back(d);
    t.equations.push_back(std::move(rows));
    return true;
  };
  for (;;) {
    const MatrixXd z = orthogonal_complement(av.transpose());  // Δ_{k−1}
    // A_k = {a : aᵀ B Φ δ = 0 for δ ∈ Δ_{k−1}}: the loop combinations that are KVL equations on φ(Δ_{k−1}) + Δ°
    const MatrixXd x = z.transpose() * phi.asDiagonal() * bl.transpose();
    const Subspace a = x.rows() ? Subspace::solutions(x, phi_scale, opt) : Subspace::whole(static_cast<int>(m));
    if (x.rows()) {
      trace.push_back(a.evidence());
      t.certain &= a.certain();
    }
    const MatrixXd r = a.columns().transpose() * bl * psi.asDiagonal();  // ψ(·) ∈ φ(Δ_{k−1}) + Δ°
    const Eigen::Index q0 = aq.rows(), v0 = av.rows();
    absorb_equations(aq, bq, r, VectorXd::Zero(r.rows()), psi_scale, psi_scale, opt, trace, t.certain);
    if (!add_step(aq, q0, 0)) break;  // M_{2k}
    absorb_equations(av, bv, r, VectorXd::Zero(r.rows()), psi_scale, psi_scale, opt, trace, t.certain);
    if (!add_step(av, v0, n)) break;  // M_{2k+1}
  }
  t.steps = static_cast<int>(t.dims.size()) - 1;
  // CEF Thm 5.4(b): ker ω_D ∩ T M_c = {δq = 0, δv ∈ Δ_j, φ δv ∈ Δ°}
  const MatrixXd zv = orthogonal_complement(av.transpose());
  if (zv.cols() == 0 || m == 0) {
    t.solution_rank = zv.cols();
    return;
  }
  const RankDecision d = decide_rank(bl * phi.asDiagonal() * zv, phi_scale, opt);
  trace.push_back(d);
  t.certain &= d.certain;
  t.solution_rank = zv.cols() - d.rank;
}

}  // namespace

bool is_physical(const CircuitGraph& g) { return lc::physical(g.branches); }

CircuitTower circuit_tower(const CircuitGraph& g, const Options& opt_in) {
  const Options opt = assessed_values(opt_in, g);
  validate(g);
  CircuitTower t;
  static_cast<lc::Tower<double>&>(t) = lc::first_step(g.nodes, g.branches);  // M_1 and the loops (dcad/lc_graph.hpp)
  t.physical = is_physical(g);
  if (g.branches.empty()) return t;
  if (t.physical) {
    lc::physical_steps(g.branches, t);  // CEF Thms 6.4, 6.6, 6.8: no rank decision
  } else {
    signed_route(g, t, opt);
  }
  t.steps = static_cast<int>(t.dims.size()) - 1;
  return t;
}

Truth condition_star(const CircuitGraph& g, const Options& opt_in) {
  const Options opt = assessed_values(opt_in, g);
  validate(g);
  const LoopData ld = loop_data(g);
  const MatrixXd& bl = ld.bl;
  const VectorXd &phi = ld.phi, &psi = ld.psi;
  const Eigen::Index m = bl.rows();
  if (m == 0) return yes;                                     // Δ = 0: nothing to find
  const MatrixXd q = full_svd(bl.transpose()).u.leftCols(m);  // orthonormal basis of Δ (the loops: rank m)
  const MatrixXd a = q.transpose() * phi.asDiagonal() * q, b = q.transpose() * psi.asDiagonal() * q;
  const double phi_scale = std::max(phi.cwiseAbs().maxCoeff(), 1e-300);
  const double psi_scale = std::max(psi.cwiseAbs().maxCoeff(), 1e-300);
  const Svd sa = full_svd(a);
  const RankDecision da = decide_rank(a, sa.sigma, phi_scale, opt);
  const MatrixXd off = sa.u.rightCols(m - da.rank);  // (im A)^⊥
  const Subspace delta1 =
      off.cols() ? Subspace::solutions(off.transpose() * b, psi_scale, opt) : Subspace::whole(static_cast<int>(m));
  if (delta1.dim() == 0) return Truth::decided(da.rank == 0, da.certain & delta1.certain());
  const RankDecision d1 = decide_rank(a * delta1.columns(), phi_scale, opt);
  return Truth::decided(d1.rank == da.rank, da.certain & delta1.certain() & d1.certain);
}

LeafBrackets leaf_brackets(const CircuitGraph& g, const Options& opt_in) {
  const Options opt = assessed_values(opt_in, g);
  validate(g);
  if (!is_physical(g))
    throw std::invalid_argument("leaf_brackets: expected a physical circuit (L, C > 0), found a negative value");
  const Eigen::Index n = static_cast<Eigen::Index>(g.branches.size()), a = static_cast<Eigen::Index>(g.nodes);
  const std::vector<Loop> pc = lc::first_step(g.nodes, g.branches).pc_loops;
  const Eigen::Index b = static_cast<Eigen::Index>(pc.size());
  MatrixXd rows = MatrixXd::Zero(2 * a + 2 * b + 2 * n, 4 * n);  // columns q, v, p, ν
  for (Eigen::Index j = 0; j < n; ++j) {
    const CircuitBranch& br = g.branches[static_cast<std::size_t>(j)];
    for (Eigen::Index off : {Eigen::Index(0), a + b + n}) {  // κ(q), κ(v)
      const Eigen::Index col = off == 0 ? j : n + j;
      if (br.from >= 0) rows(off + br.from, col) += 1;
      if (br.to >= 0) rows(off + br.to, col) -= 1;
    }
    rows(a + b + j, 2 * n + j) = 1;  // p − φ v
    if (br.kind == BranchKind::inductor) rows(a + b + j, n + j) = -br.value;
    rows(2 * a + 2 * b + n + j, 3 * n + j) = 1;  // ν
  }
  for (Eigen::Index i = 0; i < b; ++i)
    for (const LoopBranch& lb : pc[static_cast<std::size_t>(i)]) {
      const CircuitBranch& br = g.branches[lb.branch];
      if (br.kind != BranchKind::capacitor) continue;
      const Eigen::Index j = static_cast<Eigen::Index>(lb.branch);
      rows(a + i, j) += lb.sign / br.value;                  // η(ψ q)
      rows(2 * a + b + n + i, n + j) += lb.sign / br.value;  // η(ψ v)
    }
  MatrixXd j = MatrixXd::Zero(4 * n, 4 * n);  // dq ∧ dp + dv ∧ dν: J = W
  for (Eigen::Index i = 0; i < n; ++i) {
    j(i, 2 * n + i) = j(n + i, 3 * n + i) = 1;
    j(2 * n + i, i) = j(3 * n + i, n + i) = -1;
  }
  LeafBrackets out;
  out.sigma = rows * j * rows.transpose();
  out.decision = decide_rank(out.sigma, std::max(norm2(rows) * norm2(rows), 1e-300), opt);
  out.second_class = Truth::decided(out.decision.rank == out.sigma.rows(), out.decision.certain);
  return out;
}

}  // namespace dcad::fast
