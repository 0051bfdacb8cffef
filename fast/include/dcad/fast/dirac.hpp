// Linear Dirac structures in double; the twin of dcad/reference/dirac.hpp.  D is held by an
// orthonormal basis of R^{2n} (columns (v, α)).
#pragma once

#include "dcad/fast/symplectic.hpp"

namespace dcad::fast {

struct DiracStructure {
  int n = 0;
  Subspace d = Subspace::zero(0);
  /// The presymplectic form ω when D was built as its graph (dirac_from_presymplectic), else empty:
  /// then E_D = R^n and ω_D = ω (CEF §4), which the CAD uses instead of deciding them again.
  MatrixXd graph_of;
  MatrixXd v_part() const { return d.columns().topRows(n); }
  MatrixXd alpha_part() const { return d.columns().bottomRows(n); }
};

/// Lemma 4.1: dim D = n and ⟨⟨D, D⟩⟩ = 0; `why` explains a negative answer.
struct DiracCheck {
  Truth valid;
  std::string why;  ///< why D is not Dirac (also when that is only likely: valid unknown)
};
DiracCheck dirac_defect(const DiracStructure& d, const Options& opt = {});
/// Throws std::invalid_argument naming `fn` if D is certainly not Dirac; else the verdict, yes or
/// unknown (the caller's result is then not certain).
Truth require_dirac(const DiracStructure& d, const std::string& fn, const Options& opt = {});

DiracStructure dirac_from_basis(const MatrixXd& rows, const Options& opt = {});
DiracStructure dirac_from_presymplectic(const MatrixXd& w);
DiracStructure dirac_from_distribution(const Subspace& e, const MatrixXd& w);
DiracStructure dirac_from_poisson(const MatrixXd& p);

Subspace dirac_distribution(const DiracStructure& d, const Options& opt = {});
AffineSubspace dirac_flat(const DiracStructure& d, const VectorXd& x, const Options& opt = {});
Subspace dirac_flat(const DiracStructure& d, const Subspace& w, const Options& opt = {});
PresymplecticForm dirac_form(const DiracStructure& d, const Options& opt = {});
Subspace dirac_orthogonal(const DiracStructure& d, const Subspace& w, const Options& opt = {});
Truth is_presymplectic(const DiracStructure& d, const Options& opt = {});
Truth is_poisson(const DiracStructure& d, const Options& opt = {});

}  // namespace dcad::fast
