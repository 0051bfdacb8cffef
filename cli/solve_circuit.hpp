// `dcad solve` on an LC netlist by the graph route (dcad::fast::circuit_tower, CEF §6): the tower,
// KVL of purely capacitive loops and KCL by branch names, in time and space linear in the circuit for
// physical values.  The dense parts (equations of motion (5.12), the §7 constraints on T*TQ) are added
// from the generic fast CAD when the circuit has at most kDenseBranches branches.
#pragma once

#include "dcad/fast/circuit.hpp"
#include "netlist.hpp"
#include "solve.hpp"

namespace dcad::cli {

constexpr std::size_t kDenseBranches = 120;

/// The netlist for the graph route, values rounded to double (opt records whether exactly).
fast::CircuitGraph circuit_graph(const io::Netlist& n, fast::Options& opt);

/// `c`: the netlist's case (io::netlist_case) with the dense system if n ≤ kDenseBranches, else
/// variables only.
SolveReport solve_circuit_fast(const io::Netlist& n, const io::CaseFile& c);
/// The graph route; if any decision is uncertain, the whole result recomputed exactly.
SolveReport solve_circuit_certified(const io::Netlist& n, const io::CaseFile& c);

}  // namespace dcad::cli
