// The CONTRACT's linear DAE form (section "Linear and implicit DAEs (CEF (1.6))"): E ẋ = A x + f(t),
// E and A m×N exact rationals (rectangular allowed), f optional (formulas in the time), read exactly.
#pragma once

#include "dcad/io/case_file.hpp"
#include "dcad/reference/nonlinear/expression.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dcad::io {

struct DaeCase {
  std::string file, name, description;
  std::vector<std::string> variables;  ///< x's names, N of them
  /// E and A, m × N, dense — where they fit: above `dense_limit` entries or `dense_side` rows or columns only
  /// `e_entries`/`a_entries` hold them (`dense` false) and only the sparse route (fast) runs.
  QMatrix e, a;
  bool dense = true;
  long rows = 0;  ///< m; with `dense`, e.rows() is the one to read (a case built in code may set only e and a)
  /// The nonzero entries of E and A as (row, column, value), both encodings; empty in a case built in code
  /// (then e and a are the data).
  struct Entry {
    long row, col;
    Rational value;
  };
  std::vector<Entry> e_entries, a_entries;
  static constexpr long dense_limit = 4'000'000;  ///< m·N: 2,000 variables and equations (128 MB per matrix)
  static constexpr long dense_side =
      2'000;  ///< and m, N each (the exact route's left null vectors are m × m: a 3,900 × 150 case took 17 GB)
  /// f_i(t), one per equation, over the variable 0 (the time); the number 0 where f is absent.
  std::vector<reference::expr::Expr> f;
  std::string time_name;  ///< "" when the case names no time (f then constant)
  std::map<std::string, Rational> parameters;
  std::vector<std::optional<Rational>> initial;  ///< size N
  std::optional<Rational> initial_time;
  bool has_initial = false;
  std::size_t equations() const { return static_cast<std::size_t>(dense ? e.rows() : rows); }
};

/// The case's text for f_i, as given ("0" where absent), for messages and reports.
std::string source_name(std::size_t i, long order);

}  // namespace dcad::io
