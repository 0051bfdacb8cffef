// Plain types shared by the two twins (issue 15), defined once so that a value passes from
// dcad::reference to dcad::fast and back without a field-by-field copy.  Each twin names them in its
// own namespace (reference::BranchKind and fast::BranchKind are this one type).
#pragma once

#include <cstddef>

namespace dcad {

/// A branch of an LC circuit (CEF §6): an inductor, a capacitor, or empty (neither).
enum class BranchKind { inductor, capacitor, empty };

/// L(q, v) = ½ vᵀ A v + qᵀ B v + ½ qᵀ C q + aᵀ q + bᵀ v on R^n with Δ = ker K (CONTRACT `pontryagin`;
/// k = K, vv = A, qv = B, qq = C, q = a, v = b), over a twin's matrix and vector types:
/// reference::PontryaginInput<T> and fast::PontryaginInput.
template <class Mat, class Vec>
struct PontryaginData {
  std::size_t n = 0;
  Mat k, vv, qv, qq;
  Vec q, v;
};

}  // namespace dcad
