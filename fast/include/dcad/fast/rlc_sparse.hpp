// The equations of motion of an RLC circuit with sources as a sparse system, at any size (issue 27):
// the state equations of circuit theory written on node potentials, never on the 3n-dimensional
// Pontryagin bundle.  They hold where the graph route does (dcad/rlc_graph.hpp: every R and C positive,
// the inductance matrix Φ positive definite); the tower's source conditions are the caller's to decide.
//
// Construction (each step a contraction of the circuit's graph; signs: branch voltage u_b = e_from − e_to,
// current from → to, so i_C = C u̇_C, u_L = (Φ i̇)_b, u_R = R i_R, u_V = V(t), i_I = I(t)):
//  1. voltage sources and wires join nodes into supernodes: e_node = E_super + s_node(t), s a signed sum
//     of source values along the sources' spanning forest; a source that closes a loop carries no
//     current (the particular solution; the loop's condition is the tower's M_2 condition);
//  2. capacitors join supernodes into C-components; a component holding ground has all its potentials
//     differential, a floating one has a root whose level is algebraic (y = w, relative potentials);
//  3. resistors join C-components into R-components; those not holding ground are islands, bounded by
//     inductors and current sources only (the LI cutsets of the tower's M_1): the island's level is the
//     multiplier e of the constraint "KCL over the island", the other roots' levels ρ are solved for.
// With E = T (w, ρ, e) and the supernode KCL multiplied by Tᵀ:
//    C_ww ẇ = −(G_ww w + G_wρ ρ + L_w i_L + h_w(σ, σ̇))      (charges: the rows of w)
//    0       =  G_ρw w + G_ρρ ρ + L_ρ i_L + h_ρ(σ)             (C_ρρ = 0: solved, G_ρρ > 0)
//    0       =  L_e i_L + I_e σ                              (islands: differentiated for e)
//    Φ i̇_L  =  A_Lᵀ T (w, ρ, e) + o_L σ                        (fluxes)
// so the state is x = (w, i_L) with C_ww, G_ρρ, Φ and L_e Φ⁻¹ L_eᵀ positive definite (Cholesky).
// The charges through every branch that is not a capacitor are integrals of its current; the
// currents of voltage sources come from KCL along their forest.  Only the sources' values and first
// derivatives enter: the motion has no impulses at a corner of a PULSE or PWL source.
#pragma once

