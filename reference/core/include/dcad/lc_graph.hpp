// The graph route for LC circuits (CEF §6), over any number type: the tower of the circuit's
// `pontryagin` system from spanning forests and fundamental loops, without forming the 3n×3n system.
// For physical values (every L > 0, every C > 0, empty branches allowed) it decides nothing: KCL per
// node, and by Thm 6.4 S_0 is KVL on the purely capacitive loops — one equation Σ ±q_i/C_i = 0 per
// fundamental loop of the non-inductive subgraph that closes through a capacitor (the forest spans
// the empty branches first, so the other fundamental loops are the empty loops).  Thm 6.6: Δ_2 = Δ_1,
// so c = 3 if there is such a loop and c = 1 otherwise; the solution rank is the number of independent
// empty loops (Thm 6.8).  O(n + total loop length).  Written once: dcad::fast runs it in double,
// dcad::certified in exact rationals (a theorem's answer is exact).
//
// Variables x = (q, v, p) ∈ R^{3n}, n = branches: q_b = index b, v_b = n + b, p_b = 2n + b.
#pragma once

#include "dcad/graph.hpp"
#include "dcad/types.hpp"

#include <algorithm>
#include <vector>

namespace dcad::lc {

template <class N>
struct Branch {
  BranchKind kind = BranchKind::empty;
  long from = -1, to = -1;  ///< node indices, −1 = ground; current flows from → to
  N value{};                ///< L or C
};

template <class N>
struct Term {
  std::size_t var = 0;  ///< 0 … 3n−1: q, then v, then p
  N coeff{};
};
template <class N>
using Row = std::vector<Term<N>>;  ///< Σ coeff·x_var = 0

/// M_0 ⊋ M_1 and the loops; the later steps of the physical route (or of a signed one) are added to it.
template <class N>
struct Tower {
  std::vector<long> dims;                      ///< dim M_0 … M_c
  std::vector<std::vector<Row<N>>> equations;  ///< the constraints added to reach M_k (k = 0: none)
  int steps = 0;
  long solution_rank = 0;
  std::vector<graph::Loop> pc_loops;     ///< fundamental purely capacitive loops (physical: one KVLPC equation each)
  std::vector<graph::Loop> empty_loops;  ///< fundamental loops of the empty subgraph (CEF Thm 6.8)
};

template <class N>
std::vector<graph::Edge> edges(const std::vector<Branch<N>>& branches) {
  std::vector<graph::Edge> out;
  for (const Branch<N>& b : branches) out.push_back({b.from, b.to});
  return out;
}

/// No negative L or C (CEF Remark 6.7): then the route below decides nothing.
template <class N>
bool physical(const std::vector<Branch<N>>& branches) {
  for (const Branch<N>& b : branches)
    if (b.kind != BranchKind::empty && b.value < 0) return false;
  return true;
}

/// KCL per node: Σ (+1 leaving, −1 entering) v_b = 0, one node of each component without ground
/// left out (its row is minus the sum of the others), so the rows are independent.  CEF §6: Δ = ker K.
template <class N>
std::vector<Row<N>> kcl_rows(std::size_t nodes, const std::vector<Branch<N>>& branches) {
  const std::size_t n = branches.size();
  graph::UnionFind uf(nodes + 1);
  std::vector<Row<N>> rows(nodes);
  for (std::size_t b = 0; b < n; ++b) {
    const Branch<N>& br = branches[b];
    uf.join(graph::vertex(br.from), graph::vertex(br.to));
    if (br.from == br.to) continue;
    if (br.from >= 0) rows[br.from].push_back({n + b, N(1)});
    if (br.to >= 0) rows[br.to].push_back({n + b, N(-1)});
  }
  std::vector<bool> dropped(nodes + 1, false);
  dropped[uf.find(0)] = true;  // the ground's component keeps every non-ground node
  std::vector<Row<N>> out;
  for (std::size_t i = 0; i < nodes; ++i) {
    const std::size_t r = uf.find(graph::vertex(static_cast<long>(i)));
    if (!dropped[r]) {  // first node of a component without ground
      dropped[r] = true;
      continue;
    }
    out.push_back(std::move(rows[i]));  // parallel branches keep separate terms: each is its own variable
  }
  return out;
}

/// Σ_{capacitors of the loop} ±x_{offset+b}/C_b = 0.
template <class N>
Row<N> kvl_row(const std::vector<Branch<N>>& branches, const graph::Loop& loop, std::size_t offset) {
  Row<N> r;
  for (const graph::LoopBranch& lb : loop)
    if (branches[lb.branch].kind == BranchKind::capacitor)
      r.push_back({offset + lb.branch, N(lb.sign) / branches[lb.branch].value});
  std::sort(r.begin(), r.end(), [](const Term<N>& a, const Term<N>& b) { return a.var < b.var; });
  return r;
}

/// M_0, M_1 = {p = φ v, v ∈ Δ} (KCL and p_b − L_b v_b = 0) and the fundamental loops.
template <class N>
Tower<N> first_step(std::size_t nodes, const std::vector<Branch<N>>& branches) {
  const std::size_t n = branches.size();
  Tower<N> t;
  t.dims.push_back(static_cast<long>(3 * n));
  t.equations.emplace_back();
  std::vector<Row<N>> m1 = kcl_rows(nodes, branches);
  const long rank_k = static_cast<long>(m1.size());
  for (std::size_t b = 0; b < n; ++b) {  // p = φ v: p_b − L_b v_b = 0 (p_b = 0 without inductor)
    Row<N> r{{2 * n + b, N(1)}};
    if (branches[b].kind == BranchKind::inductor) r.push_back({n + b, -branches[b].value});
    m1.push_back(r);
  }
  const long d1 = static_cast<long>(2 * n) - rank_k;
  if (d1 < t.dims.back()) {
    t.dims.push_back(d1);
    t.equations.push_back(std::move(m1));
  }
  if (n == 0) return t;
  std::vector<bool> keep(n), prefer(n);
  for (std::size_t b = 0; b < n; ++b) {
    keep[b] = branches[b].kind != BranchKind::inductor;
    prefer[b] = branches[b].kind == BranchKind::empty;
  }
  for (graph::Loop& l : graph::fundamental_loops(nodes, edges(branches), keep, prefer))
    (branches[l.front().branch].kind == BranchKind::capacitor ? t.pc_loops : t.empty_loops).push_back(std::move(l));
  t.steps = static_cast<int>(t.dims.size()) - 1;
  return t;
}

/// The physical route's later steps (CEF Thms 6.4, 6.6, 6.8): M_2 = KVL of the purely capacitive
/// loops on q, M_3 the same on v; the KVLPC rows are independent on Δ and Δ_2 = Δ_1.
template <class N>
void physical_steps(const std::vector<Branch<N>>& branches, Tower<N>& t) {
  const std::size_t n = branches.size();
  t.solution_rank = static_cast<long>(t.empty_loops.size());
  if (!t.pc_loops.empty()) {  // else Thm 6.4: S_0 = E, M_2 = M_1, c = 1
    std::vector<Row<N>> q, v;
    for (const graph::Loop& l : t.pc_loops) {
      q.push_back(kvl_row(branches, l, 0));
      v.push_back(kvl_row(branches, l, n));
    }
    const long pc = static_cast<long>(t.pc_loops.size());
    t.dims.push_back(t.dims.back() - pc);
    t.equations.push_back(std::move(q));
    t.dims.push_back(t.dims.back() - pc);
    t.equations.push_back(std::move(v));
  }
  t.steps = static_cast<int>(t.dims.size()) - 1;
}

/// The whole tower of a physical circuit (no rank decision).
template <class N>
Tower<N> physical_tower(std::size_t nodes, const std::vector<Branch<N>>& branches) {
  Tower<N> t = first_step(nodes, branches);
  if (!branches.empty()) physical_steps(branches, t);
  return t;
}

}  // namespace dcad::lc
