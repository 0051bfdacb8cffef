// Netlists: the SPICE reader (includes, .lib, .param expressions, .subckt expansion, .ic) and the
// circuit it describes (the graph route's input, exact values rounded to double with range checks).
#include "fuzz_input.hpp"
#include "netlist.hpp"
#include "solve_circuit.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const dcad::io::Netlist n = dcad::io::read_netlist(dcad::fuzz::as_file(data, size, ".cir"));
    dcad::io::Units units;
    const dcad::io::Netlist twin = dcad::io::dimensionless(n, units);
    dcad::fast::Options opt;
    (void)dcad::fast::circuit_tower(dcad::cli::circuit_graph(twin, opt), opt);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
