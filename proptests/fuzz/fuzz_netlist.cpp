// Netlists: the SPICE reader (includes, .lib, .param expressions, .subckt expansion, .ic, sources and
// their waveforms, couplings) and the circuit it describes (the graph route on the dimensionless twin,
// exact values rounded to double with range checks); small decks with R, sources or K also go through
// the forced route, exact and fast (source conditions against the waveforms, loops and cutsets by name).
#include "dcad/api.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const dcad::io::Problem p = dcad::io::read_problem(dcad::fuzz::as_file(data, size, ".cir"));
    if (!p.netlist().forced) (void)dcad::fast::solve_lc(p.netlist(), p.linear(), dcad::Parts::none());
    if (p.netlist().forced && p.netlist().rlc.branches.size() <= 8) {
      (void)dcad::api::solve(p, dcad::api::Backend::reference);
      (void)dcad::api::solve(p, dcad::api::Backend::fast);
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
