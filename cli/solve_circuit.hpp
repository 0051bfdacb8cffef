// `dcad solve` on an LC netlist by the graph route (dcad::fast::circuit_tower, CEF §6): the tower,
// KVL of purely capacitive loops and KCL by branch names, in time and space linear in the circuit for
// physical values.  The dense parts (equations of motion (5.12), the §7 constraints on T*TQ) are added
// from the generic fast CAD when the circuit has at most kDenseBranches branches.
#pragma once

#include "dcad/fast/circuit.hpp"
#include "dcad/io/netlist.hpp"
#include "solve.hpp"

namespace dcad::cli {

constexpr std::size_t kDenseBranches = 120;
/// The §7 constraints adapted to the primary ones (CEF Thm 7.4, on T*TQ: 4n variables, the generic
/// pipeline) are reported up to this many branches.
constexpr std::size_t kAdaptedBranches = 24;

/// The netlist for the graph route, values rounded to double (opt records whether exactly).
fast::CircuitGraph circuit_graph(const io::Netlist& n, fast::Options& opt);

/// `c`: the netlist's case (io::netlist_case) with the dense system if n ≤ kDenseBranches, else
/// variables only.
SolveReport solve_circuit_fast(const io::Netlist& n, const io::CaseFile& c, const Parts& parts = {});
/// The structured route (solve_circuit_exact.hpp) exactly.
SolveReport solve_circuit_reference(const io::Netlist& n, const io::CaseFile& c, const Parts& parts = {});
/// The structured route on SmallRational, then WideRational; throws reference::Overflow (solve_small.cpp).
SolveReport solve_circuit_small(const io::Netlist& n, const io::CaseFile& c, const Parts& parts = {});
/// The structured route on mpq_rational alone.
SolveReport solve_circuit_rational(const io::Netlist& n, const io::CaseFile& c, const Parts& parts = {});
/// The same in ball arithmetic; throws certified::Uncertain at the first undecidable zero test.
SolveReport solve_circuit_ball(const io::Netlist& n, const io::CaseFile& c, double& max_radius, const Parts& parts = {});
/// solve_circuit_ball, recomputed exactly if a decision is uncertain there; cross-checked against
/// the graph route's combinatorial tower (physical values).
SolveReport solve_circuit_certified(const io::Netlist& n, const io::CaseFile& c, const Parts& parts = {});

}  // namespace dcad::cli
