// Circuit topology, written once for every route (dcad::core: no arithmetic, no dependency): a circuit
// is a multigraph on its nodes and ground, one edge per branch.  Both twins and the readers count and
// name loops and cutsets here — KVL equations come from loops, KCL equations from cutsets (CEF §6:
// Thm 6.4 counts the purely capacitive loops, Thm 6.8 the empty ones; YM §4's sources add loops of
// voltage sources and cutsets of current sources).
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace dcad::graph {

/// A branch as an edge: node indices, −1 = ground; its current flows from → to.
struct Edge {
  long from = -1, to = -1;
};

/// Disjoint sets with path halving: the components of a subgraph.
class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), std::size_t{0}); }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  /// Joins the sets of a and b; false if they were one set already (the edge closes a cycle).
  bool join(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    parent_[a] = b;
    return true;
  }

 private:
  std::vector<std::size_t> parent_;
};

/// Ground is vertex 0, node i is vertex i + 1.
inline std::size_t vertex(long node) { return static_cast<std::size_t>(node + 1); }

/// The cycle rank (edges − vertices + components, ground included) of the subgraph of the edges
/// with keep[b]: the number of independent loops in it.
inline std::size_t cycle_rank(std::size_t nodes, const std::vector<Edge>& edges, const std::vector<bool>& keep) {
  UnionFind uf(nodes + 1);
  std::size_t cycles = 0;
  for (std::size_t b = 0; b < edges.size(); ++b)
    if (keep[b] && !uf.join(vertex(edges[b].from), vertex(edges[b].to))) ++cycles;
  return cycles;
}

struct LoopBranch {
  std::size_t branch = 0;
  int sign = 1;  ///< +1 if the branch current runs along the loop
};
using Loop = std::vector<LoopBranch>;

/// The kept edges (keep[b], not self-loops) at each vertex, in CSR form: those at v are
/// edges[start[v]] … edges[start[v + 1] − 1].
struct Adjacency {
  std::vector<std::size_t> start, edges;
};
inline Adjacency kept_adjacency(std::size_t nv, const std::vector<Edge>& edges, const std::vector<bool>& keep) {
  Adjacency a;
  a.start.assign(nv + 1, 0);
  for (std::size_t b = 0; b < edges.size(); ++b)
    if (keep[b] && edges[b].from != edges[b].to) {
      ++a.start[vertex(edges[b].from) + 1];
      ++a.start[vertex(edges[b].to) + 1];
    }
  for (std::size_t v = 0; v < nv; ++v) a.start[v + 1] += a.start[v];
  a.edges.resize(a.start[nv]);
  std::vector<std::size_t> fill(a.start.begin(), a.start.end() - 1);
  for (std::size_t b = 0; b < edges.size(); ++b)
    if (keep[b] && edges[b].from != edges[b].to) {
      a.edges[fill[vertex(edges[b].from)]++] = b;
      a.edges[fill[vertex(edges[b].to)]++] = b;
    }
  return a;
}

