// The topology behind the state equations of an RLC circuit with sources (issue 27): three contractions
// of the circuit's graph, integers only (dcad::core: no arithmetic).  Derivation and the equations
// themselves: dcad/reference/rlc_state.hpp (exact, element by element) and dcad/fast/rlc_sparse.hpp
// (double, sparse products) — two numeric routes over this one topology.
//  1. voltage sources and wires join nodes into supernodes: e_node = E_super + Σ ±σ_j(t) along the
//     sources' spanning forest (the offset; a source closing a loop carries no current);
//  2. capacitors join supernodes into C-components; a component holding ground has every potential
//     differential, a floating one has a root whose level is not;
//  3. resistors join C-components into R-components; those without ground are islands (bounded by
//     inductors and current sources only: the LI cutsets of the tower's M_1).
// The supernode potentials are E = T (w, ρ, e): w the potentials relative to their C-component's
// root (differential), ρ the levels of floating roots solved from KCL (algebraic), e the level of an
// island (the multiplier of "KCL over the island"); an island whose level no inductor ties to the rest
// is a gauge and has none.
#pragma once

#include "dcad/rlc_graph.hpp"

#include <cstddef>
#include <utility>
#include <vector>

namespace dcad::rlc {

/// Spanning forest of the edges `use` over vertices 0 … nv−1 by breadth-first search from each
/// component's smallest vertex (0 first): the tree edges in visiting order, and for each vertex its
/// root.  An edge to a vertex already reached closes a loop and is not in the forest.
struct Forest {
  struct Edge {
    std::size_t child, parent, edge;
  };
  std::vector<Edge> tree;
  std::vector<bool> in_tree;
  std::vector<std::size_t> root;
};
inline Forest forest(std::size_t nv, const std::vector<std::pair<std::size_t, std::size_t>>& ends,
                     const std::vector<bool>& use) {
  std::vector<std::vector<std::size_t>> adj(nv);
  for (std::size_t e = 0; e < ends.size(); ++e)
    if (use[e] && ends[e].first != ends[e].second) {
      adj[ends[e].first].push_back(e);
      adj[ends[e].second].push_back(e);
    }
  Forest f;
  f.in_tree.assign(ends.size(), false);
  f.root.assign(nv, nv);
  std::vector<std::size_t> queue;
  for (std::size_t s = 0; s < nv; ++s) {
    if (f.root[s] != nv) continue;
    f.root[s] = s;
    queue.assign(1, s);
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const std::size_t v = queue[h];
      for (std::size_t e : adj[v]) {
        const std::size_t u = ends[e].first == v ? ends[e].second : ends[e].first;
        if (f.root[u] != nv) continue;
        f.root[u] = s;
        f.in_tree[e] = true;
        f.tree.push_back({u, v, e});
        queue.push_back(u);
      }
    }
  }
  return f;
}

struct StateStructure {
  std::size_t nodes = 0, supernodes = 0, nw = 0, nr = 0, ne = 0;
  std::vector<long> supernode;  ///< node → supernode (−1: ground's)
  /// per vertex (node + 1; 0 = ground): e_node − E_supernode = Σ sign·σ_source
  std::vector<std::vector<std::pair<long, int>>> offset;
  struct Levels {
    long w = -1, r = -1, e = -1;  ///< E_s = w + ρ + e, the indices of those present (−1: absent)
  };
  std::vector<Levels> levels;   ///< per supernode
  std::vector<long> root_node;  ///< supernode → the node whose potential E_s is (offset 0)
  std::vector<long> croot;      ///< supernode → its C-component's root supernode (−1: ground's component)
  struct TreeEdge {
    long node, parent;  ///< child and parent nodes (−1 ground)
    std::size_t branch;
  };
  std::vector<TreeEdge> vtree;  ///< the forest of voltage sources and wires, roots first
  long super(long node) const { return node < 0 ? -1 : supernode[static_cast<std::size_t>(node)]; }
};

/// The first contraction: the supernodes (nodes joined by voltage sources and wires, the forest `vtree`),
/// each node's offset from its supernode's potential, into st (st.nodes set).
inline void contract_voltage_sources(StateStructure& st, const std::vector<Branch>& branches,
                                     const std::vector<long>& source) {
  const std::size_t n = branches.size(), nodes = st.nodes, nv = nodes + 1;
  const auto vx = [](long node) { return static_cast<std::size_t>(node + 1); };
  std::vector<std::pair<std::size_t, std::size_t>> ends(n);
  std::vector<bool> vw(n);
  for (std::size_t b = 0; b < n; ++b) {
    ends[b] = {vx(branches[b].from), vx(branches[b].to)};
    vw[b] = branches[b].kind == Kind::voltage || branches[b].kind == Kind::wire;
  }
  const Forest fv = forest(nv, ends, vw);
  st.offset.assign(nv, {});
  for (const Forest::Edge& e : fv.tree) {
    st.offset[e.child] = st.offset[e.parent];
    if (branches[e.edge].kind == Kind::voltage)
      st.offset[e.child].emplace_back(source[e.edge], e.child == ends[e.edge].first ? 1 : -1);  // e_from − e_to = V
    st.vtree.push_back({static_cast<long>(e.child) - 1, static_cast<long>(e.parent) - 1, e.edge});
  }
  std::vector<long> sup_of_root(nv, -2);
  sup_of_root[fv.root[0]] = -1;
  st.supernode.assign(nodes, -1);
  for (std::size_t v = 1; v < nv; ++v) {
    long& s = sup_of_root[fv.root[v]];
    if (s == -2) {
      s = static_cast<long>(st.supernodes++);
      st.root_node.push_back(static_cast<long>(fv.root[v]) - 1);
    }
    st.supernode[v - 1] = s;
  }
}

