// How the reference pipeline (pipeline/*.hpp, written once over the scalar) meets its scalar: exact
// input numbers lifted into T, whether a computed T is shown as a term, and whether T is exact (then
// the solution also carries M_c exactly, for `dcad check`).  Specialized for the exact scalars here.
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/reference/fmpq.hpp"
#include "dcad/reference/small_rational.hpp"
#include "dcad/solution.hpp"

namespace dcad::reference::pipeline {

template <class T>
struct Numbers;

template <>
struct Numbers<Rational> {
  static constexpr bool exact = true;
  static Rational lift(const Rational& q) { return q; }
  static bool shown(const Rational& q) { return q != 0; }
};

template <class W>
struct Numbers<BasicSmallRational<W>> {
  static constexpr bool exact = true;
  static BasicSmallRational<W> lift(const Rational& q) { return BasicSmallRational<W>::from(q); }
  static bool shown(const BasicSmallRational<W>& q) { return q != 0; }
};

template <>
struct Numbers<Fmpq> {
  static constexpr bool exact = true;
  static Fmpq lift(const Rational& q) { return Fmpq::from(q); }
  static bool shown(const Fmpq& q) { return q != 0; }
};

template <class T>
Matrix<T> lift(const io::QMatrix& m) {
  Matrix<T> out(m.rows(), m.cols());
  for (Index i = 0; i < m.rows(); ++i)
    for (Index j = 0; j < m.cols(); ++j) out(i, j) = Numbers<T>::lift(m(i, j));
  return out;
}

template <class T>
std::vector<T> lift(const std::vector<Rational>& v) {
  std::vector<T> out;
  for (const Rational& x : v) out.push_back(Numbers<T>::lift(x));
  return out;
}

/// Row i of [a | b] as the equation a·x = b, with the terms T shows.
template <class T>
Equation<T> row_equation(const Matrix<T>& rows, Index i) {
  Equation<T> e;
  for (Index j = 0; j + 1 < rows.cols(); ++j)
    if (Numbers<T>::shown(rows(i, j))) e.terms.emplace_back(j, rows(i, j));
  e.rhs = rows(i, rows.cols() - 1);
  return e;
}

template <class T>
std::vector<Equation<T>> equations(const Matrix<T>& rows) {
  std::vector<Equation<T>> out;
  for (Index i = 0; i < rows.rows(); ++i) out.push_back(row_equation(rows, i));
  return out;
}

template <class T>
Rows<T> dense(const Matrix<T>& m) {
  Rows<T> out(m.rows());
  for (Index i = 0; i < m.rows(); ++i) out[i] = m.row(i);
  return out;
}

}  // namespace dcad::reference::pipeline
