// YM §3's implicit Hamiltonian systems in double; the twin of dcad/reference/implicit_hamiltonian.hpp.
// A different route: the reference intersects with the equations of the Dirac structure D_Δ; fast writes
// (3.41) as one linear system in X = (q̇, ṗ) — q̇ = ∂H/∂p, K q̇ = 0, Nᵀ ṗ = −Nᵀ ∂H/∂q for an orthonormal
// basis N of Δ = ker K — and decides it with its rank decisions (solvable iff K ∂H/∂p = 0).
#pragma once

#include "dcad/fast/cad.hpp"
#include "dcad/hamiltonian_data.hpp"

namespace dcad::fast {

/// H(q, p) = ½ pᵀ A p + qᵀ B p + ½ qᵀ C q + a·q + b·p with Δ = ker K (dcad/hamiltonian_data.hpp).
using HamiltonianInput = HamiltonianData<MatrixXd, VectorXd>;

/// dH(z) = (∂H/∂q, ∂H/∂p) at z = (q, p).
VectorXd hamiltonian_differential(const HamiltonianInput& in, const VectorXd& z);

/// Hamilton's equations q̇ = ∂H/∂p, ṗ = −∂H/∂q, read off  [YM Prop 3.11, (3.40)].
VectorXd hamilton_field(const HamiltonianInput& in, const VectorXd& z);

/// {X : (X, dH(z)) ∈ D_Δ(z)} = {X : (3.41)}, empty when ∂H/∂p(z) ∉ Δ  [YM Def 3.12, Prop 3.14].
AffineSubspace implicit_hamiltonian_fields(const HamiltonianInput& in, const VectorXd& z, const Options& opt = {});

/// The constraint force μ_a ω^a = ṗ + ∂H/∂q of a field X at z  [YM §3, "Coordinate Representation"].
VectorXd hamiltonian_constraint_force(const HamiltonianInput& in, const VectorXd& z, const VectorXd& x);

/// (D_Δ, H) as a Dirac dynamical system (CEF (1.1)) for the CAD, which fixes the constraint forces on M_c.
LinearSystem implicit_hamiltonian_system(const HamiltonianInput& in, const Options& opt = {});

}  // namespace dcad::fast
