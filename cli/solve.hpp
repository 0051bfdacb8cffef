// `dcad solve`: the CAD on a case file by one backend, as a report for people and as the JSON of
// ../shared/CONTRACT.md.  Numbers are already formatted: exact "p/q" (reference) or %.17g (fast).
#pragma once

#include "dcad/io/case_file.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace dcad::cli {

/// a·x = b as the nonzero coefficients (variable index, coefficient string) and the right-hand side;
/// sparse, so that circuits with 10^5 branches print in linear space.
struct Equation {
  std::vector<std::pair<std::size_t, std::string>> terms;
  std::string rhs;
};

struct SolveReport {
  std::string backend;
  bool certified = true;
  std::vector<long> dims;
  long steps = 0;
  bool consistent = true;
  long solution_rank = 0;
  struct Step {
    long dim = 0;
    std::vector<Equation> equations;  ///< constraints added to reach M_k
  };
  std::vector<Step> tower;
  bool has_reduced = false;
  std::vector<std::size_t> coords;
  std::vector<std::vector<std::string>> f_matrix, g;
  std::vector<std::string> f;
  /// more terms of ż (the forced route: the sources' jets V1(t), V1'(t), …): names and per row coefficients
  std::vector<std::string> extra_names;
  std::vector<std::vector<std::string>> extra_terms;
  long first_class = -1, second_class = -1;              ///< `constrained` systems: r − 2s and 2s on M_c
  std::vector<Equation> second_class_constraints;        ///< χ (reference)
  std::vector<std::vector<std::string>> dirac_bracket;   ///< J* (reference)
  /// Theorem 3.28 / 7.4 (reference): constraints adapted to the primary ones, in `adapted_variables`
  bool has_adapted = false;
  std::string adapted_setting;                 ///< "N" (constrained) or "T*TQ" (pontryagin, §7)
  std::vector<std::string> adapted_variables;
  long s_prime = 0, secondary_first_class = 0;
  std::vector<Equation> adapted_chi, abridged_terms;
  /// M_c exactly (reference only): point + span of the rows of the basis, for `dcad check`
  bool has_final = false;
  io::QMatrix final_basis;
  std::vector<io::Rational> final_point;
  bool has_final_constraints = false;
  std::vector<Equation> final_constraints;  ///< equations of M_c (reference and ball pipeline; JSON `final_constraints`)
  std::string note;  ///< e.g. why `certified` recomputed exactly
  long decisions_float = 0, decisions_verified = 0, decisions_exact = 0;
  long decisions_machine_words = 0;  ///< certified: 1 if the whole run was exact in 64- or 128-bit rationals
  int word_bits = 0;  ///< the run in machine words (solve_small): 64, or 128 when a number outgrew 64 bits
};

/// What `dcad solve` computes beyond the CONTRACT's required keys and the tower (`--with`): a CI
/// that wants dims and solution rank need not pay for the §7 embedding (4n variables) or the bracket.
struct Parts {
  bool final_constraints = true;  ///< "final": the equations of M_c (JSON `final_constraints`)
  bool reduced = true;            ///< "reduced": the equations of motion (CEF (5.12); JSON `reduced`)
  bool classes = true;            ///< "classes": first/second class and the Dirac bracket (`constrained` cases)
  bool adapted = true;            ///< "adapted": constraints adapted to the primary ones (Thm 3.28 / 7.4)
};
/// "all", "none" or a comma-separated list of final, reduced, classes, adapted; throws
/// std::invalid_argument naming the word it does not know.
Parts parse_parts(const std::string& list);

/// "2*x1 - 1/3*x2 = 5" in the given variable names.
std::string equation_text(const Equation& e, const std::vector<std::string>& names);
/// x as %.17g (round-trips), always as a float: "1.0", never "1" (an exact integer string) or "-0".
std::string float_text(double x);
/// Row i of [a | b] (exact) as an Equation.
Equation row_equation(const io::QMatrix& rows, std::size_t i);

/// The reference: the pipeline in exact machine words (solve_small), recomputed on mpq_rational if a
/// number outgrows 128 bits; the same result either way (small_rational.hpp).
SolveReport solve_reference(const io::CaseFile& c, const Parts& parts = {});
/// The pipeline on SmallRational, then on WideRational if a number outgrows 64 bits; throws
/// reference::Overflow if one outgrows 128 (solve_small.cpp).
SolveReport solve_small(const io::CaseFile& c, const Parts& parts = {});
/// The pipeline on mpq_rational alone.
SolveReport solve_rational(const io::CaseFile& c, const Parts& parts = {});
SolveReport solve_fast(const io::CaseFile& c, const Parts& parts = {});
/// The reference pipeline in ball arithmetic (solve_ball.cpp); throws certified::Uncertain at the
/// first zero test it cannot certify.  `max_radius`: the widest ball among the printed numbers.
SolveReport solve_ball(const io::CaseFile& c, double& max_radius, const Parts& parts = {});
/// `small` (the reference pipeline in 64-, then 128-bit rationals; skipped if empty); if it throws
/// reference::Overflow, `ball` (the pipeline in ball arithmetic); if that throws
/// certified::Uncertain, `exact` (the pipeline on mpq_rational).  Every discrete output equals the
/// reference's whichever finishes (small_rational.hpp, ball.hpp give the proofs).
SolveReport certify(const std::function<SolveReport()>& small, const std::function<SolveReport(double&)>& ball,
                    const std::function<SolveReport()>& exact);
/// certify(solve_small up to kSmallFirstUpTo variables, solve_ball, solve_rational).
SolveReport solve_certified(const io::CaseFile& c, const Parts& parts = {});

nlohmann::json to_json(const SolveReport& r, const io::CaseFile& c);
std::string to_text(const SolveReport& r, const io::CaseFile& c);

}  // namespace dcad::cli
