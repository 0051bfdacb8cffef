// The data of YM §3's implicit Hamiltonian systems, shared by the two twins (like dcad/types.hpp's
// PontryaginData): each twin names it in its own namespace, reference::HamiltonianInput<T> and
// fast::HamiltonianInput.
#pragma once

#include <cstddef>

namespace dcad {

/// H(q, p) = ½ pᵀ A p + qᵀ B p + ½ qᵀ C q + aᵀ q + bᵀ p on T*Q = R^n × R^n with Δ = ker K (k = K, pp = A,
/// qp = B, qq = C, q = a, p = b; k may have 0 rows: Δ = TQ).
template <class Mat, class Vec>
struct HamiltonianData {
  std::size_t n = 0;
  Mat k, pp, qp, qq;
  Vec q, p;
};

}  // namespace dcad
