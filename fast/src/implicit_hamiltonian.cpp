#include "dcad/fast/implicit_hamiltonian.hpp"
#include "dcad/fast/implicit_lagrangian.hpp"

#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {

void require_input(const HamiltonianInput& in, const char* fn) {
  const Eigen::Index n = static_cast<Eigen::Index>(in.n);
  const auto square = [&](const MatrixXd& m, const char* name) {
    if (m.rows() != n || m.cols() != n)
      throw std::invalid_argument(std::string(fn) + ": expected " + name + " " + std::to_string(n) + "x" +
                                  std::to_string(n) + ", found " + std::to_string(m.rows()) + "x" +
                                  std::to_string(m.cols()));
  };
  square(in.pp, "pp (A)");
  square(in.qp, "qp (B)");
  square(in.qq, "qq (C)");
  if (in.q.size() != n || in.p.size() != n)
    throw std::invalid_argument(std::string(fn) + ": expected q and p of length " + std::to_string(n) +
                                ", found lengths " + std::to_string(in.q.size()) + " and " +
                                std::to_string(in.p.size()));
  if (in.k.rows() && in.k.cols() != n)
    throw std::invalid_argument(std::string(fn) + ": expected k with " + std::to_string(n) + " columns, found " +
                                std::to_string(in.k.cols()));
  for (const MatrixXd* m : {&in.k, &in.pp, &in.qp, &in.qq}) require_finite(*m, fn);
  require_finite(in.q, fn);
  require_finite(in.p, fn);
  if (in.pp != in.pp.transpose() || in.qq != in.qq.transpose())
    throw std::invalid_argument(std::string(fn) + ": expected symmetric pp and qq, found an asymmetric one");
}

void require_vector(const HamiltonianInput& in, const VectorXd& v, const char* fn, const char* what) {
  if (v.size() != 2 * static_cast<Eigen::Index>(in.n))
    throw std::invalid_argument(std::string(fn) + ": expected " + what + " of length 2n = " + std::to_string(2 * in.n) +
                                ", found length " + std::to_string(v.size()));
  require_finite(v, fn);
}

}  // namespace

VectorXd hamiltonian_differential(const HamiltonianInput& in, const VectorXd& z) {
  require_input(in, "hamiltonian_differential");
  require_vector(in, z, "hamiltonian_differential", "z");
  const Eigen::Index n = static_cast<Eigen::Index>(in.n);
  const VectorXd q = z.head(n), p = z.tail(n);
  VectorXd dh(2 * n);
  dh.head(n) = in.qp * p + in.qq * q + in.q;
  dh.tail(n) = in.pp * p + in.qp.transpose() * q + in.p;
  return dh;
}

VectorXd hamilton_field(const HamiltonianInput& in, const VectorXd& z) {
  const VectorXd dh = hamiltonian_differential(in, z);
  const Eigen::Index n = static_cast<Eigen::Index>(in.n);
  VectorXd x(2 * n);
  x.head(n) = dh.tail(n);
  x.tail(n) = -dh.head(n);
  return x;
}

namespace {

/// {X = (q̇, ṗ) : q̇ = u ∈ Δ, ṗ + g ∈ Δ°}: Δ = ker K decided (an orthonormal basis N, and R of its complement
/// row K = Δ°), u ∈ Δ decided on Rᵀ u alone at `terms` (the size of what u and g were computed from: K's own
/// conditioning does not enter, as it would through K q̇ = 0), then X = (u, −N Nᵀ g) + {0} × Δ°.
AffineSubspace induced_fields(const MatrixXd& kmat, const VectorXd& u, const VectorXd& g, double terms,
                              const Options& opt) {
  const Eigen::Index n = u.size();
  const Subspace delta = kmat.rows() ? kernel(kmat, opt) : Subspace::whole(static_cast<int>(n));
  const MatrixXd& nb = delta.columns();
  const MatrixXd rb = orthogonal_complement(nb);  // Δ° (as vectors: row K)
  AffineSubspace out;
  out.certain = delta.certain();
  if (rb.cols() > 0) {
    const VectorXd off = rb.transpose() * u;  // u's part off Δ
    if (!(terms > 0) || !std::isfinite(terms)) {
      if (off.cwiseAbs().maxCoeff() > 0) out.certain = unknown;
    } else {
      const RankDecision d = decide_rank(off, terms, opt);
      out.certain &= d.certain;
      if (d.rank > 0) return out;  // empty: ∂H/∂p (or v) is not in Δ
    }
  }
  out.empty = false;
  out.point = VectorXd::Zero(2 * n);
  out.point.head(n) = u;
  out.point.tail(n) = -nb * (nb.transpose() * g);
  MatrixXd dir = MatrixXd::Zero(2 * n, rb.cols());
  dir.bottomRows(n) = rb;
  out.direction = Subspace::from_orthonormal_columns(dir, out.certain);
  return out;
}

}  // namespace

