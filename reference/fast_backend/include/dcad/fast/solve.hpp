// fast::solve — the fast twin on any problem (issue 26): the exact input rounded once (exact.hpp,
// with the assessment fast's certainty rests on), then fast's own routes in double —
//   linear cases        the CAD in E_D's coordinates, one rank decision per step      fast/cad.hpp
//   LC netlists         the graph route on the dimensionless twin (dcad/units.hpp)    fast/circuit.hpp
//   forces and sources  YM §4 with orthonormal jet rows                              fast/forced.hpp
//   the expression form the pointwise CAD on tracked doubles (pointwise.hpp, here in the fast backend)
// A result rests on the separation hypothesis of fast/rank.hpp: `certified` says yes only when every
// decision was on the right side of its threshold; otherwise unknown, and `note` names the cause.
#pragma once

#include "dcad/fast/rank.hpp"
#include "dcad/inspection.hpp"
#include "dcad/io/problem.hpp"
#include "dcad/solution.hpp"

namespace dcad::fast {

using Solution = dcad::Solution<double>;

/// Circuits up to this many branches get their equations of motion (dense) and, up to
/// kAdaptedBranches, the §7 adapted constraints.
constexpr std::size_t kDenseBranches = 120;
constexpr std::size_t kAdaptedBranches = 24;

/// io::InputError for bad input: a value beyond double's range, a form that is certainly not Dirac or
/// certainly degenerate.  `opt`: the decisions' thresholds (the input assessment is made here).
/// `certified` is yes only where every decision was proved in double (a nonzero beyond its rounding bound, a zero no
/// rounding touched) or the certified tier confirmed the answer (decisions.exact_verifications = 1, up to 2000
/// variables; Options::confirm_exactly): a zero decided in double rests on the separation hypothesis of rank.hpp,
/// which integer data of height 10^6 break (cases/regression-pointwise-height.json).
Solution solve(const io::Problem& p, const Parts& parts = {}, const Options& opt = {});

/// What a `dirac` case's structure is (CEF §4): each answer with its verdict; an uncertain one is
/// listed in `uncertain` with its evidence, and its value is the likely one.  A certain one is confirmed by the exact
/// reference::inspect up to 2000 variables (Options::confirm_exactly), as solve's answers are.
Inspection inspect(const io::CaseFile& c, const Options& opt = {});

/// The routes, for dcad::api's fallbacks: the expression form in double (the pointwise CAD of
/// the fast backend's pointwise CAD (pointwise.hpp) at the case's point; io::InputError for given values off M_c, as
/// the exact route) and the LC graph route.  Their `certified` is fast's own verdict, NOT confirmed: certain under
/// the separation hypothesis wherever a zero was assumed (decisions.float_tests > 0 on the expression form) — call
/// solve for an answer whose `certified` is never wrong.
Solution solve_expression(const io::LagrangianCase& c, const Options& opt = {});
/// The implicit form (CEF (1.6), pipeline/implicit.hpp) by the same pointwise algorithm in double.
Solution solve_implicit(const io::LagrangianCase& c, const Options& opt = {});
Solution solve_lc(const io::Netlist& deck, const io::CaseFile& names, const Parts& parts, const Options& opt = {});

}  // namespace dcad::fast
