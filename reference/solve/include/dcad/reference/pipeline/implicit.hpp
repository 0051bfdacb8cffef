// The implicit form (CONTRACT "Linear and implicit DAEs"): φ(t, x, ẋ) = 0, each equation affine in ẋ,
// by CEF (1.6) at a point,
//     M_0 = R^N,   M_{k+1} = {x ∈ M_k : some v ∈ T_x M_k (at fixed t: v + ∂_t) has φ(t, x, v) = 0},
// on the pointwise machinery of the expression form (reference/nonlinear/pointwise.hpp with
// LagrangianSystem::implicit: M_k as graphs in charts, the system a(t, x)·ẋ + b(t, x) = 0 for ẋ tangent
// to M_k, its Fredholm candidates the next constraints).  Written once over the number: the exact route
// (Rational, the reference and certified backends) and the double route (dcad::fast) use it.
#pragma once

#include "dcad/reference/pipeline/pointwise.hpp"

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dcad::reference::pipeline {

/// Given values must hold at M_c's point (io::InputError naming the first that the algorithm moved).
template <class T>
void check_given_implicit(const PointwiseResult<T>& r, const io::LagrangianCase& c,
                          const std::function<bool(const T&, const Rational&)>& same,
                          const std::function<std::string(const T&)>& text) {
  if (!r.consistent || r.point.size() != c.system.n) return;
  for (std::size_t i = 0; i < c.system.n; ++i)
    if (c.initial[i] && !same(r.point[i], *c.initial[i]))
      throw io::InputError(c.file + ": /initial/" + c.system.names[i] +
                           ": expected a value on M_c (the constraints give " + c.system.names[i] + " = " +
                           text(r.point[i]) + " with the other given values), found " + c.initial[i]->str());
}

/// The result as a Solution: dims of M_0 … M_c, steps, consistency, the solution rank (the dimension
/// of the affine space of ẋ ∈ T_x M_c with φ = 0), each step's constraints as tangent equations at the
/// point solved for a coordinate, the point and one ẋ with the others' differences (`gauge`).
template <class T>
dcad::Solution<T> implicit_solution(const PointwiseResult<T>& r, const io::LagrangianCase& c,
                                    const std::string& route) {
  dcad::Solution<T> out;
  out.file = c.file;
  out.name = c.name;
  out.variables = c.system.names;
  out.algorithm = Algorithm::implicit_equation;
  for (long d : r.dims) out.tower.push_back({d, {}});
  out.steps = static_cast<long>(r.steps);
  out.consistent = r.consistent;
  if (r.consistent && r.regular) out.solution_rank = static_cast<long>(r.solution_rank);
  out.pointwise = pointwise_part(r, c, route, 1);  // r.levels[0] is M_0 (nothing added)
  return out;
}

/// Which exact route: CEF (1.6) eliminated on the formulas (nonlinear/ide_formulas.hpp) where it decides
/// every step, else on jets (the default); or one of them alone (two routes to one tower, for the tests).
enum class ImplicitRoute { automatic, formulas, jets };

/// ImplicitRoute::formulas where the formulas leave a decision open (what() says which).
struct FormulasUndecided : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// CEF (1.6) on the implicit form: a proof that M_1 = ∅ — a rational combination of the equations without
/// derivatives that is a nonzero constant as a function (their canonical forms, nonlinear/polynomial.hpp; the two
/// concentric circles x² + y² = 1, x² + y² = 4 give (1)·eq 1 + (−1)·eq 2 = 3) — as text naming it, else nullopt.
/// No such combination proves nothing (the equations may still have no common zero).
std::optional<std::string> empty_m1_proof(const LagrangianSystem& s);

/// The reference's route: exact, at the given values (or dcad's default point); NotExactHere where a
/// formula is irrational there, PointwiseNoPoint where no rational point of M_c is reached.
dcad::Solution<Rational> solve_implicit_exact(const io::LagrangianCase& c,
                                              ImplicitRoute route = ImplicitRoute::automatic);

}  // namespace dcad::reference::pipeline