AffineSubspace implicit_hamiltonian_fields(const HamiltonianInput& in, const VectorXd& z, const Options& opt_in) {
  const VectorXd dh = hamiltonian_differential(in, z);
  const Options opt = assessed(opt_in, {in.k, in.pp, in.qp, in.qq, in.q, in.p, z});
  const Eigen::Index n = static_cast<Eigen::Index>(in.n);
  const double terms = (in.pp.norm() + in.qp.norm() + in.qq.norm()) * z.norm() + in.q.norm() + in.p.norm();
  return induced_fields(in.k, dh.tail(n), dh.head(n), terms, opt);
}

VectorXd legendre(const PontryaginInput& in, const VectorXd& q, const VectorXd& v) {
  pontryagin_energy(in);  // the input's checks
  if (q.size() != in.vv.rows() || v.size() != in.vv.rows())
    throw std::invalid_argument("legendre: expected q and v of length " + std::to_string(in.vv.rows()) +
                                ", found lengths " + std::to_string(q.size()) + " and " + std::to_string(v.size()));
  require_finite(q, "legendre");
  require_finite(v, "legendre");
  return in.vv * v + in.qv.transpose() * q + in.v;
}

VectorXd dirac_differential(const PontryaginInput& in, const VectorXd& q, const VectorXd& v) {
  legendre(in, q, v);  // the checks
  VectorXd out(2 * v.size());
  out.head(v.size()) = -(in.qv * v + in.qq * q + in.q);
  out.tail(v.size()) = v;
  return out;
}

AffineSubspace implicit_lagrangian_fields(const PontryaginInput& in, const VectorXd& q, const VectorXd& v,
                                          const Options& opt_in) {
  const VectorXd dl = dirac_differential(in, q, v);  // (−∂L/∂q, v)
  const Options opt = assessed(opt_in, {in.k, in.vv, in.qv, in.qq, in.q, in.v, q, v});
  const Eigen::Index n = v.size();
  const double terms = (in.qv.norm() + in.qq.norm()) * (q.norm() + v.norm()) + in.q.norm() + v.norm();
  return induced_fields(in.k, dl.tail(n), dl.head(n), terms, opt);
}

VectorXd hamiltonian_constraint_force(const HamiltonianInput& in, const VectorXd& z, const VectorXd& x) {
  const VectorXd dh = hamiltonian_differential(in, z);
  require_vector(in, x, "hamiltonian_constraint_force", "X");
  const Eigen::Index n = static_cast<Eigen::Index>(in.n);
  return x.tail(n) + dh.head(n);
}

LinearSystem implicit_hamiltonian_system(const HamiltonianInput& in, const Options& opt_in) {
  require_input(in, "implicit_hamiltonian_system");
  const Options opt = assessed(opt_in, {in.k, in.pp, in.qp, in.qq, in.q, in.p});
  const int n = static_cast<int>(in.n);
  const Subspace delta = in.k.rows() ? kernel(in.k, opt) : Subspace::whole(n);
  MatrixXd e = MatrixXd::Zero(2 * n, delta.dim() + n);  // Δ_{T*Q} = (Tπ_Q)⁻¹(Δ), orthonormal columns
  e.topLeftCorner(n, delta.dim()) = delta.columns();
  e.bottomRightCorner(n, n).setIdentity();
  MatrixXd w = MatrixXd::Zero(2 * n, 2 * n);  // Ω((a, b), (c, d)) = a·d − b·c
  w.topRightCorner(n, n).setIdentity();
  w.bottomLeftCorner(n, n) = -MatrixXd::Identity(n, n);
  LinearSystem s;
  s.d = dirac_from_distribution(Subspace::from_orthonormal_columns(e, delta.certain()), w);
  s.hessian = MatrixXd::Zero(2 * n, 2 * n);
  s.hessian.topLeftCorner(n, n) = in.qq;
  s.hessian.topRightCorner(n, n) = in.qp;
  s.hessian.bottomLeftCorner(n, n) = in.qp.transpose();
  s.hessian.bottomRightCorner(n, n) = in.pp;
  s.gradient.resize(2 * n);
  s.gradient << in.q, in.p;
  return s;
}

