// RLC circuits with sources and mutual inductance as forced Lagrangian systems on the Pontryagin
// bundle (CEF §6 with the forces and affine constraints of YM §4):
//   L(q, v) = ½ vᵀ Φ v − ½ qᵀ Ψ q,  Φ = diag(L_i) + mutual terms M_ij,  Ψ = diag(1/C_i);
//   a resistor is the force −R v_b on q_b; a voltage source (V(n+) − V(n−) = V(t), SPICE) is the
//   force −V(t) on q_b (the EMF +V(t) pushes current from n− to n+, against the branch direction);
//   a current source is the affine constraint v_b = I(t).
// KCL and the current sources together are the affine constraint K_I q̇ = R_I σ(t) with
// K_I = [K; E_I] (E_I selects the current-source branches), so Δ = ker K_I and the reaction forces
// lie in Δ° = row K_I (a current source has whatever voltage KVL gives it).  The affine set is
// Δ + Z σ(t) with Z from the exact least-squares solution of K_I Z = R_I; what K_I Z misses is a
// source condition (current sources forming a cutset must sum to zero).
#pragma once

#include "dcad/reference/circuit.hpp"
#include "dcad/reference/forced.hpp"
#include "dcad/rlc_graph.hpp"

#include <optional>

namespace dcad::reference {

/// An element's kind: the one enum the core's graph (dcad/rlc_graph.hpp) and the reference share.
using RlcKind = rlc::Kind;

template <class T>
struct RlcBranch {
  std::string name;
  RlcKind kind = RlcKind::wire;
  long from = -1, to = -1;  ///< node indices, −1 = ground; current flows from → to
  T value = T(0);           ///< L, C or R (sources: unused)
  Index source = 0;         ///< index into σ for voltage and current sources
};

template <class T>
struct Mutual {
  Index a = 0, b = 0;    ///< inductor branches
  T m = T(0);            ///< mutual inductance (Φ_ab = Φ_ba = m)
  std::optional<T> k;    ///< the coupling coefficient of the K card it came from (exact), if any
  bool rounded = false;  ///< m = k√(L_a L_b) is irrational: m is it truncated (80 digits)
};

template <class T>
struct RlcCircuit {
  std::size_t nodes = 0;
  Index sources = 0;
  std::vector<RlcBranch<T>> branches;
  std::vector<Mutual<T>> mutuals;
};

template <class T>
Matrix<T> rlc_kcl(const RlcCircuit<T>& c) {
  return incidence_matrix<T>(c.nodes, c.branches);
}

/// Φ: inductances on the diagonal, mutual inductances off it.
template <class T>
Matrix<T> rlc_inductance(const RlcCircuit<T>& c) {
  Matrix<T> phi(c.branches.size(), c.branches.size());
  for (Index b = 0; b < c.branches.size(); ++b)
    if (c.branches[b].kind == RlcKind::inductor) phi(b, b) = c.branches[b].value;
  for (const Mutual<T>& mu : c.mutuals) {
    phi(mu.a, mu.b) += mu.m;
    phi(mu.b, mu.a) += mu.m;
  }
  return phi;
}

/// [K; E_I] and [0; selection of σ]: K_I q̇ = R_I σ.
template <class T>
void affine_kcl(const RlcCircuit<T>& c, Matrix<T>& ki, Matrix<T>& ri) {
  const Matrix<T> k = rlc_kcl(c);
  ki = k;
  ri = Matrix<T>(k.rows(), c.sources);
  for (Index b = 0; b < c.branches.size(); ++b) {
    if (c.branches[b].kind != RlcKind::current) continue;
    Matrix<T> e(1, c.branches.size()), s(1, c.sources);
    e(0, b) = T(1);
    s(0, c.branches[b].source) = T(1);
    ki = vstack(ki, e);
    ri = vstack(ri, s);
  }
}

template <class T>
ForcedSystem<T> rlc_system(const RlcCircuit<T>& c) {
  const Index n = c.branches.size(), m = c.sources;
  Matrix<T> ki, ri;
  affine_kcl(c, ki, ri);
  PontryaginInput<T> in;
  in.n = n;
  in.k = ki;
  in.vv = rlc_inductance(c);
  in.qq = Matrix<T>(n, n);
  in.qv = Matrix<T>(n, n);
  in.q.assign(n, T(0));
  in.v.assign(n, T(0));
  for (Index b = 0; b < n; ++b)
    if (c.branches[b].kind == RlcKind::capacitor) in.qq(b, b) = -T(1) / c.branches[b].value;
  ForcedSystem<T> f{pontryagin_system(in), Matrix<T>(3 * n, 3 * n), m,
                    Matrix<T>(3 * n, m),   Matrix<T>(3 * n, m),     Matrix<T>(0, 1 + m)};
  for (Index b = 0; b < n; ++b) {
    const RlcBranch<T>& br = c.branches[b];
    if (br.kind == RlcKind::resistor) f.force(b, n + b) = -br.value;        // F = −R v on q_b
    if (br.kind == RlcKind::voltage) f.source_force(b, br.source) = T(-1);  // F = −V(t) on q_b
  }
  // Z: least squares K_Iᵀ K_I Z = K_Iᵀ R_I (exact); the residual R_I − K_I Z gives the conditions.
  Matrix<T> z;
  solve_particular(ki.transpose() * ki, ki.transpose() * ri, z);
  const Matrix<T> residual = ri - ki * z;
  const Matrix<T> rows = rref(residual).r;
  for (Index i = 0; i < rows.rows(); ++i)
    if (!rows.block(i, i + 1, 0, m).is_zero())
      f.given_conditions = vstack(f.given_conditions, hstack(Matrix<T>(1, 1), rows.block(i, i + 1, 0, m)));
  for (Index b = 0; b < n; ++b)
    for (Index j = 0; j < m; ++j) {
      f.shift(b, j) = z(b, j);                  // ẋ − Zσ: q̇ − z σ ∈ Δ
      f.source_force(2 * n + b, j) += z(b, j);  // β − z σ = q̇ − z σ keeps β = q̇ = v
    }
  return f;
}

}  // namespace dcad::reference
