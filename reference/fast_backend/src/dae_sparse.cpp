// The linear DAE form E ẋ = A x + f(t) at the sizes of circuit DAEs (issue 30: 10⁴ variables and more):
// fast's sparse route, on the constraints' rows rather than on bases of the subspaces (which are dense).
//
//   M_k = {x : C_k x = 0} (directions; with sources M_k(t) = p_k(t) + M_k where nonempty), C_0 empty.
//   CEF (1.6), linear: x ∈ M_{k+1} ⇔ C_k x = 0 and ∃ v with C_k v = 0, E v = A x
//                              ⇔ C_k x = 0 and z_Eᵀ A x = 0 for every (z_E, z_C) with z_Eᵀ E + z_Cᵀ C_k = 0,
//   so C_{k+1} = [C_k; Z_Eᵀ A] (Z a basis of the left null space of S_k = [E; C_k]), kept independent.
//   dim M_k = N − rank C_k; the tower stops when the rank does not grow; the solution rank is
//   dim(ker E ∩ M_c) = N − rank [E; C_c] (the last S_k).  A square pencil is regular iff that is 0
//   (see the end).
// E is factored once (EFactor): S_k's left null vectors beyond E's own come from C_k's part outside E's
// row space, factored densely (an SVD) where it is small or dense, so no dense constraint row (as where E
// has no diagonal) enters a sparse QR; where it is large and sparse (an MNA ladder with capacitors at every
// other node: nearly unit vectors) by a sparse QR of that part.
// The same tower as the dense route's Wong sequences (dae.cpp) — V_{k+1} = A⁻¹(E V_k) is
// {x : z_Eᵀ A x = 0} ∩ V_k by the same duality — computed on the equations, which stay sparse where
// the left null vectors do (a row of E that is zero, as at every node of an MNA circuit without a
// capacitor, is a unit null vector, and its constraint is a row of A).
//
// Rank decisions are Eigen's sparse QR (left-looking Householder, column by column) on matrices scaled
// by powers of two — the variables by Ruiz's balancing of |E| + |A|, each row to a largest entry near 1
// — with a threshold: a column whose remainder falls below max(Heath's 20 (m + n) ε ‖col‖_max, 1e-9
// ‖col‖_max) is dependent (rounding level alone is too fine: the null vectors carry ε times a condition
// number, and the steps compound it).  Eigen 3.4 mishandles the columns after a dependent one, so the
// dependent columns are removed and the rest refactored (CleanQr).  None of this bounds a singular
// value: the route is never certified, and its answers say uncertain with the smallest pivot kept and
// the threshold as evidence.  It agrees with the reference on 40,000 planted integer pencils, not on
// every graded one (prop_dae), so it runs only where the dense routes cannot: E and A beyond 2,000
// variables (Options::dae_sparse_from; the reference and the certified tier refuse there).
#include "dcad/fast/exact.hpp"
#include "dcad/fast/solve.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SVD>
#include <Eigen/SparseCore>
#include <Eigen/SparseQR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace dcad::fast {

