// Case files (.json): exact JSON reader, every form, strict keys; in the expression form also the
// formula reader and, for small systems, the pointwise CAD itself (exact, then double); in the dae
// and implicit forms, for small systems, CEF (1.6) on both twins.
#include "dcad/api.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string file = dcad::fuzz::as_file(data, size, ".json");
  try {
    const dcad::io::Problem p = dcad::io::read_problem(file);
    if (p.form() == dcad::io::Form::expression && p.expression().system.n <= 2 && size < 600) {
      (void)dcad::api::solve(p, dcad::api::Backend::certified);
      (void)dcad::api::solve(p, dcad::api::Backend::fast);
    }
    if (p.form() == dcad::io::Form::implicit && p.expression().system.n <= 3 && size < 600) {
      (void)dcad::api::solve(p, dcad::api::Backend::certified);
      (void)dcad::api::solve(p, dcad::api::Backend::fast);
    }
    if (p.form() == dcad::io::Form::dae && p.dae().variables.size() <= 4 && size < 600) {
      (void)dcad::api::solve(p, dcad::api::Backend::certified);
      (void)dcad::api::solve(p, dcad::api::Backend::fast);
    }
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
