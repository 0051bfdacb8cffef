// Google Benchmark of the kernels behind the sweep (issue 6); never run by ctest.
//   build/bench_kernels [--benchmark_filter=...] [--benchmark_format=csv]
// FastCad/N against ColPivQR/N is the "fast CAD at N = 500 against one pivoted QR" ratio;
// RrefExact/N against RrefBall/N is the exact kernel against its certified floating twin.
#include "dcad/fast/cad.hpp"
#include "dcad/certified/ball.hpp"
#include "dcad/reference/matrix.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>
#include <benchmark/benchmark.h>

#include <random>

namespace {

namespace fa = dcad::fast;
namespace ref = dcad::reference;

Eigen::MatrixXd small_integers(int r, int c, int bound, std::mt19937& rng) {
  std::uniform_int_distribution<int> u(-bound, bound);
  Eigen::MatrixXd m(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) m(i, j) = u(rng);
  return m;
}

/// D = graph of ω = F1ᵀF2 − F2ᵀF1 (rank ≤ N/2), E = ½ xᵀ FᵀF x + (FᵀF x0)·x: consistent, c ≥ 1.
fa::LinearSystem presymplectic_system(int n) {
  std::mt19937 rng(7);
  const Eigen::MatrixXd f1 = small_integers(n / 4, n, 1, rng), f2 = small_integers(n / 4, n, 1, rng);
  const Eigen::MatrixXd f = small_integers(n / 2, n, 1, rng);
  const Eigen::MatrixXd h = f.transpose() * f;
  return {fa::dirac_from_presymplectic(f1.transpose() * f2 - f2.transpose() * f1), h, h * small_integers(n, 1, 2, rng), 0.0};
}

void ColPivQR(benchmark::State& st) {
  std::mt19937 rng(1);
  const Eigen::MatrixXd a = small_integers(static_cast<int>(st.range(0)), static_cast<int>(st.range(0)), 3, rng);
  for (auto _ : st) benchmark::DoNotOptimize(Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(a).rank());
}
BENCHMARK(ColPivQR)->Arg(100)->Arg(200)->Arg(500)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);

void JacobiSingularValues(benchmark::State& st) {
  std::mt19937 rng(1);
  const Eigen::MatrixXd a = small_integers(static_cast<int>(st.range(0)), static_cast<int>(st.range(0)), 3, rng);
  for (auto _ : st) benchmark::DoNotOptimize(Eigen::JacobiSVD<Eigen::MatrixXd>(a).singularValues()(0));
}
BENCHMARK(JacobiSingularValues)->Arg(100)->Arg(200)->Arg(500)->Unit(benchmark::kMillisecond);

void FastCad(benchmark::State& st) {
  const fa::LinearSystem s = presymplectic_system(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(fa::constraint_tower(s).steps);
}
BENCHMARK(FastCad)->Arg(100)->Arg(200)->Arg(500)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond)->MinTime(1.0);

template <class T, class Lift>
ref::Matrix<T> lifted(const Eigen::MatrixXd& a, Lift lift) {
  ref::Matrix<T> m(a.rows(), a.cols());
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) m(i, j) = lift(a(i, j));
  return m;
}

/// A rank-deficient integer matrix (rank N/2): RREF decides N/2 pivots and N/2 zero columns.
Eigen::MatrixXd deficient(int n) {
  std::mt19937 rng(3);
  return small_integers(n, n / 2, 2, rng) * small_integers(n / 2, n, 2, rng);
}

void RrefExact(benchmark::State& st) {
  const auto m = lifted<ref::Rational>(deficient(static_cast<int>(st.range(0))), [](double x) { return ref::Rational(x); });
  for (auto _ : st) benchmark::DoNotOptimize(ref::rref(m).pivots.size());
}
BENCHMARK(RrefExact)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);

void RrefBall(benchmark::State& st) {
  const auto m = lifted<dcad::certified::Ball>(deficient(static_cast<int>(st.range(0))), [](double x) { return dcad::certified::Ball(static_cast<int>(x)); });
  std::size_t pivots = 0;
  bool certified = true;
  for (auto _ : st) {
    try {
      pivots = ref::rref(m).pivots.size();
    } catch (const dcad::certified::Uncertain&) {
      certified = false;
    }
    benchmark::DoNotOptimize(pivots);
  }
  st.SetLabel(certified ? "every test certified" : "a zero test needed the exact route");
}
BENCHMARK(RrefBall)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