namespace {

using SpMat = Eigen::SparseMatrix<double>;
using Row = std::vector<std::pair<int, double>>;          // (column, value), columns ascending
using Combination = std::vector<std::pair<int, double>>;  // Σ z_i (row i): (row, z_i), rows distinct
constexpr double eps = std::numeric_limits<double>::epsilon();
/// What this route takes as zero relative to the data it came from (an entry of a null vector against
/// its largest, a constraint's entry against the size of the rows it combines, a remainder against the
/// largest column): the forward error of a null space in double is ε times a condition number, and the
/// steps compound it, so rounding level (Heath's 20 (m + n) ε) is too fine a line.
constexpr double kRelative = 1e-9;

/// 2^-e with |x| in [2^(e-1), 2^e): a scale that rounds nothing.
double power_of_two_inverse(double x) {
  int e = 0;
  std::frexp(x, &e);
  return std::ldexp(1.0, -e);
}

/// What the QRs of one run decided, for the note.
struct Evidence {
  double smallest_pivot = HUGE_VAL;  ///< the smallest |r_ii| kept, relative to its matrix's largest column
  double threshold = 0;              ///< the largest threshold used, relative likewise
  double largest_dropped = 0;        ///< the largest remainder taken as zero, relative likewise
  long decisions = 0;
  void kept(double pivot, double scale, double tau) {
    smallest_pivot = std::min(smallest_pivot, pivot / scale);
    threshold = std::max(threshold, tau / scale);
  }
};

/// Heath's threshold on m, equilibrated: 20 (rows + cols) ε ‖col‖_max (SuiteSparseQR's, Eigen's default).
double threshold_of(const SpMat& m, double& largest) {
  largest = 0;
  for (int j = 0; j < m.outerSize(); ++j) largest = std::max(largest, m.col(j).norm());
  if (largest == 0) largest = 1;
  return 20.0 * static_cast<double>(m.rows() + m.cols()) * largest * eps;
}

/// The columns of m selected by `keep`, in that order.
SpMat columns_of(const SpMat& m, const std::vector<int>& keep) {
  SpMat out(m.rows(), static_cast<Eigen::Index>(keep.size()));
  std::vector<Eigen::Triplet<double>> t;
  for (std::size_t k = 0; k < keep.size(); ++k)
    for (SpMat::InnerIterator it(m, keep[k]); it; ++it)
      t.emplace_back(static_cast<int>(it.row()), static_cast<int>(k), it.value());
  out.setFromTriplets(t.begin(), t.end());
  out.makeCompressed();
  return out;
}

/// Rows renumbered so that column ℓ's largest entry not yet taken sits at row ℓ: Eigen's SparseQR pivots
/// on the diagonal position without permuting rows, and an entry off it fills in (a nearly diagonal E
/// put through COLAMD's order took 6 s at 10⁴ variables; [C_1; candidates]ᵀ of a 5,000-node ladder,
/// 7,500 entries, 2.4 s in the rows' own order; 0.08 s so).  Returns new row of each old one; rank and
/// which columns are independent do not depend on the rows' order.  Not a cure for every structure: the
/// rows left over (no column's pivot) sit last and gather fill in the Householder vectors along a chain
/// of columns that share rows — 180 MB at 10⁴ nodes of a ladder with capacitors at every other node, out
/// of memory at 10⁵ (bench/results/dae_circuits.md; the certified tier's elimination answers there).
std::vector<int> diagonal_first(const SpMat& m) {
  std::vector<int> row_at(static_cast<std::size_t>(m.rows()), -1);
  int next = 0;
  for (int l = 0; l < m.outerSize(); ++l) {
    int best = -1;
    double big = 0;
    for (SpMat::InnerIterator it(m, l); it; ++it)
      if (row_at[static_cast<std::size_t>(it.row())] < 0 && std::abs(it.value()) > big)
        big = std::abs(it.value()), best = static_cast<int>(it.row());
    if (best >= 0) row_at[static_cast<std::size_t>(best)] = next++;
  }
  for (int& r : row_at)
    if (r < 0) r = next++;
  return row_at;
}

/// A sparse QR of the columns of m that are independent (Heath's threshold τ), with full column rank.
/// Eigen's SparseQR moves a column whose remainder is below τ to the end, but the factorization of the
/// columns after it is then unreliable (Eigen 3.4: the column elimination tree it recomputes misses fill:
/// the four columns (x3, x1 − x2/2, x3, x1 − x2/2) came out of rank 3).  So the dependent columns found
/// are removed and the rest refactored until none is dependent; then every removed column is checked
/// against the final factor (its remainder ‖(I − Q_r Q_rᵀ) c‖ below τ), and one that is not goes back in.
template <class Ordering>
struct CleanQr {
  Eigen::SparseQR<SpMat, Ordering> qr;
  std::vector<int> kept;  ///< m's columns, in the factored matrix's order (ascending)
  long factorizations = 0;
  double smallest_pivot = HUGE_VAL;
  double largest_dropped = 0;  ///< the largest remainder of a removed column (the last round's)

