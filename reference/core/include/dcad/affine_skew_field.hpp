// A skew matrix field affine in the point, shared by the two twins (reference::AffineSkewField<T>,
// fast::AffineSkewField): a presymplectic 2-form or a Poisson bivector on M = R^n that depends on x.
#pragma once

#include <vector>

namespace dcad {

/// M(x) = constant + Σ_k x_k slopes[k] (each n×n and skew; slopes.size() = n).
template <class Mat>
struct AffineSkewData {
  Mat constant;
  std::vector<Mat> slopes;
};

}  // namespace dcad