MatrixXd constrained_poisson_tensor(const MatrixXd& a, const std::vector<MatrixXd>& da, const VectorXd& p) {
  const Eigen::Index m = a.rows(), d = a.cols(), n = d + m;
  if (static_cast<Eigen::Index>(da.size()) != n || p.size() != n)
    throw std::invalid_argument("constrained_poisson_tensor: expected dA for each of the " + std::to_string(n) +
                                " coordinates and p of " + std::to_string(n) + ", found " + std::to_string(da.size()) +
                                " and " + std::to_string(p.size()));
  for (const MatrixXd& di : da)
    if (di.rows() != m || di.cols() != d)
      throw std::invalid_argument("constrained_poisson_tensor: expected each dA of " + std::to_string(m) + " × " +
                                  std::to_string(d) + ", found " + std::to_string(di.rows()) + " × " +
                                  std::to_string(di.cols()));
  // each coordinate function's gradient (∂_q, ∂_p) on T*Q, as rows of gq and gp
  MatrixXd gq = MatrixXd::Zero(2 * d + m, n), gp = MatrixXd::Zero(2 * d + m, n);
  for (Eigen::Index i = 0; i < n; ++i) gq(i, i) = 1;  // r^α and s^a
  const VectorXd ps = p.tail(m);
  for (Eigen::Index al = 0; al < d; ++al) {  // p̃_α = p_α − Σ_b A^b_α p_b
    for (Eigen::Index i = 0; i < n; ++i) gq(n + al, i) = -da[static_cast<std::size_t>(i)].col(al).dot(ps);
    gp(n + al, al) = 1;
    for (Eigen::Index b = 0; b < m; ++b) gp(n + al, d + b) = -a(b, al);
  }
  const MatrixXd out = gq * gp.transpose() - gp * gq.transpose();
  if (!out.allFinite() || !a.allFinite() || !p.allFinite())
    throw std::invalid_argument("constrained_poisson_tensor: expected finite A, dA and p");
  return out;
}

VectorXd horizontal_form_differential(const MatrixXd& a, const std::vector<MatrixXd>& da, const VectorXd& y,
                                      const VectorXd& z) {
  const Eigen::Index m = a.rows(), d = a.cols(), n = d + m;
  if (static_cast<Eigen::Index>(da.size()) != n || y.size() != d || z.size() != d)
    throw std::invalid_argument("horizontal_form_differential: expected dA for each of the " + std::to_string(n) +
                                " coordinates and y, z of " + std::to_string(d) + ", found " +
                                std::to_string(da.size()) + ", " + std::to_string(y.size()) + " and " +
                                std::to_string(z.size()));
  for (const MatrixXd& di : da)
    if (di.rows() != m || di.cols() != d)
      throw std::invalid_argument("horizontal_form_differential: expected each dA of " + std::to_string(m) + " × " +
                                  std::to_string(d) + ", found " + std::to_string(di.rows()) + " × " +
                                  std::to_string(di.cols()));
  VectorXd hy(n), hz(n);  // the horizontal lifts, (r, s)
  hy << y, -a * y;
  hz << z, -a * z;
  VectorXd bracket_s = VectorXd::Zero(m);  // [hor y, hor z] on s: Σ_i (hor y)_i ∂_i(−A z) − (hor z)_i ∂_i(−A y)
  for (Eigen::Index i = 0; i < n; ++i) {
    const MatrixXd& di = da[static_cast<std::size_t>(i)];
    bracket_s += -hy(i) * (di * z) + hz(i) * (di * y);
  }
  const VectorXd out = -bracket_s;  // −ω([hor y, hor z]): its r part is 0
  if (!out.allFinite() || !a.allFinite())
    throw std::invalid_argument("horizontal_form_differential: expected finite A, dA, y and z");
  return out;
}

}  // namespace dcad::fast