  CleanQr(const SpMat& m, double tau) {
    std::vector<int> alive;
    for (int j = 0; j < m.outerSize(); ++j)
      for (SpMat::InnerIterator it(m, j); it; ++it)
        if (it.value() != 0) {
          alive.push_back(j);
          break;
        }
    // no nonzero column (every constraint inside E's row space): nothing to factor — and Eigen 3.4's
    // SparseQR writes past its arrays on a matrix without columns (AddressSanitizer, prop_dae)
    if (alive.empty()) return;
    std::vector<int> removed;
    qr.setPivotThreshold(tau);
    for (int round = 0;; ++round) {
      for (;;) {  // refactor without the dependent columns
        qr.compute(columns_of(m, alive));
        ++factorizations;
        if (qr.info() != Eigen::Success) throw std::runtime_error("a sparse QR failed: " + qr.lastErrorMessage());
        if (qr.rank() == static_cast<Eigen::Index>(alive.size())) break;
        const auto& idx = qr.colsPermutation().indices();  // (A P).col(p) = A.col(indices(p))
        std::vector<char> dead(alive.size(), 0);
        for (Eigen::Index p = qr.rank(); p < static_cast<Eigen::Index>(alive.size()); ++p)
          dead[static_cast<std::size_t>(idx(p))] = 1;
        std::vector<int> next;
        for (std::size_t j = 0; j < alive.size(); ++j) (dead[j] ? removed : next).push_back(alive[j]);
        alive = std::move(next);
        if (alive.empty()) break;  // every column below τ: rank 0 (and no QR of a matrix without columns)
      }
      // each removed column against the final factor: its remainder beyond the first `rank` rows of Qᵀ c
      std::vector<int> back, still;
      const Eigen::Index r = alive.empty() ? 0 : qr.rank();
      for (int j : removed) {
        const Eigen::VectorXd c = Eigen::VectorXd(m.col(j));
        const double rest = alive.empty() ? c.norm() : [&] {
          const Eigen::VectorXd qc = qr.matrixQ().transpose() * c;
          return qc.tail(qc.size() - r).norm();
        }();
        (rest >= tau ? back : still).push_back(j);
        if (rest < tau) largest_dropped = std::max(largest_dropped, rest);
      }
      if (back.empty() || round > 20) break;
      largest_dropped = 0;
      alive.insert(alive.end(), back.begin(), back.end());
      std::sort(alive.begin(), alive.end());
      removed = std::move(still);
    }
    kept = alive;
    if (alive.empty()) return;
    const SpMat rr = qr.matrixR();
    for (Eigen::Index i = 0; i < qr.rank(); ++i) smallest_pivot = std::min(smallest_pivot, std::abs(rr.coeff(i, i)));
  }
};

template <class Ordering>
void record(const CleanQr<Ordering>& c, double tau, double largest, Evidence& ev) {
  ev.decisions += c.factorizations;
  if (!c.kept.empty())
    ev.kept(c.smallest_pivot, largest, tau);
  else
    ev.threshold = std::max(ev.threshold, tau / largest);
  ev.largest_dropped = std::max(ev.largest_dropped, c.largest_dropped / largest);
}

/// Rows and columns of `s` scaled by powers of two until each row's and column's largest entry is
/// within a factor 4 of 1 (Ruiz's iteration: each pass divides by √max; a matrix D_r B D_c with B's
/// entries of one size comes back to B's, to within powers of two); returns the row scales (a left null
/// vector w of the scaled matrix is z = D_r w for s itself).
std::vector<double> equilibrate(SpMat& s) {
  std::vector<double> scale_r(static_cast<std::size_t>(s.rows()), 1.0);
  for (int pass = 0; pass < 40; ++pass) {
    std::vector<double> row(static_cast<std::size_t>(s.rows()), 0.0), col(static_cast<std::size_t>(s.cols()), 0.0);
    for (int j = 0; j < s.outerSize(); ++j)
      for (SpMat::InnerIterator it(s, j); it; ++it) {
        const double x = std::abs(it.value());
        row[static_cast<std::size_t>(it.row())] = std::max(row[static_cast<std::size_t>(it.row())], x);
        col[static_cast<std::size_t>(j)] = std::max(col[static_cast<std::size_t>(j)], x);
      }
    bool balanced = true;
    const auto factor = [&](double mx) {
      if (mx == 0 || (mx >= 0.25 && mx <= 4)) return 1.0;
      balanced = false;
      return power_of_two_inverse(std::sqrt(mx));
    };
    for (double& r : row) r = factor(r);
    for (double& c : col) c = factor(c);
    if (balanced) break;
    for (int j = 0; j < s.outerSize(); ++j)
      for (SpMat::InnerIterator it(s, j); it; ++it)
        it.valueRef() *= row[static_cast<std::size_t>(it.row())] * col[static_cast<std::size_t>(j)];
    for (std::size_t i = 0; i < row.size(); ++i) scale_r[i] *= row[i];
  }
  return scale_r;
}

/// E factored once, for every step: the QR of (D_r E D_c)ᵀ over E's nonzero rows (D_c the variables'
/// units, D_r each row to a largest entry near 1), without its dependent columns — rows of E — (CleanQr).
/// A left null vector of S_k = [E; C_k] is (z_E, z_C) with Eᵀ z_E = −C_kᵀ z_C: either z_C = 0 and z_E
/// is one of E's own (its zero rows, and each dependent row less its combination of the others), or
/// z_C is a null vector of C_k's part outside E's row space — Qᵀ C_kᵀ below the rank, a dense matrix of
/// dim ker E rows — and z_E solves the least-squares problem, exact there.  So rank S_k = rank E + the
/// rank of that part, and only small dense matrices are factored after the first step (a dense
/// constraint row, as E's null vectors give where E has no diagonal, never enters a sparse QR).
class EFactor {
 public:
  EFactor(const SpMat& e, const std::vector<double>& col_scale, Evidence& ev)
      : m_(static_cast<int>(e.rows())), col_scale_(col_scale) {
    const int n = static_cast<int>(e.cols());
    std::vector<int> at(static_cast<std::size_t>(m_), -1);
    std::vector<double> largest_in_row(static_cast<std::size_t>(m_), 0.0);
    for (int j = 0; j < e.outerSize(); ++j)
      for (SpMat::InnerIterator it(e, j); it; ++it)
        largest_in_row[static_cast<std::size_t>(it.row())] =
            std::max(largest_in_row[static_cast<std::size_t>(it.row())],
                     std::abs(it.value()) * col_scale[static_cast<std::size_t>(j)]);
    for (int i = 0; i < m_; ++i)
      if (largest_in_row[static_cast<std::size_t>(i)] > 0) {
        at[static_cast<std::size_t>(i)] = static_cast<int>(live_.size());
        live_.push_back(i);
        dr_.push_back(power_of_two_inverse(largest_in_row[static_cast<std::size_t>(i)]));
      } else {
        null_of_e.push_back({{i, 1.0}});
      }
    if (live_.empty()) return;
    std::vector<Eigen::Triplet<double>> t;
    for (int j = 0; j < e.outerSize(); ++j)
      for (SpMat::InnerIterator it(e, j); it; ++it) {
        const int l = at[static_cast<std::size_t>(it.row())];
        t.emplace_back(j, l, it.value() * col_scale[static_cast<std::size_t>(j)] * dr_[static_cast<std::size_t>(l)]);
      }
    {  // rows (variables) in diagonal_first's order
      SpMat raw(n, static_cast<Eigen::Index>(live_.size()));
      raw.setFromTriplets(t.begin(), t.end());
      raw.makeCompressed();
      row_at_ = diagonal_first(raw);
      for (auto& x : t) x = Eigen::Triplet<double>(row_at_[static_cast<std::size_t>(x.row())], x.col(), x.value());
    }
    et_ = SpMat(n, static_cast<Eigen::Index>(live_.size()));
    et_.setFromTriplets(t.begin(), t.end());
    et_.makeCompressed();
    double largest = 0;
    const double heath = threshold_of(et_, largest);
    const double tau = std::max(heath, kRelative * largest);
    qr_ = std::make_unique<CleanQr<Eigen::NaturalOrdering<int>>>(et_, tau);
    record(*qr_, tau, largest, ev);
    rank = static_cast<long>(qr_->kept.size());
    std::vector<char> kept(live_.size(), 0);
    for (int l : qr_->kept) kept[static_cast<std::size_t>(l)] = 1;
    for (std::size_t l = 0; l < live_.size(); ++l) {  // a dependent row less its combination of the kept ones
      if (kept[l]) continue;
      const Eigen::VectorXd x = qr_->qr.solve(Eigen::VectorXd(et_.col(static_cast<Eigen::Index>(l))));
      Combination z{{live_[l], dr_[l]}};
      add_kept(z, -x);
      null_of_e.push_back(std::move(z));
    }
  }

