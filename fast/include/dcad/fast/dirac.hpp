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
  /// The raw data it was built from when not a graph (basis rows, a Poisson bivector, a distribution's
  /// form): what `assessed` (rank.hpp) reads of a caller's Dirac structure.
  MatrixXd given;
  MatrixXd v_part() const { return d.columns().topRows(n); }
  MatrixXd alpha_part() const { return d.columns().bottomRows(n); }
};

/// The raw data of a Dirac structure for `assessed` (rank.hpp): the presymplectic form it is the graph of,
/// else its basis (orthonormal, so a deficiency decided on it is certain only if the caller vouches for it).
inline const MatrixXd& dirac_data(const DiracStructure& d) {
  return d.graph_of.size() ? d.graph_of : d.given.size() ? d.given : d.d.columns();
}

/// Lemma 4.1: dim D = n and ⟨⟨D, D⟩⟩ = 0; `why` explains a negative answer.
struct DiracCheck {
  Truth valid = unknown;  ///< unknown until dirac_defect decides
  std::string why;        ///< why D is not Dirac (also when that is only likely: valid unknown)
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
