#include "dcad/fast/dirac_bergmann.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <stdexcept>

namespace dcad::fast {

MatrixXd poisson_tensor(const MatrixXd& w, const Options& opt_in, Truth& certain) {
  const Options opt = assessed(opt_in, {w});
  certain &= require_symplectic(w, "poisson_tensor", opt);
  return w.transpose().fullPivLu().inverse();
}

DiracBergmannResult dirac_bergmann(const ConstrainedSystem& s, const Options& opt_in) {
  const Options opt = assessed(opt_in, {s.omega, s.hessian, s.gradient, s.primary});
  const int n = static_cast<int>(s.omega.rows());
  if (s.primary.cols() != n + 1)
    throw std::invalid_argument("dirac_bergmann: expected primary constraint rows [a | b] of width " +
                                std::to_string(n + 1) + ", found width " + std::to_string(s.primary.cols()));
  DiracBergmannResult out;
  const MatrixXd j = poisson_tensor(s.omega, opt, out.certain);
  const MatrixXd p = s.primary.leftCols(n);
  const double jn = norm2(j);
  MatrixXd a(0, n);
  VectorXd b(0);
  std::vector<RankDecision> trace;
  if (absorb_equations(a, b, p, s.primary.col(n), std::max(norm2(p), 1e-300), s.primary.col(n).norm(), opt, trace,
                       out.certain) < 0) {
    out.consistent = false;
    AffineSubspace empty;
    out.tower.push_back(empty);
    return out;
  }
  out.tower.push_back(affine_from_orthonormal(a, b));
  const double hscale = jn * std::max(norm2(s.hessian), s.gradient.norm());
  for (;;) {
    const MatrixXd c = a * j * p.transpose();  // {φ_j, φ_i}: rows the orthonormal constraints, cols primary
    const Svd sc = full_svd(c);
    const RankDecision dc = decide_rank(c, sc.sigma, jn * std::max(1.0, norm2(p)), opt);
    out.certain &= dc.certain;
    const MatrixXd mu = sc.u.rightCols(c.rows() - dc.rank).transpose();  // μ C = 0
    const MatrixXd ca = mu * a * j * s.hessian;
    const VectorXd cb = -(mu * a * j * s.gradient);
    const double xscale = hscale * (1 + out.tower.back().point.norm());
    const int added = absorb_equations(a, b, ca, cb, hscale, xscale, opt, trace, out.certain);
    if (added < 0) {
      out.consistent = false;
      out.tower.push_back(AffineSubspace());
      break;
    }
    if (added == 0) break;
    out.tower.push_back(affine_from_orthonormal(a, b));
  }
  out.constraints.resize(a.rows(), n + 1);
  out.constraints << a, b;
  return out;
}

AffineSubspace multipliers(const ConstrainedSystem& s, const DiracBergmannResult& r, const VectorXd& x,
                           const Options& opt_in) {
  const Options opt = assessed(opt_in, {s.omega, s.hessian, s.gradient, s.primary});  // x: a point of M_c, not data
  const int n = static_cast<int>(s.omega.rows());
  Truth nondegenerate = yes;
  const MatrixXd j = poisson_tensor(s.omega, opt, nondegenerate), a = r.constraints.leftCols(n),
                 p = s.primary.leftCols(n);
  const MatrixXd c = a * j * p.transpose();
  // each side at the scale of its factors: −A J (H x + g) is exactly 0 off im C on M_c, and its rounding
  // grows with ‖H‖‖x‖ (at ‖x‖ = 10^7 the residue was decided a certain inconsistency against ‖J‖ alone)
  const double aj = norm2(a) * norm2(j);
  AffineSubspace out = solve(c, -(a * j * (s.hessian * x + s.gradient)), opt, aj * std::max(1.0, norm2(p)),
                             aj * (norm2(s.hessian) * x.norm() + s.gradient.norm()));
  out.certain &= nondegenerate & r.certain;
  return out;
}

ConstraintClasses classify_constraints(const MatrixXd& w, const MatrixXd& constraints, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w, constraints});
  const int n = static_cast<int>(w.rows());
  ConstraintClasses out;
  const MatrixXd j = poisson_tensor(w, opt, out.certain);
  // orthonormal basis of the constraint gradients, carrying the right-hand sides along
  const Svd sv = full_svd(constraints.leftCols(n));
  const RankDecision dr = decide_rank(constraints.leftCols(n), sv.sigma, -1, opt);
  out.certain &= dr.certain;
  const MatrixXd t = (sv.u.leftCols(dr.rank) * sv.sigma.head(dr.rank).cwiseInverse().asDiagonal()).transpose();
  const MatrixXd basis = t * constraints;  // rows [q_i | β_i], q orthonormal
  const MatrixXd q = basis.leftCols(n);
  const MatrixXd c = q * j * q.transpose();
  const Svd sc = full_svd(c);
  const RankDecision ds = decide_rank(c, sc.sigma, norm2(j), opt);
  out.certain &= ds.certain;
  if (ds.rank % 2 != 0) out.certain = unknown;  // the rank of a skew matrix is even: rounding decided this one
  out.s = ds.rank / 2;
  // first class: the null space of C (C is skew: left = right); second class: its complement
  out.first = sc.v.rightCols(c.cols() - ds.rank).transpose() * basis;
  out.second = sc.v.leftCols(ds.rank).transpose() * basis;
  const MatrixXd g = out.second.leftCols(n);
  out.dirac_tensor =
      g.rows() ? MatrixXd(j - j * g.transpose() * (g * j * g.transpose()).fullPivLu().inverse() * g * j) : j;
  return out;
}

