#include "dcad/fast/cad.hpp"
#include "methods.hpp"

#include <Eigen/SVD>

namespace dcad::bench {

namespace {

Eigen::MatrixXd to_double(const families::QM& m, fast::Options& opt) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (reference::Index i = 0; i < m.rows(); ++i)
    for (reference::Index j = 0; j < m.cols(); ++j) {
      d(i, j) = m(i, j).convert_to<double>();
      if (families::Q(d(i, j)) != m(i, j)) opt.input_exact = false;
    }
  fast::assess_input(d, opt);
  return d;
}

Eigen::VectorXd to_double(const std::vector<families::Q>& v, fast::Options& opt) {
  families::QM m(v.size(), 1);
  for (reference::Index i = 0; i < v.size(); ++i) m(i, 0) = v[i];
  return to_double(m, opt).col(0);
}

}  // namespace

Outcome run_fast(const families::Instance& in) {
  fast::Options opt;
  Outcome o;
  try {
    fast::LinearSystem s;
    if (in.pontryagin) {
      const auto& p = in.circuit;
      s = fast::pontryagin_system(to_double(p.k, opt), to_double(p.vv, opt), to_double(p.qv, opt), to_double(p.qq, opt),
                                  to_double(p.q, opt), to_double(p.v, opt), opt);
    } else {
      s = {fast::dirac_from_presymplectic(to_double(in.omega, opt)), to_double(in.hessian, opt), to_double(in.gradient, opt), 0.0};
    }
    const fast::CadResult r = fast::constraint_tower(s, opt);
    o.consistent = r.consistent;
    o.solution_rank = r.solution_rank;
    o.uncertain = !r.certain;
    for (const auto& st : r.tower) {
      o.dims.push_back(st.dim());
      o.tower.push_back(st.m.empty ? Eigen::MatrixXd() : st.m.direction.basis());
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
