#include "dcad/fast/cad.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <stdexcept>

namespace dcad::fast {

LinearSystem pontryagin_energy(const PontryaginInput& in) {
  const MatrixXd &k = in.k, &vv = in.vv, &qv = in.qv, &qq = in.qq;
  const VectorXd &q = in.q, &v = in.v;
  const int n = static_cast<int>(vv.rows());
  if (in.n != vv.rows() || vv.cols() != n || qq.rows() != n || qq.cols() != n || qv.rows() != n || qv.cols() != n ||
      q.size() != n || v.size() != n || (k.rows() && k.cols() != n))
    throw std::invalid_argument("pontryagin_system: expected n = " + std::to_string(in.n) +
                                " rows and columns in vv, qv, qq, entries in q, v and columns in k");
  for (const MatrixXd* m : {&k, &vv, &qv, &qq}) require_finite(*m, "pontryagin_system");
  require_finite(q, "pontryagin_system");
  require_finite(v, "pontryagin_system");
  if (vv != vv.transpose() || qq != qq.transpose())
    throw std::invalid_argument("pontryagin_system: expected symmetric vv and qq, found an asymmetric one");
  MatrixXd h = MatrixXd::Zero(3 * n, 3 * n);
  h.block(0, 0, n, n) = -qq;
  h.block(0, n, n, n) = -qv;
  h.block(n, 0, n, n) = -qv.transpose();
  h.block(n, n, n, n) = -vv;
  h.block(n, 2 * n, n, n).setIdentity();
  h.block(2 * n, n, n, n).setIdentity();
  VectorXd g = VectorXd::Zero(3 * n);
  g.head(n) = -q;
  g.segment(n, n) = -v;
  LinearSystem s;
  s.d.n = 3 * n;
  s.hessian = h;
  s.gradient = g;
  return s;
}

LinearSystem pontryagin_system(const PontryaginInput& in, const Options& opt_in) {
  const Options opt = assessed(opt_in, {in.k, in.vv, in.qv, in.qq, in.q, in.v});
  LinearSystem s = pontryagin_energy(in);  // E = p·v − L, and the input's checks
  const int n = static_cast<int>(in.vv.rows());
  const Subspace delta = in.k.rows() ? kernel(in.k, opt) : Subspace::whole(n);
  MatrixXd e = MatrixXd::Zero(3 * n, delta.dim() + 2 * n);
  e.topLeftCorner(n, delta.dim()) = delta.columns();
  e.bottomRightCorner(2 * n, 2 * n).setIdentity();
  MatrixXd w = MatrixXd::Zero(3 * n, 3 * n);
  w.block(0, 2 * n, n, n).setIdentity();
  w.block(2 * n, 0, n, n) = -MatrixXd::Identity(n, n);
  // the columns of e are orthonormal already: Δ's basis in the q-block, the identity below
  s.d = dirac_from_distribution(Subspace::from_orthonormal_columns(e, delta.certain()), w);
  return s;
}

namespace {

void record(CadResult& r, const RankDecision& d) {
  r.certain &= d.certain;
  r.decisions.push_back(d);
}

}  // namespace

int absorb_equations(MatrixXd& a, VectorXd& b, const MatrixXd& ca, const VectorXd& cb, double scale, double rhs_scale,
                     const Options& opt, std::vector<RankDecision>& trace, Truth& certain) {
  const MatrixXd y = ca * a.transpose();
  const MatrixXd ra = ca - y * a;
  const VectorXd rb = cb - y * b;
  const RankRevealing f(ra.transpose(), scale, opt);  // the new rows: an orthonormal basis of im raᵀ
  RankDecision d = f.decision();
  const int room = static_cast<int>(a.cols() - a.rows());
  if (d.rank > room) {  // more new rows than codimensions left: only rounding can say so
    d.rank = room;
    d.certain = unknown;
  }
  trace.push_back(d);
  const MatrixXd rows = f.range().leftCols(d.rank).transpose();
  // x0: the minimum-norm solution of ra x = rb on the decided rank; what is left of the
  // right-hand side, rb − ra x0, must be 0 (its norm bounds rb's distance from im ra from above)
  const VectorXd x0 = f.min_norm_transposed(rb);
  const VectorXd rest = rb - ra * x0;
  const RankDecision dc = decide_rank(MatrixXd(rest), std::max(rhs_scale, scale), opt);
  certain &= d.certain & dc.certain;
  trace.push_back(dc);
  if (dc.rank > 0) return -1;
  if (d.rank == 0) return 0;
  MatrixXd a2(a.rows() + d.rank, a.cols());
  a2 << a, rows;
  VectorXd b2(b.size() + d.rank);
  b2 << b, rows * x0;
  a = a2;
  b = b2;
  return d.rank;
}

AffineSubspace affine_from_orthonormal(const MatrixXd& a, const VectorXd& b) {
  AffineSubspace m;
  m.empty = false;
  m.point = a.transpose() * b;
  m.direction = Subspace::from_orthonormal_columns(orthogonal_complement(a.transpose()), yes);
  return m;
}

namespace {

/// D in the coordinates of its distribution E = E_D (CEF §4, Prop. 4.3): an orthonormal basis Q_E of
/// E (n×e) and the matrix of ω_D in it, Ω_ij = ω_D(q_i, q_j) = α_i(q_j) for (q_i, α_i) ∈ D — the α_i
/// differ by elements of E° between solutions, which vanish on E.  For a D built as the graph of ω,
/// E = R^n and Ω = ω with nothing to decide.
struct Frame {
  bool whole = false;  ///< E = R^n and Q_E = I
  MatrixXd qe;
  MatrixXd omega;
  double scale = 1;  ///< of Ω's entries, as dirac_form's: ‖α‖ for unit q
  /// Coordinates in E of the columns of x (n×m), and back.
  MatrixXd to_e(const MatrixXd& x) const { return whole ? x : MatrixXd(qe.transpose() * x); }
  MatrixXd from_e(const MatrixXd& y) const { return whole ? y : MatrixXd(qe * y); }
};

Frame frame_of(const DiracStructure& d, const Options& opt, CadResult& out) {
  Frame f;
  out.certain &= d.d.certain();
  if (d.graph_of.size()) {
    f.whole = true;
    f.omega = d.graph_of;
    f.scale = std::max(1.0, norm2(d.graph_of));
    return f;
  }
  const RankRevealing fv(d.v_part(), 1.0, opt);  // E_D = im V, as dirac_distribution decides it
  record(out, fv.decision());
  f.qe = fv.range();
  const MatrixXd alphas = d.alpha_part() * fv.solve_range(f.qe);  // V c_i = q_i, α_i = A c_i
  const MatrixXd g = alphas.transpose() * f.qe;
  f.omega = (g - g.transpose()) / 2;  // skew up to rounding; keep it exactly skew
  f.scale = std::max(1.0, norm2(alphas));
  return f;
}

/// W_k^D in E's coordinates, from its definition (CEF §4, (5.5)–(5.6)): with R_k = Q_Eᵀ A_kᵀ (the
/// equations' rows seen on E), W_k = T M_k ∩ E_D = ker R_kᵀ, and for W ⊆ E_D, D^♭(W) = ω_D^♭(W) + E_D°,
/// so W_k^D = {s ∈ E : ω_D(w, s) = 0 ∀ w ∈ W_k} = ker(W_kᵀ Ω).  Both from orthonormal bases, decided on
/// the data's scale (1 for R, Ω's for Ω W).  Also dim(ker ω_D ∩ T M_k) = dim ker(Ω W_k) = dim W_k −
/// rank(Ω W_k) (Thm 5.4(b)), from the same decision.
struct DOrthogonal {
  MatrixXd basis;      ///< W_k^D, orthonormal columns in E's coordinates
  int kernel_dim = 0;  ///< dim(ker ω_D ∩ W_k)
};

DOrthogonal d_orthogonal(const Frame& f, const MatrixXd& a, const Options& opt, CadResult& out) {
  const Eigen::Index e = f.omega.rows();
  MatrixXd w;  // W_k, orthonormal columns in E's coordinates
  if (a.rows() == 0) {
    w = MatrixXd::Identity(e, e);
  } else if (f.whole) {
    w = orthogonal_complement(a.transpose());  // the rows are orthonormal: nothing to decide
  } else {
    const RankRevealing fr(f.to_e(a.transpose()), 1.0, opt);  // a row may vanish on E
    record(out, fr.decision());
    w = fr.corange();
  }
  const RankRevealing fo(a.rows() == 0 ? f.omega : MatrixXd(f.omega * w), f.scale, opt);  // ker (Ω W)ᵀ = ker Wᵀ Ω
  record(out, fo.decision());
  return {fo.corange(), static_cast<int>(w.cols()) - fo.rank()};
}

}  // namespace

namespace {
/// The given values of a start point, assessed as a caller's data (absent values are no data).
Options assessed_given(const Options& opt, const std::vector<std::optional<double>>& given) {
  VectorXd g = VectorXd::Zero(static_cast<Eigen::Index>(given.size()));
  for (std::size_t i = 0; i < given.size(); ++i)
    if (given[i]) g(static_cast<Eigen::Index>(i)) = *given[i];
  return assessed(opt, {g});
}
}  // namespace

CadResult constraint_tower(const LinearSystem& s, const Options& opt_in, const MatrixXd& initial) {
  const Options opt = assessed(opt_in, {dirac_data(s.d), s.hessian, s.gradient, initial});
  const int n = s.d.n;
  require_finite(s.hessian, "constraint_tower");
  require_finite(s.gradient, "constraint_tower");
  if (s.hessian.rows() != n || s.hessian.cols() != n || s.gradient.size() != n)
    throw std::invalid_argument("constraint_tower: expected an " + std::to_string(n) + "x" + std::to_string(n) +
                                " Hessian and a gradient of length " + std::to_string(n) + ", found other sizes");
  if (s.hessian != s.hessian.transpose())
    throw std::invalid_argument("constraint_tower: expected a symmetric Hessian, found an asymmetric one");
  if (initial.rows() && initial.cols() != n + 1)
    throw std::invalid_argument("constraint_tower: expected initial equations [a | b] of width " +
                                std::to_string(n + 1) + ", found width " + std::to_string(initial.cols()));
  CadResult out;
  const Frame frame = frame_of(s.d, opt, out);
  const double hscale = std::max(norm2(s.hessian), s.gradient.norm());
  MatrixXd a(0, n);  // orthonormal rows
  VectorXd b(0);
  const auto push_empty = [&] {
    CadStep empty;
    empty.m.empty = true;
    empty.equations = MatrixXd(0, n + 1);
    out.tower.push_back(empty);
    out.consistent = false;
  };
  // absorbs candidate equations ca x = cb; returns the new rows' count (−1: inconsistent)
  const auto absorb = [&](const MatrixXd& ca, const VectorXd& cb, double cscale, double xscale) {
    const Eigen::Index before = a.rows();
    const int added = absorb_equations(a, b, ca, cb, cscale, xscale, opt, out.decisions, out.certain);
    if (added > 0) {
      CadStep step;
      step.m = affine_from_orthonormal(a, b);
      step.equations.resize(added, n + 1);
      step.equations << a.bottomRows(a.rows() - before), b.tail(b.size() - before);
      out.tower.push_back(step);
    }
    return added;
  };
  // M_0: R^n, or {initial} (Gotay–Nester), whose rows go through the same reduction as the steps
  if (initial.rows()) {
    if (absorb(initial.leftCols(n), initial.col(n), std::max(norm2(initial.leftCols(n)), 1e-300),
               initial.col(n).norm()) < 0) {
      push_empty();
      out.steps = 0;
      return out;
    }
  }
  if (out.tower.empty()) {  // no initial equations, or each was 0 = 0
    CadStep whole;
    whole.m = affine_from_orthonormal(a, b);
    whole.equations = MatrixXd(0, n + 1);
    out.tower.push_back(whole);
  }
  // M_{k+1} = {x ∈ M_k : ⟨H x + g, u⟩ = 0, u ∈ W_k^D} until no equation is new
  for (;;) {
    const DOrthogonal wd = d_orthogonal(frame, a, opt, out);
    const MatrixXd u = frame.from_e(wd.basis);  // orthonormal
    const MatrixXd ca = u.transpose() * s.hessian;
    const VectorXd cb = -(u.transpose() * s.gradient);
    const double xscale = hscale * (1 + out.tower.back().m.point.norm()) + s.gradient.norm();
    const int added = u.cols() ? absorb(ca, cb, hscale, xscale) : 0;
    if (added < 0) {
      push_empty();
      break;
    }
    if (added == 0) {  // M_{k+1} = M_k = M_c
      out.solution_rank = wd.kernel_dim;
      break;
    }
  }
  out.steps = static_cast<int>(out.tower.size()) - 1;
  return out;
}

ReducedEquations reduced_equations(const LinearSystem& s, const CadResult& r, std::vector<int> coords,
                                   const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(s.d), s.hessian, s.gradient});
  if (!r.consistent) throw std::invalid_argument("reduced_equations: expected a consistent system, found M_c empty");
  const int n = s.d.n;
  const MatrixXd b = r.final_step().m.direction.columns();  // n × m
  const int m = static_cast<int>(b.cols());
  ReducedEquations red;
  if (coords.empty()) {  // greedy: variable j joins if it raises the rank of the selected rows of B
    MatrixXd rows(0, m);
    for (int j = 0; j < n && static_cast<int>(coords.size()) < m; ++j) {
      MatrixXd more(rows.rows() + 1, m);
      more << rows, b.row(j);
      const RankDecision d = decide_rank(more, 1.0, opt);
      red.certain &= d.certain;
      if (d.rank > rows.rows()) {
        rows = more;
        coords.push_back(j);
      }
    }
  }
  if (static_cast<int>(coords.size()) != m)
    throw std::invalid_argument("reduced_equations: expected " + std::to_string(m) + " coordinates (dim M_c), found " +
                                std::to_string(coords.size()));
  MatrixXd sel = MatrixXd::Zero(m, n);
  for (int i = 0; i < m; ++i) sel(i, coords[i]) = 1;
  const MatrixXd t = sel * b;
  const RankDecision dt = decide_rank(t, 1.0, opt);
  if (dt.rank < m)
    throw std::invalid_argument(
        "reduced_equations: expected coordinates that parametrize M_c, found variables that do not");
  red.certain &= dt.certain;
  const MatrixXd tinv = m ? MatrixXd(t.fullPivLu().inverse()) : MatrixXd(0, 0);  // M_c may be a point
  const VectorXd x0 = r.final_step().m.point;
  // (B w, dE) ∈ D ⇔ B w = V c, dE = A c for some c: solve [V; A] c = [B w; dE] — in w and c jointly:
  //   V c − B w = 0,  A c = H (x0 + B y) + g.
  const MatrixXd dv = s.d.v_part(), da = s.d.alpha_part();
  const int k = static_cast<int>(dv.cols());
  MatrixXd lhs = MatrixXd::Zero(2 * n, k + m);
  lhs.topLeftCorner(n, k) = dv;
  lhs.topRightCorner(n, m) = -b;
  lhs.bottomLeftCorner(n, k) = da;
  const RankRevealing fl(lhs.transpose(), 1.0 + norm2(s.hessian), opt);  // ker lhs = (im lhsᵀ)^⊥
  red.certain &= fl.decision().certain;
  MatrixXd rhs_y = MatrixXd::Zero(2 * n, m);
  rhs_y.bottomRows(n) = s.hessian * b;
  VectorXd rhs0 = VectorXd::Zero(2 * n);
  rhs0.tail(n) = s.hessian * x0 + s.gradient;
  const MatrixXd p = fl.min_norm_transposed(rhs_y).bottomRows(m);
  const VectorXd p0 = fl.min_norm_transposed(rhs0).bottomRows(m);
  const MatrixXd kernel_w = fl.corange().bottomRows(m);  // w-parts of the null space
  red.coords = coords;
  red.f_matrix = t * p * tinv;
  red.f = t * p0 - red.f_matrix * (sel * x0);
  if (kernel_w.cols()) {
    const Subspace free = Subspace::span_columns(kernel_w, 1.0, opt);
    red.certain &= free.certain();
    red.g = t * free.columns();
  } else {
    red.g = MatrixXd(m, 0);
  }
  return red;
}

