// libFuzzer targets for dcad's readers: the fuzzer's bytes go to a per-process file (the readers
// take file names, as the CLI does) and the reader must either return or throw
// std::invalid_argument (the CLI's exit 1, bad input).  Any other exception, a signal, a sanitizer
// report, a hang or a leak is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

namespace dcad::fuzz {

/// The input as a file with the given extension (a netlist's .include resolves beside it).
inline std::string as_file(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const std::string path = "/tmp/dcad_fuzz_" + std::to_string(getpid()) + ext;
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace dcad::fuzz
