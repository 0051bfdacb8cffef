// Families of exact inputs on which numerical methods fail, each with a planted exact answer
// (issue 6).  Plain std::mt19937_64, no RapidCheck, so that the property tests (prop_certified)
// and the benchmark sweep (bench/sweep.cpp) draw the very same instances from a seed.
//
//   tower(c)        the planted long tower of gen.hpp's long_tower_system: (q, p, z) ∈ Q^{2m+1},
//                   ω = Σ dq_i∧dp_i, E = z q_1 + Σ p_i q_{i+1} + ½ p_m²; c = N = 2m+1, dims N … 0.
//   graded(κ)       the same tower (m = 3) moved by x = U G y, G = diag of powers of two spanning
//                   √κ, U a unimodular shear product: the data is exact in double (dyadic), its
//                   condition is ≈ κ, and the CAD is coordinate free, so the planted dims stay.
//   perturbed(k)    ω = Sᵀ (J_r ⊕ 0) S + 2^-k Sᵀ (e_a∧e_b) S with a, b in the kernel block, E = 0:
//                   rank ω = 2r + 2 exactly (2r at k = ∞), so c = 0 and solution rank n − 2r − 2.
//   lc(span)        the 4-port of CEF §6 (Fig. 6.1) with L, C log-uniform over 10^-span … 10^3
//                   (decimal values: not representable in double): physical, so by CEF Thms
//                   6.4, 6.6, 6.8 the dims are [12, 6, 5, 4] whatever the values.
//   cancel(d)       the 4-port with C3 = −C1 (1 − 10^-d) (signed, CEF Remark 6.7): the answer is
//                   the reference's; C1 + C3 = 0 exactly would change the tower.
//   size(m)         graded(10^2) with growing m (N = 2m + 1).
#pragma once

#include "dcad/reference/circuit.hpp"
#include "dcad/reference/dirac.hpp"
#include "dcad/reference/rational.hpp"

#include <cmath>
#include <random>
#include <string>

