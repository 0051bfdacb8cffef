// `dcad check`'s result reader: another implementation's JSON result for a fixed small case (the
// harmonic oscillator of cases/), compared against the reference.
#include "check.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const dcad::io::CaseFile c = dcad::io::read_case(DCAD_CASES_DIR "/harmonic-oscillator.json");
  try {
    (void)dcad::cli::check_result(dcad::fuzz::as_file(data, size, ".json"), c, nullptr);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
