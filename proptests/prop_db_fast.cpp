// fast Dirac–Bergmann and constraint classes = reference on every discrete output unless fast says
// uncertain (tower dims, consistency, dim Λ^(c), 2s, number of first class constraints); the fast
// Dirac tensor satisfies Lemma 3.23 (e) and gives the canonical motion on M_c, up to rounding.
#include "support/convert.hpp"
#include "support/tally.hpp"

#include "dcad/fast/dirac_bergmann.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

RC_GTEST_PROP(FastVsReference, DiracBergmann, ()) {
  const ref::ConstrainedSystem<Q> s = any_constrained_system();
  fast::Options opt;
  const fast::ConstrainedSystem fs{to_double(s.omega, &opt), to_double(s.hessian, &opt),
                                   to_double(QM::column(s.gradient), &opt).col(0), to_double(s.primary, &opt)};
  const ref::DiracBergmannResult<Q> r = ref::dirac_bergmann(s);
  const fast::DiracBergmannResult f = fast::dirac_bergmann(fs, opt);
  bool same = f.tower.size() == r.tower.size();
  for (Index k = 0; same && k < r.tower.size(); ++k)
    same = (f.tower[k].empty ? -1 : f.tower[k].direction.dim()) == (r.tower[k].empty ? -1L : static_cast<long>(r.tower[k].direction.dim()));
  RC_ASSERT(!tally("DB dims of M_k", f.certain, same));
  RC_ASSERT(!tally("DB consistent", f.certain, f.consistent == r.consistent));
  if (!r.consistent || !f.consistent || !f.certain || !same) return;
  const ref::ConstraintClasses<Q> rc_ = ref::classify_constraints(s.omega, r.constraints);
  const fast::ConstraintClasses fc = fast::classify_constraints(fs.omega, f.constraints, opt);
  RC_ASSERT(!tally("second class 2s", fc.certain, static_cast<Index>(fc.s) == rc_.s));
  RC_ASSERT(!tally("first class count", fc.certain, static_cast<Index>(fc.first.rows()) == rc_.first.rows()));
  const std::vector<Q> x = some_point(r.tower.back());
  const ref::AffineSubspace<Q> rl = ref::multipliers(s, r, x);
  const fast::AffineSubspace fl = fast::multipliers(fs, f, to_double(x), opt);
  RC_ASSERT(!tally("dim Lambda^(c)", fl.certain, !fl.empty && static_cast<Index>(fl.direction.dim()) == rl.direction.dim()));
  if (!fc.certain || fl.empty || !fl.certain) return;
  // Lemma 3.23 (e) and the motion: J* skew, G J* = 0, J*(dE + λ·a) = J(dE + λ·a) on M_c
  const int n = static_cast<int>(fs.omega.rows());
  const Eigen::MatrixXd j = fast::poisson_tensor(fs.omega);
  const double scale = 1 + fast::norm2(j) * fast::norm2(j) * (1 + fast::norm2(fs.hessian) + fs.gradient.norm()) * (1 + fl.point.norm() + to_double(x).norm());
  const double tol = 1e-8 * scale;
  RC_ASSERT((fc.dirac_tensor + fc.dirac_tensor.transpose()).norm() <= tol);
  RC_ASSERT((fc.second.leftCols(n) * fc.dirac_tensor).norm() <= tol);
  const Eigen::VectorXd de = fs.hessian * to_double(x) + fs.gradient + fs.primary.leftCols(n).transpose() * fl.point;
  RC_ASSERT((fc.dirac_tensor * de - j * de).norm() <= tol);
}
