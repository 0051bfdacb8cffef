// The exact flow of an RLC netlist on the sparse route (simulate_sparse.cpp), evaluated at any times:
// the state equations (dcad/fast/rlc_sparse.hpp) with the sources' exosystem, advanced by the Krylov
// exponential action from SPICE's initial state (CONTRACT "Circuit initial state").  `simulate` reads
// it on its uniform grid, `check` at a simulator's own time points (no interpolation).
#pragma once

#include "dcad/api.hpp"
#include "dcad/fast/expv.hpp"
#include "dcad/fast/rlc_sparse.hpp"
#include "dcad/io/netlist.hpp"

#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace dcad::api {

namespace sr = dcad::fast::sparse_rlc;
using Vec = Eigen::VectorXd;

sr::Network circuit_of(const io::Netlist& d);
/// The capacitors and inductors whose value can jump at t = 0 at all: a capacitor on a loop of capacitors,
/// voltage sources and wires (KVL may move its charge), an inductor on a cutset of inductors and current
/// sources (KCL may move its current).  Every other one keeps its value exactly, whatever double says.
std::vector<bool> jump_places(const sr::Network& c);

class SparseFlow {
 public:
  /// From the deck's initial state (`initial`; its rule and every jump at t = 0 go to `log`).  `step` is
  /// the typical distance between evaluations (the error control's unit), `horizon` the last time asked.
  /// Bad input (outside the graph route, no unique operating point, an inconsistent circuit): InputError.
  SparseFlow(const io::Netlist& deck, const std::string& file, Initial initial, double step, double horizon,
             std::ostream& log);
  ~SparseFlow();

  /// Advances to `t` ≥ time(), cut at the sources' breakpoints.  InputError when the route cannot (stiff,
  /// overflow).
  void advance_to(double t);
  double time() const { return t_; }

  /// Every branch's q, i, p, u at time(); `left`: with the sources' derivatives just before time() (the
  /// other one-sided value at a corner of a PULSE or PWL source).
  sr::BranchValues values(bool left = false) const;
  /// Every node's potential at time() (ground 0).
  Vec node_potentials(bool left = false) const;
  /// Whether `t` is a corner of some source (a one-sided value may differ there).
  bool corner(double t) const;
  /// How many capacitor charges and inductor currents jumped at t = 0.
  long jumps() const { return jumps_; }
  /// Their variables (q_C, v_L), decided in double among the branches jump_places allows.
  const std::vector<std::string>& jumped() const { return jumped_; }

  const sr::Network& network() const { return circ_; }
  const sr::Model& model() const { return *model_; }
  /// The Krylov estimate summed so far, relative to the largest state norm (energy units).
  double error_estimate() const;
  long products() const;
  long substeps() const;

 private:
  const io::Netlist& deck_;
  std::string file_;
  double step_ = 1;
  sr::Network circ_;
  std::unique_ptr<sr::Model> model_;
  std::unique_ptr<fast::KrylovExp> krylov_;
  std::size_t nx_ = 0;
  Vec d_, dinv_, y_, q_;
  std::vector<double> breaks_;
  std::size_t next_break_ = 0;
  double t_ = 0, max_norm_ = 0;
  long jumps_ = 0;
  std::vector<std::string> jumped_;
  Vec state() const;
  void sources(double t, bool left, std::vector<double>& sig, std::vector<double>& dsig) const;
};

}  // namespace dcad::api
