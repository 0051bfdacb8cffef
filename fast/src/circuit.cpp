#include "dcad/fast/circuit.hpp"

#include "dcad/fast/cad.hpp"
#include "dcad/fast/subspace.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

using graph::vertex;  // ground is vertex 0

void validate(const CircuitGraph& g) {
  for (std::size_t b = 0; b < g.branches.size(); ++b) {
    const CircuitBranch& br = g.branches[b];
    const long n = static_cast<long>(g.nodes);
    if (br.from < -1 || br.from >= n || br.to < -1 || br.to >= n)
      throw std::invalid_argument("circuit_tower: branch " + std::to_string(b + 1) + ": expected nodes in [-1, " +
                                  std::to_string(n) + "), found " + std::to_string(br.from) + ", " + std::to_string(br.to));
    if (br.kind != BranchKind::empty && (!std::isfinite(br.value) || br.value == 0))
      throw std::invalid_argument("circuit_tower: branch " + std::to_string(b + 1) +
                                  ": expected a finite nonzero L or C in double, found " + std::to_string(br.value));
  }
}

/// KCL per node: Σ (+1 leaving, −1 entering) v_b = 0, one node of each component without ground
/// left out (its row is minus the sum of the others), so the rows are independent.  CEF §6: Δ = ker K.
std::vector<SparseRow> kcl_rows(const CircuitGraph& g, std::size_t n) {
  const std::size_t nv = g.nodes + 1;
  graph::UnionFind uf(nv);
  std::vector<std::vector<Term>> rows(g.nodes);
  for (std::size_t b = 0; b < g.branches.size(); ++b) {
    const CircuitBranch& br = g.branches[b];
    uf.join(vertex(br.from), vertex(br.to));
    if (br.from == br.to) continue;
    if (br.from >= 0) rows[br.from].push_back({n + b, 1.0});
    if (br.to >= 0) rows[br.to].push_back({n + b, -1.0});
  }
  std::vector<bool> dropped(nv, false);
  dropped[uf.find(0)] = true;  // the ground's component keeps every non-ground node
  std::vector<SparseRow> out;
  for (std::size_t i = 0; i < g.nodes; ++i) {
    const std::size_t r = uf.find(vertex(static_cast<long>(i)));
    if (!dropped[r]) {  // first node of a component without ground
      dropped[r] = true;
      continue;
    }
    // parallel branches keep separate terms: each is its own variable
    out.push_back(std::move(rows[i]));
  }
  return out;
}

/// p = φ v: p_b − L_b v_b = 0 (p_b = 0 without inductor).
std::vector<SparseRow> flux_rows(const CircuitGraph& g, std::size_t n) {
  std::vector<SparseRow> out;
  for (std::size_t b = 0; b < n; ++b) {
    SparseRow r{{2 * n + b, 1.0}};
    if (g.branches[b].kind == BranchKind::inductor) r.push_back({n + b, -g.branches[b].value});
    out.push_back(r);
  }
  return out;
}

/// Σ_{capacitors of the loop} ±x_{offset+b}/C_b = 0.
SparseRow kvl_row(const CircuitGraph& g, const Loop& loop, std::size_t offset) {
  SparseRow r;
  for (const LoopBranch& lb : loop)
    if (g.branches[lb.branch].kind == BranchKind::capacitor) r.push_back({offset + lb.branch, lb.sign / g.branches[lb.branch].value});
  std::sort(r.begin(), r.end(), [](const Term& a, const Term& b) { return a.var < b.var; });
  return r;
}

SparseRow sparse(const Eigen::RowVectorXd& row, std::size_t offset) {
  SparseRow r;
  const double big = row.cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < row.size(); ++j)
    if (std::abs(row(j)) > 1e-13 * big) r.push_back({offset + static_cast<std::size_t>(j), row(j)});
  return r;
}

