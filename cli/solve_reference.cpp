// The CAD by the exact reference (the one translation unit that instantiates it for solve).
#include "dcad/reference/adapted.hpp"
#include "solve.hpp"

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;

ref::DiracStructure<Q> reference_dirac(const io::DiracInput& d);  // inspect_reference.cpp

namespace {

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

namespace {

/// Theorem 3.28 on (W, [primary; secondary; leaf]) with primary and leaf rows flagged primary.
void adapted_report(SolveReport& out, const io::QMatrix& w, const io::QMatrix& prim, const io::QMatrix& secondary,
                    const io::QMatrix& leaf) {
  const io::QMatrix all = ref::vstack(ref::vstack(prim, secondary), leaf);
  std::vector<bool> primary(all.rows(), false);
  for (ref::Index i = 0; i < all.rows(); ++i) primary[i] = i < prim.rows() || i >= prim.rows() + secondary.rows();
  const ref::AdaptedConstraints<Q> ad = ref::adapted_constraints(w, all, primary);
  out.has_adapted = true;
  out.s_prime = static_cast<long>(ad.s_prime);
  out.adapted_second = static_cast<long>(2 * ad.s);
  for (ref::Index i : ad.chi) out.adapted_chi.push_back(row_equation(all, i));
  for (ref::Index k : ad.abridged) out.abridged_terms.push_back(row_equation(all, k));
  const long first = static_cast<long>(all.rows() - 2 * ad.s), primary_first = static_cast<long>(ad.abridged.size());
  out.secondary_first_class = first - primary_first;
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
    for (ref::Index i = 0; i < st.equations.rows(); ++i) step.equations.push_back(row_equation(st.equations, i));
    out.dims.push_back(step.dim);
    out.tower.push_back(step);
  }
  if (r.consistent) {
    out.has_final = true;
    out.final_basis = r.final_step().m.direction.basis();
    out.final_point = r.final_step().m.point;
    const io::QMatrix a = ref::annihilator(r.final_step().m.direction).basis();  // M_c = {a x = a·point}
    io::QMatrix rows(a.rows(), c.n + 1);
    for (ref::Index i = 0; i < a.rows(); ++i) {
      for (ref::Index j = 0; j < c.n; ++j) {
        rows(i, j) = a(i, j);
        rows(i, c.n) += a(i, j) * out.final_point[j];
      }
      out.final_constraints.push_back(row_equation(rows, i));
    }
  }
  if (c.has_constrained && r.consistent) {  // first and second class on M_c, Dirac bracket  [Lemma 3.23]
    io::QMatrix all(0, c.n + 1);
    for (const auto& st : r.tower) all = ref::vstack(all, st.equations);
    const ref::ConstraintClasses<Q> cl = ref::classify_constraints(c.constrained.w, all);
    out.second_class = static_cast<long>(2 * cl.s);
    out.first_class = static_cast<long>(all.rows() - 2 * cl.s);
    for (ref::Index i : cl.second) out.second_class_constraints.push_back(row_equation(all, i));
    for (ref::Index i = 0; i < c.n; ++i) {
      out.dirac_bracket.push_back({});
      for (ref::Index j = 0; j < c.n; ++j) out.dirac_bracket.back().push_back(cl.dirac_tensor(i, j).str());
    }
  }
  if (c.has_constrained && r.consistent) {
    io::QMatrix secondary(0, c.n + 1);
    for (ref::Index k = 1; k < r.tower.size(); ++k) secondary = ref::vstack(secondary, r.tower[k].equations);
    out.adapted_setting = "N";
    out.adapted_variables = c.variables;
    adapted_report(out, c.constrained.w, r.tower[0].equations, secondary, io::QMatrix(0, c.n + 1));
  }
  if (c.has_pontryagin && r.consistent) {  // §7: S' = {ν = 0} ⊂ T*TQ, leaves κ·q = C
    const io::PontryaginInput& p = c.pontryagin;
    const ref::FoliatedEmbedding<Q> f =
        ref::tangent_cotangent_embedding(ref::PontryaginInput<Q>{p.n, p.k, p.vv, p.qv, p.qq, p.q, p.v});
    const io::QMatrix both = ref::vstack(f.primary, f.leaf);
    const ref::LinearSystem<Q> ls{ref::dirac_from_distribution(ref::kernel(ref::gradients(both)), f.omega), f.hessian, f.gradient, Q(0)};
    const ref::CadResult<Q> rf = ref::constraint_tower(ls, f.primary);
    io::QMatrix secondary(0, 4 * p.n + 1);
    for (ref::Index k = 1; k < rf.tower.size(); ++k) secondary = ref::vstack(secondary, rf.tower[k].equations);
    out.adapted_setting = "T*TQ";
    out.adapted_variables = c.variables;
    for (std::size_t i = 0; i < p.n; ++i) out.adapted_variables.push_back("nu_" + c.variables[p.n + i]);
    adapted_report(out, f.omega, f.primary, secondary, f.leaf);
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
