#include "dcad/fast/vignolo.hpp"

#include <Eigen/LU>
#include <Eigen/QR>

#include <cmath>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

using Eigen::Index;

Index rows_of(const VignoloPoint& d) { return d.g.rows(); }

void check(const VignoloPoint& d, const char* fn) {
  const Index n = static_cast<Index>(d.n), m = rows_of(d);
  const auto fail = [&](const std::string& expected, const std::string& found) {
    throw std::invalid_argument(std::string(fn) + ": expected " + expected + ", found " + found);
  };
  const auto vec = [&](const VectorXd& v, Index len, const char* name) {
    if (v.size() != len)
      fail(std::string(name) + " of length " + std::to_string(len), "length " + std::to_string(v.size()));
    require_finite(v, std::string(fn) + " (" + name + ")");
  };
  const auto mat = [&](const MatrixXd& a, Index r, Index c, const char* name) {
    if (a.rows() != r || a.cols() != c)
      fail(std::string(name) + " " + std::to_string(r) + "x" + std::to_string(c),
           std::to_string(a.rows()) + "x" + std::to_string(a.cols()));
    require_finite(a, std::string(fn) + " (" + name + ")");
  };
  vec(d.qdot, n, "qdot");
  vec(d.lq, n, "lq");
  vec(d.lv, n, "lv");
  vec(d.ltv, n, "ltv");
  if (!std::isfinite(d.lt)) fail("a finite lt", std::to_string(d.lt));
  mat(d.lqv, n, n, "lqv");
  mat(d.lvv, n, n, "lvv");
  if (d.lvv != d.lvv.transpose()) fail("a symmetric lvv (second derivatives)", "an asymmetric one");
  if (m) mat(d.g, m, n, "g");
  vec(d.g0, m, "g0");
  vec(d.phi_t, m, "phi_t");
  if (m) mat(d.phi_q, m, n, "phi_q");
  if (m)
    if (const int r = decide_rank(d.g).rank; r < m)
      fail("independent constraints (rank g = rows, V (2.6))",
           "rank " + std::to_string(r) + " of " + std::to_string(m));
  for (Index s = 0; s < m; ++s) {
    const double phi = d.g.row(s).dot(d.qdot) + d.g0(s);
    const double terms = d.g.row(s).cwiseAbs().dot(d.qdot.cwiseAbs()) + std::abs(d.g0(s));
    if (std::abs(phi) > 64 * 2.220446049250313e-16 * (static_cast<double>(n) + 1) * terms)
      fail("z on the constraint submanifold (g q̇ + g0 = 0, V (2.7a))",
           "constraint " + std::to_string(s) + " = " + std::to_string(phi));
  }
}

/// [φ_t | φ_q | g], dφ on j₁.
MatrixXd dphi_j1(const VignoloPoint& d) {
  const Index n = static_cast<Index>(d.n), m = rows_of(d);
  MatrixXd a(m, 2 * n + 1);
  if (m) a << d.phi_t, d.phi_q, d.g;
  return a;
}

/// The span of `cols`, known to have full column rank (the image of a basis under an injective map): no decision.
Subspace injective_image(const MatrixXd& cols, Truth certain) {
  if (cols.cols() == 0) return Subspace::zero(static_cast<int>(cols.rows()));
  const Eigen::HouseholderQR<MatrixXd> qr(cols);
  const MatrixXd q = qr.householderQ() * MatrixXd::Identity(cols.rows(), cols.cols());
  return Subspace::from_orthonormal_columns(q, certain);
}

