// fast::solve: each input form dispatched once, to the fast twin's route.
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/certified/solve.hpp"

#include <new>
#include <sstream>
#include <typeinfo>

namespace dcad::fast {

Solution solve_linear(const io::CaseFile& c, const Parts& parts, const Options& options);
Solution solve_forced_netlist(const io::Netlist& deck, const std::vector<std::string>& variables,
                              const Options& options);
Solution solve_forced_case(const io::CaseFile& c, const Options& options);
Solution solve_dae(const io::DaeCase& c, const Options& options);

namespace {

/// The size up to which the fast backend confirms its certain answers by the certified tier (fast's own bound for
/// dense DAEs, Options::dae_sparse_from).
constexpr std::size_t kConfirmExactlyUpTo = 2000;

/// Whether the answer rests on a rank decided in double: a decision by σ's, |r_ii|, a norm or two routes, or
/// the expression and implicit forms' zero tests (their pivots are in `pointwise`, not the trace).
bool decided_in_double(const Solution& s) {
  // the Lagrangian form counts its zeros that rest on the hypothesis (ToleranceDecisions::assumed): none, and every
  // decision was proved in double (a nonzero beyond its rounding bound, a zero no rounding touched)
  if (s.pointwise && s.algorithm == Algorithm::cad) return s.decisions.float_tests > 0;
  if (s.pointwise || s.decisions.float_tests > 0) return true;
  for (const Decision& d : s.trace)
    if (d.by != DecidedBy::exact && d.by != DecidedBy::graph) return true;
  return false;
}

/// The discrete answer: what a rank decision can change.
/// `both`: the parts both answers carry (a route may leave the motion, classes or adapted constraints out).
struct Carried {
  bool classes = false, adapted = false, motion = false;
};

template <class N>
std::string discrete(const dcad::Solution<N>& s, const Carried& both) {
  std::ostringstream o;
  o << "dims";
  for (long d : s.dims()) o << " " << d;
  o << ", " << (s.consistent ? "consistent" : "inconsistent");
  if (s.solution_rank) o << ", solution rank " << *s.solution_rank;
  if (s.pointwise && !s.pointwise->regular) o << ", singular";
  if (s.regular_pencil) o << (*s.regular_pencil ? ", regular pencil" : ", singular pencil");
  if (both.classes) o << ", classes " << s.classes->first_class << "/" << s.classes->second_class;
  if (both.adapted)
    o << ", adapted s' " << s.adapted->s_prime << " secondary first class " << s.adapted->secondary_first_class
      << " chi " << s.adapted->chi.size() << " abridged " << s.adapted->abridged.size();
  if (both.motion)
    o << ", motion in " << s.motion->coordinates.size() << " coordinates, G with "
      << (s.motion->g.empty() ? 0 : s.motion->g[0].size()) << " columns";
  for (const SourceCondition& c : s.source_conditions) o << ", " << c.text << ": " << c.holds.text();
  return o.str();
}

/// A zero decided in double is certain only under the separation hypothesis (dcad/fast/rank.hpp): an exact nonzero is
/// never within a few rounding-error bounds of 0.  Integer data of height 10^6–10^7 break it: the kinetic matrix
/// [[13400166, −1023502, 9211667], …] has determinant 6 and a last singular value 3.9e-10 (cases/
/// regression-pointwise-height.json), which no test in double tells from 0, and the fast routes said certified with a
/// rank one too small.  So a certain answer that rests on double is confirmed by the certified tier (exact rationals:
/// dcad/certified/solve.hpp, `--backend certified`) up to kConfirmExactlyUpTo variables: certified where every discrete
/// key agrees (decisions.exact_verification = 1), not certified otherwise, saying what the exact route found.  Beyond
/// that size, or where the exact route cannot run, it is not certified: `--backend certified` proves it.
void confirm_exactly(const io::Problem& p, const Parts& parts, Solution& s) {
  if (!s.certified.yes() || !decided_in_double(s)) return;
  std::string why;
  if (s.variables.size() > kConfirmExactlyUpTo) {
    why =
        "its ranks were decided in double (certain only under the separation hypothesis of dcad/fast/rank.hpp) and "
        "not confirmed exactly: " +
        std::to_string(s.variables.size()) + " variables, beyond the " + std::to_string(kConfirmExactlyUpTo) +
        " the fast backend confirms; --backend certified proves them";
  } else {
    try {
      const certified::Solution e = certified::solve(p, parts);
      const Carried both{e.classes && s.classes, e.adapted && s.adapted, e.motion && s.motion};
      const std::string want = discrete(e, both), got = discrete(s, both);
      if (want == got && e.certified.yes()) {
        s.decisions.exact_verifications = 1;
        return;
      }
      why = want != got ? "the exact route (the certified tier) finds " + want + " where double found " + got +
                              ": a zero decided in double was not one (the separation hypothesis of "
                              "dcad/fast/rank.hpp failed)"
                        : "the certified tier agrees (" + want + ") but is not certified itself (" + e.note + ")";
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& x) {
      // a plain logic_error is the exact tier's internal disagreement ("please report it"): never hidden; the others
      // (NotExactHere, jets too large, no rational point, given values no exact place is near) leave no exact route
      if (typeid(x) == typeid(std::logic_error)) throw;
      why =
          std::string("its ranks were decided in double and the exact route could not confirm them (") + x.what() + ")";
    }
  }
  s.certified = unknown;
  s.note = "not certified: " + why + (s.note.empty() ? "" : "; " + s.note);
}

}  // namespace

Solution solve(const io::Problem& p, const Parts& parts, const Options& opt) {
  io::validate(p);
  Solution s;
  if (p.form() == io::Form::expression) {
    s = solve_expression(p.expression(), opt);
  } else if (p.form() == io::Form::implicit) {
    s = solve_implicit(p.expression(), opt);
  } else if (p.form() == io::Form::dae) {
    s = solve_dae(p.dae(), opt);
  } else if (p.form() == io::Form::netlist) {
    s = p.netlist().forced ? solve_forced_netlist(p.netlist(), p.linear().variables, opt)
                           : solve_lc(p.netlist(), p.linear(), parts, opt);
    s.circuit = io::circuit_facts(p.netlist());
  } else {
    const io::CaseFile& c = p.linear();
    s = io::at_input(c, [&] {
      return c.has_pontryagin && c.pontryagin.has_forces ? solve_forced_case(c, opt) : solve_linear(c, parts, opt);
    });
  }
  if (p.form() == io::Form::netlist &&
      !p.netlist().rounded.empty()) {  // irrational values: exact only for the rounded deck
    s.certified = unknown;
    s.note += (s.note.empty() ? "" : "; ") + io::rounded_note(p.netlist());
  }
  s.backend = Backend::fast;
  if (opt.confirm_exactly) confirm_exactly(p, parts, s);
  uncertain_exact_entries(s);
  s.warnings = p.warnings();
  keep_parts(s, parts);
  return s;
}

}  // namespace dcad::fast
