// Benchmark (not a test): the CAD by reference (exact, mpq_rational: the library call on your own
// matrices), fast (double) and certified (certified::constraint_tower: the reference in machine words,
// in FLINT's fmpq past 128 bits) on random linear systems of growing N, timed side by side in one
// run.  Data: D from (E, ω_E) with dim E = N − N/4 and small-integer skew ω of rank ≤ N/2, E = ½ xᵀ H x + gᵀ x with
// H symmetric of rank N/2 and g in the range of H (so systems are consistent with c ≥ 1).
//   build/bench_cad [max_N_reference=120] [max_N=200]
#include "dcad/fast/cad.hpp"
#include "dcad/certified/cad.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/rational.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace ref = dcad::reference;
namespace fa = dcad::fast;
using Q = ref::Rational;
using QM = ref::Matrix<Q>;

namespace {

struct Problem {
  ref::LinearSystem<Q> exact;
  fa::LinearSystem dbl;
};

QM random_matrix(std::mt19937& rng, std::size_t r, std::size_t c, int bound) {
  std::uniform_int_distribution<int> u(-bound, bound);
  QM m(r, c);
  for (std::size_t i = 0; i < r; ++i)
    for (std::size_t j = 0; j < c; ++j) m(i, j) = Q(u(rng));
  return m;
}

Eigen::MatrixXd to_double(const QM& m) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t j = 0; j < m.cols(); ++j) d(i, j) = m(i, j).convert_to<double>();
  return d;
}

Problem make(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  const QM e = random_matrix(rng, n - n / 4, n, 2);
  const QM f1 = random_matrix(rng, n / 4, n, 1), f2 = random_matrix(rng, n / 4, n, 1);
  const QM w = f1.transpose() * f2 - f2.transpose() * f1;  // rank ≤ N/2: ker ω_D ≠ 0, so c ≥ 1
  const QM f = random_matrix(rng, n / 2, n, 1);
  const QM h = f.transpose() * f;
  const std::vector<Q> g = (h * QM::column(random_matrix(rng, n, 1, 2).col(0))).col(0);
  Problem p;
  p.exact = {ref::dirac_from_distribution(ref::Subspace<Q>::span(e), w), h, g, Q(0)};
  p.dbl = {fa::dirac_from_distribution(fa::Subspace::span(to_double(e)), to_double(w)), to_double(h),
           to_double(QM::column(g)).col(0), 0.0};
  return p;
}

template <class F>
double seconds(F&& f, int repeat) {
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < repeat; ++i) f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / repeat;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t max_ref = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : 120;
  const std::size_t max_n = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 200;
  std::printf("%6s %4s %12s %12s %12s %10s %10s %s\n", "N", "c", "reference_s", "fast_s", "certified_s", "ref/fast",
              "cert/fast", "fast certain, certified route");
  for (std::size_t n : {10, 20, 40, 80, 120, 160, 200}) {
    if (n > max_n) break;
    const Problem p = make(n, 1000 + static_cast<unsigned>(n));
    fa::CadResult fr;
    const int rep = n <= 40 ? 20 : 3;
    const double tf = seconds([&] { fr = fa::constraint_tower(p.dbl); }, rep);
    double tr = -1, tc = -1;
    long c = fr.steps;
    const char* route = "";
    if (n <= max_ref) {
      ref::CadResult<Q> rr;
      tr = seconds([&] { rr = ref::constraint_tower(p.exact); }, 1);
      c = static_cast<long>(rr.steps);
      dcad::certified::CertifiedTower ct;
      tc = seconds([&] { ct = dcad::certified::constraint_tower(p.exact); }, 1);
      route = dcad::certified::tier_name(ct.tier);
    }
    std::printf("%6zu %4ld %12.4g %12.4g %12.4g %10.3g %10.3g %s %s\n", n, c, tr, tf, tc, tr > 0 ? tr / tf : 0.0,
                tc / tf, fr.certain.yes() ? "yes" : "no", route);
    std::fflush(stdout);
  }
}
