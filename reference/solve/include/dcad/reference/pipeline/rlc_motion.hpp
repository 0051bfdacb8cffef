// The exact motion of an RLC circuit with sources, reduced from its state equations (rlc_state.hpp)
// rather than from the dense forced tower: the certified tier's model beyond the dense route's size
// (issue 28: enclosures up to 200 branches; forced_tower alone takes > 15 min at 199 branches).
//
// State y = (w, i_L, q_x): the potentials relative to their C-component's root, the inductor currents,
// and the charges of every branch that is not a capacitor (integrals of its current).  With
// u = (1, σ, σ̇) and u_ext = (1, σ, σ̇, σ̈) (the certified engine's `orders` = 2), each step an exact
// solve of the equations written in rlc_state.hpp's header:
//   ρ  = −G_ρρ⁻¹ (G_ρw w + L_ρ i + H_ρ σ)                               (KCL over floating C-components)
//   ẇ  = −C_ww⁻¹ (G_ww w + G_wρ ρ + L_w i + H_w σ + H_wd σ̇)             (charge balance)
//   e  = −S⁻¹ (L_e Φ⁻¹ F₀ + I_e σ̇),  S = L_e Φ⁻¹ L_eᵀ,  F₀ = L_wᵀ w + L_ρᵀ ρ + O_L σ
//        (KCL over an island, L_e i + I_e σ = 0, differentiated)
//   i̇  = Φ⁻¹ (F₀ + L_eᵀ e)                                                (the fluxes: Φ i̇ = u_L)
// and per branch b (u_b = d_bᵀ (w, ρ, e) + o_bᵀ σ, branch_potential): a capacitor's q = C u_b and
// current C u̇_b; a resistor's current u_b / R; an inductor's current i_k and flux linkage (Φ i)_b; a
// current source's σ_j; voltage sources and wires by KCL along their forest (leaves first).  Every
// row is exact; the model is x = X0 u + Bᵀ y, ẏ = A_y y + A_u u_ext, ẋ = V_y y + V_u u_ext — the
// certified engine's data (certified/enclosure.hpp), on the dense route's variables (q_b, v_b, p_b).
// A corner of a source moves σ̇ only: y has no impulse (σ̈'s columns of A_u are zero).
#pragma once

#include "dcad/io/netlist.hpp"
#include "dcad/reference/matrix.hpp"
#include "dcad/reference/rational.hpp"

#include <cstddef>
#include <stdexcept>
#include <vector>

namespace dcad::reference::pipeline {

struct StateMotion {
  std::size_t nw = 0, nl = 0, nq = 0;  ///< y = (w, i_L, q_x)
  std::vector<std::size_t> charges;    ///< the branches whose charge is q_x (every non-capacitor), in order
  Matrix<Rational> x0, bt;             ///< x = X0 u + Bᵀ y: (3·branches) × (1 + 2m), (3·branches) × dim y
  Matrix<Rational> ay, au, vy, vu;     ///< ẏ = A_y y + A_u u_ext, ẋ = V_y y + V_u u_ext (u_ext: 1 + 3m)
};

/// The model of the header comment.  Throws std::invalid_argument (the reason, for `certified: false`)
/// where the graph route does not hold, a mutual inductance was rounded, a source condition of the
/// tower is not proved to hold, or the solutions are not unique (a loop of voltage sources and wires).
StateMotion state_motion(const io::Netlist& deck);

/// y(0+) exactly, from σ(0) (`sigma0`, exact):
///  - op: the DC operating point (capacitors open, inductors shorted), which must be unique;
///  - uic: IC= values (charges C·IC, inductor currents), moved onto M_c(0+) as the sparse double route
///    moves them (fast/rlc_sparse.hpp, Model::from_charges): every C-component keeps its charge
///    C_ww w = Σ_C d_w (q_C − C o_Cᵀ σ), the inductor currents move only along island levels
///    (i⁺ = i⁻ − Φ⁻¹L_eᵀ S⁻¹ (L_e i⁻ + I_e σ)), and q_x holds the charges the impulsive currents carried
///    through voltage sources and wires (KCL with the capacitors' jumps).
/// Throws std::invalid_argument naming what is missing (a non-unique operating point, `.ic` node holds).
std::vector<Rational> state_start(const io::Netlist& deck, const StateMotion& m, bool op,
                                  const std::vector<Rational>& sigma0);

}  // namespace dcad::reference::pipeline