/// Z ⌟ Ω_l + c dt ∈ span(χ rows), dt(Z) = 1, dφ Z = 0 (and χ Z = 0): (Z, c) in j₁ × R (c = 0 fixed unless
/// `with_c`).  Ω̃_l = dφ_l ∧ dt + π*Ω_l makes (3.3) this with c = dφ_l(Ẑ) and dt(Ẑ) = 1.
AffineSubspace solve_on_j1(const VignoloPoint& d, bool with_c, bool constrained, bool chetaev_condition,
                           const Options& opt) {
  const Index n = static_cast<Index>(d.n), dim = 2 * n + 1, m = constrained ? rows_of(d) : 0;
  const MatrixXd w = poincare_cartan(d), chi = m ? MatrixXd(d.g * contact_forms(d)) : MatrixXd(0, dim);
  const MatrixXd dphi = m ? dphi_j1(d) : MatrixXd(0, dim);
  const Index extra = with_c ? 1 : 0, unknowns = dim + extra + m;
  const Index eqs = dim + 1 + m + (chetaev_condition ? m : 0);
  MatrixXd a = MatrixXd::Zero(eqs, unknowns);
  VectorXd b = VectorXd::Zero(eqs);
  a.topLeftCorner(dim, dim) = w.transpose();
  if (with_c) a(0, dim) = 1.0;
  a.block(0, dim + extra, dim, m) = -chi.transpose();
  a(dim, 0) = 1.0;
  b(dim) = 1.0;
  a.block(dim + 1, 0, m, dim) = dphi;
  if (chetaev_condition) a.block(dim + 1 + m, 0, m, dim) = chi;
  const double scale = a.norm();
  const AffineSubspace full = solve(a, b, opt, scale, scale);
  AffineSubspace out;
  out.certain = full.certain;
  out.empty = full.empty;
  // the multipliers are functions of (Z, c) (χ's rows are independent): dropping them is injective on the solutions
  out.direction = injective_image(full.direction.columns().topRows(dim + extra), full.direction.certain());
  if (!full.empty) out.point = full.point.head(dim + extra);
  return out;
}

/// (Z, c) ↦ Ẑ = (Z, dL(Z) + c): the field on 𝓛 whose dφ_l is c.
AffineSubspace lift_with_c(const VignoloPoint& d, const AffineSubspace& zc) {
  const Index dim = 2 * static_cast<Index>(d.n) + 1;
  MatrixXd t = MatrixXd::Zero(dim + 1, dim + 1);
  t.topLeftCorner(dim, dim).setIdentity();
  t.block(dim, 0, 1, dim) = lagrangian_differential(d).transpose();
  t(dim, dim) = 1.0;
  AffineSubspace out;
  out.certain = zc.certain;
  out.empty = zc.empty;
  out.direction = injective_image(t * zc.direction.columns(), zc.direction.certain());  // t is invertible
  if (!zc.empty) out.point = t * zc.point;
  return out;
}

Options assessed_point(const VignoloPoint& d, const Options& opt) {
  return assessed(opt,
                  {VectorXd::Constant(1, d.lt), d.qdot, d.lq, d.lv, d.ltv, d.lqv, d.lvv, d.g, d.g0, d.phi_t, d.phi_q});
}

}  // namespace

MatrixXd contact_forms(const VignoloPoint& d) {
  check(d, "contact_forms");
  const Index n = static_cast<Index>(d.n);
  MatrixXd c = MatrixXd::Zero(n, 2 * n + 1);
  c.col(0) = -d.qdot;
  c.block(0, 1, n, n).setIdentity();
  return c;
}

AffineSubspace dynamical_flows(const VignoloPoint& d) {
  check(d, "dynamical_flows");
  const Index n = static_cast<Index>(d.n);
  AffineSubspace out;
  out.empty = false;
  out.point = VectorXd::Zero(2 * n + 1);
  out.point(0) = 1.0;
  out.point.segment(1, n) = d.qdot;
  MatrixXd dir = MatrixXd::Zero(2 * n + 1, n);
  dir.bottomRows(n).setIdentity();
  out.direction = Subspace::from_orthonormal_columns(dir, yes);
  return out;
}

Subspace contact_bundle(const VignoloPoint& d, const Options& opt) {
  const MatrixXd c = contact_forms(d);
  return Subspace::span(c, -1, assessed_point(d, opt));
}

