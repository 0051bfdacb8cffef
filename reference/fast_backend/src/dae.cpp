// The linear DAE form E ẋ = A x + f(t) by the fast twin: Wong sequences on orthonormal bases, a
// different route from the reference's RREF of left null vectors (reference/linear_ide.hpp).
//   V_0 = R^N, V_{k+1} = A⁻¹(E V_k) = {x : A x ∈ E V_k}   (Wong 1974; the limit V* is the largest
//   subspace with A V* ⊆ E V*).  For f ≡ 0 this is CEF (1.6) itself: M_{k+1} = M_k ∩ A⁻¹(E M_k), and
//   A⁻¹(E V_k) ⊆ A⁻¹(E V_{k−1}) = V_k by induction, so the intersection is the preimage.  With
//   sources, M_k(t) = p_k(t) + V_k where nonempty: the directions, hence dims, are the same.
//   W_0 = {0}, W_{i+1} = E⁻¹(A W_i); a square pencil sE − A is regular iff V* ⊕ W* = R^N (Berger,
//   Ilchmann & Trenn, "The quasi-Kronecker form for matrix pencils", LAA 436 (2012), Thm 2.6 and
//   Cor. 2.9) — a second route to regularity besides the reference's det(sE − A) at N + 1 points.
//   solution rank = dim(ker E ∩ V_c) = dim V_c − rank(E V_c).
// Every rank is a decision of fast/rank.hpp with its evidence; `certified` says whether all were certain.
// Consistency with sources: a regular pencil is solvable for every f; a singular or rectangular one
// with f ≢ 0 has conditions on f (0 = Σ c f_i^(d)(t)) that fast does not decide — those come from the
// exact route (the note says so).
#include "dcad/fast/exact.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/fast/subspace.hpp"
#include "dcad/reference/pipeline/dae.hpp"

namespace dcad::fast {

namespace {

/// Orthonormal rows n ∈ V_k with n ⊥ V_{k+1}: the equations n·x = 0 that cut V_{k+1} out of V_k.
MatrixXd cut_rows(const Subspace& vk, const Subspace& vnext) {
  const MatrixXd inside = vk.columns().transpose() * vnext.columns();  // V_{k+1} in V_k's coordinates
  const MatrixXd rest = orthogonal_complement(inside);  // inside has orthonormal columns (V_{k+1} ⊆ V_k)
  return (vk.columns() * rest).transpose();
}

}  // namespace

Solution solve_dae_sparse(const io::DaeCase& c, const Options& opt_in);

bool has_sources(const io::DaeCase& c) {
  for (const auto& fi : c.f)
    if (!reference::expr::is_number(fi, 0)) return true;
  return false;
}

bool exact_source_conditions(const io::DaeCase& c, Solution& out) {
  const dcad::Solution<reference::Rational> exact = reference::pipeline::solve_dae(c);
  out.source_conditions = exact.source_conditions;
  if (!exact.consistent) {  // M_k = ∅: the tower ends there
    out.consistent = false;
    out.steps = exact.steps;
    out.tower.resize(static_cast<std::size_t>(exact.steps));
    out.tower.push_back({-1, {}});
    out.solution_rank.reset();
  }
  return !exact.certified.unknown();
}

Solution dae_solution(const io::DaeCase& c) {
  Solution out;
  out.backend = Backend::fast;
  out.file = c.file;
  out.name = c.name;
  out.variables = c.variables;
  out.algorithm = Algorithm::implicit_equation;
  out.tower.push_back({static_cast<long>(c.variables.size()), {}});
  return out;
}

/// ẋ = X x + K λ on M_c = V_c (`constrained`: V_c is not the whole space): X the minimum-norm solution
/// of [E; C_c] v = [A x; 0], K spanning ker E ∩ V_c; its rank decision counted in `certain`, `trace`.
static Motion<double> dae_motion(const MatrixXd& e, const MatrixXd& a, const Subspace& vc, bool constrained,
                                 double scale, const Options& opt, Truth& certain, std::vector<Decision>& trace) {
  const int n = static_cast<int>(e.cols());
  const MatrixXd cc = constrained ? MatrixXd(orthogonal_complement(vc.columns()).transpose()) : MatrixXd(0, n);
  MatrixXd stacked(e.rows() + cc.rows(), n), rhs = MatrixXd::Zero(e.rows() + cc.rows(), n);
  stacked << e, cc;
  rhs.topRows(e.rows()) = a;
  const RankRevealing rr(stacked, scale, opt);
  trace.push_back(traced(rr.decision(), "motion: rank [E; C_c] (CEF (5.12))"));
  certain &= rr.decision().certain;
  const MatrixXd x = rr.solve_range(rhs);
  const Subspace ker = kernel(e, opt);
  trace.push_back(traced(ker, "motion: ker E"));
  const Subspace gauge = intersection(ker, vc, opt);  // G: its certainty is the answer's too
  trace.push_back(traced(gauge, "motion: the free directions ker E ∩ V_c"));
  certain &= gauge.certain();
  Motion<double> mo;
  for (int i = 0; i < n; ++i) mo.coordinates.push_back(static_cast<std::size_t>(i));
  mo.f_matrix.assign(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(n)));
  mo.f.assign(static_cast<std::size_t>(n), 0.0);
  mo.g.assign(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(gauge.dim())));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) mo.f_matrix[i][j] = x(i, j);
    for (int j = 0; j < gauge.dim(); ++j) mo.g[i][j] = gauge.columns()(i, j);
  }
  return mo;
}

