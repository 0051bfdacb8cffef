#include "dcad/fast/dirac.hpp"

#include <Eigen/QR>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace dcad::fast {

namespace {
/// Orthonormal basis of the columns of a matrix known to have full column rank.
Subspace orthonormalize(const MatrixXd& cols) {
  Eigen::HouseholderQR<MatrixXd> qr(cols);
  const MatrixXd q = qr.householderQ() * MatrixXd::Identity(cols.rows(), cols.cols());
  return Subspace::from_orthonormal_columns(q, yes);
}
}  // namespace

DiracCheck dirac_defect(const DiracStructure& d, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  if (d.d.ambient() != 2 * d.n) return {no, "a subspace of R^" + std::to_string(2 * d.n)};
  if (d.d.dim() != d.n)
    return {Truth::decided(false, d.d.certain()), "dim D = " + std::to_string(d.d.dim()) + " (a Dirac structure on R^" +
                                                      std::to_string(d.n) + " has dim " + std::to_string(d.n) + ")"};
  // ⟨⟨a, b⟩⟩ = α_a·v_b + α_b·v_a: Gram matrix Aᵀ V + Vᵀ A in the orthonormal basis.
  const MatrixXd g = d.alpha_part().transpose() * d.v_part() + d.v_part().transpose() * d.alpha_part();
  const RankDecision r = decide_rank(g, d.d.conditioning(), opt);
  if (r.rank > 0) return {Truth::decided(false, r.certain & d.d.certain()), "D is not isotropic: " + r.describe()};
  return {Truth::decided(true, r.certain & d.d.certain()), ""};
}

Truth require_dirac(const DiracStructure& d, const std::string& fn, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  const DiracCheck c = dirac_defect(d, opt);
  if (c.valid.no()) throw std::invalid_argument(fn + ": expected a Dirac structure (Lemma 4.1), found " + c.why);
  return c.valid;
}

DiracStructure dirac_from_basis(const MatrixXd& rows, const Options& opt_in) {
  const Options opt = assessed(opt_in, {rows});
  if (rows.cols() % 2 != 0)
    throw std::invalid_argument("dirac_from_basis: expected rows (v, α) of even length 2n, found length " +
                                std::to_string(rows.cols()));
  DiracStructure d{static_cast<int>(rows.cols() / 2), Subspace::span_columns(rows.transpose(), -1, opt)};
  d.given = rows;
  d.d.and_certain(require_dirac(d, "dirac_from_basis", opt));
  return d;
}

DiracStructure dirac_from_presymplectic(const MatrixXd& w) {
  require_skew(w, "dirac_from_presymplectic");
  const int n = static_cast<int>(w.rows());
  MatrixXd cols(2 * n, n);  // columns (e_i, Wᵀ e_i)
  cols << MatrixXd::Identity(n, n), w.transpose();
  return {n, orthonormalize(cols), w};
}

DiracStructure dirac_from_distribution(const Subspace& e, const MatrixXd& w) {
  require_skew(w, "dirac_from_distribution");
  const int n = static_cast<int>(w.rows());
  if (e.ambient() != n)
    throw std::invalid_argument("dirac_from_distribution: expected a form on R^" + std::to_string(e.ambient()) +
                                ", found " + std::to_string(n) + "x" + std::to_string(n));
  // (q_i, Wᵀ q_i) for an orthonormal basis q of E, and (0, γ) for γ ∈ E° — then project the α of
  // the first kind onto E's dual (subtract its E° part), which keeps the span and orthogonality.
  const MatrixXd q = e.columns(), g = annihilator(e).columns();
  MatrixXd cols = MatrixXd::Zero(2 * n, n);
  cols.topLeftCorner(n, q.cols()) = q;
  cols.bottomLeftCorner(n, q.cols()) = q * (q.transpose() * w.transpose() * q);
  cols.bottomRightCorner(n, g.cols()) = g;
  DiracStructure d{n, orthonormalize(cols)};
  d.given = w;
  d.d.and_certain(e.certain());
  return d;
}

DiracStructure dirac_from_poisson(const MatrixXd& p) {
  require_skew(p, "dirac_from_poisson");
  const int n = static_cast<int>(p.rows());
  MatrixXd cols(2 * n, n);  // columns (P e_i, e_i)
  cols << p, MatrixXd::Identity(n, n);
  DiracStructure d{n, orthonormalize(cols)};
  d.given = p;
  return d;
}

Subspace dirac_distribution(const DiracStructure& d, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  return Subspace::span_columns(d.v_part(), 1.0, opt).and_certain(d.d.certain());
}

AffineSubspace dirac_flat(const DiracStructure& d, const VectorXd& x, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});  // x: a point, its scale the right-hand side's
  // (x, α) ∈ D  ⇔  x = V c, α = A c for some c.
  const AffineSubspace c = solve(d.v_part(), x, opt, 1.0);  // v-part of an orthonormal basis
  AffineSubspace out;
  out.empty = c.empty;
  out.certain = c.certain & d.d.certain();
  out.direction = Subspace::span_columns(d.alpha_part() * c.direction.columns(), 1.0, opt)
                      .and_certain(c.direction.certain() & d.d.certain());
  if (!c.empty) out.point = d.alpha_part() * c.point;
  return out;
}

Subspace dirac_flat(const DiracStructure& d, const Subspace& w, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  const Subspace c = preimage(d.v_part(), w, opt, 1.0);  // {c : V c ∈ W}
  return Subspace::span_columns(d.alpha_part() * c.columns(), 1.0, opt).and_certain(c.certain() & d.d.certain());
}

PresymplecticForm dirac_form(const DiracStructure& d, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  Subspace e = dirac_distribution(d, opt);
  const MatrixXd q = e.columns();
  // α_i with (q_i, α_i) ∈ D: c_i = V⁺ q_i (q_i ∈ im V), α_i = A c_i;  G_ij = α_i(q_j).
  // c_i: the minimum-norm solution of V c = q_i, on the rank decided for E (V = (Vᵀ)ᵀ)
  const RankRevealing f(d.v_part().transpose(), 1.0, opt);
  e.and_certain(f.decision().certain);  // the α_i rest on this decision as much as E does on its own
  const MatrixXd alphas = d.alpha_part() * f.min_norm_transposed(q);  // columns α_i
  MatrixXd g = alphas.transpose() * q;
  g = (g - g.transpose()) / 2;  // skew up to rounding; keep it exactly skew
  // ω_D's entries are α(q) with ‖α‖ ≤ ‖A V⁺‖: that is the scale of its rank decisions.
  return {e, q * g * q.transpose(), std::max(1.0, norm2(alphas))};
}

Subspace dirac_orthogonal(const DiracStructure& d, const Subspace& w, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  const Subspace c = preimage(d.v_part(), w, opt, 1.0);
  return Subspace::solutions((d.alpha_part() * c.columns()).transpose(), 1.0, opt)
      .and_certain(c.certain() & d.d.certain());
}

Truth is_presymplectic(const DiracStructure& d, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  const Subspace e = dirac_distribution(d, opt);
  return Truth::decided(e.dim() == d.n, e.certain());
}

Truth is_poisson(const DiracStructure& d, const Options& opt_in) {
  const Options opt = assessed(opt_in, {dirac_data(d)});
  const Subspace a = Subspace::span_columns(d.alpha_part(), 1.0, opt).and_certain(d.d.certain());
  return Truth::decided(a.dim() == d.n, a.certain());
}

}  // namespace dcad::fast