LinearSystem gotay_nester_system(const ConstrainedSystem& s, const Options& opt_in) {
  const Options opt = assessed(opt_in, {s.omega, s.hessian, s.gradient, s.primary});
  return {dirac_from_distribution(kernel(s.primary.leftCols(s.omega.rows()), opt), s.omega), s.hessian, s.gradient,
          0.0};
}

CadResult gotay_nester(const ConstrainedSystem& s, const Options& opt_in) {
  const Options opt = assessed(opt_in, {s.omega, s.hessian, s.gradient, s.primary});
  return constraint_tower(gotay_nester_system(s, opt), opt, s.primary);
}

MatrixXd secondary_constraints(const CadResult& r) {
  MatrixXd out(0, r.tower.front().equations.cols());
  for (std::size_t k = 1; k < r.tower.size(); ++k) {
    MatrixXd more(out.rows() + r.tower[k].equations.rows(), out.cols());
    more << out, r.tower[k].equations;
    out = more;
  }
  return out;
}

SecondClassChoice second_class_choice(const MatrixXd& w, const AffineSubspace& s, const Subspace& v,
                                      const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  SecondClassChoice out;
  const Subspace kerw = form_kernel(restrict_form(w, s.direction), opt);
  const Subspace comp = symplectic_complement(w, s.direction, opt);
  const Subspace both = sum(v, kerw, opt);
  const Truth complement = equal(both, comp, opt);
  out.certain = s.certain & v.certain() & kerw.certain() & comp.certain() & complement;
  if (both.dim() != v.dim() + kerw.dim()) out.certain = unknown;  // V ∩ ker ω ≠ 0, or a rank off
  if (complement.no())
    throw std::invalid_argument(
        "second_class_choice: expected V with V ⊕ ker ω = (TS)^Ω (CEF (3.12)), found another subspace");
  out.tangent = symplectic_complement(w, v, opt);
  out.certain &= out.tangent.certain();
  const int n = static_cast<int>(w.rows());
  const MatrixXd a = v.columns().transpose() * w;  // row i: y ↦ Ω(v_i, y)
  out.chi.resize(a.rows(), n + 1);
  out.chi << a, a * s.point;
  Truth nondegenerate = yes;
  out.sigma = a * poisson_tensor(w, opt, nondegenerate) * a.transpose();
  const MatrixXd& q = out.tangent.columns();
  const MatrixXd g = q.transpose() * w.transpose() * q;
  const RankDecision d = decide_rank(g, std::max(norm2(w), 1e-300), opt);
  out.certain &= nondegenerate & d.certain;
  if (d.rank < g.rows())
    throw std::invalid_argument("second_class_choice: expected a symplectic V^Ω, found a degenerate one");
  out.dirac_tensor =
      q.rows() > 0 && q.cols() > 0 ? MatrixXd(q * g.fullPivLu().inverse() * q.transpose()) : MatrixXd::Zero(n, n);
  return out;
}

Truth is_first_class_submanifold(const MatrixXd& w, const Subspace& ts, const Options& opt_in) {
  const Options opt = assessed(opt_in, {w});
  Truth certain = ts.certain();
  const MatrixXd j = poisson_tensor(w, opt, certain);
  const MatrixXd a = annihilator(ts).columns().transpose();
  if (a.rows() == 0) return Truth::decided(true, certain);  // S = P
  const RankDecision d = decide_rank(a * j * a.transpose(), std::max(norm2(j), 1e-300), opt);
  certain &= d.certain;
  return Truth::decided(d.rank == 0, certain);
}

Truth weakly_zero(const MatrixXd& constraints, const QuadraticFunction& f, const Options& opt_in) {
  const Options opt = assessed(opt_in, {constraints, f.a, f.b});
  const int n = static_cast<int>(f.a.rows()), k = static_cast<int>(constraints.rows());
  if (k == 0) return f.a.isZero(0) && f.b.isZero(0) && f.c == 0 ? yes : no;  // M_c = N: f ≡ 0 (data, not computed)
  const MatrixXd a = constraints.leftCols(n);
  const VectorXd beta = constraints.col(n);
  // unknowns: N_ip at i * n + p, ν0_i at k n + i;  equations: A_pq (p ≤ q), b_p, c
  const int unknowns = k * n + k, rows = n * (n + 1) / 2 + n + 1;
  MatrixXd m = MatrixXd::Zero(rows, unknowns);
  VectorXd rhs(rows);
  int r = 0;
  for (int p = 0; p < n; ++p)
    for (int q = p; q < n; ++q, ++r) {  // A_pq = Σ_i N_ip a_iq + a_ip N_iq
      for (int i = 0; i < k; ++i) {
        m(r, i * n + p) += a(i, q);
        m(r, i * n + q) += a(i, p);
      }
      rhs(r) = f.a(p, q);
    }
  for (int p = 0; p < n; ++p, ++r) {  // b_p = Σ_i ν0_i a_ip − β_i N_ip
    for (int i = 0; i < k; ++i) {
      m(r, k * n + i) = a(i, p);
      m(r, i * n + p) = -beta(i);
    }
    rhs(r) = f.b(p);
  }
  for (int i = 0; i < k; ++i) m(r, k * n + i) = -beta(i);  // c = −Σ ν0_i β_i
  rhs(r) = f.c;
  const AffineSubspace sol = solve(m, rhs, opt);
  return Truth::decided(!sol.empty, sol.certain);
}

}  // namespace dcad::fast
