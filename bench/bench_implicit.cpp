// Benchmark (not a test): the implicit form's two exact routes side by side in one process — CEF (1.6)
// eliminated on the formulas (reference/nonlinear/ide_formulas.hpp) and on jets (pointwise.hpp) — and
// fast's derivative array, on the case files given (bench/implicit_chain.py writes pendulum chains):
//   build/bench_implicit CASE.json…
// Prints a Markdown row per case and route: seconds (best of 3, or one run above 2 s), dims, certified.
#include "dcad/fast/solve.hpp"
#include "dcad/io/problem.hpp"
#include "dcad/reference/pipeline/implicit.hpp"

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

namespace {

std::string dims_text(const std::vector<long>& d) {
  std::string s;
  for (long x : d) s += (s.empty() ? "" : ", ") + std::to_string(x);
  return "[" + s + "]";
}

/// Best of three runs (one if it takes over 2 s): seconds and the result's dims and certainty, or the error.
void row(const std::string& file, std::size_t n, const char* route,
         const std::function<std::pair<std::vector<long>, bool>()>& f) {
  double best = 1e300;
  std::string what;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const auto [d, certified] = f();
      what = dims_text(d) + " | " + (certified ? "yes" : "no");
    } catch (const std::exception& e) {
      what = std::string("fails: ") + std::string(e.what()).substr(0, 60) + " |";
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    if (best > 2) break;
  }
  std::printf("| %s | %zu | %s | %.4f | %s |\n", file.c_str(), n, route, best, what.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  using dcad::reference::pipeline::ImplicitRoute;
  std::printf("| case | variables | route | seconds | dims | certified |\n|---|---|---|---|---|---|\n");
  for (int a = 1; a < argc; ++a) {
    const dcad::io::Problem p = dcad::io::read_problem(argv[a]);
    const std::size_t n = p.expression().system.n;
    for (const auto& [route, name] :
         {std::pair{ImplicitRoute::formulas, "exact, on formulas"}, std::pair{ImplicitRoute::jets, "exact, on jets"}})
      row(argv[a], n, name, [&, r = route] {
        const auto s = dcad::reference::pipeline::solve_implicit_exact(p.expression(), r);
        return std::make_pair(s.dims(), s.certified.yes());
      });
    row(argv[a], n, "fast (derivative array)", [&] {
      const auto s = dcad::fast::solve(p);
      return std::make_pair(s.dims(), s.certified.yes());
    });
  }
}