  std::vector<Combination> null_of_e;  ///< z with zᵀ E = 0
  long rank = 0;                       ///< rank E

  /// D_c c_i / ‖D_c c_i‖ for each row c_i, in et_'s row order.
  std::vector<Eigen::SparseVector<double>> unit_rows(const std::vector<Row>& c) const {
    const int n = static_cast<int>(col_scale_.size());
    std::vector<Eigen::SparseVector<double>> y;
    for (const Row& r : c) {
      Eigen::SparseVector<double> v(n);
      std::vector<std::pair<int, double>> at;
      double norm2 = 0;
      for (const auto& [j, x] : r) {
        at.emplace_back(row_at_.empty() ? j : row_at_[static_cast<std::size_t>(j)],
                        x * col_scale_[static_cast<std::size_t>(j)]);
        norm2 += at.back().second * at.back().second;
      }
      std::sort(at.begin(), at.end());
      const double norm = std::sqrt(norm2);
      for (const auto& [j, x] : at) v.insert(j) = x / norm;
      y.push_back(std::move(v));
    }
    return y;
  }

  /// The z_E of a basis of S_k's left null vectors beyond E's own; `extra` = rank S_k − rank E.
  /// The part outside E's row space is factored densely (an SVD) where it is small or dense, by a sparse
  /// QR (CleanQr, the threshold as for E) where it is large and sparse: an MNA ladder with a capacitor at
  /// every other node has 5,000 constraints whose parts outside are nearly unit vectors (the SVD of that
  /// 5,000 × 5,000 took 270 s at 10⁴ nodes).
  std::vector<Combination> with(const std::vector<Row>& c, long& extra, Evidence& ev, int sparse_qr_from) const {
    const int n = static_cast<int>(col_scale_.size());
    const Eigen::Index k = static_cast<Eigen::Index>(c.size());
    const std::vector<Eigen::SparseVector<double>> y = unit_rows(c);
    const Eigen::Index below = n - rank;
    std::vector<Eigen::Triplet<double>> t;  // the part of each y outside E's row space
    Eigen::VectorXd yi(n), q(n);            // reused across the constraints
    for (Eigen::Index i = 0; i < k; ++i) {
      yi.setZero();
      for (Eigen::SparseVector<double>::InnerIterator it(y[static_cast<std::size_t>(i)]); it; ++it)
        yi(it.index()) = it.value();
      if (qr_)
        q.noalias() = qr_->qr.matrixQ().transpose() * yi;
      else
        q = yi;
      for (Eigen::Index r = 0; r < below; ++r)
        if (q(rank + r) != 0) t.emplace_back(static_cast<int>(r), static_cast<int>(i), q(rank + r));
    }
    ++ev.decisions;
    std::vector<Combination> out;
    if (below == 0) {  // E has full column rank: every combination of C lies in its row space
      extra = 0;
      for (Eigen::Index i = 0; i < k; ++i) out.push_back(z_of(y, {{static_cast<int>(i), 1.0}}));
      return out;
    }
    if (sparse_qr_from == 0 ||
        (k >= sparse_qr_from &&
         static_cast<double>(t.size()) <= 0.05 * static_cast<double>(below) * static_cast<double>(k))) {
      SpMat outside(below, k);
      outside.setFromTriplets(t.begin(), t.end());
      outside.makeCompressed();
      // the columns are parts of unit vectors: 1 is the scale, as for the SVD below (not the largest part,
      // which is rounding residue where every constraint lies in E's row space)
      const double tau = std::max(20.0 * static_cast<double>(below + k) * eps, kRelative);
      const CleanQr<Eigen::COLAMDOrdering<int>> clean(outside, tau);
      record(clean, tau, 1.0, ev);
      extra = static_cast<long>(clean.kept.size());
      std::vector<char> kept(static_cast<std::size_t>(k), 0);
      for (int j : clean.kept) kept[static_cast<std::size_t>(j)] = 1;
      for (Eigen::Index j = 0; j < k; ++j) {  // a dependent column less its combination of the kept ones
        if (kept[static_cast<std::size_t>(j)]) continue;
        Combination u{{static_cast<int>(j), 1.0}};
        if (!clean.kept.empty()) {
          const Eigen::VectorXd x = clean.qr.solve(Eigen::VectorXd(outside.col(j)));
          const double top = x.size() ? x.cwiseAbs().maxCoeff() : 0;
          for (std::size_t l = 0; l < clean.kept.size(); ++l)
            if (std::abs(x(static_cast<Eigen::Index>(l))) > kRelative * top)
              u.emplace_back(clean.kept[l], -x(static_cast<Eigen::Index>(l)));
        }
        out.push_back(z_of(y, u));
      }
      return out;
    }
    SpMat sparse_outside(below, k);
    sparse_outside.setFromTriplets(t.begin(), t.end());
    const Eigen::MatrixXd outside(sparse_outside);
    Eigen::BDCSVD<Eigen::MatrixXd> svd(outside, Eigen::ComputeFullV);
    const auto& sigma = svd.singularValues();
    extra = 0;
    for (Eigen::Index i = 0; i < sigma.size(); ++i)
      if (sigma(i) > kRelative) ++extra;  // the columns have unit norm: 1 is the scale
    if (extra > 0) ev.kept(sigma(extra - 1), 1.0, kRelative);
    if (extra < sigma.size()) ev.largest_dropped = std::max(ev.largest_dropped, sigma(extra));
    for (Eigen::Index i = extra; i < k; ++i) {
      Combination u;
      for (Eigen::Index j = 0; j < k; ++j) u.emplace_back(static_cast<int>(j), svd.matrixV()(j, i));
      out.push_back(z_of(y, u));
    }
    return out;
  }

