// `dcad check WAVEFORM DECK`'s readers (dcad/io/traces.hpp): ngspice raw (binary and ASCII), wrdata,
// gnucap tables and CSV, recognised from their content.  The reader must return or throw
// std::invalid_argument (exit 1); a returned Traces must be consistent (a column per name, a value per time).
#include "dcad/io/input_error.hpp"
#include "dcad/io/traces.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const dcad::io::Traces t = dcad::io::parse_traces(text, "fuzz");
    if (t.values.size() != t.names.size()) std::abort();
    for (const auto& v : t.values)
      if (v.size() != t.time.size()) std::abort();
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
