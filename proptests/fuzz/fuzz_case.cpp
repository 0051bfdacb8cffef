// Case files (.json): exact JSON reader, every form, strict keys; in the expression form also the
// formula reader and, for small systems, the pointwise CAD itself (exact, then double).
#include "dcad/io/case_file.hpp"
#include "fuzz_input.hpp"
#include "dcad/io/lagrangian_case.hpp"
#include "solve_lagrangian.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = dcad::fuzz::as_file(data, size, ".json");
  try {
    if (!dcad::io::is_expression_file(file)) {
      (void)dcad::io::read_case(file);
      return 0;
    }
    const dcad::io::LagrangianCase c = dcad::io::read_lagrangian_case(file);
    if (c.system.n <= 2 && size < 600) {
      (void)dcad::cli::solve_lagrangian(c, "certified");
      (void)dcad::cli::solve_lagrangian(c, "fast");
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
