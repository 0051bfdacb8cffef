// Google Benchmark of the kernels behind the sweep (issue 6); never run by ctest.
//   build/bench_kernels [--benchmark_filter=...] [--benchmark_format=csv]
// FastCad/N against ColPivQR/N is the "fast CAD at N = 500 against one pivoted QR" ratio;
// RrefExact/N (mpq_rational), RrefFmpq/N (FLINT's fmpq) and RrefWords/N (64-bit words) are the exact
// kernel on each scalar the reference and the certified cascade can run on; CadBeyondWords/{Mpq,Fmpq}/N
// the whole CAD where the words overflow (the regime of the exact tier: the perturbed family scaled
// by 3^90/7, every entry beyond 128 bits).
#include "dcad/fast/cad.hpp"
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/matrix.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/small_rational.hpp"
#include "families.hpp"

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
  return {fa::dirac_from_presymplectic(f1.transpose() * f2 - f2.transpose() * f1), h, h * small_integers(n, 1, 2, rng),
          0.0};
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
  const auto m =
      lifted<ref::Rational>(deficient(static_cast<int>(st.range(0))), [](double x) { return ref::Rational(x); });
  for (auto _ : st) benchmark::DoNotOptimize(ref::rref(m).pivots.size());
}
BENCHMARK(RrefExact)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);

void RrefFmpq(benchmark::State& st) {
  const auto m = lifted<ref::Fmpq>(deficient(static_cast<int>(st.range(0))),
                                   [](double x) { return ref::Fmpq(static_cast<int>(x)); });
  for (auto _ : st) benchmark::DoNotOptimize(ref::rref(m).pivots.size());
}
BENCHMARK(RrefFmpq)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);

void RrefWords(benchmark::State& st) {
  const auto m = lifted<ref::SmallRational>(deficient(static_cast<int>(st.range(0))),
                                            [](double x) { return ref::SmallRational(static_cast<int>(x)); });
  std::size_t pivots = 0;
  bool fits = true;
  for (auto _ : st) {
    try {
      pivots = ref::rref(m).pivots.size();
    } catch (const ref::Overflow&) {
      fits = false;
    }
    benchmark::DoNotOptimize(pivots);
  }
  st.SetLabel(fits ? "every number fitted in 64 bits" : "overflowed 64 bits");
}
BENCHMARK(RrefWords)->Arg(20)->Arg(50)->Arg(100)->Unit(benchmark::kMillisecond);

/// The perturbed family (ω = Sᵀ (J ⊕ 2^-60 e_a∧e_b ⊕ 0) S, E = 0) scaled by 3^90/7: beyond 128 bits.
dcad::families::Instance beyond_words(int n) {
  std::mt19937_64 rng(11);
  dcad::families::Instance in = dcad::families::perturbed(60, rng, n);
  const ref::Rational scale = ref::Rational(boost::multiprecision::pow(boost::multiprecision::mpz_int(3), 90)) / 7;
  for (ref::Index i = 0; i < in.omega.rows(); ++i)
    for (ref::Index j = 0; j < in.omega.cols(); ++j) in.omega(i, j) *= scale;
  return in;
}

template <class T>
void CadBeyondWords(benchmark::State& st) {
  const auto s =
      dcad::families::system_over<T>(beyond_words(static_cast<int>(st.range(0))), [](const ref::Rational& q) {
        if constexpr (std::is_same<T, ref::Rational>::value)
          return q;
        else
          return T::from(q);
      });
  for (auto _ : st) benchmark::DoNotOptimize(ref::constraint_tower(s).steps);
}
BENCHMARK_TEMPLATE(CadBeyondWords, ref::Rational)
    ->Name("CadBeyondWords/Mpq")
    ->Arg(8)
    ->Arg(16)
    ->Arg(24)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(CadBeyondWords, ref::Fmpq)
    ->Name("CadBeyondWords/Fmpq")
    ->Arg(8)
    ->Arg(16)
    ->Arg(24)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
