// The CAD by the exact reference (the one translation unit that instantiates it for solve).
#include "dcad/reference/cad.hpp"
#include "solve.hpp"

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;

ref::DiracStructure<Q> reference_dirac(const io::DiracInput& d);  // inspect_reference.cpp

namespace {

std::string exact(const Q& q) { return q == 0 ? "" : q.str(); }

ref::LinearSystem<Q> reference_system(const io::CaseFile& c) {
  if (c.has_pontryagin) {
    const io::PontryaginInput& p = c.pontryagin;
    return ref::pontryagin_system(ref::PontryaginInput<Q>{p.n, p.k, p.vv, p.qv, p.qq, p.q, p.v});
  }
  ref::LinearSystem<Q> s{reference_dirac(c.dirac), c.energy.hessian, c.energy.gradient, c.energy.constant};
  ref::require_dirac(s.d, "solve");
  return s;
}

}  // namespace

SolveReport solve_reference(const io::CaseFile& c) {
  const ref::LinearSystem<Q> s = reference_system(c);
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  SolveReport out;
  out.backend = "reference";
  out.consistent = r.consistent;
  out.steps = static_cast<long>(r.steps);
  out.solution_rank = static_cast<long>(r.solution_rank);
  for (const auto& st : r.tower) {
    SolveReport::Step step;
    step.dim = st.dim();
    for (ref::Index i = 0; i < st.equations.rows(); ++i) {
      Equation e;
      for (ref::Index j = 0; j + 1 < st.equations.cols(); ++j) e.coeff.push_back(exact(st.equations(i, j)));
      e.rhs = st.equations(i, st.equations.cols() - 1).str();
      step.equations.push_back(e);
    }
    out.dims.push_back(step.dim);
    out.tower.push_back(step);
  }
  if (r.consistent) {
    const ref::ReducedEquations<Q> red = ref::reduced_equations(s, r, c.coordinates);
    out.has_reduced = true;
    out.coords = red.coords;
    for (ref::Index i = 0; i < red.coords.size(); ++i) {
      out.f_matrix.push_back({});
      for (ref::Index j = 0; j < red.coords.size(); ++j) out.f_matrix.back().push_back(red.f_matrix(i, j).str());
      out.f.push_back(red.f[i].str());
      out.g.push_back({});
      for (ref::Index j = 0; j < red.g.cols(); ++j) out.g.back().push_back(red.g(i, j).str());
    }
  }
  return out;
}

}  // namespace dcad::cli