 private:
  /// z_E with Eᵀ z_E = −Σ u_i y_i (least squares on the kept rows; exact where the sum is in E's row space);
  /// u as (index of y, coefficient).
  Combination z_of(const std::vector<Eigen::SparseVector<double>>& y, const Combination& u) const {
    Combination z;
    if (!qr_) return z;
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(col_scale_.size()));
    for (const auto& [i, ui] : u)
      for (Eigen::SparseVector<double>::InnerIterator it(y[static_cast<std::size_t>(i)]); it; ++it)
        sum(it.index()) += ui * it.value();
    add_kept(z, -Eigen::VectorXd(qr_->qr.solve(sum)));
    return z;
  }
  /// z += the combination x of the kept rows (in E's units), its entries at rounding level dropped.
  void add_kept(Combination& z, const Eigen::VectorXd& x) const {
    const double top = x.size() ? x.cwiseAbs().maxCoeff() : 0;
    for (std::size_t k = 0; k < qr_->kept.size(); ++k) {
      const double v = x(static_cast<Eigen::Index>(k));
      if (std::abs(v) > kRelative * top) {
        const int l = qr_->kept[k];
        z.emplace_back(live_[static_cast<std::size_t>(l)], dr_[static_cast<std::size_t>(l)] * v);  // rows distinct
      }
    }
  }

