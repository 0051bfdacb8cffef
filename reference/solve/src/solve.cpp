// reference::solve: each input form dispatched once, to its exact route.
#include "dcad/reference/solve.hpp"

#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/pipeline/dae.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/implicit.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"

namespace dcad::reference {

namespace {

Solution linear(const io::CaseFile& c, const Parts& parts) {
  return io::at_input(c, [&] {
    if (c.has_pontryagin && c.pontryagin.has_forces) return pipeline::solve_forced(c);
    int bits = 0;
    try {
      return pipeline::solve_linear_words(c, parts, bits);
    } catch (const Overflow&) {
      return pipeline::solve_linear_fmpq(c, parts);
    }
  });
}

Solution netlist(const io::Problem& p, const Parts& parts) {
  const io::Netlist& deck = p.netlist();
  if (deck.forced) {
    Solution s = pipeline::solve_forced(deck, p.linear().variables);
    s.circuit = io::circuit_facts(deck);
    return s;
  }
  Solution s;
  if (deck.circuit.branches.size() > pipeline::kStructuredBranches) {  // beyond the dense exact elimination
    const std::string n = std::to_string(deck.circuit.branches.size()),
                      limit = std::to_string(pipeline::kStructuredBranches);
    if (!lc::physical(pipeline::lc_graph_of(deck)))
      throw io::InputError(deck.file + ": expected at most " + limit +
                           " branches for an LC circuit with a negative L or C (dense exact " +
                           "elimination, O(n^3)), found " + n +
                           " (physical circuits take the graph route at any size)");
    s = pipeline::lc_graph_solution<Rational>(deck, p.linear().variables, [](const Rational& q) { return q; });
    s.circuit = io::circuit_facts(deck);
    s.note =
        "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8: L, C > 0 decide nothing), exact: the "
        "tower, its "
        "equations and the state equations (dcad/reference/rlc_state.hpp); the motion in (q, v, p) comes from the "
        "structured route "
        "(dense exact elimination), up to " +
        limit + " branches";
    if (parts.reduced && pipeline::graph_route_holds(deck.rlc))
      s.state = pipeline::deck_state_equations<Rational>(deck);
    return s;
  }
  int bits = 0;
  try {
    s = pipeline::solve_lc_words(deck, p.linear(), parts, bits);
  } catch (const Overflow&) {
    s = pipeline::solve_lc_fmpq(deck, p.linear(), parts);
  }
  s.circuit = io::circuit_facts(deck);
  if (parts.reduced && pipeline::graph_route_holds(deck.rlc)) s.state = pipeline::deck_state_equations<Rational>(deck);
  s.note = "structured route for circuits (CEF §6 closed form and D̄_Δ on M_c, exact)" +
           std::string(deck.circuit.branches.size() <= pipeline::kAdaptedBranches
                           ? ""
                           : "; the §7 adapted constraints (T*TQ, 4n variables) are given up to " +
                                 std::to_string(pipeline::kAdaptedBranches) + " branches");
  return s;
}

Solution expression(const io::LagrangianCase& c) {
  return pipeline::pointwise_input_errors(c, [&] {
    try {
      return pipeline::solve_pointwise_exact_near(c);
    } catch (const NotExactHere& e) {
      throw NoExactPoint(
          c.file +
              ": /initial: expected a point where every value of the formulas is rational (the exact route), found " +
              e.what() + "; give such a point (e.g. angles 0) or use --backend fast or certified",
          e.what());
    }
  });
}

Solution implicit(const io::LagrangianCase& c) {
  return pipeline::pointwise_input_errors(c, [&] {
    try {
      return pipeline::solve_implicit_exact(c);
    } catch (const NotExactHere& e) {
      if (!c.has_initial)
        throw NoExactPoint(c.file +
                               ": /implicit: expected equations whose values are rational at dcad's default points "
                               "(the exact route), found " +
                               e.what() + "; give `initial` values where they are, or use --backend fast or certified",
                           e.what());
      throw NoExactPoint(
          c.file +
              ": /initial: expected a point where every value of the equations is rational (the exact route), found " +
              e.what() + "; give such a point or use --backend fast or certified",
          e.what());
    }
  });
}

}  // namespace

Solution solve(const io::Problem& p, const Parts& parts) {
  io::validate(p);
  Solution s = p.form() == io::Form::expression ? expression(p.expression())
               : p.form() == io::Form::implicit ? implicit(p.expression())
               : p.form() == io::Form::dae      ? pipeline::solve_dae(p.dae())
               : p.form() == io::Form::netlist  ? netlist(p, parts)
                                                : linear(p.linear(), parts);
  if (p.form() == io::Form::netlist &&
      !p.netlist().rounded.empty()) {  // irrational values: exact only for the rounded deck
    s.certified = unknown;
    s.note += (s.note.empty() ? "" : "; ") + io::rounded_note(p.netlist());
  }
  s.backend = Backend::reference;
  s.exact = true;
  trace_exact_levels(s, DecidedBy::exact, "exact rational arithmetic (the reference)");
  s.warnings = p.warnings();
  keep_parts(s, parts);
  return s;
}

}  // namespace dcad::reference
