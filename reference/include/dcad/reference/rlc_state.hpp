// The state equations of an RLC circuit with sources, element by element, in any number type (exact
// for the reference: every entry is a sum of ±C, ±1/R, ±L, M over the elements that touch it).
//
// Derivation (YM §4: R the force −R·v, V the force +V(t), I the affine constraint v = I(t); CEF §6's
// LC circuits are the case without R, V, I).  Branch voltage u_b = e_from − e_to, current i_b from → to;
// i_C = C u̇_C, u_L = (Φ i̇)_b, u_R = R i_R, u_V = V(t), i_I = I(t).  The contractions of dcad/rlc_state.hpp
// write every node potential as e_node = (T z)_supernode + o_node·σ with z = (w, ρ, e), so each branch b
// has u_b = d_bᵀ z + o_bᵀ σ, d_b = T_from − T_to, o_b = o_from − o_to (integer vectors).  KCL at every
// supernode, multiplied by Tᵀ (the virtual potentials δz), is Σ_b d_b i_b = 0 over the branches that
// are not voltage sources or wires (theirs are internal to a supernode); with the branch laws:
//   capacitor  i = C (d_wᵀ ẇ + o_bᵀ σ̇)          → C_ww += C d_w d_wᵀ,  H_wd += C d_w o_bᵀ
//   resistor   i = (d_wᵀ w + d_rᵀ ρ + o_bᵀ σ)/R  → G += d dᵀ/R on (w, ρ),  H_w, H_r += d o_bᵀ/R
//   current    i = σ_j                           → H_w, H_r, I_e += d e_jᵀ
//   inductor   i = i_k                           → L_w, L_r, L_e column k = d;  Φ i̇ = u: O_L row k = o_bᵀ
// (a capacitor's d has no ρ or e part: both ends lie in one C-component; a resistor's no e part.)
// The rows of w are the charge balance, those of ρ KCL over a floating C-component (no capacitor
// current crosses it), those of e KCL over an island.  dcad/fast/rlc_sparse.hpp reaches the same
// blocks by sparse products of incidence matrices and integrates them (simulate's sparse route);
// proptests/prop_sparse.cpp holds the two equal.
#pragma once

#include "dcad/reference/rlc.hpp"
#include "dcad/rlc_state.hpp"
#include "dcad/solution.hpp"

#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace dcad::reference {

inline rlc::Kind graph_kind(RlcKind k) {
  switch (k) {
    case RlcKind::inductor: return rlc::Kind::inductor;
    case RlcKind::capacitor: return rlc::Kind::capacitor;
    case RlcKind::resistor: return rlc::Kind::resistor;
    case RlcKind::voltage: return rlc::Kind::voltage;
    case RlcKind::current: return rlc::Kind::current;
    default: return rlc::Kind::wire;
  }
}

/// The contractions of `c` (dcad/rlc_state.hpp).
template <class T>
rlc::StateStructure state_structure(const RlcCircuit<T>& c) {
  std::vector<rlc::Branch> topo;
  std::vector<long> src;
  for (const RlcBranch<T>& b : c.branches) {
    topo.push_back({graph_kind(b.kind), b.from, b.to});
    src.push_back(static_cast<long>(b.source));
  }
  return rlc::state_structure(c.nodes, topo, src);
}

/// A branch's voltage u_b = e_from − e_to = d_bᵀ (w, ρ, e) + o_bᵀ σ: d_b split into its w, ρ and e
/// parts and o_b, each a list of (index, ±1) (an index may appear twice with opposite signs: both
/// ends on one level, which cancels).
struct BranchPotential {
  std::vector<std::pair<long, int>> w, r, e, o;
};
inline BranchPotential branch_potential(const rlc::StateStructure& st, long from, long to) {
  BranchPotential p;
  const auto levels = [&](long node, int sign) {
    const long s = st.super(node);
    if (s < 0) return;
    const rlc::StateStructure::Levels& l = st.levels[static_cast<std::size_t>(s)];
    if (l.w >= 0) p.w.emplace_back(l.w, sign);
    if (l.r >= 0) p.r.emplace_back(l.r, sign);
    if (l.e >= 0) p.e.emplace_back(l.e, sign);
  };
  levels(from, 1);
  levels(to, -1);
  p.o = st.offset[static_cast<std::size_t>(from + 1)];
  for (const auto& [j, sg] : st.offset[static_cast<std::size_t>(to + 1)]) p.o.emplace_back(j, -sg);
  return p;
}

/// The blocks of the state equations as they are accumulated: one map (row, column) → value per block, in
/// StateEquations' order C_ww, G_ww, G_wr, G_rr, L_w, L_r, L_e, Phi, H_w, H_wd, H_r, I_e, O_L.
template <class N>
struct StateBlocks {
  using Acc = std::map<std::pair<long, long>, N>;
  std::array<Acc, 13> maps;
  static void add(Acc& a, long i, long j, const N& v) {
    auto [it, fresh] = a.emplace(std::make_pair(i, j), v);
    if (!fresh) it->second += v;
  }
  /// Into out.blocks, nonzero entries only (nw, nr, ne: the levels; nl: inductors; ms: sources).
  void emit(StateEquations<N>& out, long nw, long nr, long ne, long nl, long ms) const {
    static const char* const names[13] = {"C_ww", "G_ww", "G_wr", "G_rr", "L_w", "L_r", "L_e",
                                          "Phi",  "H_w",  "H_wd", "H_r",  "I_e", "O_L"};
    const long rows[13] = {nw, nw, nw, nr, nw, nr, ne, nl, nw, nw, nr, ne, nl};
    const long cols[13] = {nw, nw, nr, nr, nl, nl, nl, nl, ms, ms, ms, ms, ms};
    for (std::size_t k = 0; k < 13; ++k) {
      SparseBlock<N> b{rows[k], cols[k], {}};
      for (const auto& [ij, v] : maps[k])
        if (v != N(0)) b.entries.emplace_back(ij.first, ij.second, v);
      out.blocks.emplace_back(names[k], std::move(b));
    }
  }
};

