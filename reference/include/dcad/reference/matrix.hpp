// Dense matrices over an exact field and exact row reduction.
// Everything here is a literal textbook algorithm: no pivoting strategy, no tolerance;
// a zero test is `x == 0`.  The scalar must be an exact field (std::numeric_limits<T>::is_exact,
// e.g. mpq_rational, SmallRational, Fmpq) or declare what its zero test is (`T::zero_test`): the
// benchmark's ball scalars (bench/ball.hpp, bench/method_arb.cpp) answer it with a proof or throw, and
// its tolerance scalars (bench/approx.hpp) answer it approximately (comparison methods there, never
// part of the product).
#pragma once

#include <cstddef>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dcad::reference {

template <class T>
struct is_exact_field {
  static constexpr bool value =
      std::numeric_limits<T>::is_specialized && std::numeric_limits<T>::is_exact && !std::numeric_limits<T>::is_integer;
};

template <class T, class = void>
struct declares_zero_test : std::false_type {};
template <class T>
struct declares_zero_test<T, std::void_t<decltype(T::zero_test)>> : std::true_type {};

template <class T>
struct admissible_scalar {
  static constexpr bool value = is_exact_field<T>::value || declares_zero_test<T>::value;
};

/// x == 0 where skipping a zero is only an optimization (no decision is needed; a ball overloads it).
template <class T>
bool known_zero(const T& x) {
  return x == 0;
}

using Index = std::size_t;

/// Row-major dense matrix over an exact field.  Vectors are r×1 or 1×c matrices or std::vector<T>.
template <class T>
class Matrix {
  static_assert(admissible_scalar<T>::value,
                "dcad::reference works over an exact field (e.g. mpq_rational), or a scalar that declares its zero "
                "test (T::zero_test)");

 public:
  Matrix() = default;
  Matrix(Index rows, Index cols) : rows_(rows), cols_(cols), a_(rows * cols) {}  // T() is 0
  static Matrix identity(Index n) {
    Matrix m(n, n);
    for (Index i = 0; i < n; ++i) m(i, i) = T(1);
    return m;
  }
  /// Rows given as vectors, all of length `cols`.
  static Matrix from_rows(const std::vector<std::vector<T>>& rows, Index cols) {
    Matrix m(rows.size(), cols);
    for (Index i = 0; i < rows.size(); ++i) {
      if (rows[i].size() != cols) throw std::invalid_argument("Matrix::from_rows: row length mismatch");
      for (Index j = 0; j < cols; ++j) m(i, j) = rows[i][j];
    }
    return m;
  }
  static Matrix column(const std::vector<T>& v) { return from_rows({v}, v.size()).transpose(); }

  Index rows() const { return rows_; }
  Index cols() const { return cols_; }
  T& operator()(Index i, Index j) { return a_[i * cols_ + j]; }
  const T& operator()(Index i, Index j) const { return a_[i * cols_ + j]; }
  std::vector<T> row(Index i) const { return std::vector<T>(a_.begin() + i * cols_, a_.begin() + (i + 1) * cols_); }
  std::vector<T> col(Index j) const {
    std::vector<T> v(rows_);
    for (Index i = 0; i < rows_; ++i) v[i] = (*this)(i, j);
    return v;
  }
  bool operator==(const Matrix& o) const { return rows_ == o.rows_ && cols_ == o.cols_ && a_ == o.a_; }
  bool operator!=(const Matrix& o) const { return !(*this == o); }
  bool is_zero() const {
    for (const T& x : a_)
      if (x != 0) return false;
    return true;
  }

  Matrix transpose() const {
    Matrix t(cols_, rows_);
    for (Index i = 0; i < rows_; ++i)
      for (Index j = 0; j < cols_; ++j) t(j, i) = (*this)(i, j);
    return t;
  }
  /// Rows [r0, r1) and columns [c0, c1).
  Matrix block(Index r0, Index r1, Index c0, Index c1) const {
    Matrix b(r1 - r0, c1 - c0);
    for (Index i = r0; i < r1; ++i)
      for (Index j = c0; j < c1; ++j) b(i - r0, j - c0) = (*this)(i, j);
    return b;
  }

 private:
  Index rows_ = 0, cols_ = 0;
  std::vector<T> a_;
};

template <class T>
std::string shape(const Matrix<T>& m) {
  return std::to_string(m.rows()) + "x" + std::to_string(m.cols());
}

/// Throws std::invalid_argument "fn: expected …, found …".
inline void require(bool ok, const std::string& fn, const std::string& expected, const std::string& found) {
  if (!ok) throw std::invalid_argument(fn + ": expected " + expected + ", found " + found);
}

