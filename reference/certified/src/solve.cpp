// certified::solve: each input form dispatched once; the linear and LC routes through the one cascade.
#include "dcad/certified/solve.hpp"

#include "dcad/certified/cascade.hpp"
#include "dcad/io/report.hpp"
#include "dcad/lc_graph.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/pointwise.hpp"
#include "dcad/reference/solve.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace dcad::certified {

dcad::Solution<Ball> solve_linear_balls(const io::CaseFile& c, const Parts& parts);
dcad::Solution<Ball> solve_lc_balls(const io::Netlist& deck, const io::CaseFile& c, const Parts& parts);

std::string number_text(const Number& x) { return x.exact ? x.q.str() : io::float_text(x.mid); }

namespace {

Number exact_number(const Rational& q) { return {true, q, 0, 0}; }

/// A point ball is its exact value (ball.hpp); any other is kept as an enclosure.
Number ball_number(const Ball& b) {
  if (b.rad() == 0 && std::isfinite(b.mid())) return exact_number(Rational(b.mid()));
  return {false, Rational(0), b.mid(), b.rad()};
}

Solution exact_solution(const reference::Solution& s) {
  Solution out = map_numbers<Number>(s, exact_number);
  out.exact = true;
  return out;
}

/// The widest ball among the numbers of a solution.
double widest(const Solution& s) {
  double w = 0;
  map_numbers<int>(s, [&](const Number& x) {
    w = std::max(w, x.rad);
    return 0;
  });
  return w;
}

std::string joined(const std::string& note, const std::string& more) { return note.empty() ? more : note + "; " + more; }

/// The result of the cascade with its route in `decisions` and `note` (what the CLI has always printed).
Solution from_cascade(const Cascaded<Solution>& c) {
  Solution r = c.result;
  const std::string overflow = c.overflow.empty() ? "" : "exact 128-bit rationals gave up (" + c.overflow + "); ";
  if (c.route == Route::machine_words) {
    r.decisions.machine_words = 1;
    r.decisions.word_bits = c.word_bits;
    r.note = joined(r.note, "the reference algorithm in exact " + std::to_string(c.word_bits) + "-bit rationals (every number fitted in machine words" +
                                (c.word_bits > 64 ? ", once 64 bits gave up)" : ")"));
  } else if (c.route == Route::balls) {
    r.decisions.float_tests = c.counts.decisions;
    r.decisions.exact_verifications = c.counts.verifications;
    std::ostringstream o;
    o.precision(2);
    o << (r.note.empty() ? "" : r.note + "; ") << overflow << "the reference algorithm in ball arithmetic: " << c.counts.decisions
      << " zero tests certified in floating point, " << c.counts.verifications
      << " by exact comparison of input numbers; numbers are ball midpoints, exact values within " << widest(r);
    r.note = o.str();
  } else {
    r.decisions.float_tests = c.counts.decisions;
    r.decisions.exact_verifications = c.counts.verifications;
    r.decisions.exact_recomputation = 1;
    r.note = (r.note.empty() ? "" : r.note + "; ") + overflow + "zero test " + std::to_string(c.counts.decisions + 1) +
             " undecidable in floating point (" + c.uncertain + "): recomputed exactly from the exact input";
  }
  r.exact = c.route != Route::balls;
  r.certified = yes;
  return r;
}

Solution balls(const dcad::Solution<Ball>& s) { return map_numbers<Number>(s, ball_number); }

Solution linear(const io::CaseFile& c, const Parts& parts) {
  namespace pl = reference::pipeline;
  return io::at_input(c, [&] {
    if (c.has_pontryagin && c.pontryagin.has_forces) return exact_solution(pl::solve_forced(c));
    return from_cascade(cascade<Solution>(
        [&](int& bits) { return exact_solution(pl::solve_linear_words(c, parts, bits)); },
        [&] { return balls(solve_linear_balls(c, parts)); }, [&] { return exact_solution(pl::solve_linear_fmpq(c, parts)); }));
  });
}

std::vector<lc::Branch<Rational>> graph_of(const io::Netlist& deck) {
  std::vector<lc::Branch<Rational>> out;
  for (const auto& b : deck.circuit.branches) out.push_back({b.kind, b.from, b.to, b.value});
  return out;
}

/// A physical LC circuit by the graph route, exactly: CEF Thms 6.4, 6.6, 6.8 decide every step.
Solution graph_route(const io::Netlist& deck, const std::vector<std::string>& variables) {
  const lc::Tower<Rational> t = lc::physical_tower(deck.circuit.nodes, graph_of(deck));
  Solution s;
  s.variables = variables;
  for (std::size_t k = 0; k < t.dims.size(); ++k) {
    Level<Number> level{t.dims[k], {}};
    for (const lc::Row<Rational>& row : t.equations[k]) {
      Equation<Number> e;
      for (const lc::Term<Rational>& term : row) e.terms.emplace_back(term.var, exact_number(term.coeff));
      e.rhs = exact_number(Rational(0));
      level.constraints.push_back(e);
    }
    s.tower.push_back(level);
  }
  s.steps = t.steps;
  s.consistent = true;  // no sources: x = 0 solves
  s.solution_rank = t.solution_rank;
  s.exact = true;
  s.note = "graph route (forests and fundamental loops, CEF Thms 6.4, 6.6, 6.8; no rank decision), exact; equations of motion omitted above " +
           std::to_string(kDenseBranches) + " branches (dense), see `dcad solve --backend reference`";
  return s;
}

Solution lc_circuit(const io::Problem& p, const Parts& parts) {
  namespace pl = reference::pipeline;
  const io::Netlist& deck = p.netlist;
  const std::vector<lc::Branch<Rational>> graph = graph_of(deck);
  const bool physical = lc::physical(graph);
  if (deck.circuit.branches.size() > kDenseBranches && physical) return graph_route(deck, p.linear.variables);
  Solution s = from_cascade(cascade<Solution>(
      [&](int& bits) { return exact_solution(pl::solve_lc_words(deck, p.linear, parts, bits)); },
      [&] { return balls(solve_lc_balls(deck, p.linear, parts)); }, [&] { return exact_solution(pl::solve_lc_fmpq(deck, p.linear, parts)); }));
  if (physical && lc::physical_tower(deck.circuit.nodes, graph).dims != s.dims())  // a theorem disagrees with a certified computation
    throw std::logic_error("graph route and certified CAD disagree on " + deck.file + "; please report it");
  return s;
}

}  // namespace

Solution solve(const io::Problem& p, const Parts& parts) {
  Solution s;
  if (p.form == io::Form::expression) {
    s = exact_solution(reference::pipeline::pointwise_input_errors(p.expression, [&] { return reference::pipeline::solve_pointwise_exact(p.expression); }));
  } else if (p.form == io::Form::netlist) {
    s = p.netlist.forced ? exact_solution(reference::pipeline::solve_forced(p.netlist, p.linear.variables)) : lc_circuit(p, parts);
    s.file = p.netlist.file;
    s.name = p.netlist.title;
    s.circuit = io::circuit_facts(p.netlist);
  } else {
    s = linear(p.linear, parts);
  }
  s.backend = "certified";
  s.warnings = p.warnings();
  keep_parts(s, parts);
  return s;
}

}  // namespace dcad::certified
