// Typed inputs built in code (issue 45 §5): the fuzzer's bytes pick a valid problem of some form and one to
// three malformations of it (typed_mutations.hpp); every public entry point must refuse the result as bad
// input.  An answer to a malformed problem aborts (a finding), as does any crash or sanitizer report.
#include "typed_mutations.hpp"

#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<dcad::io::Problem> bases = dcad::fuzz::typed_bases();
  if (size < 3) return 0;
  dcad::io::Problem p = bases[data[0] % bases.size()];
  bool broken = false;
  unsigned touched = 0;  // the fields malformed so far (bits of malformed_field)
  for (std::size_t i = 1; i + 1 < size && i < 7; i += 2) {
    const unsigned field = 1u << dcad::fuzz::malformed_field(p, data[i]);
    if (touched & field) continue;
    if (dcad::fuzz::malform(p, data[i], data[i + 1])) broken = true, touched |= field;
  }
  if (broken) {
    std::string what;
    if (!dcad::fuzz::all_refuse(p, what)) {
      std::fprintf(stderr, "%s\n", what.c_str());
      std::abort();
    }
  }
  std::ostringstream log;
  try {
    (void)dcad::api::check_waveform(dcad::fuzz::malformed_traces(data[1], data[2]), bases[3], {}, log);
    std::abort();  // malformed traces answered
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