AffineSubspace constraint_velocities(const VignoloPoint& d, const Options& opt) {
  check(d, "constraint_velocities");
  AffineSubspace out;
  out.empty = false;
  out.point = d.qdot;
  out.direction = rows_of(d) ? kernel(d.g, assessed_point(d, opt)) : Subspace::whole(static_cast<int>(d.n));
  out.certain = out.direction.certain();
  return out;
}

Subspace constraint_tangent(const VignoloPoint& d, const Options& opt) {
  check(d, "constraint_tangent");
  return rows_of(d) ? kernel(dphi_j1(d), assessed_point(d, opt)) : Subspace::whole(2 * static_cast<int>(d.n) + 1);
}

AffineSubspace tau_constraint(const VignoloPoint& d, const Options& opt_in) {
  check(d, "tau_constraint");
  const Options opt = assessed_point(d, opt_in);
  const Index n = static_cast<Index>(d.n), m = rows_of(d);
  AffineSubspace w;  // the q̇-rates: g w = −(φ_t + φ_q q̇)
  if (m) {
    const VectorXd rhs = -(d.phi_t + d.phi_q * d.qdot);
    w = solve(d.g, rhs, opt, -1, d.phi_t.norm() + d.phi_q.norm() * d.qdot.norm());
  } else {
    w.empty = false;
    w.point = VectorXd::Zero(n);
    w.direction = Subspace::whole(static_cast<int>(n));
  }
  AffineSubspace out;
  out.empty = w.empty;
  out.certain = w.certain;
  MatrixXd embed = MatrixXd::Zero(2 * n + 1, n);
  embed.bottomRows(n).setIdentity();
  out.direction = Subspace::from_orthonormal_columns(embed * w.direction.columns(), w.direction.certain());
  if (!w.empty) {
    out.point = VectorXd::Zero(2 * n + 1);
    out.point(0) = 1.0;
    out.point.segment(1, n) = d.qdot;
    out.point.tail(n) = w.point;
  }
  return out;
}

Subspace chetaev_bundle(const VignoloPoint& d, const Options& opt) {
  const MatrixXd c = contact_forms(d);
  if (!rows_of(d)) return Subspace::zero(2 * static_cast<int>(d.n) + 1);
  return Subspace::span(d.g * c, -1, assessed_point(d, opt));
}

MatrixXd lagrangian_bundle_form(const VignoloPoint& d) {
  check(d, "lagrangian_bundle_form");
  const Index n = static_cast<Index>(d.n), dim = 2 * n + 2;
  MatrixXd dp = MatrixXd::Zero(n, dim), om = MatrixXd::Zero(n, dim);  // rows dp_i and ω^i
  dp.col(0) = d.ltv;
  dp.block(0, 1, n, n) = d.lqv;
  dp.block(0, 1 + n, n, n) = d.lvv;
  om.col(0) = -d.qdot;
  om.block(0, 1, n, n).setIdentity();
  VectorXd p = VectorXd::Zero(dim), et = VectorXd::Zero(dim), eu = VectorXd::Zero(dim);
  p.segment(1 + n, n) = d.lv;
  et(0) = 1.0;
  eu(dim - 1) = 1.0;
  const MatrixXd a = dp.transpose() * om, b = eu * et.transpose() - p * et.transpose();
  return a - a.transpose() + b - b.transpose();
}

VectorXd lagrangian_differential(const VignoloPoint& d) {
  check(d, "lagrangian_differential");
  const Index n = static_cast<Index>(d.n);
  VectorXd dl(2 * n + 1);
  dl << d.lt, d.lq, d.lv;
  return dl;
}

MatrixXd section_tangent(const VignoloPoint& d) {
  const VectorXd dl = lagrangian_differential(d);
  MatrixXd s = MatrixXd::Zero(dl.size() + 1, dl.size());
  s.topRows(dl.size()).setIdentity();
  s.bottomRows(1) = dl.transpose();
  return s;
}

MatrixXd poincare_cartan(const VignoloPoint& d) {
  const MatrixXd s = section_tangent(d);
  return s.transpose() * lagrangian_bundle_form(d) * s;
}