/// The names of the state levels: w = E_s − E_root (its C-component's root), ρ = E_root − E_island (the
/// island's first root), e = E_island, each written with the potentials e(node) of `node_names`.
template <class N>
void name_state_levels(const rlc::StateStructure& st, const std::vector<std::string>& node_names,
                       StateEquations<N>& out) {
  out.w.resize(st.nw);
  out.r.resize(st.nr);
  out.e.resize(st.ne);
  const auto pot = [&](long supernode) {
    return "e(" + node_names.at(static_cast<std::size_t>(st.root_node[static_cast<std::size_t>(supernode)])) + ")";
  };
  std::vector<long> island_root(st.ne, -1);
  for (std::size_t s = 0; s < st.supernodes; ++s) {
    const rlc::StateStructure::Levels& l = st.levels[s];
    if (l.w < 0 && l.r < 0 && l.e >= 0) {
      island_root[static_cast<std::size_t>(l.e)] = static_cast<long>(s);
      out.e[static_cast<std::size_t>(l.e)] = pot(static_cast<long>(s));
    }
  }
  for (std::size_t s = 0; s < st.supernodes; ++s) {
    const rlc::StateStructure::Levels& l = st.levels[s];
    const long root = st.croot[s];
    if (l.w >= 0)
      out.w[static_cast<std::size_t>(l.w)] =
          root >= 0 ? pot(static_cast<long>(s)) + "-" + pot(root) : pot(static_cast<long>(s));
    else if (l.r >= 0)
      out.r[static_cast<std::size_t>(l.r)] =
          pot(static_cast<long>(s)) + (l.e >= 0 ? "-" + pot(island_root[static_cast<std::size_t>(l.e)]) : "");
  }
}

/// The state equations of `c` (dcad/solution.hpp's StateEquations), with every R, C positive and Φ
/// positive definite (the caller's precondition: graph_route_holds).  `node_names` name the non-ground
/// nodes, `source_names` σ's entries.
template <class N>
StateEquations<N> state_equations(const RlcCircuit<N>& c, const std::vector<std::string>& node_names,
                                  const std::vector<std::string>& source_names) {
  const rlc::StateStructure st = state_structure(c);
  const long nw = static_cast<long>(st.nw), nr = static_cast<long>(st.nr), ne = static_cast<long>(st.ne);
  const long ms = static_cast<long>(c.sources);
  StateEquations<N> out;
  name_state_levels(st, node_names, out);
  out.sources = source_names;
  StateBlocks<N> acc;  // one map per block, (row, column) → value
  auto& [Cww, Gww, Gwr, Grr, Lw, Lr, Le, Phi, Hw, Hwd, Hr, Ie, Ol] = acc.maps;
  using Acc = typename StateBlocks<N>::Acc;
  const auto add = [](Acc& a, long i, long j, const N& v) { StateBlocks<N>::add(a, i, j, v); };
  const auto outer = [&](Acc& a, const std::vector<std::pair<long, int>>& x, const std::vector<std::pair<long, int>>& y,
                         const N& v) {
    for (const auto& [i, si] : x)
      for (const auto& [j, sj] : y) add(a, i, j, si * sj > 0 ? v : N(-v));
  };
  std::vector<long> inductor(c.branches.size(), -1);
  long nl = 0;
  for (std::size_t k = 0; k < c.branches.size(); ++k) {
    const RlcBranch<N>& b = c.branches[k];
    const BranchPotential d = branch_potential(st, b.from, b.to);
    const std::vector<std::pair<long, int>>& o = d.o;
    switch (b.kind) {
      case RlcKind::capacitor:
        outer(Cww, d.w, d.w, b.value);
        outer(Hwd, d.w, o, b.value);
        break;
      case RlcKind::resistor: {
        const N g = N(1) / b.value;
        outer(Gww, d.w, d.w, g);
        outer(Gwr, d.w, d.r, g);
        outer(Grr, d.r, d.r, g);
        outer(Hw, d.w, o, g);
        outer(Hr, d.r, o, g);
        break;
      }
      case RlcKind::current: {
        const std::vector<std::pair<long, int>> sel{{static_cast<long>(b.source), 1}};
        outer(Hw, d.w, sel, N(1));
        outer(Hr, d.r, sel, N(1));
        outer(Ie, d.e, sel, N(1));
        break;
      }
      case RlcKind::inductor: {
        const std::vector<std::pair<long, int>> col{{nl, 1}};
        outer(Lw, d.w, col, N(1));
        outer(Lr, d.r, col, N(1));
        outer(Le, d.e, col, N(1));
        outer(Ol, col, o, N(1));
        add(Phi, nl, nl, b.value);
        inductor[k] = nl++;
        break;
      }
      default: break;  // voltage sources and wires: inside a supernode
    }
  }
  for (const Mutual<N>& mu : c.mutuals) {
    add(Phi, inductor.at(static_cast<std::size_t>(mu.a)), inductor.at(static_cast<std::size_t>(mu.b)), mu.m);
    add(Phi, inductor.at(static_cast<std::size_t>(mu.b)), inductor.at(static_cast<std::size_t>(mu.a)), mu.m);
  }
  for (std::size_t k = 0; k < c.branches.size(); ++k)
    if (c.branches[k].kind == RlcKind::inductor) out.i.push_back("v_" + c.branches[k].name);
  acc.emit(out, nw, nr, ne, nl, ms);
  return out;
}

}  // namespace dcad::reference
