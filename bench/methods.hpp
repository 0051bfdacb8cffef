// The methods compared by the sweep (issue 6), one translation unit each (heavy templates):
//   reference  the exact CAD (64-, then 128-bit words, FLINT's fmpq on Overflow)  method_reference.cpp
//   bf100/bf50 the same algorithm in cpp_bin_float_100/_50, |x| ≤ 1e-85/1e-40 × scale is zero
//   naive      the same algorithm in double, |x| ≤ 1e-9 × scale is zero   method_approx_*.cpp
//   fast       dcad::fast (orthogonal decompositions, SVD rank decisions)  method_fast.cpp
//   certified  machine words first, FLINT's fmpq on Overflow (dcad/certified/cascade.hpp)  method_certified.cpp
//   tier_*     one tier alone (issue 26): tier_mpq mpq_rational, tier_fmpq FLINT's fmpq (the reference's
//              Gauss–Jordan), tier_flint fmpq with fmpq_mat_rref, tier_ball bench/ball.hpp (the cascade's ball tier
//              until issue 26) and tier_arb Arb's arb_t (each recomputed in fmpq on an uncertain test)   method_*.cpp
#pragma once

#include "families.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace dcad::bench {

struct Outcome {
  std::vector<long> dims;
  long solution_rank = -1;
  bool consistent = true;
  bool uncertain = false;      ///< the method said so (fast's verdict)
  bool recomputed = false;     ///< certified: some zero test needed the exact recomputation
  bool machine_words = false;  ///< certified: decided exactly in 64- or 128-bit rationals
  bool failed = false;         ///< threw (message in `error`): counted as a wrong answer
  std::string error;
  std::vector<Eigen::MatrixXd> tower;  ///< columns span T M_k, k = 0 … c (double)
};

using Method = Outcome (*)(const families::Instance&);
Outcome run_reference(const families::Instance&);
/// The reference in machine words — SmallRational, then WideRational — or reference::Overflow: the
/// first tier of both `reference` and `certified`, one instantiation, so that the two are timed on the
/// same code, as in `dcad solve`.
Outcome run_small(const families::Instance&);
/// The reference on mpq_rational only: the truth of the adversarial check, independent of SmallRational.
Outcome run_mpq(const families::Instance&);
Outcome run_bf100(const families::Instance&);
Outcome run_bf50(const families::Instance&);
Outcome run_naive(const families::Instance&);
Outcome run_fast(const families::Instance&);
Outcome run_certified(const families::Instance&);
/// The exact tiers measured against the machine words (issue 26): the reference's Gauss–Jordan on FLINT's
/// fmpq (method_fmpq.cpp), and with every RREF by FLINT's fmpq_mat_rref (method_flint.cpp).
Outcome run_fmpq(const families::Instance&);
Outcome run_flint(const families::Instance&);
/// The ball tier alone, on an Uncertain recomputed in fmpq: bench/ball.hpp, and Arb's arb_t (method_arb.cpp).
Outcome run_ball(const families::Instance&);
Outcome run_arb(const families::Instance&);

/// Largest principal angle between two subspaces (columns); π/2 if the dimensions differ.
double largest_angle(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b);

}  // namespace dcad::bench
