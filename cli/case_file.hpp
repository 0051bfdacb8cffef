// Case files (.json) per ../shared/CONTRACT.md, read with exact numbers.
// Errors are InputError: "FILE: JSON-PATH: expected …, found …" (or FILE:LINE:COLUMN for syntax).
#pragma once

#include "dcad/reference/matrix.hpp"
#include "dcad/reference/rational.hpp"

#include <nlohmann/json.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::io {

using reference::Rational;
using QMatrix = reference::Matrix<Rational>;

struct InputError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

/// Parses JSON text keeping every non-integer number as its exact source text (a string), so
/// that 0.1 is read as 1/10, not as the double nearest to it.
/// Nesting deeper than 64 levels is refused (a case needs 4).
nlohmann::json parse_json_exact(const std::string& text, const std::string& file);
/// parse_json_exact of a file's contents (InputError if it cannot be read).
nlohmann::json read_json_file(const std::string& file);

/// The `dirac` member: one of the CONTRACT's forms.
struct DiracInput {
  std::string form;  ///< presymplectic | distribution | poisson | basis
  std::string path;  ///< JSON path of the form's data, for messages
  QMatrix w;         ///< presymplectic W, or the `form` of `distribution`
  QMatrix b;         ///< `distribution` rows
  QMatrix p;         ///< `poisson` P
  QMatrix g;         ///< `basis` rows (v, α)
};

/// The `pontryagin` member: L(q, v) = ½ vᵀ A v + qᵀ B v + ½ qᵀ C q + aᵀ q + bᵀ v, Δ = ker K.
struct PontryaginInput {
  std::size_t n = 0;
  QMatrix k, vv, qv, qq;
  std::vector<Rational> q, v;
  /// `forces`: F(q, v) = F_q q + F_v v, a horizontal one-form (YM §4); zero if absent
  bool has_forces = false;
  QMatrix fq, fv;
};

/// E(x) = ½ xᵀ H x + gᵀ x + c.
struct EnergyInput {
  QMatrix hessian;
  std::vector<Rational> gradient;
  Rational constant = 0;
};

/// The `constrained` member: (N, Ω, E, M) with Ω = `symplectic` and M = {a_i·x = b_i}, rows [a_i | b_i].
struct ConstrainedInput {
  QMatrix w, primary;
};

struct CaseFile {
  std::string file, name, description;
  std::size_t n = 0;
  std::vector<std::string> variables;
  bool has_dirac = false;
  DiracInput dirac;
  EnergyInput energy;       ///< zero if absent (or for `pontryagin`)
  bool has_pontryagin = false;
  PontryaginInput pontryagin;
  bool has_constrained = false;
  ConstrainedInput constrained;
  std::vector<std::size_t> coordinates;  ///< optional: variables to write the reduced equations in
  std::vector<Rational> initial;         ///< optional: x(0) for `simulate` (all N values)
  nlohmann::json expect;    ///< optional golden expectations (raw)
};

CaseFile read_case(const std::string& file);

/// A reading context: file name plus JSON path, for messages.
struct Where {
  std::string file, path;
  Where operator/(const std::string& key) const { return {file, path + "/" + key}; }
  Where operator/(std::size_t i) const { return {file, path + "/" + std::to_string(i)}; }
  [[noreturn]] void fail(const std::string& expected, const std::string& found) const;
};

/// The allowed name closest to `key` (edit distance, case-insensitive) if it is close enough to be a
/// likely misspelling, else "".
std::string nearest_name(const std::string& key, const std::vector<std::string>& allowed);

/// Bad input unless every key of the object `j` is one of `allowed` (a misspelt key would otherwise
/// be ignored and another system solved); the message suggests the nearest allowed key.
void require_known_keys(const nlohmann::json& j, const Where& at, const std::vector<std::string>& allowed);

Rational read_number(const nlohmann::json& j, const Where& at);
QMatrix read_matrix(const nlohmann::json& j, const Where& at, long rows = -1, long cols = -1);
std::string describe(const nlohmann::json& j);
std::vector<Rational> read_vector(const nlohmann::json& j, const Where& at, long size);

}  // namespace dcad::io
