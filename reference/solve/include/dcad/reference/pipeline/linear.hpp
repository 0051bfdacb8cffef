// The reference pipeline on a linear case (CEF §5 tower, §2.1/Lemma 3.23 classes, Thm 3.28 / 7.4,
// (5.12)), written once over the scalar T: the reference runs it on SmallRational, WideRational and
// FLINT's fmpq (reference/solve), and the certified cascade takes the same runs (dcad::certified).
#pragma once

#include "dcad/reference/adapted.hpp"
#include "dcad/reference/pipeline/numbers.hpp"

#include <stdexcept>

namespace dcad::reference::pipeline {

template <class T>
DiracStructure<T> dirac_of(const io::DiracInput& d) {
  if (d.form == "presymplectic") return dirac_from_presymplectic(lift<T>(d.w));
  if (d.form == "distribution") return dirac_from_distribution(Subspace<T>::span(lift<T>(d.b)), lift<T>(d.w));
  if (d.form == "poisson") return dirac_from_poisson(lift<T>(d.p));
  return {d.g.cols() / 2, Subspace<T>::span(lift<T>(d.g))};  // `basis`: validated by the caller
}

template <class T>
PontryaginInput<T> pontryagin_of(const io::PontryaginInput& p) {
  return {p.n, lift<T>(p.k), lift<T>(p.vv), lift<T>(p.qv), lift<T>(p.qq), lift<T>(p.q), lift<T>(p.v)};
}

/// The case's linear system: D and E (`dirac`), D̄_Δ and E = p·v − L (`pontryagin`, CEF §6), or
/// D_{(T M, Ω)} and E (`constrained`: Gotay–Nester from M_0 = M, CEF §2.2).
template <class T>
LinearSystem<T> system_of(const io::CaseFile& c) {
  const T constant = Numbers<T>::lift(c.energy.constant);
  if (c.has_constrained) {
    const Matrix<T> w = lift<T>(c.constrained.w), prim = lift<T>(c.constrained.primary), h = lift<T>(c.energy.hessian);
    const std::vector<T> g = lift<T>(c.energy.gradient);
    require_symplectic(w, "solve");
    require_regular_primary(ConstrainedSystem<T>{w, h, g, prim}, "solve");
    LinearSystem<T> s = gotay_nester_system(ConstrainedSystem<T>{w, h, g, prim});
    s.constant = constant;
    return s;
  }
  if (c.has_pontryagin) return pontryagin_system(pontryagin_of<T>(c.pontryagin));
  LinearSystem<T> s{dirac_of<T>(c.dirac), lift<T>(c.energy.hessian), lift<T>(c.energy.gradient), constant};
  require_dirac(s.d, "solve");
  return s;
}

/// Theorem 3.28 on (W, [primary; secondary; leaf]) with primary and leaf rows flagged primary.
template <class T>
Adapted<T> adapted_of(const Matrix<T>& w, const Matrix<T>& prim, const Matrix<T>& secondary, const Matrix<T>& leaf) {
  const AdaptedToPrimary<T> to = adapted_to_primary(w, prim, secondary, leaf);
  const Matrix<T>& all = to.constraints;
  const AdaptedConstraints<T>& ad = to.adapted;
  Adapted<T> out;
  out.s_prime = static_cast<long>(ad.s_prime);
  for (Index i : ad.chi) out.chi.push_back(row_equation(all, i));
  for (Index k : ad.abridged) out.abridged.push_back(row_equation(all, k));
  const long first = static_cast<long>(all.rows() - 2 * ad.s), primary_first = static_cast<long>(ad.abridged.size());
  out.secondary_first_class = first - primary_first;
  return out;
}

/// §7 (CEF App. A, Thm 7.4): the Pontryagin system embedded in T*TQ, S' = {ν = 0}, leaves κ·q = C;
/// its constraints adapted to the primary ones, in the variables x and ν_v.
template <class T>
Adapted<T> foliated_adapted(const io::PontryaginInput& p, const std::vector<std::string>& variables) {
  const FoliatedEmbedding<T> f = tangent_cotangent_embedding(pontryagin_of<T>(p));
  const CadResult<T> rf = foliated_tower(f);
  Adapted<T> out = adapted_of(f.omega, f.primary, secondary_constraints(rf), f.leaf);
  out.setting = "T*TQ";
  out.variables = variables;
  for (std::size_t i = 0; i < p.n; ++i) out.variables.push_back("nu_" + variables[p.n + i]);
  return out;
}

template <class T>
Motion<T> motion_of(const ReducedEquations<T>& red) {
  Motion<T> m;
  m.coordinates = red.coords;
  m.f_matrix = dense(red.f_matrix);
  m.f = red.f;
  m.g = dense(red.g);
  return m;
}

/// M_c = {a x = a·point} from its point and direction, as rows [a | b].
template <class T>
Matrix<T> final_rows(const AffineSubspace<T>& mc) {
  const Matrix<T> a = annihilator(mc.direction).basis();
  const Index n = a.cols();
  Matrix<T> rows(a.rows(), n + 1);
  for (Index i = 0; i < a.rows(); ++i)
    for (Index j = 0; j < n; ++j) {
      rows(i, j) = a(i, j);
      rows(i, n) += a(i, j) * mc.point[j];
    }
  return rows;
}

/// The CAD of a linear case, with what `parts` asks for.
template <class T>
dcad::Solution<T> solve_linear(const io::CaseFile& c, const Parts& parts) {
  if (c.has_pontryagin && c.pontryagin.has_forces)  // the unforced pipeline must never drop them silently
    throw std::invalid_argument("a case with `forces` goes by the forced route (solve_forced), not this one");
  const LinearSystem<T> s = system_of<T>(c);
  const Matrix<T> primary = c.has_constrained ? lift<T>(c.constrained.primary) : Matrix<T>();
  const CadResult<T> r = constraint_tower(s, primary);
  dcad::Solution<T> out;
  out.certified = Numbers<T>::exact ? yes : unknown;  // every rank an exact zero test in exact T
  out.file = c.file;
  out.name = c.name;
  out.variables = c.variables;
  out.consistent = r.consistent;
  out.steps = static_cast<long>(r.steps);
  if (r.consistent) out.solution_rank = static_cast<long>(r.solution_rank);
  for (const CadStep<T>& st : r.tower) out.tower.push_back({st.dim(), equations(st.equations)});
  if (r.consistent && parts.final_constraints) {
    out.final_constraints = equations(final_rows(r.final_step().m));
    if constexpr (Numbers<T>::exact)
      out.final_exact = ExactSubspace<T>{dense(r.final_step().m.direction.basis()), r.final_step().m.point};
  }
  if (c.has_constrained && r.consistent &&
      parts.classes) {  // first and second class on M_c, Dirac bracket  [Lemma 3.23]
    Matrix<T> all(0, c.n + 1);
    for (const CadStep<T>& st : r.tower) all = vstack(all, st.equations);
    const ConstraintClasses<T> cl = classify_constraints(lift<T>(c.constrained.w), all);
    Classes<T> k;
    k.second_class = static_cast<long>(2 * cl.s);
    k.first_class = static_cast<long>(all.rows() - 2 * cl.s);
    for (Index i : cl.second) k.second_class_constraints.push_back(row_equation(all, i));
    k.dirac_bracket = dense(cl.dirac_tensor);
    out.classes = k;
  }
  if (c.has_constrained && r.consistent && parts.adapted) {  // Theorem 3.28 on N
    Adapted<T> a =
        adapted_of(lift<T>(c.constrained.w), r.tower[0].equations, secondary_constraints(r), Matrix<T>(0, c.n + 1));
    a.setting = "N";
    a.variables = c.variables;
    out.adapted = a;
  }
  if (c.has_pontryagin && r.consistent && parts.adapted) out.adapted = foliated_adapted<T>(c.pontryagin, c.variables);
  if (r.consistent && parts.reduced) out.motion = motion_of(reduced_equations(s, r, c.coordinates));
  return out;
}

}  // namespace dcad::reference::pipeline
