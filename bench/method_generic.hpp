// The reference CAD over a scalar T, from an exact Instance (included by one .cpp per T).
#pragma once

#include "approx.hpp"
#include "dcad/reference/cad.hpp"
#include "methods.hpp"

namespace dcad::bench {

template <class T, class Lift, class ToDouble>
Outcome run_generic(const families::Instance& in, Lift lift, ToDouble to_double) {
  namespace ref = dcad::reference;
  const ref::LinearSystem<T> s = families::system_over<T>(in, lift);
  const ref::CadResult<T> r = ref::constraint_tower(s);
  Outcome o;
  o.consistent = r.consistent;
  o.solution_rank = static_cast<long>(r.solution_rank);
  for (const auto& st : r.tower) {
    o.dims.push_back(st.dim());
    const ref::Matrix<T>& b = st.m.direction.basis();
    Eigen::MatrixXd d(b.cols(), b.rows());
    for (ref::Index i = 0; i < b.rows(); ++i)
      for (ref::Index j = 0; j < b.cols(); ++j) d(j, i) = to_double(b(i, j));
    o.tower.push_back(d);
  }
  return o;
}

/// max |entry| of the input, the scale of the tolerance methods.
inline double input_scale(const families::Instance& in) {
  double m = 0;
  const auto scan = [&](const families::QM& a) {
    for (reference::Index i = 0; i < a.rows(); ++i)
      for (reference::Index j = 0; j < a.cols(); ++j) m = std::max(m, std::abs(a(i, j).convert_to<double>()));
  };
  if (in.pontryagin) {
    scan(in.circuit.k), scan(in.circuit.vv), scan(in.circuit.qq), scan(in.circuit.qv);
  } else {
    scan(in.omega), scan(in.hessian);
  }
  return m > 0 ? m : 1.0;
}

/// The reference algorithm on Approx<F> (approx.hpp): zero means |x| ≤ relative × input scale.
template <class F>
Outcome run_approx(const families::Instance& in, const F& relative) {
  using A = Approx<F>;
  A::tolerance() = relative * F(input_scale(in));
  try {
    return run_generic<A>(
        in, [](const families::Q& q) { return A(F(q)); }, [](const A& a) { return static_cast<double>(a.v); });
  } catch (const std::exception& e) {
    Outcome o;
    o.failed = true;
    o.error = e.what();
    return o;
  }
}

}  // namespace dcad::bench