VectorXd trivialization_differential(const VignoloPoint& d) {
  const VectorXd dl = lagrangian_differential(d);
  VectorXd w(dl.size() + 1);
  w << -dl, 1.0;
  return w;
}

VectorXd bundle_horizontal_lift(const VignoloPoint& d, const VectorXd& x) {
  if (x.size() != 2 * static_cast<Index>(d.n) + 1)
    throw std::invalid_argument("bundle_horizontal_lift: expected X of length 2n + 1, found length " +
                                std::to_string(x.size()));
  return section_tangent(d) * x;
}

VectorXd vertical_endomorphism(const VignoloPoint& d, const VectorXd& x) {
  const Index n = static_cast<Index>(d.n);
  if (x.size() != 2 * n + 2)
    throw std::invalid_argument("vertical_endomorphism: expected X of length 2n + 2, found length " +
                                std::to_string(x.size()));
  const VectorXd c = contact_forms(d) * x.head(2 * n + 1);
  VectorXd out = VectorXd::Zero(2 * n + 2);
  out.segment(1 + n, n) = c;
  out(2 * n + 1) = d.lv.dot(c);
  return out;
}

MatrixXd bundle_constraint_differentials(const VignoloPoint& d) {
  check(d, "bundle_constraint_differentials");
  MatrixXd a = MatrixXd::Zero(rows_of(d), 2 * static_cast<Index>(d.n) + 2);
  a.leftCols(a.cols() - 1) = dphi_j1(d);
  return a;
}

MatrixXd chetaev_forms(const VignoloPoint& d) {
  const MatrixXd c = contact_forms(d);
  MatrixXd a = MatrixXd::Zero(rows_of(d), c.cols() + 1);
  if (rows_of(d)) a.leftCols(c.cols()) = -d.g * c;
  return a;
}

AffineSubspace lagrange_chetaev_fields(const VignoloPoint& d, bool chetaev_condition, const Options& opt) {
  check(d, "lagrange_chetaev_fields");
  return solve_on_j1(d, false, true, chetaev_condition, assessed_point(d, opt));
}

AffineSubspace nonholonomic_fields(const VignoloPoint& d, bool chetaev_condition, const Options& opt_in) {
  check(d, "nonholonomic_fields");
  const Options opt = assessed_point(d, opt_in);
  return lift_with_c(d, solve_on_j1(d, true, true, chetaev_condition, opt));
}

AffineSubspace unconstrained_fields(const VignoloPoint& d, const Options& opt_in) {
  check(d, "unconstrained_fields");
  const Options opt = assessed_point(d, opt_in);
  return lift_with_c(d, solve_on_j1(d, true, false, false, opt));
}

ConstrainedSplitting constrained_splitting(const VignoloPoint& d, const Options& opt_in) {
  check(d, "constrained_splitting");
  const Options opt = assessed_point(d, opt_in);
  const int dim = 2 * static_cast<int>(d.n) + 2;
  const MatrixXd w = lagrangian_bundle_form(d);
  const Subspace chi0 = rows_of(d) ? Subspace::solutions(chetaev_forms(d), -1, opt) : Subspace::whole(dim);
  const Subspace tan =
      rows_of(d) ? Subspace::solutions(bundle_constraint_differentials(d), -1, opt) : Subspace::whole(dim);
  return {symplectic_complement(w, chi0, opt), symplectic_complement(w, tan, opt), intersection(chi0, tan, opt)};
}

