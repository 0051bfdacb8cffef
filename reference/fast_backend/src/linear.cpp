// The fast twin on a linear case: the CAD in E_D's coordinates (fast/cad.hpp), Gotay–Nester for
// `constrained` cases, the first/second class count, Thm 3.28 / 7.4 and the equations of motion.
#include "dcad/fast/adapted.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/input_error.hpp"

#include <Eigen/LU>

#include <cmath>

namespace dcad::fast {

namespace {

/// E's constant term: no decision reads it, so only exact.hpp's range check applies.
double energy_constant(const io::CaseFile& c) {
  Options range;
  return to_double(c.energy.constant, range);
}

/// `why_uncertain`: set when an input property could not be decided (a result, not bad input).
LinearSystem system_of(const io::CaseFile& c, Options& opt, std::string& why_uncertain, std::vector<Decision>& trace) {
  if (c.has_constrained) {
    const MatrixXd w = to_double(c.constrained.w, opt), prim = to_double(c.constrained.primary, opt);
    const Truth symplectic = is_symplectic(w, opt);  // degenerate: bad input; undecided: the result says so
    if (symplectic.no())
      throw std::invalid_argument("solve: expected a nondegenerate form, found " + decide_rank(w, -1, opt).describe());
    if (symplectic.unknown())
      why_uncertain =
          "whether the symplectic form is nondegenerate is uncertain (" + decide_rank(w, -1, opt).describe() + ")";
    Decision nondegenerate;
    nondegenerate.what = "the symplectic form is nondegenerate (input)";
    nondegenerate.rows = nondegenerate.cols = nondegenerate.rank = w.rows();
    nondegenerate.by = DecidedBy::singular_values;
    nondegenerate.certain = symplectic;
    nondegenerate.evidence = symplectic.yes() ? "full rank, certain" : why_uncertain;
    trace.push_back(nondegenerate);
    LinearSystem s =
        gotay_nester_system({w, to_double(c.energy.hessian, opt), to_double(c.energy.gradient, opt), prim}, opt);
    s.constant = energy_constant(c);
    return s;
  }
  if (c.has_pontryagin) return pontryagin_system(to_fast(c.pontryagin, opt), opt);
  DiracStructure d = to_fast(c.dirac, opt);
  if (c.dirac.form == "basis") {  // certainly not Dirac: bad input; uncertain: the result says so
    d.d.and_certain(require_dirac(d, "solve", opt));
  }
  return {d, to_double(c.energy.hessian, opt), to_double(c.energy.gradient, opt), energy_constant(c)};
}

/// A row of [a | b] (a unit row) as an equation; coefficients at rounding level are shown as absent.
Equation<double> display_row(const MatrixXd& rows, Eigen::Index i) {
  Equation<double> e;
  for (Eigen::Index j = 0; j + 1 < rows.cols(); ++j)
    if (std::abs(rows(i, j)) > 1e-13) e.terms.emplace_back(static_cast<std::size_t>(j), rows(i, j));
  e.rhs = rows(i, rows.cols() - 1);
  return e;
}

/// Theorem 3.28 on (W, [primary; secondary; leaf]).
Adapted<double> adapted_of(const MatrixXd& w, const MatrixXd& prim, const MatrixXd& secondary, const MatrixXd& leaf,
                           const Options& opt, Truth& certain) {
  const AdaptedToPrimary to = adapted_to_primary(w, prim, secondary, leaf, opt);
  const AdaptedConstraints& ad = to.adapted;
  certain &= ad.certain;
  Adapted<double> out;
  out.s_prime = ad.s_prime;
  for (int i : ad.chi) out.chi.push_back(display_row(to.constraints, i));
  for (int k : ad.abridged) out.abridged.push_back(display_row(to.constraints, k));
  out.secondary_first_class =
      static_cast<long>(to.constraints.rows()) - 2 * ad.s - static_cast<long>(ad.abridged.size());
  return out;
}

Rows<double> rows_of(const MatrixXd& m) {
  Rows<double> out(m.rows());
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) out[i].push_back(m(i, j));
  return out;
}

/// The equations of motion on M_c for display: entries at rounding level relative to the largest shown as 0.
Motion<double> motion_of(const ReducedEquations& red) {
  Motion<double> m;
  m.coordinates.assign(red.coords.begin(), red.coords.end());
  const double tiny = 1e-13 * (1 + (red.f_matrix.size() ? red.f_matrix.cwiseAbs().maxCoeff() : 0.0) +
                               (red.f.size() ? red.f.cwiseAbs().maxCoeff() : 0.0));  // M_c may be a point
  const auto shown = [&](double x) { return std::abs(x) <= tiny ? 0.0 : x; };
  m.f_matrix = rows_of(red.f_matrix.unaryExpr(shown));
  for (Eigen::Index i = 0; i < red.f.size(); ++i) m.f.push_back(shown(red.f(i)));
  m.g = rows_of(red.g);
  return m;
}

/// First and second class among the tower's constraints (CEF §2.1, Lemma 3.23): 2s = rank {φ_i, φ_j} =
/// rank A Ω⁻ᵀ Aᵀ, A the constraints' rows, decided with its evidence (certain &= the decision's).
Classes<double> classes_of(const CadResult& r, const MatrixXd& omega, const Options& opt, Truth& certain,
                           std::vector<Decision>& trace) {
  const Eigen::Index n = omega.cols();
  MatrixXd a(0, n);
  for (const CadStep& st : r.tower) {
    MatrixXd more(a.rows() + st.equations.rows(), n);
    more << a, st.equations.leftCols(n);
    a = more;
  }
  const MatrixXd j = omega.transpose().inverse();
  const RankDecision d = decide_rank(a * j * a.transpose(), norm2(j), opt);
  certain &= d.certain;
  trace.push_back(traced(d, "classes: rank of {phi_i, phi_j} = A Omega^-T A^T (CEF Lemma 3.23)"));
  Classes<double> k;
  k.second_class = d.rank;
  k.first_class = a.rows() - d.rank;
  return k;
}
}  // namespace

