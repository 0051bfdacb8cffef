// `dcad check`'s result reader: another implementation's JSON result for a fixed small case (the
// harmonic oscillator of cases/), compared against the reference.
#include "dcad/api.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dcad::io::Problem p = dcad::io::read_problem(DCAD_CASES_DIR "/harmonic-oscillator.json");
  try {
    (void)dcad::api::check(dcad::fuzz::as_file(data, size, ".json"), p);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
