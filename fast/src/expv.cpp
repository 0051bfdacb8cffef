// Krylov exponential action with Expokit's error control (dcad/fast/expv.hpp).
#include "dcad/fast/expv.hpp"

#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

/// Rounds a step to 2 significant digits upwards, as Expokit does (keeps step lengths repeatable).
double round_step(double t) {
  if (!(t > 0) || !std::isfinite(t)) return t;
  const double s = std::pow(10.0, std::floor(std::log10(t)) - 1);
  return std::ceil(t / s) * s;
}

}  // namespace

void KrylovExp::advance(double tau, Eigen::VectorXd& w, Eigen::VectorXd& integral) {
  using Mat = Eigen::MatrixXd;
  using Vec = Eigen::VectorXd;
  const int m = std::max(2, std::min<int>(opt_.max_basis, static_cast<int>(w.size())));
  const double eps = std::numeric_limits<double>::epsilon(), gamma = 0.9, delta = 1.2;
  double t_now = 0;
  std::vector<Vec> v(static_cast<std::size_t>(m + 2)), side(static_cast<std::size_t>(m + 2));
  Vec p(w.size()), pside(static_cast<Eigen::Index>(side_size_));
  const long budget = products_ + opt_.max_products;
  while (t_now < tau) {
    if (products_ > budget)
      throw std::runtime_error("the Krylov integrator needed more than " + std::to_string(opt_.max_products) +
                               " operator products for a step of " + std::to_string(tau) + " s (reached " +
                               std::to_string(t_now) + " s): the operator is stiff against the step");
    double beta = w.norm();
    if (beta == 0) {  // exp(sA)·0 = 0: nothing moves, nothing flows
      t_now = tau;
      break;
    }
    double t_step = std::min(tau - t_now, suggestion_ > 0 ? suggestion_ : tau - t_now);
    Mat h = Mat::Zero(m + 2, m + 2);
    v[0] = w / beta;
    bool have_next = false;  // p = A v[j] already computed (by the previous check)
    int mb = 0;
    bool happy = false;
    double err = 0, xm = 1.0 / m, avnorm = 0, anorm = 0;
    Vec f;                             // β exp(τH) e₁ on the basis
    Vec fint;                          // β ∫ exp(sH) e₁ ds on the basis
    const auto exps = [&](int size) {  // [[τH, τe₁], [0, 0]] of the leading `size` block
      Mat aug = Mat::Zero(size + 1, size + 1);
      aug.topLeftCorner(size, size) = t_step * h.topLeftCorner(size, size);
      aug(0, size) = t_step;
      const Mat e = aug.exp();
      f = beta * e.col(0).head(size);
      fint = beta * e.col(size).head(size);
    };
    for (int j = 0; j < m; ++j) {
      if (!have_next) {
        a_(v[static_cast<std::size_t>(j)], p, side_size_ ? &pside : nullptr);
        ++products_;
        side[static_cast<std::size_t>(j)] = pside;
      }
      have_next = false;
      for (int i = 0; i <= j; ++i) {
        h(i, j) = v[static_cast<std::size_t>(i)].dot(p);
        p -= h(i, j) * v[static_cast<std::size_t>(i)];
      }
      const double s = p.norm();
      anorm = std::max(anorm, h.topLeftCorner(j + 1, j + 1).cwiseAbs().colwise().sum().maxCoeff());
      if (!std::isfinite(s) || !std::isfinite(anorm))
        throw std::runtime_error("the operator's products are not finite (coefficients out of double's range)");
      // an invariant subspace: exact on it — when what it neglects (about β·s per unit time) is within tolerance
      if (s <= 1e-14 * std::max(anorm, std::numeric_limits<double>::min()) && s * beta <= opt_.tol) {
        mb = j + 1;
        happy = true;
        t_step = tau - t_now;
        exps(mb);
        // exp(τH) overflows for a stiff H over a long τ (its transient grows before it decays): shorter steps
        for (int shrink = 0; shrink < 60 && !(f.allFinite() && fint.allFinite()); ++shrink) {
          t_step /= 8;
          exps(mb);
        }
        if (!(f.allFinite() && fint.allFinite()))
          throw std::runtime_error(
              "the exponential of the Krylov matrix is not finite (coefficients out of double's range, or a growing "
              "source)");
        err = 0;
        break;
      }
      h(j + 1, j) = s;
      v[static_cast<std::size_t>(j + 1)] = p / s;
      const int k = j + 1;
      if (!(k == m || k == 4 || k == 8 || k == 12 || k == 16 || k == 20 || k == 25)) continue;
      // the corrected scheme: one more product for the error estimate (reused by the next step)
      a_(v[static_cast<std::size_t>(k)], p, side_size_ ? &pside : nullptr);
      ++products_;
      side[static_cast<std::size_t>(k)] = pside;
      have_next = true;
      avnorm = p.norm();
      h(k + 1, k) = 1;
      bool accepted = false;
      for (int reject = 0; reject < 50; ++reject) {
        exps(k + 2);
        const double phi1 = std::abs(f(k)), phi2 = std::abs(f(k + 1)) * avnorm;
        if (phi1 > 10 * phi2)
          err = phi2, xm = 1.0 / k;
        else if (phi1 > phi2)
          err = phi1 * phi2 / (phi1 - phi2), xm = 1.0 / k;
        else
          err = phi1, xm = 1.0 / (k - 1);
        if (!std::isfinite(err) || !f.allFinite() ||
            !fint.allFinite()) {  // too long a step for a stiff H: a shorter one
          if (reject == 49 || !(t_step / 8 > 0))
            throw std::runtime_error(
                "the exponential of the Krylov matrix is not finite (coefficients out of double's range, or a growing "
                "source)");
          t_step /= 8;
          continue;
        }
        if (err <= delta * t_step * opt_.tol) {
          accepted = true;
          break;
        }
        if (k < m) break;  // a longer basis first
        if (reject == 49)
          throw std::runtime_error("the Krylov step was rejected 50 times at " + std::to_string(t_now) +
                                   " s (local error " + std::to_string(err) + " against " +
                                   std::to_string(delta * t_step * opt_.tol) + ")");
        t_step = round_step(gamma * t_step * std::pow(t_step * opt_.tol / err, xm));
        t_step = std::min(t_step, tau - t_now);
        if (!(t_step > 0)) throw std::runtime_error("the Krylov step length is not positive");
      }
      h(k + 1, k) = 0;
      if (accepted) {
        mb = k + 1;  // v[0 … k]: the corrected approximation
        f.conservativeResize(mb);
        fint.conservativeResize(mb);
        break;
      }
    }
    Vec next = Vec::Zero(w.size());
    for (int i = 0; i < mb; ++i) next += f(i) * v[static_cast<std::size_t>(i)];
    if (side_size_)
      for (int i = 0; i < mb; ++i) integral += fint(i) * side[static_cast<std::size_t>(i)];
    w = next;
    t_now += t_step;
    ++substeps_;
    // the truncation estimate, at least the rounding of H = VᵀAV itself: ε‖A‖ per unit time (Expokit's
    // rndoff) — on a stiff operator (‖A‖·τ ≫ 1) that is what bounds the accuracy, and what is reported
    error_ += std::max(err, eps * std::max(anorm, avnorm) * t_step * beta);
    if (!happy && err > 0)
      suggestion_ = round_step(gamma * t_step * std::pow(t_step * opt_.tol / err, xm));
    else if (happy)
      suggestion_ = std::max(suggestion_, t_step);
    else
      suggestion_ = 2 * t_step;
  }
}

}  // namespace dcad::fast