namespace dcad::families {

using Q = reference::Rational;
using QM = reference::Matrix<Q>;
using reference::Index;

/// The exact input of one instance: a presymplectic (ω, H, g) or a Pontryagin (circuit) system.
struct Instance {
  std::string family;
  double param = 0;  ///< κ, k, c, span, d or N, as the family says
  bool pontryagin = false;
  QM omega, hessian;  ///< presymplectic form and ∂²E (when !pontryagin)
  std::vector<Q> gradient;
  reference::PontryaginInput<Q> circuit;  ///< when pontryagin
  bool planted = false;                   ///< dims/solution_rank below are known by construction
  std::vector<long> dims;
  long solution_rank = 0;
  Index n() const { return pontryagin ? 3 * circuit.n : omega.rows(); }
};

inline QM shears(Index n, std::mt19937_64& rng, int count) {
  QM a = QM::identity(n);
  std::uniform_int_distribution<Index> idx(0, n - 1);
  std::uniform_int_distribution<int> coef(-2, 2);
  for (int s = 0; s < count && n > 1; ++s) {
    const Index i = idx(rng), j = idx(rng);
    const int c = coef(rng);
    if (i == j || c == 0) continue;
    for (Index k = 0; k < n; ++k) a(i, k) += Q(c) * a(j, k);
  }
  return a;
}

/// diag(2^{-e_i}) with e_i spread over [0, log2 √κ], shuffled.
inline QM grading(Index n, double kappa, std::mt19937_64& rng) {
  const double top = 0.5 * std::log2(std::max(kappa, 1.0));
  std::vector<long> e(n);
  for (Index i = 0; i < n; ++i)
    e[i] = n > 1 ? std::lround(top * static_cast<double>(i) / static_cast<double>(n - 1)) : 0;
  std::shuffle(e.begin(), e.end(), rng);
  QM g(n, n);
  for (Index i = 0; i < n; ++i) g(i, i) = Q(1) / Q(boost::multiprecision::pow(boost::multiprecision::mpz_int(2), e[i]));
  return g;
}

/// The planted tower in coordinates x = S y: ω ↦ Sᵀ ω S, H ↦ Sᵀ H S.
inline Instance tower_instance(Index m, const QM& s, const std::string& family, double param) {
  const Index n = 2 * m + 1, z = 2 * m;
  QM w(n, n), h(n, n);
  for (Index i = 0; i < m; ++i) {
    w(i, m + i) = Q(1);
    w(m + i, i) = Q(-1);
  }
  h(z, 0) = h(0, z) = Q(1);
  for (Index i = 0; i + 1 < m; ++i) h(m + i, i + 1) = h(i + 1, m + i) = Q(1);
  h(2 * m - 1, 2 * m - 1) = Q(1);
  Instance in;
  in.family = family;
  in.param = param;
  in.omega = s.transpose() * w * s;
  in.hessian = s.transpose() * h * s;
  in.gradient.assign(n, Q(0));
  in.planted = true;
  for (long d = static_cast<long>(n); d >= 0; --d) in.dims.push_back(d);
  in.solution_rank = 0;
  return in;
}

inline Instance tower(Index m, std::mt19937_64& rng) {
  const Index n = 2 * m + 1;
  return tower_instance(m, shears(n, rng, static_cast<int>(2 * n)), "tower", static_cast<double>(n));
}

inline Instance graded(double kappa, std::mt19937_64& rng, Index m = 3, const std::string& family = "graded") {
  const Index n = 2 * m + 1;
  Instance in = tower_instance(m, shears(n, rng, static_cast<int>(n)) * grading(n, kappa, rng), family, kappa);
  if (family == "size") in.param = static_cast<double>(n);
  return in;
}

inline Instance perturbed(int k, std::mt19937_64& rng, Index n = 8, Index r = 2) {
  QM j(n, n);
  for (Index i = 0; i < r; ++i) {
    j(i, r + i) = Q(1);
    j(r + i, i) = Q(-1);
  }
  const Index a = 2 * r, b = 2 * r + 1;
  const Q eps = Q(1) / Q(boost::multiprecision::pow(boost::multiprecision::mpz_int(2), k));
  j(a, b) = eps;
  j(b, a) = -eps;
  const QM s = shears(n, rng, static_cast<int>(n));
  Instance in;
  in.family = "perturbed";
  in.param = k;
  in.omega = s.transpose() * j * s;
  in.hessian = QM(n, n);
  in.gradient.assign(n, Q(0));
  in.planted = true;
  in.dims = {static_cast<long>(n)};
  in.solution_rank = static_cast<long>(n - 2 * r - 2);
  return in;
}

/// m·10^e with m ∈ [1, 99], e so that the value is log-uniform in [10^lo, 10^hi]: exact decimal.
inline Q decimal_value(double lo, double hi, std::mt19937_64& rng) {
  const double x = std::uniform_real_distribution<double>(lo, hi)(rng);
  const long e = static_cast<long>(std::floor(x)) - 1;
  const long mant = std::lround(std::pow(10.0, x - static_cast<double>(e)));
  const Q ten = Q(10);
  Q scale = 1;
  for (long i = 0; i < std::labs(e); ++i) scale *= ten;
  return e >= 0 ? Q(mant) * scale : Q(mant) / scale;
}

/// The 4-port of CEF Fig. 6.1: L1 ground→1, C1 1→2, C2 2→ground, C3 1→2.
inline reference::Circuit<Q> four_port(const Q& l1, const Q& c1, const Q& c2, const Q& c3) {
  using reference::BranchKind;
  reference::Circuit<Q> c;
  c.nodes = 2;
  c.branches = {{"L1", BranchKind::inductor, -1, 0, l1},
                {"C1", BranchKind::capacitor, 0, 1, c1},
                {"C2", BranchKind::capacitor, 1, -1, c2},
                {"C3", BranchKind::capacitor, 0, 1, c3}};
  return c;
}

inline Instance lc(double span, std::mt19937_64& rng) {
  Instance in;
  in.family = "lc";
  in.param = span;
  in.pontryagin = true;
  const double lo = -span;
  in.circuit = reference::circuit_lagrangian(four_port(decimal_value(lo, 3, rng), decimal_value(lo, 3, rng),
                                                       decimal_value(lo, 3, rng), decimal_value(lo, 3, rng)));
  in.planted = true;
  in.dims = {12, 6, 5, 4};
  in.solution_rank = 0;
  return in;
}

inline Instance cancel(int d, std::mt19937_64& rng) {
  Instance in;
  in.family = "cancel";
  in.param = d;
  in.pontryagin = true;
  const Q c1 = decimal_value(-1, 1, rng);
  Q tiny = 1;
  for (int i = 0; i < d; ++i) tiny /= Q(10);
  in.circuit = reference::circuit_lagrangian(
      four_port(decimal_value(-1, 1, rng), c1, decimal_value(-1, 1, rng), -c1 * (Q(1) - tiny)));
  in.planted = false;  // the reference decides
  return in;
}

/// The instance as a linear system over T, every input number lifted by `lift` (exact → T).
template <class T, class Lift>
reference::LinearSystem<T> system_over(const Instance& in, Lift lift) {
  namespace ref = dcad::reference;
  const auto lm = [&](const QM& m) {
    ref::Matrix<T> out(m.rows(), m.cols());
    for (Index i = 0; i < m.rows(); ++i)
      for (Index j = 0; j < m.cols(); ++j) out(i, j) = lift(m(i, j));
    return out;
  };
  const auto lv = [&](const std::vector<Q>& v) {
    std::vector<T> out;
    for (const Q& x : v) out.push_back(lift(x));
    return out;
  };
  if (in.pontryagin) {
    const auto& p = in.circuit;
    return ref::pontryagin_system(
        ref::PontryaginInput<T>{p.n, lm(p.k), lm(p.vv), lm(p.qv), lm(p.qq), lv(p.q), lv(p.v)});
  }
  return {ref::dirac_from_presymplectic(lm(in.omega)), lm(in.hessian), lv(in.gradient), T(0)};
}

}  // namespace dcad::families