void physical_route(const CircuitGraph& g, CircuitTower& t) {
  const std::size_t n = g.branches.size();
  t.solution_rank = static_cast<long>(t.empty_loops.size());
  if (t.pc_loops.empty()) return;  // Thm 6.4: S_0 = E, M_2 = M_1, c = 1
  std::vector<SparseRow> q, v;
  for (const Loop& l : t.pc_loops) {
    q.push_back(kvl_row(g, l, 0));
    v.push_back(kvl_row(g, l, n));
  }
  // Thm 6.4 + the proof of Thm 6.6: the KVLPC rows are independent on Δ, and Δ_2 = Δ_1
  const long pc = static_cast<long>(t.pc_loops.size());
  t.dims.push_back(t.dims.back() - pc);
  t.equations.push_back(std::move(q));
  t.dims.push_back(t.dims.back() - pc);
  t.equations.push_back(std::move(v));
  t.steps = 3;
}

/// The closed form with each rank decided: q-constraints aq (rows of S^⊥), v-constraints av (Δ_k^⊥).
void signed_route(const CircuitGraph& g, CircuitTower& t, const Options& opt) {
  const std::size_t n = g.branches.size();
  const std::vector<Loop> loops = graph::fundamental_loops(g.nodes, edges(g), std::vector<bool>(n, true), std::vector<bool>(n, false));
  const Eigen::Index m = static_cast<Eigen::Index>(loops.size()), nn = static_cast<Eigen::Index>(n);
  MatrixXd bl = MatrixXd::Zero(m, nn);  // rows: loop currents, a basis of Δ
  for (Eigen::Index i = 0; i < m; ++i)
    for (const LoopBranch& lb : loops[i]) bl(i, static_cast<Eigen::Index>(lb.branch)) += lb.sign;
  VectorXd phi = VectorXd::Zero(nn), psi = VectorXd::Zero(nn);
  for (std::size_t b = 0; b < n; ++b) {
    if (g.branches[b].kind == BranchKind::inductor) phi(b) = g.branches[b].value;
    if (g.branches[b].kind == BranchKind::capacitor) psi(b) = 1.0 / g.branches[b].value;
  }
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

bool is_physical(const CircuitGraph& g) {
  for (const CircuitBranch& b : g.branches)
    if (b.kind != BranchKind::empty && b.value < 0) return false;
  return true;
}

std::vector<graph::Edge> edges(const CircuitGraph& g) {
  std::vector<graph::Edge> out;
  for (const CircuitBranch& b : g.branches) out.push_back({b.from, b.to});
  return out;
}

CircuitTower circuit_tower(const CircuitGraph& g, const Options& opt) {
  validate(g);
  const std::size_t n = g.branches.size();
  CircuitTower t;
  t.dims.push_back(static_cast<long>(3 * n));
  t.equations.emplace_back();
  std::vector<SparseRow> m1 = kcl_rows(g, n);
  const long rank_k = static_cast<long>(m1.size());
  for (SparseRow& r : flux_rows(g, n)) m1.push_back(std::move(r));
  const long d1 = static_cast<long>(2 * n) - rank_k;  // M_1 = {p = φ v, v ∈ Δ}
  if (d1 < t.dims.back()) {
    t.dims.push_back(d1);
    t.equations.push_back(std::move(m1));
  }
  t.physical = is_physical(g);
  if (n == 0) return t;
  std::vector<bool> keep(n), prefer(n);
  for (std::size_t b = 0; b < n; ++b) {
    keep[b] = g.branches[b].kind != BranchKind::inductor;
    prefer[b] = g.branches[b].kind == BranchKind::empty;
  }
  for (Loop& l : graph::fundamental_loops(g.nodes, edges(g), keep, prefer))
    (g.branches[l.front().branch].kind == BranchKind::capacitor ? t.pc_loops : t.empty_loops).push_back(std::move(l));
  if (t.physical) {
    physical_route(g, t);
  } else {
    signed_route(g, t, opt);
  }
  t.steps = static_cast<int>(t.dims.size()) - 1;
  return t;
}

}  // namespace dcad::fast