#include "dcad/rlc_state.hpp"

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dcad::fast::sparse_rlc {

using SpMat = Eigen::SparseMatrix<double>;
using Vec = Eigen::VectorXd;

struct Element {
  rlc::Kind kind = rlc::Kind::wire;
  long from = -1, to = -1;  ///< node indices, −1 = ground
  double value = 0;         ///< L, C or R
  long source = -1;         ///< index of σ for V and I
};
struct Coupling {
  std::size_t a = 0, b = 0;  ///< inductor branches
  double m = 0;              ///< mutual inductance
};
struct Network {
  std::size_t nodes = 0, sources = 0;
  std::vector<Element> branches;
  std::vector<Coupling> mutuals;
  std::vector<std::string> node_names;  ///< for messages (optional)
  std::vector<std::string> branch_names;
};

/// Every branch's charge q, current i and flux linkage p (0 except on inductors), as in the dense
/// route's variables (q_b, v_b, p_b).
struct BranchValues {
  Vec q, i, p;
  Vec u;  ///< branch voltages e_from − e_to (for the energy balance: Tellegen's Σ u_b i_b = 0)
};

/// Why the model cannot be built (a zero or negative value, a singular coupling block): std::invalid_argument.
class Model {
 public:
  explicit Model(const Network& c);

  std::size_t state_size() const { return nw_ + nl_; }    ///< x = (w, i_L)
  std::size_t charge_size() const { return qx_.size(); }  ///< integrated charges (non-capacitor branches)
  std::size_t branches() const { return c_.branches.size(); }
  std::size_t islands() const { return ne_; }
  std::size_t inductors() const { return nl_; }

  /// ẋ = f(x, σ, σ̇) and, if `current` is given, the currents of the non-capacitor branches
  /// (charge_size(), in the order of charge_branches()).  Linear in (x, σ, σ̇).
  void rate(const double* x, const double* sigma, const double* dsigma, double* xdot, double* current = nullptr,
            Vec* potentials = nullptr) const;
  const std::vector<std::size_t>& charge_branches() const { return qx_; }

  /// All branch quantities at a state, with the integrated charges `qx` (charge_size()).
  BranchValues values(const double* x, const double* qx, const double* sigma, const double* dsigma) const;

  /// Every node's potential (ground 0) at a state: the supernode's level plus its sources' offset.
  Vec node_potentials(const double* x, const double* sigma, const double* dsigma) const;

  /// A scale per state entry for the Krylov norm: √(C_ww)ᵢᵢ for potentials, √Φᵢᵢ for currents (√energy).
  Vec energy_scale() const;

  /// The state from charges q_C and flux linkages p_L just before t = 0 (per branch; other entries
  /// ignored), moved onto M_c(0+) as circuit theory says: the charge of every C-component and supernode
  /// is kept (impulsive currents through capacitors and sources obey KCL), the flux linkages only move
  /// along island levels (impulsive voltages obey KVL): i⁺ = i⁻ − Φ⁻¹L_eᵀ (L_e Φ⁻¹ L_eᵀ)⁻¹ (L_e i⁻ + I_e σ).
  Vec from_charges(const Vec& q_before, const Vec& i_before, const double* sigma) const;

  /// The charges (charge_size()) the impulsive currents of that jump carry through voltage sources and
  /// wires: KCL with the capacitors' q_after − q_before (per branch; other entries ignored).
  Vec impulse_charges(const Vec& q_before, const Vec& q_after) const;

  /// The DC operating point at σ (capacitors open, inductors shorted) as the state x.  Throws
  /// std::domain_error naming a node or inductor where it is not unique (ngspice: singular matrix).
  /// `held`: `.ic` node voltages (node index, volts), held as ngspice holds them at DC — through an
  /// ideal source at the node, whose current the node's KCL then absorbs (std::domain_error when two
  /// holds contradict each other or ground).
  Vec operating_point(const double* sigma, const std::vector<std::pair<long, double>>& held = {}) const;

  /// The equations of motion as sparse matrices (the library's route to them at any size).
  struct Matrices {
    SpMat T;  ///< supernode potentials E = T (w, ρ, e)
    SpMat Cww, Gww, Gwr, Grr, Lw, Lr, Le, phi;
    SpMat Hw, Hwd, Hr, Ie, Ol;  ///< source maps: h_w = Hw σ + Hwd σ̇, h_ρ = Hr σ, I_e, o_L
  };
  const Matrices& matrices() const { return m_; }

 private:
  Network c_;
  std::size_t nsup_ = 0, nw_ = 0, nr_ = 0, ne_ = 0, nl_ = 0;
  std::vector<long> sup_;         ///< node → supernode (−1 ground)
  std::vector<long> wv_, croot_;  ///< supernode → its w variable (−1: a root), its C-component's root (−1: ground's)
  std::vector<std::size_t> lidx_;  ///< inductor k → branch
  std::vector<long> lof_;          ///< branch → inductor index or −1
  std::vector<std::size_t> qx_;    ///< non-capacitor branches
  // V forest for the currents of voltage sources (leaves first): (node, branch, parent node)
  struct TreeEdge {
    long node, parent;
    std::size_t branch;
  };
  std::vector<TreeEdge> vtree_;
  Matrices m_;
  SpMat phi_inv_, ob_,
      on_;  ///< …; o per node (nodes × sources)  ///< Φ⁻¹ (block inverse); o_b for every branch (branches × sources)
  SpMat AC_, AR_, AL_, AI_;  ///< supernode incidences (rows supernodes) per kind
  SpMat Crow_;  ///< i_C = C (A_Cᵀ T_w ẇ + o_C σ̇): the map ẇ → capacitor currents (C-branches × w)
  std::vector<std::size_t> cidx_, ridx_, iidx_;
  Eigen::SimplicialLLT<SpMat> cww_, grr_, schur_;
  Vec rdiag_g_, cdiag_;
  std::string name(long node) const;
  std::size_t vertex(long node) const;  ///< a node's DC vertex: its supernode + 1 (0: ground's)
  /// `.ic` holds at DC: a held node fixes its DC node's (forest root's) level P, e_node = P + t + o_node σ (`on`);
  /// std::domain_error where two holds, or a hold and ground, contradict each other.
  struct DcHolds {
    std::vector<double> fixed;   ///< per root: its level where held
    std::vector<bool> is_fixed;  ///< per root: held
    std::vector<long> hold_at;   ///< per root: the vertex whose hold source feeds it (−1: none)
  };
  DcHolds dc_holds(const std::vector<std::pair<long, double>>& held, const rlc::Forest& fl,
                   const std::vector<double>& t, const Vec& on) const;
  /// The resistors on the DC nodes (`dc`: a root's unknown index, −1 when its level is known): a Laplacian grounded
  /// at ground's DC node into `tg` and `rhs`, known levels and offsets moved to the right; their DC-node ends.
  void dc_resistors(const rlc::Forest& fl, const std::vector<long>& dc, const std::vector<double>& t,
                    const DcHolds& holds, const Vec& obs, std::vector<Eigen::Triplet<double>>& tg, Vec& rhs,
                    std::vector<std::pair<std::size_t, std::size_t>>& rends, std::vector<bool>& rall) const;
  /// The inductor currents at DC (operating_point): KCL along the inductor forest `fl`, leaves first, with the
  /// outflow of resistors (at the supernode potentials E) and current sources; a hold source (`.ic`) delivers
  /// what its DC node's KCL lacks, at its own vertex hold_at[root].
  Vec dc_inductor_currents(const Vec& E, const double* sigma, const Vec& obs, const rlc::Forest& fl,
                           const std::vector<std::pair<std::size_t, std::size_t>>& ends,
                           const std::vector<bool>& is_fixed, const std::vector<long>& hold_at) const;
  /// ib (per branch) of the voltage sources and wires from KCL with every other branch's value in ib.
  void source_currents(std::vector<double>& ib) const;
};

}  // namespace dcad::fast::sparse_rlc
