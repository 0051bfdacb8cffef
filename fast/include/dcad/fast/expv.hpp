// The action of a matrix exponential on a vector, w ← exp(τA) w, for an A given only by its
// products (a sparse or implicit operator), with Krylov subspaces and the error control of
// Expokit's expv (R. B. Sidje, ACM TOMS 24 (1998) 130–156): Arnoldi to at most m vectors, the
// "corrected" approximation with one more vector, substeps chosen so that the local error estimate
// stays below tol per unit time.  Alongside, the integral ∫₀^τ g(exp(sA) w) ds of a linear side output
// g the operator computes with each product (a circuit's branch currents: their integrals are the
// charges), from the same Hessenberg matrix: exp([[τH, τe₁], [0, 0]]) holds both.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace dcad::fast {

/// y = A v; if `side` is not null it receives g(v) (its size fixed by the caller).
using Operator = std::function<void(const Eigen::VectorXd& v, Eigen::VectorXd& y, Eigen::VectorXd* side)>;

struct KrylovOptions {
  int max_basis = 30;           ///< m: Arnoldi vectors per substep
  double tol = 1e-14;           ///< local error per unit of τ, absolute, in the norm of w (scale w first)
  long max_products = 2000000;  ///< per advance(): beyond it std::runtime_error (a stiff operator: never a hang)
};

/// One integrator kept across calls: its step suggestion and its statistics.
class KrylovExp {
 public:
  KrylovExp(Operator a, std::size_t side_size, KrylovOptions opt = {})
      : a_(std::move(a)), side_size_(side_size), opt_(opt) {}
  /// w ← exp(τA) w; `integral` (side_size) += ∫₀^τ g(exp(sA) w) ds.  τ ≥ 0.  std::runtime_error after
  /// max_products products in one call.
  void advance(double tau, Eigen::VectorXd& w, Eigen::VectorXd& integral);
  double error_estimate() const { return error_; }  ///< sum of the local error estimates (absolute)
  long products() const { return products_; }
  long substeps() const { return substeps_; }
  void set_tolerance(double tol) { opt_.tol = tol; }

 private:
  Operator a_;
  std::size_t side_size_;
  KrylovOptions opt_;
  double suggestion_ = 0;  ///< the next substep's length (0: none yet)
  double error_ = 0;
  long products_ = 0, substeps_ = 0;
};

}  // namespace dcad::fast
