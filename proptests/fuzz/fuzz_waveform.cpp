// `dcad check WAVEFORM DECK`'s readers (dcad/io/traces.hpp): ngspice raw (binary and ASCII), wrdata,
// gnucap tables and CSV, recognised from their content.  The reader must return or throw
// std::invalid_argument (exit 1); a returned Traces must be consistent (a column per name, a value per time).
// The same bytes as a file through io::open_traces (an ngspice binary raw file streams from disk): it
// refuses what parse_traces refuses and streams exactly the points parse_traces reads.
#include "dcad/io/input_error.hpp"
#include "dcad/io/traces.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <fstream>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  bool parsed = false;
  dcad::io::Traces t;
  try {
    t = dcad::io::parse_traces(text, "fuzz");
    if (t.values.size() != t.names.size()) std::abort();
    for (const auto& v : t.values)
      if (v.size() != t.time.size()) std::abort();
    parsed = true;
  } catch (const std::invalid_argument&) {
  }
  static const std::string file = "/tmp/dcad-fuzz-waveform-" + std::to_string(getpid());
  std::ofstream(file, std::ios::binary).write(text.data(), static_cast<std::streamsize>(text.size()));
  try {
    const std::unique_ptr<dcad::io::TraceStream> s = dcad::io::open_traces(file);
    std::vector<double> time, chunk;
    std::vector<std::vector<double>> values, v;
    while (s->next(3, chunk, v)) {  // small chunks: every boundary
      if (v.size() != s->names().size()) std::abort();
      values.resize(v.size());
      for (std::size_t k = 0; k < v.size(); ++k) {
        if (v[k].size() != chunk.size()) std::abort();
        values[k].insert(values[k].end(), v[k].begin(), v[k].end());
      }
      time.insert(time.end(), chunk.begin(), chunk.end());
    }
    if (!parsed || time != t.time || s->names() != t.names || s->points() != t.time.size()) std::abort();
    for (std::size_t k = 0; k < values.size(); ++k)
      for (std::size_t i = 0; i < time.size(); ++i)
        if (!(values[k][i] == t.values[k][i] || (values[k][i] != values[k][i] && t.values[k][i] != t.values[k][i])))
          std::abort();  // NaN is NaN
  } catch (const std::invalid_argument&) {
    if (parsed) std::abort();
  }
  return 0;
}
