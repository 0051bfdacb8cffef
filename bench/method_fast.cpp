#include "dcad/fast/exact.hpp"
#include "dcad/fast/cad.hpp"
#include "methods.hpp"

#include <Eigen/SVD>

namespace dcad::bench {

using fast::to_double;  // exact → double with the CLI's bookkeeping of input exactness and scaling

Outcome run_fast(const families::Instance& in) {
  fast::Options opt;
  Outcome o;
  try {
    fast::LinearSystem s;
    if (in.pontryagin) {
      const auto& p = in.circuit;
      s = fast::pontryagin_system({p.n, to_double(p.k, opt), to_double(p.vv, opt), to_double(p.qv, opt),
                                   to_double(p.qq, opt), to_double(p.q, opt), to_double(p.v, opt)},
                                  opt);
    } else {
      s = {fast::dirac_from_presymplectic(to_double(in.omega, opt)), to_double(in.hessian, opt),
           to_double(in.gradient, opt), 0.0};
    }
    const fast::CadResult r = fast::constraint_tower(s, opt);
    o.consistent = r.consistent;
    o.solution_rank = r.solution_rank;
    o.uncertain = r.certain.unknown();
    for (const auto& st : r.tower) {
      o.dims.push_back(st.dim());
      o.tower.push_back(st.m.empty ? Eigen::MatrixXd() : st.m.direction.columns());
    }
  } catch (const std::exception& e) {
    o.failed = true;
    o.error = e.what();
  }
  return o;
}

double largest_angle(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.cols() != b.cols()) return 1.5707963267948966;
  if (a.cols() == 0) return 0;
  // sin θ_max = ‖(I − P_A) Q_B‖₂ with orthonormal bases Q_A, Q_B (accurate for small angles).
  const Eigen::MatrixXd qa = Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeThinU).matrixU();
  const Eigen::MatrixXd qb = Eigen::JacobiSVD<Eigen::MatrixXd>(b, Eigen::ComputeThinU).matrixU();
  const Eigen::MatrixXd r = qb - qa * (qa.transpose() * qb);
  const double s = r.size() ? Eigen::JacobiSVD<Eigen::MatrixXd>(r).singularValues()(0) : 0.0;
  return std::asin(std::min(1.0, s));
}

}  // namespace dcad::bench