Solution solve_linear(const io::CaseFile& c, const Parts& parts, const Options& options) {
  if (c.has_pontryagin && c.pontryagin.has_forces)  // the unforced pipeline must never drop them silently
    throw std::invalid_argument("a case with `forces` goes by the forced route, not this one");
  Options opt = options;
  std::string why_uncertain;
  Solution out;
  const LinearSystem s = system_of(c, opt, why_uncertain, out.trace);
  out.trace.push_back(traced(s.d.d, "the Dirac structure D (input, CEF §3.1)"));
  Options in_opt = opt;
  const MatrixXd initial = c.has_constrained ? to_double(c.constrained.primary, in_opt) : MatrixXd();
  const CadResult r = constraint_tower(s, opt, initial);
  out.file = c.file;
  out.name = c.name;
  out.variables = c.variables;
  out.certified = r.certain;
  out.consistent = r.consistent;
  out.steps = r.steps;
  if (r.consistent) out.solution_rank = r.solution_rank;
  out.decisions.float_tests = static_cast<long>(r.decisions.size());
  append_traced(out.trace, r.decisions, "CAD (CEF (5.5)-(5.6))");
  for (const CadStep& st : r.tower) {
    Level<double> level{st.dim(), {}};
    for (Eigen::Index i = 0; i < st.equations.rows(); ++i) level.constraints.push_back(display_row(st.equations, i));
    out.tower.push_back(level);
  }
  // the classes and the adapted constraints need Ω⁻¹: not from a form whose nondegeneracy is undecided
  const bool invertible = why_uncertain.empty();
  if (c.has_constrained && r.consistent && parts.classes && invertible)  // 2s = rank {φ_i, φ_j} on M_c, decided
    out.classes = classes_of(r, to_double(c.constrained.w, in_opt), opt, out.certified, out.trace);
  if (c.has_constrained && r.consistent && parts.adapted && invertible) {  // Theorem 3.28 on N
    Adapted<double> a = adapted_of(to_double(c.constrained.w, in_opt), r.tower[0].equations, secondary_constraints(r),
                                   MatrixXd(0, c.n + 1), opt, out.certified);
    a.setting = "N";
    a.variables = c.variables;
    out.adapted = a;
  }
  if (c.has_pontryagin && r.consistent && parts.adapted) {  // §7: S' = {ν = 0} ⊂ T*TQ, leaves κ·q = C
    const std::size_t n = c.pontryagin.n;
    const FoliatedEmbedding f = tangent_cotangent_embedding(to_fast(c.pontryagin, in_opt), opt);
    const CadResult rf = foliated_tower(f, opt);
    out.certified &= rf.certain;
    append_traced(out.trace, rf.decisions, "CAD on T*TQ (CEF §7)");
    if (rf.consistent) {
      Adapted<double> a = adapted_of(f.omega, f.primary, secondary_constraints(rf), f.leaf, opt, out.certified);
      a.setting = "T*TQ";
      a.variables = c.variables;
      for (std::size_t i = 0; i < n; ++i) a.variables.push_back("nu_" + c.variables[n + i]);
      out.adapted = a;
    }
  }
  if (r.consistent && parts.reduced) {
    const ReducedEquations red =
        reduced_equations(s, r, std::vector<int>(c.coordinates.begin(), c.coordinates.end()), opt);
    out.certified &= red.certain;
    out.motion = motion_of(red);
  }
  if (!why_uncertain.empty()) {
    out.certified = unknown;
    if (c.has_constrained && (parts.classes || parts.adapted))
      why_uncertain += "; constraint classes and adapted constraints not computed";
  }
  const std::string caveat = input_caveat(opt);
  if (out.certified.unknown())
    out.note = (!why_uncertain.empty() ? why_uncertain
                : !caveat.empty()      ? caveat
                                       : std::string("a rank decision fell between the zero and nonzero thresholds")) +
               " (see `dcad solve --backend certified`)";
  return out;
}

}  // namespace dcad::fast
