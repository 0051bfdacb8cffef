// certified::solve: each input form dispatched once; the linear and LC routes through the one cascade.
#include "dcad/certified/solve.hpp"

#include "dcad/certified/dae_sparse.hpp"

#include "dcad/certified/cascade.hpp"
#include "dcad/io/report.hpp"
#include "dcad/lc_graph.hpp"
#include "dcad/reference/pipeline/circuit.hpp"
#include "dcad/reference/pipeline/dae.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/implicit.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"
#include "dcad/reference/solve.hpp"

#include <stdexcept>

namespace dcad::certified {

std::string number_text(const Number& x) { return x.exact ? x.q.str() : io::float_text(x.mid); }

namespace {

Number exact_number(const Rational& q) { return {true, q, 0, 0}; }

Solution exact_solution(const reference::Solution& s) {
  Solution out = map_numbers<Number>(s, exact_number);
  out.exact = true;
  return out;
}

std::string joined(const std::string& note, const std::string& more) {
  return note.empty() ? more : note + "; " + more;
}

/// The result of the cascade with its route in `decisions` and `note`.
Solution from_cascade(const Cascaded<Solution>& c) {
  Solution r = c.result;
  if (c.tier == Tier::machine_words) {
    r.decisions.machine_words = 1;
    r.decisions.word_bits = c.word_bits;
    r.note = joined(r.note, "the reference algorithm in exact " + std::to_string(c.word_bits) +
                                "-bit rationals (every number fitted in machine words" +
                                (c.word_bits > 64 ? ", once 64 bits gave up)" : ")"));
  } else {
    r.decisions.exact_recomputation = 1;
    r.note = joined(
        r.note, "exact 128-bit rationals gave up (" + c.overflow + "): recomputed in FLINT's exact rationals (fmpq)");
  }
  r.exact = true;
  r.certified = yes;
  return r;
}

Solution linear(const io::CaseFile& c, const Parts& parts) {
  namespace pl = reference::pipeline;
  return io::at_input(c, [&] {
    if (c.has_pontryagin && c.pontryagin.has_forces) return exact_solution(pl::solve_forced(c));
    return from_cascade(
        cascade<Solution>([&](int& bits) { return exact_solution(pl::solve_linear_words(c, parts, bits)); },
                          [&] { return exact_solution(pl::solve_linear_fmpq(c, parts)); }));
  });
}

/// A physical LC circuit by the graph route, exactly: CEF Thms 6.4, 6.6, 6.8 decide every step.
Solution graph_route(const io::Netlist& deck, const std::vector<std::string>& variables) {
  Solution s = reference::pipeline::lc_graph_solution<Number>(deck, variables,
                                                              [](const Rational& q) { return exact_number(q); });
  s.note =
      "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision), exact; the state "
      "equations at any size "
      "(dcad/reference/rlc_state.hpp), the motion in (q, v, p) up to " +
      std::to_string(kDenseBranches) + " branches (dense)";
  return s;
}

Solution lc_circuit(const io::Problem& p, const Parts& parts) {
  namespace pl = reference::pipeline;
  const io::Netlist& deck = p.netlist();
  const std::vector<lc::Branch<Rational>> graph = reference::pipeline::lc_graph_of(deck);
  const bool physical = lc::physical(graph);
  if (deck.circuit.branches.size() > kDenseBranches && physical) return graph_route(deck, p.linear().variables);
  Solution s = from_cascade(
      cascade<Solution>([&](int& bits) { return exact_solution(pl::solve_lc_words(deck, p.linear(), parts, bits)); },
                        [&] { return exact_solution(pl::solve_lc_fmpq(deck, p.linear(), parts)); }));
  if (physical && lc::physical_tower(deck.circuit.nodes, graph).dims !=
                      s.dims())  // a theorem disagrees with a certified computation
    throw std::logic_error("graph route and certified CAD disagree on " + deck.file + "; please report it");
  return s;
}

/// An LC circuit's state equations where the graph route holds (L, C > 0), exact.
void add_state(Solution& s, const io::Netlist& deck, const Parts& parts) {
  if (parts.reduced && reference::pipeline::graph_route_holds(deck.rlc))
    s.state = map_state<Number>(reference::pipeline::deck_state_equations<Rational>(deck),
                                [](const Rational& q) { return exact_number(q); });
}

/// Which exact tier decided, for the trace's evidence.
std::string tier(const Decisions& d) {
  if (d.machine_words) return "exact " + std::to_string(d.word_bits) + "-bit rationals (the cascade's first tier)";
  if (d.exact_recomputation) return "FLINT's exact rationals (fmpq), the cascade's second tier";
  return "exact rational arithmetic";
}

}  // namespace

Solution solve(const io::Problem& p, const Parts& parts) {
  io::validate(p);
  Solution s;
  if (p.form() == io::Form::expression) {
    s = exact_solution(reference::pipeline::pointwise_input_errors(
        p.expression(), [&] { return reference::pipeline::solve_pointwise_exact_near(p.expression()); }));
  } else if (p.form() == io::Form::implicit) {  // CEF (1.6) at a point, exact: every decision an exact zero test
    s = exact_solution(reference::pipeline::pointwise_input_errors(p.expression(), [&] {
      try {
        return reference::pipeline::solve_implicit_exact(p.expression());
      } catch (const std::length_error&
                   e) {  // jets too large for the exact tier: no exact tier here (api falls back, not certified)
        throw reference::NotExactHere(std::string("the exact route's jets are too large (") + e.what() + ")");
      } catch (const reference::PointwiseNoPoint& e) {
        // no rational point of M_c reached (lam² = 8 on a pendulum whose multiplier enters squared): no exact
        // tier here either — fast's answer, not certified (given values that miss M_c are bad input there too)
        throw reference::NotExactHere(std::string("the exact route reaches no rational point of M_c (") + e.what() +
                                      ")");
      }
    }));
  } else if (p.form() == io::Form::dae) {  // the reference's CEF (1.6), exact: every decision is an exact zero test
    // beyond 200 variables or equations, the sparse route: modular elimination, every null vector verified in
    // rationals (dae_sparse.hpp; a 1,001-node ladder: 0.2 s against the dense route's 2–24 s, a random graded
    // circuit of 516 variables: against more than 300 s) — it forms no equations of motion (dense N × N; the
    // reference backend does, up to 2,000); where it reaches no proof, NotExactHere (api: fast, not certified)
    const bool sparse = !p.dae().dense || p.dae().variables.size() > 200 || p.dae().equations() > 200;
    s = exact_solution(sparse ? solve_dae_sparse(p.dae()) : reference::pipeline::solve_dae(p.dae()));
  } else if (p.form() == io::Form::netlist) {
    if (p.netlist().forced) {
      s = exact_solution(reference::pipeline::solve_forced(p.netlist(), p.linear().variables));
    } else {
      s = lc_circuit(p, parts);
      add_state(s, p.netlist(), parts);
    }
    s.file = p.netlist().file;
    s.name = p.netlist().title;
    s.circuit = io::circuit_facts(p.netlist());
  } else {
    s = linear(p.linear(), parts);
  }
  if (p.form() == io::Form::netlist &&
      !p.netlist().rounded.empty()) {  // irrational values: exact only for the rounded deck
    s.certified = unknown;
    s.note += (s.note.empty() ? "" : "; ") + io::rounded_note(p.netlist());
  }
  s.backend = Backend::certified;
  trace_exact_levels(s, DecidedBy::exact, tier(s.decisions));
  s.warnings = p.warnings();
  keep_parts(s, parts);
  return s;
}

}  // namespace dcad::certified