/// The three contractions of a circuit with `nodes` non-ground nodes; `source[b]` is branch b's index
/// into σ (voltage sources; ignored elsewhere).
inline StateStructure state_structure(std::size_t nodes, const std::vector<Branch>& branches,
                                      const std::vector<long>& source) {
  const std::size_t n = branches.size();
  StateStructure st;
  st.nodes = nodes;
  contract_voltage_sources(st, branches, source);  // 1. supernodes
  // 2./3. C-components and R-components of supernodes (vertex 0 ground, k + 1 supernode k)
  const std::size_t ns = st.supernodes;
  std::vector<std::pair<std::size_t, std::size_t>> sends(n);
  std::vector<bool> isc(n), iscr(n);
  for (std::size_t b = 0; b < n; ++b) {
    sends[b] = {static_cast<std::size_t>(st.super(branches[b].from) + 1),
                static_cast<std::size_t>(st.super(branches[b].to) + 1)};
    isc[b] = branches[b].kind == Kind::capacitor;
    iscr[b] = isc[b] || branches[b].kind == Kind::resistor;
  }
  const Forest fc = forest(ns + 1, sends, isc), fr = forest(ns + 1, sends, iscr);
  // w per supernode unless it is the root of a floating C-component; ρ per floating C-component unless
  // it is the first of its island; e per island (dropped below where a gauge)
  std::vector<long> wv(ns, -1), rv(ns + 1, -1), island_of(ns + 1, -1), island_root_comp, isl_id(ns + 1, -1);
  for (std::size_t s = 1; s <= ns; ++s) {
    const std::size_t cc = fc.root[s], rc = fr.root[s];
    if (cc == fc.root[0] || s != cc) wv[s - 1] = static_cast<long>(st.nw++);
    if (rc != fr.root[0]) {
      if (isl_id[rc] < 0) {
        isl_id[rc] = static_cast<long>(island_root_comp.size());
        island_root_comp.push_back(static_cast<long>(cc));
      }
      island_of[s] = isl_id[rc];
    }
  }
  // islands whose levels are a gauge: components of (islands + the rest, inductors) without the rest
  const std::size_t nis = island_root_comp.size();
  std::vector<long> ev(nis, -1);
  {
    std::vector<std::pair<std::size_t, std::size_t>> iends;
    std::vector<bool> all;
    for (std::size_t b = 0; b < n; ++b) {
      if (branches[b].kind != Kind::inductor) continue;
      iends.emplace_back(static_cast<std::size_t>(island_of[sends[b].first] + 1),
                         static_cast<std::size_t>(island_of[sends[b].second] + 1));
      all.push_back(true);
    }
    const Forest fi = forest(nis + 1, iends, all);
    for (std::size_t i = 0; i < nis; ++i)
      if (fi.root[i + 1] == fi.root[0] || fi.root[i + 1] != i + 1)
        ev[i] = static_cast<long>(st.ne++);  // a component's first island is its gauge
  }
  st.croot.assign(ns, -1);
  for (std::size_t s = 1; s <= ns; ++s)
    if (fc.root[s] != fc.root[0]) st.croot[s - 1] = static_cast<long>(fc.root[s]) - 1;
  for (std::size_t s = 1; s <= ns; ++s) {
    const std::size_t cc = fc.root[s];
    if (cc == fc.root[0] || rv[cc] >= 0) continue;
    if (island_of[s] >= 0 && island_root_comp[static_cast<std::size_t>(island_of[s])] == static_cast<long>(cc))
      continue;
    rv[cc] = static_cast<long>(st.nr++);
  }
  st.levels.assign(ns, {});
  for (std::size_t s = 1; s <= ns; ++s) {
    StateStructure::Levels& l = st.levels[s - 1];
    l.w = wv[s - 1];
    l.r = rv[fc.root[s]];
    if (island_of[s] >= 0) l.e = ev[static_cast<std::size_t>(island_of[s])];
  }
  return st;
}

}  // namespace dcad::rlc