  int m_;
  const std::vector<double>& col_scale_;
  std::vector<int> live_;   ///< E's nonzero rows: the columns of et_
  std::vector<double> dr_;  ///< their scales
  SpMat et_;
  std::vector<int> row_at_;  ///< variable j is row row_at_[j] of et_
  std::unique_ptr<CleanQr<Eigen::NaturalOrdering<int>>> qr_;
};

/// The rows of `candidates` that are independent of `kept` and of each other, in order (a greedy
/// pivoted QR of [kept; candidates]ᵀ in its natural order: a row whose remainder falls below the
/// threshold is dependent).  Each row is scaled by the size of what produced it (`sizes`: Σ |z_i| ‖A_i‖,
/// so a row that cancelled to rounding residue stays small and is dropped).
std::vector<std::size_t> independent(const std::vector<Row>& kept, const std::vector<Row>& candidates,
                                     const std::vector<double>& sizes, const std::vector<double>& col_scale,
                                     Evidence& ev) {
  const int n = static_cast<int>(col_scale.size());
  const std::size_t c = kept.size() + candidates.size();
  std::vector<Eigen::Triplet<double>> t;
  // in the variables' units (col_scale: from the data, never from these rows, whose entries at rounding
  // level must stay small)
  const auto add = [&](const Row& r, std::size_t j, double size) {
    for (const auto& [i, x] : r)
      t.emplace_back(i, static_cast<int>(j), x * col_scale[static_cast<std::size_t>(i)] / size);
  };
  for (std::size_t j = 0; j < kept.size(); ++j) {
    double size = 0;
    for (const auto& e : kept[j])
      size = std::max(size, std::abs(e.second * col_scale[static_cast<std::size_t>(e.first)]));
    add(kept[j], j, size);
  }
  // a candidate by the size of what it combines (Σ |z_i| ‖A_i‖): a row that is mostly cancellation
  // carries its error at that scale, and its remainder is judged there
  for (std::size_t j = 0; j < candidates.size(); ++j) add(candidates[j], kept.size() + j, sizes[j]);
  SpMat ct(n, static_cast<Eigen::Index>(c));
  ct.setFromTriplets(t.begin(), t.end());
  ct.makeCompressed();
  {  // rows in diagonal_first's order (the columns', which decide, unchanged)
    const std::vector<int> row_at = diagonal_first(ct);
    for (auto& x : t) x = Eigen::Triplet<double>(row_at[static_cast<std::size_t>(x.row())], x.col(), x.value());
    ct.setFromTriplets(t.begin(), t.end());
    ct.makeCompressed();
  }
  double largest = 0;
  // the candidates carry the error of the null vectors they come from (a QR's, amplified by [E; C_k]'s
  // conditioning), not only their own rounding: a remainder below 1e-9 of the largest is taken as zero
  const double heath = threshold_of(ct, largest);
  const double tau = std::max(heath, kRelative * largest);
  const CleanQr<Eigen::NaturalOrdering<int>> clean(ct, tau);
  record(clean, tau, largest, ev);
  std::vector<std::size_t> out;
  for (int j : clean.kept)
    if (static_cast<std::size_t>(j) >= kept.size()) out.push_back(static_cast<std::size_t>(j) - kept.size());
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

bool has_sources(const io::DaeCase& c);       // f ≢ 0 (dae.cpp)
Solution dae_solution(const io::DaeCase& c);  // a result's name, variables and M_0 (dae.cpp)
/// The exact route's conditions on the sources into `out` (and M_k = ∅ where one fails); false where it
/// left one undecided (dae.cpp).
bool exact_source_conditions(const io::DaeCase& c, Solution& out);

/// The route's decisions as one trace entry: thresholds on remainders bound no singular value, so it is uncertain.
static Decision summary_decision(const Evidence& ev, long m, long n, long dim) {
  Decision all;
  all.what = "sparse QR: " + std::to_string(ev.decisions) + " rank decisions by their extremes (rank: dim M_c)";
  all.rows = m;
  all.cols = n;
  all.rank = dim;
  all.by = DecidedBy::pivoted_qr;
  all.certain = unknown;
  all.zero_threshold = all.nonzero_threshold = ev.threshold;
  all.gap = ev.largest_dropped > 0 ? ev.smallest_pivot / ev.largest_dropped : HUGE_VAL;
  std::ostringstream why;
  why << "the smallest pivot kept " << ev.smallest_pivot << ", the largest remainder taken as zero "
      << ev.largest_dropped << ", threshold " << ev.threshold << " (relative): not certified";
  all.evidence = why.str();
  return all;
}

Solution solve_dae_sparse(const io::DaeCase& c, const Options& opt_in) {
  Options opt = opt_in;
  const int n = static_cast<int>(c.variables.size());
  const int m = static_cast<int>(c.equations());
  // E and A in double, from the entries (or from the dense matrices of a case built in code)
  std::vector<Eigen::Triplet<double>> te, ta;
  std::vector<double> values;
  const auto convert = [&](const std::vector<io::DaeCase::Entry>& entries, const io::QMatrix& dense,
                           std::vector<Eigen::Triplet<double>>& t) {
    if (!entries.empty() || !c.dense) {
      for (const auto& e : entries) {
        t.emplace_back(static_cast<int>(e.row), static_cast<int>(e.col), to_double(e.value, opt));
        values.push_back(t.back().value());
      }
      return;
    }
    for (std::size_t i = 0; i < dense.rows(); ++i)
      for (std::size_t j = 0; j < dense.cols(); ++j)
        if (dense(i, j) != 0) {
          t.emplace_back(static_cast<int>(i), static_cast<int>(j), to_double(dense(i, j), opt));
          values.push_back(t.back().value());
        }
  };
  convert(c.e_entries, c.e, te);
  convert(c.a_entries, c.a, ta);
  assess_input(Eigen::Map<const Eigen::MatrixXd>(values.data(), 1, static_cast<Eigen::Index>(values.size())), opt);
  SpMat e(m, n), a(m, n);
  e.setFromTriplets(te.begin(), te.end());
  a.setFromTriplets(ta.begin(), ta.end());
  e.makeCompressed();
  a.makeCompressed();
  const SpMat at = a.transpose();
  // the variables' units: column scales of |E| + |A| balanced (Ruiz), by which constraint rows are compared
  std::vector<double> col_scale(static_cast<std::size_t>(n), 1.0);
  {
    SpMat both(m, n);  // |E| + |A|: an equation's row scale is E's and A's alike, as a variable's column scale
    std::vector<Eigen::Triplet<double>> tb;
    for (const auto& x : te) tb.emplace_back(x.row(), x.col(), std::abs(x.value()));
    for (const auto& x : ta) tb.emplace_back(x.row(), x.col(), std::abs(x.value()));
    both.setFromTriplets(tb.begin(), tb.end());
    SpMat tr = both.transpose();
    const std::vector<double> rs = equilibrate(tr);  // rows of the transpose: the variables
    for (int j = 0; j < n; ++j) col_scale[static_cast<std::size_t>(j)] = rs[static_cast<std::size_t>(j)];
  }
  std::vector<double> a_row_size(static_cast<std::size_t>(m), 0.0);  // ‖A_i‖_∞ in the variables' units
  for (int j = 0; j < a.outerSize(); ++j)
    for (SpMat::InnerIterator it(a, j); it; ++it)
      a_row_size[static_cast<std::size_t>(it.row())] =
          std::max(a_row_size[static_cast<std::size_t>(it.row())],
                   std::abs(it.value()) * col_scale[static_cast<std::size_t>(j)]);

  Evidence ev;
  std::vector<Row> constraints;  // C_k, independent rows
  std::vector<long> dims{n};
  std::vector<std::vector<Row>> cut;  // the rows each step added
  long last_rank = 0;                 // rank [E; C_c]
  const EFactor ef(e, col_scale, ev);
  Eigen::VectorXd acc = Eigen::VectorXd::Zero(n);
  std::vector<char> hit(static_cast<std::size_t>(n), 0);
  for (int step = 0; step <= n; ++step) {
    long extra = 0;
    const std::vector<Combination> zs =
        step == 0 ? ef.null_of_e : ef.with(constraints, extra, ev, opt_in.dae_sparse_qr_from);
    last_rank = ef.rank + extra;
    std::vector<Row> candidates;
    std::vector<double> sizes;
    for (const Combination& ze : zs) {
      double size = 0;
      long terms = 0;
      for (const auto& [i, zi] : ze)
        if (zi != 0) size += std::abs(zi) * a_row_size[static_cast<std::size_t>(i)], ++terms;
      if (size == 0) continue;   // a combination of the constraints alone: nothing new
      std::vector<int> touched;  // Σ z_i A_i, on the columns it touches (acc is all zero between rows)
      for (const auto& [i, zi] : ze)
        for (SpMat::InnerIterator it(at, i); it; ++it) {
          if (!hit[static_cast<std::size_t>(it.row())])
            hit[static_cast<std::size_t>(it.row())] = 1, touched.push_back(static_cast<int>(it.row()));
          acc(it.row()) += zi * it.value();
        }
      std::sort(touched.begin(), touched.end());
      Row r;
      for (int j : touched) {  // below: the error of z (a QR's, times [E; C_k]'s conditioning) and of the sum
        if (std::abs(acc(j)) * col_scale[static_cast<std::size_t>(j)] > kRelative * size) r.emplace_back(j, acc(j));
        acc(j) = 0, hit[static_cast<std::size_t>(j)] = 0;
      }
      if (r.empty()) continue;
      candidates.push_back(std::move(r));
      sizes.push_back(size);
    }
    const std::vector<std::size_t> fresh =
        candidates.empty() ? std::vector<std::size_t>{} : independent(constraints, candidates, sizes, col_scale, ev);
    if (fresh.empty()) break;
    std::vector<Row> added;
    for (std::size_t k : fresh) added.push_back(candidates[k]);
    constraints.insert(constraints.end(), added.begin(), added.end());
    dims.push_back(n - static_cast<long>(constraints.size()));
    cut.push_back(std::move(added));
  }
  const bool has_f = has_sources(c);
  Solution out = dae_solution(c);
  for (std::size_t k = 0; k < cut.size(); ++k) {
    Level<double> level;
    level.dim = dims[k + 1];
    if (!has_f)  // with sources the right-hand sides are the exact route's (jets); fast gives the directions
      for (const Row& r : cut[k]) {
        double size = 0;
        for (const auto& e : r) size += e.second * e.second;
        size = std::sqrt(size);
        Equation<double> eq;
        for (const auto& [j, x] : r) eq.terms.emplace_back(static_cast<std::size_t>(j), x / size);
        level.constraints.push_back(std::move(eq));
      }
    out.tower.push_back(std::move(level));
  }
  out.steps = static_cast<long>(cut.size());
  out.solution_rank = n - last_rank;
  // A square pencil is singular iff its Kronecker form has an L_ε block (square: as many L_ε as L_ηᵀ),
  // and an L_ε block (E = [I 0], A = [0 I], ε × (ε+1); ε = 0 a zero column) leaves a velocity free in
  // V*: solution rank ≥ 1; without one ker E ∩ V* = 0.  So the tower decides it, with no second
  // factorization (the reference evaluates det(sE − A) at N + 1 points: a different route).
  if (m == n) out.regular_pencil = out.solution_rank == 0;
  std::ostringstream note;
  note << "sparse route: the constraints' rows C_{k+1} = [C_k; Z^T A], Z the left null space of [E; C_k] by sparse QR "
          "(reference/fast_backend/src/dae_sparse.cpp); ranks by a threshold on remainders (the smallest pivot kept "
       << ev.smallest_pivot << ", the largest remainder taken as zero " << ev.largest_dropped << ", the threshold "
       << ev.threshold << ", relative to their matrices), which bounds no singular value: not certified";
  if (ev.smallest_pivot < 1e3 * ev.threshold || ev.largest_dropped > 1e-3 * ev.threshold)
    note << " (and a decision fell within a factor 1000 of the threshold: graded data this route may misjudge)";
  const bool regular = out.regular_pencil && *out.regular_pencil;
  if (has_f && !regular) {  // conditions on the sources: the exact route decides them, where it runs
    if (!c.dense)
      throw std::invalid_argument(std::string(m == n
                                                  ? "a pencil this route does not find regular (singular, or a "
                                                    "threshold decision on graded data: it is not certified either way)"
                                                  : "a rectangular pencil") +
                                  " with sources at this size: the conditions on the sources are decided by the exact "
                                  "route, which takes at most " +
                                  std::to_string(io::DaeCase::dense_limit) +
                                  " entries of E (m·N = " + std::to_string(static_cast<long>(m) * n) + ") and " +
                                  std::to_string(io::DaeCase::dense_side) + " rows or columns");
    exact_source_conditions(c, out);  // not certified either way
    note << "; the conditions on the sources (a singular or rectangular pencil with f) decided by the exact route";
  }
  note << "; the equations of motion are not formed on this route (dense N × N)";
  if (!input_caveat(opt).empty()) note << "; " << input_caveat(opt);
  out.decisions.float_tests = ev.decisions;
  out.certified = unknown;
  out.note = note.str();
  out.trace.push_back(summary_decision(ev, static_cast<long>(m), static_cast<long>(n), out.tower.back().dim));
  return out;
}

}  // namespace dcad::fast