Solution solve_dae(const io::DaeCase& c, const Options& opt_in) {
  if (!c.dense || static_cast<long>(c.variables.size()) >= opt_in.dae_sparse_from) return solve_dae_sparse(c, opt_in);
  Options opt = opt_in;
  const MatrixXd e = to_double(c.e, opt), a = to_double(c.a, opt);
  assess_input(e, opt);
  assess_input(a, opt);
  const int n = static_cast<int>(e.cols());
  const double scale = std::max({norm2(e), norm2(a), 1e-300});
  Truth certain = yes;
  std::vector<Decision> trace;
  std::vector<Subspace> v{Subspace::whole(n)};
  for (;;) {  // the first Wong sequence
    const Subspace ev = map(e, v.back(), opt);
    Subspace next = preimage(a, ev, opt, scale);
    const std::string k = std::to_string(v.size());
    trace.push_back(traced(ev, "Wong: E V_" + std::to_string(v.size() - 1)));
    trace.push_back(traced(next, "Wong: V_" + k + " = A^-1(E V_" + std::to_string(v.size() - 1) + ")"));
    certain &= ev.certain() & next.certain();
    if (next.dim() >= v.back().dim()) break;  // V_{k+1} = V_k (never larger: nested)
    v.push_back(std::move(next));
  }
  const bool has_f = has_sources(c);
  Solution out = dae_solution(c);
  for (std::size_t k = 1; k < v.size(); ++k) {
    Level<double> level;
    level.dim = v[k].dim();
    if (!has_f) {  // with sources the right-hand sides are the exact route's (jets); fast gives the directions
      const MatrixXd rows = cut_rows(v[k - 1], v[k]);
      for (Eigen::Index i = 0; i < rows.rows(); ++i) {
        Equation<double> eq;
        for (int j = 0; j < n; ++j)
          if (rows(i, j) != 0) eq.terms.emplace_back(static_cast<std::size_t>(j), rows(i, j));
        level.constraints.push_back(eq);
      }
    }
    out.tower.push_back(level);
  }
  out.steps = static_cast<long>(v.size()) - 1;
  const Subspace& vc = v.back();
  const RankRevealing evc(e * vc.columns(), scale, opt);
  trace.push_back(traced(evc.decision(), "solution rank: rank E V_c (CEF Thm 5.4(b))"));
  certain &= evc.decision().certain;
  out.solution_rank = vc.dim() - evc.rank();
  if (e.rows() == e.cols()) {  // the second Wong sequence and V* ⊕ W* = R^N
    Subspace w = Subspace::zero(n);
    for (int i = 0; i <= n; ++i) {
      const Subspace aw = map(a, w, opt);
      Subspace next = preimage(e, aw, opt, scale);
      trace.push_back(traced(aw, "second Wong sequence: A W_" + std::to_string(i)));
      trace.push_back(traced(next, "second Wong sequence: W_" + std::to_string(i + 1)));
      certain &= aw.certain() & next.certain();
      if (next.dim() <= w.dim()) break;
      w = std::move(next);
    }
    const Subspace both = sum(vc, w, opt);
    trace.push_back(traced(both, "regular pencil: dim(V* + W*)"));
    certain &= both.certain();
    out.regular_pencil = vc.dim() + w.dim() == n && both.dim() == n;
  }
  std::string note = "Wong sequences V_{k+1} = A^-1(E V_k) on orthonormal bases (reference/fast_backend/src/dae.cpp)";
  const bool regular = out.regular_pencil && *out.regular_pencil;
  if (has_f && !regular) {  // conditions on the sources: the exact route decides them
    if (!exact_source_conditions(c, out)) certain = unknown;
    note += "; the conditions on the sources (a singular or rectangular pencil with f) decided by the exact route";
  }
  if (out.consistent && !has_f) out.motion = dae_motion(e, a, vc, v.size() > 1, scale, opt, certain, trace);
  out.decisions.float_tests = static_cast<long>(trace.size());
  out.trace = std::move(trace);
  out.certified = certain;
  const std::string caveat = input_caveat(opt);
  out.note = note + (caveat.empty() ? "" : "; " + caveat) +
             (certain.yes() ? "" : "; a rank decision was not certain (uncertain result)");
  return out;
}

}  // namespace dcad::fast
