// Case files (.json): exact JSON reader, every form, strict keys.
#include "case_file.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)dcad::io::read_case(dcad::fuzz::as_file(data, size, ".json"));
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