VectorXd energy_differential(const LinearSystem& s, const VectorXd& x) { return s.hessian * x + s.gradient; }

AffineSubspace velocities(const LinearSystem& s, const CadResult& r, const VectorXd& x, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(s.d), s.hessian, s.gradient});  // x: a point of M_c, not data
  const int n = s.d.n;
  // ẋ = B w (B: basis of T M_c); (B w, dE) ∈ D ⇔ Γ_v B w = −Γ_α dE for the equations Γ of D
  const MatrixXd& b = r.final_step().m.direction.columns();
  const MatrixXd g = annihilator(s.d.d).columns();
  const MatrixXd gv = g.topRows(n).transpose(), ga = g.bottomRows(n).transpose();
  // scales of the factors (b orthonormal; dE = Hx + g rounded at ‖H‖‖x‖ + ‖g‖), not of the products:
  // where Γ_v B is rounding residue (T M_c ⊂ ker Γ_v, e.g. a 1-dim E_D), its own norm called it rank 1
  const double de_scale = norm2(s.hessian) * x.norm() + s.gradient.norm();
  const AffineSubspace w = solve(gv * b, -(ga * energy_differential(s, x)), opt, norm2(gv), norm2(ga) * de_scale);
  AffineSubspace out;
  out.empty = w.empty;
  out.certain = w.certain & r.certain;
  out.direction = map(b, w.direction, opt);
  if (!w.empty) out.point = b * w.point;
  return out;
}

