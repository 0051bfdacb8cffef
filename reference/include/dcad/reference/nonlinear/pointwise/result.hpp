// The pointwise CAD's result and its exact zero tests (pointwise.hpp: the algorithm).
#pragma once

#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/symbolic/lagrangian_system.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::reference {

/// Zero tests of the exact route: x == 0.  Pivots: the first nonzero candidate.  (The double
/// route, fast/pointwise.hpp, decides each number relative to the magnitude it was computed from.)
template <class T>
struct ExactDecisions {
  /// The step's data (the constant terms of its linear system), before its decisions.  A route in
  /// floating point uses it to see graded data, where no zero can be certain; here nothing.
  void step_data(const std::vector<T>&) {}
  bool zero(const T& x) { return x == 0; }
  bool zero(const Jet<T>& j) { return j.is_zero(); }
  /// A value taken as zero that one more Newton step could still make smaller (rounding routes).
  bool polish(const T&) { return false; }
  /// The index of the pivot among `values`, or values.size() if all are zero.
  std::size_t pivot(const std::vector<T>& values) {
    for (std::size_t i = 0; i < values.size(); ++i)
      if (values[i] != 0) return i;
    return values.size();
  }
};

template <class T>
struct PointwisePivot {
  std::string row, column;
  T value;
};

/// A constraint added at some step: solved for one chart coordinate; its tangent equation at the
/// point, Σ_j g_j s_j = rhs over the chart of the previous M_k (g of the solved coordinate is 1).
template <class T>
struct PointwiseConstraint {
  std::size_t solved_for = 0;  ///< a variable index (q, v or t of LagrangianSystem)
  std::vector<std::pair<std::size_t, T>> gradient;
  T rhs = T(0);
};

template <class T>
struct PointwiseLevel {
  long dim = 0;                               ///< dim M_k (at fixed time)
  std::vector<std::size_t> chart;             ///< its coordinates (variable indices), time first if any
  std::vector<PointwiseConstraint<T>> added;  ///< the constraints that cut M_k out of M_{k−1}
  std::vector<PointwisePivot<T>> pivots;      ///< of the (ṡ, λ) system on M_k
};

template <class T>
struct PointwiseResult {
  std::vector<long> dims;  ///< dim M_k, k = 0…c (−1: empty)
  std::size_t steps = 0;
  bool consistent = true;
  bool regular = true;  ///< false: a rank drops at the point (`why`); dims are then partial
  std::string why;
  std::size_t solution_rank = 0;
  std::vector<T> point;  ///< (q, v, p) at the point, 3n values
  T time = T(0);
  std::vector<T> velocity;            ///< ẋ at the point, one solution (3n)
  std::vector<std::vector<T>> gauge;  ///< a basis of the other solutions' differences (solution_rank rows)
  std::vector<std::vector<T>> tangent;  ///< a basis of T_x M_c (at fixed time) in x = (q, v, p): ∂x/∂s_j, s M_c's chart
  std::vector<PointwiseLevel<T>> levels;  ///< levels[k] describes M_{k+1}
  long order = 0;                         ///< jets were computed to this order
  long checked_order = 0;                 ///< the last step's constraints vanish on M_c to this order
  std::size_t moves = 0;                  ///< Newton steps that moved the given point onto M_c
  /// The coordinates solved for at each step: plan[0] the dependent velocities of M_1, plan[k] those
  /// of M_{k+1}.  Given back to pointwise_cad at a nearby point, the same choices are made there
  /// (where their pivots are nonzero): the projection onto M_c is then one fixed map.
  std::vector<std::vector<std::size_t>> plan;
};

using symbolic::PointwiseNoPoint;

}  // namespace dcad::reference
