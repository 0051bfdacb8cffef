// The forced CAD with sources in double; the twin of dcad/reference/forced.hpp.  Same problem,
// (ẋ − Zσ, (H − F)x + g − Bσ) ∈ D, same jet rows [x | 1 | σ⁽⁰⁾ | σ⁽¹⁾ | …], a different route: the
// left kernel of the λ-system from an SVD, the equations kept with orthonormal x-parts, each step
// projecting the candidates off them and deciding (decide_rank, with evidence) how many are new
// and how many source conditions remain.
#pragma once

#include "dcad/fast/cad.hpp"

namespace dcad::fast {

struct ForcedSystem {
  LinearSystem s;
  MatrixXd force;  ///< F (N×N; empty = 0)
  int sources = 0;
  MatrixXd source_force;      ///< B (N×m)
  MatrixXd shift;             ///< Z (N×m)
  MatrixXd given_conditions;  ///< rows [1 | σ⁽⁰⁾]
};

struct ForcedResult {
  std::vector<long> dims;
  int steps = 0;
  bool consistent = true;
  int orders = 1;
  MatrixXd equations;   ///< jet rows, x-parts orthonormal
  MatrixXd conditions;  ///< source conditions [1 | σ …], orthonormal rows
  int solution_rank = 0;
  Truth certain = yes;
  std::vector<RankDecision> decisions;
};

ForcedResult forced_tower(const ForcedSystem& f, const Options& opt = {});

}  // namespace dcad::fast
