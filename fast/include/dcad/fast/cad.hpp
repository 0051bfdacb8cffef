// The CAD on linear systems in double; the twin of dcad/reference/cad.hpp.  Constraints are kept as
// orthonormal rows A (with right-hand sides b), so M_k = {x : A x = b} = Aᵀ b + (row A)^⊥ needs no
// further decision; each step projects the candidate equations ⟨H x + g, u⟩ = 0, u ∈ W_k^D, off the
// old rows and decides (a) how many are new and (b) whether the rest is consistent.
// Cost (issue 14): E_D and ω_D are decided once (not at all for the graph of a presymplectic form),
// and each step works in E_D's coordinates: W_k = T M_k ∩ E_D is the complement of the equations'
// rows and W_k^D = ker(W_kᵀ Ω) one decision — no intersections of annihilators in R^{2n} (cad.cpp,
// d_orthogonal).
#pragma once

#include "dcad/fast/dirac.hpp"
#include "dcad/types.hpp"

#include <optional>

namespace dcad::fast {

struct LinearSystem {
  DiracStructure d;
  MatrixXd hessian;
  VectorXd gradient;
  double constant = 0;
};

/// The `pontryagin` data in double (dcad/types.hpp; the reference's is PontryaginInput<T>).
using PontryaginInput = PontryaginData<MatrixXd, VectorXd>;

/// Same formulas as dcad::reference::pontryagin_system (CEF §6), Δ = ker K decided here.
LinearSystem pontryagin_system(const PontryaginInput& in, const Options& opt = {});
/// Its energy alone, E = p·v − L (hessian and gradient; no Dirac structure, nothing decided).
LinearSystem pontryagin_energy(const PontryaginInput& in);

/// One level of the tower.  Unlike the reference's, it does not hold W_k = T M_k ∩ E_D: the fast CAD
/// never forms it (intersection(m.direction, dirac_distribution(d)) does, at the cost of a decision).
struct CadStep {
  AffineSubspace m;
  MatrixXd equations;  ///< new equations [a | b] (orthonormal a, orthogonal to earlier ones)
  long dim() const { return m.empty ? -1 : m.direction.dim(); }
};

struct CadResult {
  std::vector<CadStep> tower;
  bool consistent = true;
  int steps = 0;
  int solution_rank = 0;
  Truth certain = yes;                  ///< yes if every decision below was certain, else unknown
  std::vector<RankDecision> decisions;  ///< every decision, in order (the trace's evidence)
  bool unique() const { return consistent && solution_rank == 0; }
  const CadStep& final_step() const { return tower.back(); }
};

/// `initial` rows [a | b] restrict M_0 to {a x = b} (Gotay–Nester for (N, Ω, E, M_0) with D = D_{(T M_0, Ω)}).
CadResult constraint_tower(const LinearSystem& s, const Options& opt = {}, const MatrixXd& initial = MatrixXd());

/// The step shared by the fast CAD and the fast Dirac–Bergmann: adds the equations ca x = cb to the
/// orthonormal system a x = b — projects them off the rows of a, decides (scale `scale`) how many are
/// new and (scale max(rhs_scale, scale)) whether what is left is consistent.  Appends the new rows
/// to a, b and returns how many, or −1 if inconsistent.  Both decisions go to `trace` and their
/// verdicts into `certain`.
int absorb_equations(MatrixXd& a, VectorXd& b, const MatrixXd& ca, const VectorXd& cb, double scale, double rhs_scale,
                     const Options& opt, std::vector<RankDecision>& trace, Truth& certain);

/// {x : a x = b} for orthonormal rows a: point aᵀ b, direction the complement of the rows.
AffineSubspace affine_from_orthonormal(const MatrixXd& a, const VectorXd& b);

/// dE(x) = H x + g.
VectorXd energy_differential(const LinearSystem& s, const VectorXd& x);

/// {ẋ ∈ T M_c : (ẋ, dE(x)) ∈ D} at a point x of M_c: the solutions of (5.7)–(5.8) (the twin of the
/// reference's).  `certain` is cleared if the tower or the solve decided anything uncertainly.
AffineSubspace velocities(const LinearSystem& s, const CadResult& r, const VectorXd& x, const Options& opt = {});

/// A consistent initial point (the twin of the reference's): a point of M_c with the given values, the
/// free ones 0 where M_c allows; or the first level M_k whose equations the given values cannot meet.
struct InitialPoint {
  bool consistent = false;
  VectorXd point;
  int level = 0;
  VectorXd violated;    ///< the first equation they cannot meet, [a | b]
  Truth certain = yes;  ///< every consistency decision was certain (and the tower was)
};
InitialPoint consistent_initial_point(const CadResult& r, const std::vector<std::optional<double>>& given,
                                      const Options& opt = {});

struct ReducedEquations {
  std::vector<int> coords;
  MatrixXd f_matrix;
  VectorXd f;
  MatrixXd g;
  Truth certain = yes;
};
/// Default coordinates as in the reference: the first variables, in order, independent on T M_c.
ReducedEquations reduced_equations(const LinearSystem& s, const CadResult& r, std::vector<int> coords = {},
                                   const Options& opt = {});

}  // namespace dcad::fast
