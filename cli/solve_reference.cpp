// The CAD by the exact reference (the one translation unit that instantiates it for solve).
#include "dcad/reference/dirac_bergmann.hpp"
#include "solve.hpp"

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;

ref::DiracStructure<Q> reference_dirac(const io::DiracInput& d);  // inspect_reference.cpp

namespace {

std::string exact(const Q& q) { return q == 0 ? "" : q.str(); }

ref::LinearSystem<Q> reference_system(const io::CaseFile& c) {
  if (c.has_constrained) {  // Gotay–Nester for (N, Ω, E, M): D = D_{(T M, Ω)} from M_0 = M  [CEF §2.2]
    ref::require_symplectic(c.constrained.w, "solve");
    ref::require_regular_primary(ref::ConstrainedSystem<Q>{c.constrained.w, c.energy.hessian, c.energy.gradient, c.constrained.primary},
                                 "solve");
    return {ref::dirac_from_distribution(ref::kernel(ref::gradients(c.constrained.primary)), c.constrained.w), c.energy.hessian,
            c.energy.gradient, c.energy.constant};
  }
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
  const ref::CadResult<Q> r = ref::constraint_tower(s, c.has_constrained ? c.constrained.primary : io::QMatrix());
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
  if (c.has_constrained && r.consistent) {  // first and second class on M_c, Dirac bracket  [Lemma 3.23]
    io::QMatrix all(0, c.n + 1);
    for (const auto& st : r.tower) all = ref::vstack(all, st.equations);
    const ref::ConstraintClasses<Q> cl = ref::classify_constraints(c.constrained.w, all);
    out.second_class = static_cast<long>(2 * cl.s);
    out.first_class = static_cast<long>(all.rows() - 2 * cl.s);
    for (ref::Index i : cl.second) {
      Equation e;
      for (ref::Index j = 0; j < c.n; ++j) e.coeff.push_back(exact(all(i, j)));
      e.rhs = all(i, c.n).str();
      out.second_class_constraints.push_back(e);
    }
    for (ref::Index i = 0; i < c.n; ++i) {
      out.dirac_bracket.push_back({});
      for (ref::Index j = 0; j < c.n; ++j) out.dirac_bracket.back().push_back(cl.dirac_tensor(i, j).str());
    }
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
