// The reference pipeline of `dcad solve` (CEF §5 tower, §2.1/Lemma 3.23 classes, Thm 3.28, (5.12)),
// written once over the scalar T and instantiated twice, one translation unit each:
//   T = Rational (solve_reference.cpp): the reference itself;
//   T = Ball     (solve_ball.cpp): the same algorithm in certified interval arithmetic — every
//     branch it takes is the exact one or it throws certified::Uncertain (see ball.hpp), so its
//     discrete outputs are the reference's by construction.
// `Scalar<T>` lifts the exact input and prints numbers.
#pragma once

#include "dcad/reference/adapted.hpp"
#include "solve.hpp"

namespace dcad::cli {

template <class T>
struct Scalar;  // lift(Rational) -> T, text(T) -> string, printable(T) -> whether to print a term

template <class T>
reference::Matrix<T> lift(const io::QMatrix& m) {
  reference::Matrix<T> out(m.rows(), m.cols());
  for (reference::Index i = 0; i < m.rows(); ++i)
    for (reference::Index j = 0; j < m.cols(); ++j) out(i, j) = Scalar<T>::lift(m(i, j));
  return out;
}

template <class T>
std::vector<T> lift(const std::vector<io::Rational>& v) {
  std::vector<T> out;
  for (const io::Rational& x : v) out.push_back(Scalar<T>::lift(x));
  return out;
}

template <class T>
reference::DiracStructure<T> exact_dirac(const io::DiracInput& d) {
  namespace ref = dcad::reference;
  if (d.form == "presymplectic") return ref::dirac_from_presymplectic(lift<T>(d.w));
  if (d.form == "distribution") return ref::dirac_from_distribution(ref::Subspace<T>::span(lift<T>(d.b)), lift<T>(d.w));
  if (d.form == "poisson") return ref::dirac_from_poisson(lift<T>(d.p));
  return {d.g.cols() / 2, ref::Subspace<T>::span(lift<T>(d.g))};  // `basis`: validated by the caller
}

template <class T>
Equation row_equation(const reference::Matrix<T>& rows, std::size_t i) {
  Equation e;
  for (std::size_t j = 0; j + 1 < rows.cols(); ++j)
    if (Scalar<T>::printable(rows(i, j))) e.terms.emplace_back(j, Scalar<T>::text(rows(i, j)));
  e.rhs = Scalar<T>::text(rows(i, rows.cols() - 1));
  return e;
}

template <class T>
reference::LinearSystem<T> exact_system(const io::CaseFile& c) {
  namespace ref = dcad::reference;
  const T constant = Scalar<T>::lift(c.energy.constant);
  if (c.has_constrained) {  // Gotay–Nester for (N, Ω, E, M): D = D_{(T M, Ω)} from M_0 = M  [CEF §2.2]
    const ref::Matrix<T> w = lift<T>(c.constrained.w), prim = lift<T>(c.constrained.primary), h = lift<T>(c.energy.hessian);
    const std::vector<T> g = lift<T>(c.energy.gradient);
    ref::require_symplectic(w, "solve");
    ref::require_regular_primary(ref::ConstrainedSystem<T>{w, h, g, prim}, "solve");
    ref::LinearSystem<T> s = ref::gotay_nester_system(ref::ConstrainedSystem<T>{w, h, g, prim});
    s.constant = constant;
    return s;
  }
  if (c.has_pontryagin) {
    const io::PontryaginInput& p = c.pontryagin;
    return ref::pontryagin_system(
        ref::PontryaginInput<T>{p.n, lift<T>(p.k), lift<T>(p.vv), lift<T>(p.qv), lift<T>(p.qq), lift<T>(p.q), lift<T>(p.v)});
  }
  ref::LinearSystem<T> s{exact_dirac<T>(c.dirac), lift<T>(c.energy.hessian), lift<T>(c.energy.gradient), constant};
  ref::require_dirac(s.d, "solve");
  return s;
}

/// Theorem 3.28 on (W, [primary; secondary; leaf]) with primary and leaf rows flagged primary.
template <class T>
void exact_adapted(SolveReport& out, const reference::Matrix<T>& w, const reference::Matrix<T>& prim,
                   const reference::Matrix<T>& secondary, const reference::Matrix<T>& leaf) {
  namespace ref = dcad::reference;
  const ref::AdaptedToPrimary<T> to = ref::adapted_to_primary(w, prim, secondary, leaf);
  const ref::Matrix<T>& all = to.constraints;
  const ref::AdaptedConstraints<T>& ad = to.adapted;
  out.has_adapted = true;
  out.s_prime = static_cast<long>(ad.s_prime);
  for (ref::Index i : ad.chi) out.adapted_chi.push_back(row_equation(all, i));
  for (ref::Index k : ad.abridged) out.abridged_terms.push_back(row_equation(all, k));
  const long first = static_cast<long>(all.rows() - 2 * ad.s), primary_first = static_cast<long>(ad.abridged.size());
  out.secondary_first_class = first - primary_first;
}

/// §7 (CEF App. A, Thm 7.4): the Pontryagin system embedded in T*TQ, S' = {ν = 0}, leaves κ·q = C;
/// its constraints adapted to the primary ones.
template <class T>
void exact_foliated(SolveReport& out, const io::CaseFile& c) {
  namespace ref = dcad::reference;
  const io::PontryaginInput& p = c.pontryagin;
  const ref::FoliatedEmbedding<T> f = ref::tangent_cotangent_embedding(
      ref::PontryaginInput<T>{p.n, lift<T>(p.k), lift<T>(p.vv), lift<T>(p.qv), lift<T>(p.qq), lift<T>(p.q), lift<T>(p.v)});
  const ref::CadResult<T> rf = ref::foliated_tower(f);
  const ref::Matrix<T> secondary = ref::secondary_constraints(rf);
  out.adapted_setting = "T*TQ";
  out.adapted_variables = c.variables;
  for (std::size_t i = 0; i < p.n; ++i) out.adapted_variables.push_back("nu_" + c.variables[p.n + i]);
  exact_adapted(out, f.omega, f.primary, secondary, f.leaf);
}

/// The equations of motion (5.12) into the report.
template <class T>
void keep_reduced(SolveReport& out, const reference::ReducedEquations<T>& red) {
  out.has_reduced = true;
  out.coords = red.coords;
  for (reference::Index i = 0; i < red.coords.size(); ++i) {
    out.f_matrix.push_back({});
    for (reference::Index j = 0; j < red.coords.size(); ++j) out.f_matrix.back().push_back(Scalar<T>::text(red.f_matrix(i, j)));
    out.f.push_back(Scalar<T>::text(red.f[i]));
    out.g.push_back({});
    for (reference::Index j = 0; j < red.g.cols(); ++j) out.g.back().push_back(Scalar<T>::text(red.g(i, j)));
  }
}

template <class T>
SolveReport solve_exact(const io::CaseFile& c, const Parts& parts = {}) {
  if (c.has_pontryagin && c.pontryagin.has_forces)  // the unforced pipeline must never drop them silently
    throw std::invalid_argument("a case with `forces` goes by the forced route (solve_forced_case), not this one");
  namespace ref = dcad::reference;
  const ref::LinearSystem<T> s = exact_system<T>(c);
  const ref::Matrix<T> primary = c.has_constrained ? lift<T>(c.constrained.primary) : ref::Matrix<T>();
  const ref::CadResult<T> r = ref::constraint_tower(s, primary);
  SolveReport out;
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
  if (r.consistent && parts.final_constraints) {
    const ref::Matrix<T> a = ref::annihilator(r.final_step().m.direction).basis();  // M_c = {a x = a·point}
    const std::vector<T>& point = r.final_step().m.point;
    ref::Matrix<T> rows(a.rows(), c.n + 1);
    for (ref::Index i = 0; i < a.rows(); ++i) {
      for (ref::Index j = 0; j < c.n; ++j) {
        rows(i, j) = a(i, j);
        rows(i, c.n) += a(i, j) * point[j];
      }
      out.final_constraints.push_back(row_equation(rows, i));
    }
    out.has_final_constraints = true;
    Scalar<T>::keep_final(out, r.final_step().m.direction.basis(), point);
  }
  if (c.has_constrained && r.consistent && parts.classes) {  // first and second class on M_c, Dirac bracket  [Lemma 3.23]
    ref::Matrix<T> all(0, c.n + 1);
    for (const auto& st : r.tower) all = ref::vstack(all, st.equations);
    const ref::Matrix<T> w = lift<T>(c.constrained.w);
    const ref::ConstraintClasses<T> cl = ref::classify_constraints(w, all);
    out.second_class = static_cast<long>(2 * cl.s);
    out.first_class = static_cast<long>(all.rows() - 2 * cl.s);
    for (ref::Index i : cl.second) out.second_class_constraints.push_back(row_equation(all, i));
    for (ref::Index i = 0; i < c.n; ++i) {
      out.dirac_bracket.push_back({});
      for (ref::Index j = 0; j < c.n; ++j) out.dirac_bracket.back().push_back(Scalar<T>::text(cl.dirac_tensor(i, j)));
    }
  }
  if (c.has_constrained && r.consistent && parts.adapted) {  // Theorem 3.28 on N
    const ref::Matrix<T> w = lift<T>(c.constrained.w);
    const ref::Matrix<T> secondary = ref::secondary_constraints(r);
    out.adapted_setting = "N";
    out.adapted_variables = c.variables;
    exact_adapted(out, w, r.tower[0].equations, secondary, ref::Matrix<T>(0, c.n + 1));
  }
  if (c.has_pontryagin && r.consistent && parts.adapted) exact_foliated<T>(out, c);
  if (r.consistent && parts.reduced) keep_reduced(out, ref::reduced_equations(s, r, c.coordinates));
  return out;
}

}  // namespace dcad::cli