/// The fundamental loops of the spanning forest of the edges with keep[b] that spans the edges with
/// prefer[b] first: one loop per kept edge outside the forest, that edge first with sign +1.  The
/// forest is breadth first (short loops) and takes whole components of preferred edges at once.
/// (With keep = non-inductive and prefer = empty, the loops through a capacitor are CEF Thm 6.4's
/// KVLPC loops and the others lie in the empty subgraph.)  O(edges + total loop length).
inline std::vector<Loop> fundamental_loops(std::size_t nodes, const std::vector<Edge>& edges,
                                           const std::vector<bool>& keep, const std::vector<bool>& prefer) {
  const std::size_t nv = nodes + 1, n = edges.size();
  const Adjacency csr = kept_adjacency(nv, edges, keep);
  const std::vector<std::size_t>&start = csr.start, &adj = csr.edges;
  const std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> parent_edge(nv, none), parent(nv, none), depth(nv, 0), queue, flood;
  std::vector<bool> seen(nv, false), in_tree(n, false);
  const auto other = [&](std::size_t b, std::size_t v) {
    return vertex(edges[b].from) == v ? vertex(edges[b].to) : vertex(edges[b].from);
  };
  const auto reach = [&](std::size_t b, std::size_t from, std::size_t to) {
    seen[to] = true;
    parent_edge[to] = b;
    parent[to] = from;
    depth[to] = depth[from] + 1;
    in_tree[b] = true;
  };
  const auto flood_from = [&](std::size_t v0) {  // the preferred component of v0, at once
    flood.assign(1, v0);
    for (std::size_t i = 0; i < flood.size(); ++i) {
      const std::size_t x = flood[i];
      queue.push_back(x);
      for (std::size_t k = start[x]; k < start[x + 1]; ++k) {
        const std::size_t b = adj[k], y = other(b, x);
        if (prefer[b] && !seen[y]) {
          reach(b, x, y);
          flood.push_back(y);
        }
      }
    }
  };
  for (std::size_t root = 0; root < nv; ++root) {
    if (seen[root]) continue;
    seen[root] = true;
    queue.clear();
    flood_from(root);
    for (std::size_t i = 0; i < queue.size(); ++i) {  // breadth first: short loops
      const std::size_t x = queue[i];
      for (std::size_t k = start[x]; k < start[x + 1]; ++k) {
        const std::size_t b = adj[k], y = other(b, x);
        if (!seen[y]) {
          reach(b, x, y);
          flood_from(y);
        }
      }
    }
  }
  std::vector<Loop> loops;
  for (std::size_t b = 0; b < n; ++b) {
    if (!keep[b] || in_tree[b]) continue;
    Loop up{{b, 1}}, down;  // b runs from → to; back to `from` through the tree
    std::size_t x = vertex(edges[b].to), y = vertex(edges[b].from);
    while (x != y) {
      if (depth[x] >= depth[y]) {  // x → parent(x)
        const std::size_t e = parent_edge[x];
        up.push_back({e, vertex(edges[e].from) == x ? 1 : -1});
        x = parent[x];
      } else {  // parent(y) → y, collected upwards
        const std::size_t e = parent_edge[y];
        down.push_back({e, vertex(edges[e].to) == y ? 1 : -1});
        y = parent[y];
      }
    }
    up.insert(up.end(), down.rbegin(), down.rend());
    loops.push_back(std::move(up));
  }
  return loops;
}

/// A cutset by its edges, each signed +1 if its current leaves the cut's side.
using Cutset = std::vector<LoopBranch>;

/// Independent cutsets made only of the edges with in[b]: every other edge is contracted, and the cut
/// around each resulting super-node (one per connected piece of the in-edges left out) is a cutset;
/// those with at least one edge with must[b] are returned.
inline std::vector<Cutset> cutsets(std::size_t nodes, const std::vector<Edge>& edges, const std::vector<bool>& in,
                                   const std::vector<bool>& must) {
  const std::size_t v = nodes + 1;
  UnionFind contracted(v);
  for (std::size_t b = 0; b < edges.size(); ++b)
    if (!in[b]) contracted.join(vertex(edges[b].from), vertex(edges[b].to));
  // super-nodes joined by the kept edges: drop one super-node per connected piece
  UnionFind piece(v);
  for (std::size_t b = 0; b < edges.size(); ++b)
    if (in[b]) piece.join(contracted.find(vertex(edges[b].from)), contracted.find(vertex(edges[b].to)));
  // one pass over the edges: each crossing edge goes to the cuts of its two super-nodes (O(edges))
  std::vector<Cutset> around(v);
  std::vector<bool> needed(v, false);
  for (std::size_t b = 0; b < edges.size(); ++b) {
    if (!in[b]) continue;
    const std::size_t f = contracted.find(vertex(edges[b].from)), t = contracted.find(vertex(edges[b].to));
    if (f == t) continue;
    around[f].push_back({b, 1});
    around[t].push_back({b, -1});
    if (must[b]) needed[f] = needed[t] = true;
  }
  std::vector<Cutset> out;
  for (std::size_t s = 0; s < v; ++s) {
    if (contracted.find(s) != s || piece.find(s) == s) continue;  // not a super-node, or the dropped representative
    if (needed[s] && !around[s].empty()) out.push_back(std::move(around[s]));
  }
  return out;
}

}  // namespace dcad::graph
