// Netlists: the SPICE reader (includes, .lib, .param expressions, .subckt expansion, .ic, sources and
// their waveforms, couplings) and the circuit it describes (the graph route's input, exact values
// rounded to double with range checks); small decks with R, sources or K also go through the forced
// route, exact and fast (source conditions against the waveforms, loops and cutsets by name).
#include "fuzz_input.hpp"
#include "dcad/io/netlist.hpp"
#include "solve_circuit.hpp"
#include "solve_forced.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const dcad::io::Netlist n = dcad::io::read_netlist(dcad::fuzz::as_file(data, size, ".cir"));
    dcad::io::Units units;
    const dcad::io::Netlist twin = dcad::io::dimensionless(n, units);
    dcad::fast::Options opt;
    (void)dcad::fast::circuit_tower(dcad::cli::circuit_graph(twin, opt), opt);
    if (n.forced && n.rlc.branches.size() <= 8) {
      (void)dcad::cli::solve_forced(n, "reference");
      (void)dcad::cli::solve_forced(n, "fast");
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
