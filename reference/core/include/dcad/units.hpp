// Units, written once (issue 26): the dimensionless twin of a circuit and how its results map back.
// Every L is divided by L0 = 10^a, every C by C0 = 10^b, with 10^a and 10^b the powers of ten nearest
// the geometric means of the inductances and capacitances (b one up if a + b is odd, so that a power-
// of-ten C becomes 1/10 and its elastance 10 stays exact in double), so that the time unit
// T = √(L0 C0) = 10^m, m = (a + b)/2, is exact; resistances by R0 = √(L0/C0) = 10^((a−b)/2), mutual
// inductances by L0.  A solution of the twin gives one of the circuit by t = T t̃, q = q̃, v = ṽ/T,
// p = (L0/T) p̃ (ν = L0 ν̃ on T*TQ), V = Ṽ/C0, I = Ĩ/T: the Lagrangian and the forces become C0⁻¹ times
// the twin's (CEF §6: L = ½ vᵀΦv − ½ qᵀΨq; YM §4), so the towers are equal and the equations of motion
// correspond (x = S x̃, d/dt = T⁻¹ d/dt̃).  dcad::io makes the twin exactly (io::dimensionless); the fast
// twin computes on it and maps its rows and equations back with these scales.
#pragma once

#include <cmath>
#include <vector>

namespace dcad {

struct Units {
  int a = 0, b = 0;                      ///< L0 = 10^a, C0 = 10^b (a + b even)
  int m() const { return (a + b) / 2; }  ///< T = 10^m
  int r() const { return (a - b) / 2; }  ///< R0 = 10^r

  /// The exponents from the means of log10 of the inductances and of the capacitances (0 for none).
  static Units nearest(double mean_log10_l, double mean_log10_c) {
    Units u;
    u.a = static_cast<int>(std::lround(mean_log10_l));
    u.b = static_cast<int>(std::lround(mean_log10_c));
    if ((u.a + u.b) % 2 != 0) ++u.b;  // C0 one decade up: 1/C̃ = 10 stays exact in double
    return u;
  }
  // long double (range 1e±4932): a deck's scales may leave double's range while its twin is in it
  long double time() const { return std::pow(10.0L, m()); }
  long double inductance() const { return std::pow(10.0L, a); }

  /// S with x = S x̃ for x = (q, v, p[, ν]) of a circuit of `branches` branches: 1, 1/T, L0/T[, L0].
  std::vector<long double> variable_scales(std::size_t branches, bool with_nu) const {
    const long double t = time(), l0 = inductance();
    std::vector<long double> s(3 * branches, 1.0L);
    for (std::size_t i = 0; i < branches; ++i) {
      s[branches + i] = 1 / t;
      s[2 * branches + i] = l0 / t;
    }
    if (with_nu) s.resize(4 * branches, l0);
    return s;
  }
};

}  // namespace dcad