VectorXd constrained_projection(const VignoloPoint& d, const VectorXd& x) {
  check(d, "constrained_projection");
  const Index m = rows_of(d);
  if (x.size() != 2 * static_cast<Index>(d.n) + 2)
    throw std::invalid_argument("constrained_projection: expected X of length 2n + 2, found length " +
                                std::to_string(x.size()));
  require_finite(x, "constrained_projection (X)");
  const MatrixXd w = lagrangian_bundle_form(d), nu = chetaev_forms(d), dphi = bundle_constraint_differentials(d);
  if (const int r = decide_rank(w).rank; r < w.rows())
    throw std::invalid_argument("constrained_projection: expected L regular (Ω̃_l symplectic), found rank " +
                                std::to_string(r) + " of " + std::to_string(w.rows()) + " (decided in double)");
  if (m == 0) return x;
  MatrixXd cols(x.size(), 2 * m);  // X_{dφ^σ} and X_{ν^σ}: α^♯ with ♯(α) ⌟ Ω̃_l = α
  const Eigen::FullPivLU<MatrixXd> lu(w.transpose());
  cols.leftCols(m) = lu.solve(MatrixXd(dphi.transpose()));
  cols.rightCols(m) = lu.solve(MatrixXd(nu.transpose()));
  MatrixXd conditions(2 * m, x.size());
  conditions << nu, dphi;
  const MatrixXd c = conditions * cols;  // [0 C; −C ·]: singular iff C = g Γ⁻¹ gᵀ is (V's proof of Prop 3.1)
  if (const int r = decide_rank(c, conditions.norm() * cols.norm()).rank; r < 2 * m)
    throw std::invalid_argument(
        "constrained_projection: expected C = g Γ⁻¹ gᵀ invertible (the direct sum (3.7), V Prop 3.1), found the "
        "conditions' matrix of rank " +
        std::to_string(r) + " of " + std::to_string(2 * m) + " (decided in double)");
  const VectorXd coef = c.fullPivLu().solve(conditions * x);
  return x - cols * coef;
}

Subspace first_level_directions(const VignoloPoint& d, const Options& opt) {
  check(d, "first_level_directions");
  const Index m = rows_of(d);
  MatrixXd rows(1 + 2 * m, 2 * static_cast<Index>(d.n) + 2);
  rows << trivialization_differential(d).transpose(), bundle_constraint_differentials(d), chetaev_forms(d);
  return Subspace::solutions(rows, -1, assessed_point(d, opt));
}

Subspace first_constraint_directions(const VignoloPoint& d, const Options& opt_in) {
  const Options opt = assessed_point(d, opt_in);
  const MatrixXd w = lagrangian_bundle_form(d);
  const Subspace chi0 =
      rows_of(d) ? Subspace::solutions(chetaev_forms(d), -1, opt) : Subspace::whole(static_cast<int>(w.rows()));
  return intersection(symplectic_complement(w, first_level_directions(d, opt), opt), chi0, opt);
}

Truth in_first_constraint_manifold(const VignoloPoint& d, const Options& opt_in) {
  const Options opt = assessed_point(d, opt_in);
  const Subspace a = first_constraint_directions(d, opt);
  if (a.dim() == 0) return a.certain();
  const VectorXd dphil = trivialization_differential(d);
  const MatrixXd values = (a.columns().transpose() * dphil).transpose();
  const RankDecision r = decide_rank(values, dphil.norm(), opt);
  return Truth::decided(r.rank == 0, a.certain() & r.certain);
}

Subspace sode_obstruction(const VignoloPoint& d, const Options& opt) {
  check(d, "sode_obstruction");
  const Index n = static_cast<Index>(d.n), m = rows_of(d);
  MatrixXd a(n + m, n);
  a.topRows(n) = d.lvv;
  if (m) a.bottomRows(m) = d.g;
  const Subspace v = kernel(a, assessed_point(d, opt));
  MatrixXd embed = MatrixXd::Zero(2 * n + 1, v.dim());
  embed.bottomRows(n) = v.columns();
  return Subspace::from_orthonormal_columns(embed, v.certain());
}

Subspace lifted_sode_obstruction(const VignoloPoint& d, const Options& opt) {
  const Subspace o = sode_obstruction(d, opt);
  const Index n = static_cast<Index>(d.n);
  MatrixXd cols = MatrixXd::Zero(2 * n + 2, o.dim());
  cols.topRows(2 * n + 1) = o.columns();
  cols.bottomRows(1) = d.lv.transpose() * o.columns().bottomRows(n);
  return Subspace::span_columns(cols, -1, assessed_point(d, opt)).and_certain(o.certain());
}

}  // namespace dcad::fast