InitialPoint consistent_initial_point(const CadResult& r, const std::vector<std::optional<double>>& given,
                                      const Options& opt_in) {
  const Options opt = assessed_given(opt_in, given);
  const int n = static_cast<int>(given.size());
  std::vector<int> rows_of_level;  // equations of the tower, level by level
  int total = 0;
  for (const CadStep& st : r.tower) rows_of_level.push_back(total += static_cast<int>(st.equations.rows()));
  MatrixXd constraints(total, n + 1);
  for (int k = 0, at = 0; k < static_cast<int>(r.tower.size()); at = rows_of_level[k++])
    constraints.middleRows(at, r.tower[k].equations.rows()) = r.tower[k].equations;
  int fixed = 0;
  for (const auto& g : given) fixed += g.has_value();
  InitialPoint out;
  out.certain = r.certain;
  // the given values, the first `rows` equations of the tower and, with `defaults`, the free variables = 0
  const auto system = [&](int rows, bool defaults) {
    const int m = fixed + rows + (defaults ? n - fixed : 0);
    MatrixXd a = MatrixXd::Zero(m, n);
    VectorXd b = VectorXd::Zero(m);
    int at = 0;
    for (int i = 0; i < n; ++i)
      if (given[i]) a(at, i) = 1, b(at++) = *given[i];
    a.middleRows(at, rows) = constraints.topLeftCorner(rows, n);
    b.segment(at, rows) = constraints.col(n).head(rows);
    at += rows;
    if (defaults)
      for (int i = 0; i < n; ++i)
        if (!given[i]) a(at++, i) = 1;
    const AffineSubspace s = solve(a, b, opt);
    out.certain &= s.certain;
    return s;
  };
  if (system(total, false).empty) {
    int lo = 0, hi = total;  // meets(lo), !meets(hi)
    while (hi - lo > 1) {
      const int mid = (lo + hi) / 2;
      (system(mid, false).empty ? hi : lo) = mid;
    }
    out.violated = constraints.row(hi - 1).transpose();
    while (rows_of_level[out.level] < hi) ++out.level;
    return out;
  }
  const AffineSubspace with_defaults = system(total, true);
  out.consistent = true;
  out.point = (with_defaults.empty ? system(total, false) : with_defaults).point;
  return out;
}

}  // namespace dcad::fast