template <class T>
Matrix<T> operator*(const Matrix<T>& a, const Matrix<T>& b) {
  require(a.cols() == b.rows(), "operator*", "inner dimensions to agree", shape(a) + " * " + shape(b));
  Matrix<T> c(a.rows(), b.cols());
  for (Index i = 0; i < a.rows(); ++i)
    for (Index k = 0; k < a.cols(); ++k) {
      if (known_zero(a(i, k))) continue;
      for (Index j = 0; j < b.cols(); ++j) c(i, j) += a(i, k) * b(k, j);
    }
  return c;
}

template <class T>
Matrix<T> operator+(Matrix<T> a, const Matrix<T>& b) {
  require(a.rows() == b.rows() && a.cols() == b.cols(), "operator+", "equal shapes", shape(a) + " + " + shape(b));
  for (Index i = 0; i < a.rows(); ++i)
    for (Index j = 0; j < a.cols(); ++j) a(i, j) += b(i, j);
  return a;
}

template <class T>
Matrix<T> operator-(const Matrix<T>& a) {
  Matrix<T> m = a;
  for (Index i = 0; i < m.rows(); ++i)
    for (Index j = 0; j < m.cols(); ++j) m(i, j) = -m(i, j);
  return m;
}

template <class T>
Matrix<T> operator-(const Matrix<T>& a, const Matrix<T>& b) {
  return a + (-b);
}

/// [a; b] (rows of a, then rows of b).
template <class T>
Matrix<T> vstack(const Matrix<T>& a, const Matrix<T>& b) {
  require(a.cols() == b.cols(), "vstack", "equal column counts", shape(a) + " over " + shape(b));
  Matrix<T> m(a.rows() + b.rows(), a.cols());
  for (Index i = 0; i < a.rows(); ++i)
    for (Index j = 0; j < a.cols(); ++j) m(i, j) = a(i, j);
  for (Index i = 0; i < b.rows(); ++i)
    for (Index j = 0; j < b.cols(); ++j) m(a.rows() + i, j) = b(i, j);
  return m;
}

/// [a b] (columns of a, then columns of b).
template <class T>
Matrix<T> hstack(const Matrix<T>& a, const Matrix<T>& b) {
  require(a.rows() == b.rows(), "hstack", "equal row counts", shape(a) + " beside " + shape(b));
  Matrix<T> m(a.rows(), a.cols() + b.cols());
  for (Index i = 0; i < a.rows(); ++i) {
    for (Index j = 0; j < a.cols(); ++j) m(i, j) = a(i, j);
    for (Index j = 0; j < b.cols(); ++j) m(i, a.cols() + j) = b(i, j);
  }
  return m;
}

template <class T>
bool is_square(const Matrix<T>& m) {
  return m.rows() == m.cols();
}

template <class T>
bool is_skew(const Matrix<T>& m) {
  return is_square(m) && m == -m.transpose();
}

template <class T>
bool is_symmetric(const Matrix<T>& m) {
  return is_square(m) && m == m.transpose();
}

template <class T, class = void>
struct has_pivot_weight : std::false_type {};
template <class T>
struct has_pivot_weight<T, std::void_t<decltype(pivot_weight(std::declval<const T&>()))>> : std::true_type {};

/// The row p ≥ row holding the pivot of column `col`, or m.rows() if the column is zero there.
/// Exact scalars: the first nonzero entry.  Any nonzero entry gives the same RREF (the RREF of a
/// matrix is unique), so a scalar with a `pivot_weight` (a ball) first takes its largest entry that
/// is certainly nonzero, and tests entries for zero only when there is none.
template <class T>
Index pivot_row(const Matrix<T>& m, Index row, Index col) {
  if constexpr (has_pivot_weight<T>::value) {
    Index best = m.rows();
    double w = 0;
    for (Index p = row; p < m.rows(); ++p)
      if (pivot_weight(m(p, col)) > w) {
        w = pivot_weight(m(p, col));
        best = p;
      }
    if (best < m.rows()) return best;
  }
  Index p = row;
  while (p < m.rows() && m(p, col) == 0) ++p;
  return p;
}

/// Reduced row echelon form with its pivot columns (Gauss–Jordan, exact).
template <class T>
struct Rref {
  Matrix<T> r;
  std::vector<Index> pivots;
};

template <class T>
Rref<T> rref(Matrix<T> m) {
  std::vector<Index> pivots;
  Index row = 0;
  for (Index col = 0; col < m.cols() && row < m.rows(); ++col) {
    const Index p = pivot_row(m, row, col);
    if (p == m.rows()) continue;
    for (Index j = 0; j < m.cols(); ++j) std::swap(m(row, j), m(p, j));
    const T inv = T(1) / m(row, col);
    for (Index j = 0; j < m.cols(); ++j) m(row, j) *= inv;
    T f, t;  // reused: an assignment into a scalar that has its limbs already allocates nothing
    for (Index i = 0; i < m.rows(); ++i) {
      if (i == row || known_zero(m(i, col))) continue;
      f = m(i, col);
      for (Index j = 0; j < m.cols(); ++j) {  // row i −= f · row `row` (a zero entry of it changes nothing)
        if (known_zero(m(row, j))) continue;
        t = f;
        t *= m(row, j);
        m(i, j) -= t;
      }
    }
    pivots.push_back(col);
    ++row;
  }
  return {m.block(0, row, 0, m.cols()), pivots};
}

