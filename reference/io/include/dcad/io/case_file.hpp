// Linear case files (.json) per ../shared/CONTRACT.md, read with exact numbers: the `dirac`,
// `pontryagin` and `constrained` forms.  Errors are InputError: "FILE: JSON-PATH: expected …, found …"
// (or FILE:LINE:COLUMN for syntax).
#pragma once

#include "dcad/io/input_error.hpp"
#include "dcad/reference/matrix.hpp"
#include "dcad/reference/rational.hpp"

#include <string>
#include <vector>

namespace dcad::io {

using reference::Rational;
using QMatrix = reference::Matrix<Rational>;

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
  EnergyInput energy;  ///< zero if absent (or for `pontryagin`)
  bool has_pontryagin = false;
  PontryaginInput pontryagin;
  bool has_constrained = false;
  ConstrainedInput constrained;
  std::vector<std::size_t> coordinates;  ///< optional: variables to write the reduced equations in
  std::vector<Rational> initial;         ///< optional: x(0) for `simulate` (all N values)
};

/// A linear case file (InputError for bad input, or for a case in the expression form).
CaseFile read_case(const std::string& file);

}  // namespace dcad::io
