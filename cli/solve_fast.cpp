#include "dcad/fast/adapted.hpp"
#include "dcad/fast/exact.hpp"
#include "solve.hpp"

#include <Eigen/LU>

#include <cmath>
#include <sstream>

namespace dcad::cli {

namespace fa = dcad::fast;

namespace {

/// `why_uncertain`: set when an input property could not be decided (a result, not bad input).
fa::LinearSystem fast_system(const io::CaseFile& c, fa::Options& opt, std::string& why_uncertain) {
  if (c.has_constrained) {
    const Eigen::MatrixXd w = fa::to_double(c.constrained.w, opt), prim = fa::to_double(c.constrained.primary, opt);
    const Truth symplectic = fa::is_symplectic(w, opt);  // degenerate: bad input; undecided: the result says so
    if (symplectic.no())
      throw std::invalid_argument("solve: expected a nondegenerate form, found " + fa::decide_rank(w, -1, opt).describe());
    if (symplectic.unknown())
      why_uncertain = "whether the symplectic form is nondegenerate is uncertain (" + fa::decide_rank(w, -1, opt).describe() + ")";
    fa::LinearSystem s = fa::gotay_nester_system({w, fa::to_double(c.energy.hessian, opt), fa::to_double(c.energy.gradient, opt), prim}, opt);
    s.constant = c.energy.constant.convert_to<double>();
    return s;
  }
  if (c.has_pontryagin) {
    const io::PontryaginInput& p = c.pontryagin;
    return fa::pontryagin_system(fast::to_fast(p, opt), opt);
  }
  fa::DiracStructure d = fast::to_fast(c.dirac, opt);
  if (c.dirac.form == "basis") {  // certainly not Dirac: bad input; uncertain: the result says so
    fa::require_dirac(d, "solve", opt);
    d.d.and_certain(fa::dirac_defect(d, opt).valid);  // not no: require_dirac threw
  }
  return {d, fa::to_double(c.energy.hessian, opt), fa::to_double(c.energy.gradient, opt), c.energy.constant.convert_to<double>()};
}

}  // namespace

/// Theorem 3.28 on (W, [primary; secondary; leaf]) by the fast backend; rows shown as in the tower.
void fast_adapted(SolveReport& out, const Eigen::MatrixXd& w, const Eigen::MatrixXd& prim, const Eigen::MatrixXd& secondary,
                  const Eigen::MatrixXd& leaf, const fa::Options& opt) {
  const fa::AdaptedToPrimary to = fa::adapted_to_primary(w, prim, secondary, leaf, opt);
  const Eigen::MatrixXd& all = to.constraints;
  const fa::AdaptedConstraints& ad = to.adapted;
  out.certified = out.certified && ad.certain.yes();
  out.has_adapted = true;
  out.s_prime = ad.s_prime;
  const auto row = [&](int i) {
    Equation e;
    for (Eigen::Index j = 0; j + 1 < all.cols(); ++j)
      if (std::abs(all(i, j)) > 1e-13) e.terms.emplace_back(j, float_text(all(i, j)));
    e.rhs = float_text(all(i, all.cols() - 1));
    return e;
  };
  for (int i : ad.chi) out.adapted_chi.push_back(row(i));
  for (int k : ad.abridged) out.abridged_terms.push_back(row(k));
  out.secondary_first_class = static_cast<long>(all.rows()) - 2 * ad.s - static_cast<long>(ad.abridged.size());
}

SolveReport solve_fast(const io::CaseFile& c, const Parts& parts) {
  if (c.has_pontryagin && c.pontryagin.has_forces)  // the unforced pipeline must never drop them silently
    throw std::invalid_argument("a case with `forces` goes by the forced route (solve_forced_case), not this one");
  fa::Options opt;
  std::string why_uncertain;
  const fa::LinearSystem s = fast_system(c, opt, why_uncertain);
  fa::Options in_opt = opt;
  const Eigen::MatrixXd initial = c.has_constrained ? fa::to_double(c.constrained.primary, in_opt) : Eigen::MatrixXd();
  const fa::CadResult r = fa::constraint_tower(s, opt, initial);
  SolveReport out;
  out.backend = "fast";
  out.certified = r.certain.yes();
  out.consistent = r.consistent;
  out.steps = r.steps;
  out.solution_rank = r.solution_rank;
  out.decisions_float = static_cast<long>(r.decisions.size());
  for (const auto& st : r.tower) {
    SolveReport::Step step;
    step.dim = st.dim();
    for (Eigen::Index i = 0; i < st.equations.rows(); ++i) {
      Equation e;
      // display only: coefficients at rounding level of this (unit) row are shown as absent
      for (Eigen::Index j = 0; j + 1 < st.equations.cols(); ++j)
        if (std::abs(st.equations(i, j)) > 1e-13) e.terms.emplace_back(j, float_text(st.equations(i, j)));
      e.rhs = float_text(st.equations(i, st.equations.cols() - 1));
      step.equations.push_back(e);
    }
    out.dims.push_back(step.dim);
    out.tower.push_back(step);
  }
  // the classes and the adapted constraints need Ω⁻¹: not from a form whose nondegeneracy is undecided
  const bool invertible = why_uncertain.empty();
  if (c.has_constrained && r.consistent && parts.classes && invertible) {  // 2s = rank {φ_i, φ_j} on M_c, decided
    Eigen::MatrixXd a(0, c.n);
    for (const auto& st : r.tower) {
      Eigen::MatrixXd more(a.rows() + st.equations.rows(), c.n);
      more << a, st.equations.leftCols(c.n);
      a = more;
    }
    const Eigen::MatrixXd j = fa::to_double(c.constrained.w, in_opt).transpose().inverse();
    const fa::RankDecision d = fa::decide_rank(a * j * a.transpose(), fa::norm2(j), opt);
    out.certified = out.certified && d.certain.yes();
    out.second_class = d.rank;
    out.first_class = a.rows() - d.rank;
  }
  if (c.has_constrained && r.consistent && parts.adapted && invertible) {  // Theorem 3.28 on N
    out.adapted_setting = "N";
    out.adapted_variables = c.variables;
    fast_adapted(out, fa::to_double(c.constrained.w, in_opt), r.tower[0].equations, fa::secondary_constraints(r),
                 Eigen::MatrixXd(0, c.n + 1), opt);
  }
  if (c.has_pontryagin && r.consistent && parts.adapted) {  // §7: S' = {ν = 0} ⊂ T*TQ, leaves κ·q = C
    const std::size_t n = c.pontryagin.n;
    const fa::FoliatedEmbedding f = fa::tangent_cotangent_embedding(fast::to_fast(c.pontryagin, in_opt), opt);
    const fa::CadResult rf = fa::foliated_tower(f, opt);
    out.certified = out.certified && rf.certain.yes();
    out.adapted_setting = "T*TQ";
    out.adapted_variables = c.variables;
    for (std::size_t i = 0; i < n; ++i) out.adapted_variables.push_back("nu_" + c.variables[n + i]);
    if (rf.consistent) fast_adapted(out, f.omega, f.primary, fa::secondary_constraints(rf), f.leaf, opt);
  }
  if (r.consistent && parts.reduced) {
    std::vector<int> coords(c.coordinates.begin(), c.coordinates.end());
    const fa::ReducedEquations red = fa::reduced_equations(s, r, coords, opt);
    out.certified = out.certified && red.certain.yes();
    out.has_reduced = true;
    out.coords.assign(red.coords.begin(), red.coords.end());
    // display: entries at rounding level relative to the largest are shown as 0
    const double tiny = 1e-13 * (1 + (red.f_matrix.size() ? red.f_matrix.cwiseAbs().maxCoeff() : 0.0) +
                                  (red.f.size() ? red.f.cwiseAbs().maxCoeff() : 0.0));  // M_c may be a point
    const auto shown = [&](double x) { return float_text(std::abs(x) <= tiny ? 0.0 : x); };
    for (std::size_t i = 0; i < red.coords.size(); ++i) {
      out.f_matrix.push_back({});
      for (std::size_t j = 0; j < red.coords.size(); ++j) out.f_matrix.back().push_back(shown(red.f_matrix(i, j)));
      out.f.push_back(shown(red.f(i)));
      out.g.push_back({});
      for (Eigen::Index j = 0; j < red.g.cols(); ++j) out.g.back().push_back(float_text(red.g(i, j)));
    }
  }
  if (!why_uncertain.empty()) {
    out.certified = false;
    if (c.has_constrained && (parts.classes || parts.adapted)) why_uncertain += "; constraint classes and adapted constraints not computed";
  }
  const std::string caveat = fast::input_caveat(opt);
  if (!out.certified)
    out.note = (!why_uncertain.empty() ? why_uncertain
                : !caveat.empty()      ? caveat
                                       : std::string("a rank decision fell between the zero and nonzero thresholds")) +
               " (see `dcad solve --backend certified`)";
  return out;
}

}  // namespace dcad::cli