template <class T>
Index rank(const Matrix<T>& m) {
  return rref(m).pivots.size();
}

/// A basis (as rows) of {x : m x = 0}, read off the RREF: one vector per free column.
template <class T>
Matrix<T> nullspace(const Matrix<T>& m) {
  const Rref<T> e = rref(m);
  std::vector<bool> is_pivot(m.cols(), false);
  for (Index p : e.pivots) is_pivot[p] = true;
  Matrix<T> k(m.cols() - e.pivots.size(), m.cols());
  Index out = 0;
  for (Index f = 0; f < m.cols(); ++f) {
    if (is_pivot[f]) continue;
    k(out, f) = T(1);
    for (Index i = 0; i < e.pivots.size(); ++i) k(out, e.pivots[i]) = -e.r(i, f);
    ++out;
  }
  return k;
}

/// One solution x of m x = b (as a vector), or nothing if the system is inconsistent.
template <class T>
bool solve_particular(const Matrix<T>& m, const std::vector<T>& b, std::vector<T>& x) {
  require(b.size() == m.rows(), "solve_particular", "right-hand side of length " + std::to_string(m.rows()),
          "length " + std::to_string(b.size()));
  const Rref<T> e = rref(hstack(m, Matrix<T>::column(b)));
  if (!e.pivots.empty() && e.pivots.back() == m.cols()) return false;  // pivot in b's column: 0 = 1
  x.assign(m.cols(), T(0));
  for (Index i = 0; i < e.pivots.size(); ++i) x[e.pivots[i]] = e.r(i, m.cols());
  return true;
}

/// X with m X = b, column by column the particular solution of solve_particular (free variables
/// zero), from one Gauss–Jordan on [m b]; false if some column is inconsistent.
template <class T>
bool solve_particular(const Matrix<T>& m, const Matrix<T>& b, Matrix<T>& x) {
  require(b.rows() == m.rows(), "solve_particular", "right-hand sides with " + std::to_string(m.rows()) + " rows",
          std::to_string(b.rows()) + " rows");
  const Rref<T> e = rref(hstack(m, b));
  x = Matrix<T>(m.cols(), b.cols());
  for (Index i = 0; i < e.pivots.size(); ++i) {
    if (e.pivots[i] >= m.cols()) return false;  // 0 = nonzero in some column of b
    for (Index j = 0; j < b.cols(); ++j) x(e.pivots[i], j) = e.r(i, m.cols() + j);
  }
  return true;
}

/// m is invertible: its inverse by Gauss–Jordan on [m I].
template <class T>
Matrix<T> inverse(const Matrix<T>& m) {
  require(is_square(m), "inverse", "a square matrix", shape(m));
  const Rref<T> e = rref(hstack(m, Matrix<T>::identity(m.rows())));
  require(e.pivots.size() == m.rows() && (m.rows() == 0 || e.pivots.back() < m.rows()), "inverse",
          "an invertible matrix", "a singular " + shape(m) + " matrix");
  return e.r.block(0, m.rows(), m.rows(), 2 * m.rows());
}

/// det m by Gaussian elimination (exact): product of the pivots, sign from the row swaps.
template <class T>
T determinant(Matrix<T> m) {
  require(is_square(m), "determinant", "a square matrix", shape(m));
  T det(1);
  for (Index c = 0; c < m.rows(); ++c) {
    const Index p = pivot_row(m, c, c);
    if (p == m.rows()) return T(0);
    if (p != c) {
      for (Index j = 0; j < m.cols(); ++j) std::swap(m(c, j), m(p, j));
      det = -det;
    }
    det *= m(c, c);
    std::vector<Index> nonzero;  // the pivot row's nonzero entries: a sparse matrix's rows change only there
    for (Index j = c; j < m.cols(); ++j)
      if (!known_zero(m(c, j))) nonzero.push_back(j);
    T f, t;
    for (Index i = c + 1; i < m.rows(); ++i) {
      if (known_zero(m(i, c))) continue;  // nothing to eliminate
      f = m(i, c) / m(c, c);
      for (Index j : nonzero) {
        t = f;
        t *= m(c, j);
        m(i, j) -= t;
      }
    }
  }
  return det;
}

template <class T>
T dot(const std::vector<T>& a, const std::vector<T>& b) {
  require(a.size() == b.size(), "dot", "vectors of equal length",
          std::to_string(a.size()) + " and " + std::to_string(b.size()));
  T s(0);
  for (Index i = 0; i < a.size(); ++i) s += a[i] * b[i];
  return s;
}

}  // namespace dcad::reference
