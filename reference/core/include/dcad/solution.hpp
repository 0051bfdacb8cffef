// dcad::Solution<N> — what every backend's solve returns for every problem kind (issue 26): the
// constraint tower with each step's constraints, M_c, the equations of motion, the constraint classes
// and the Dirac bracket, the constraints adapted to the primary ones, and how each answer was decided.
// N is the twin's number: reference::Rational (exact), double (fast), certified::Number (exact, or a
// double where no exact tier can run).  Plain data: text and JSON are written once, by dcad::io (io/report.hpp).
//
// CEF: the tower M_0 ⊇ M_1 ⊇ … ⊇ M_c (§5), the solution rank dim(ker ω_D ∩ T M_c) (Thm 5.4(b)), the
// equations of motion ż = F z + f + G λ on M_c (5.12), first/second class and J* (Lemma 3.23), the
// adapted constraints (Thm 3.28 / 7.4); YM §4: forces and sources; V §3: moving M_k(t).
#pragma once

#include "dcad/backend.hpp"
#include "dcad/trace.hpp"
#include "dcad/truth.hpp"
#include "dcad/types.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace dcad {

/// Which algorithm made the tower: the CAD of a Dirac system (CEF §5), or the algorithm of an implicit differential
/// equation (CEF (1.6)) that the DAE forms run.
enum class Algorithm { cad, implicit_equation };

/// What a solve computes beyond the CONTRACT's required keys and the tower (`dcad solve --with`): a
/// CI that wants dims and the solution rank need not pay for the §7 embedding (4n variables).
struct Parts {
  bool final_constraints = true;  ///< "final": the equations of M_c
  bool reduced = true;            ///< "reduced": the equations of motion (CEF (5.12))
  bool classes = true;            ///< "classes": first/second class and the Dirac bracket (`constrained` cases)
  bool adapted = true;            ///< "adapted": constraints adapted to the primary ones (Thm 3.28 / 7.4)
  static Parts none() { return {false, false, false, false}; }
};

/// Σ_j a_j x_j = rhs, sparse: (column, coefficient) with the columns of Solution::columns().
template <class N>
struct Equation {
  std::vector<std::pair<std::size_t, N>> terms;
  N rhs{};
};

/// A dense matrix by rows.
template <class N>
using Rows = std::vector<std::vector<N>>;

/// M_k: its dimension (−1: empty) and the constraints that cut it out of M_{k−1}.
template <class N>
struct Level {
  long dim = 0;
  std::vector<Equation<N>> constraints;
};

/// ż = F z + f + S u(t) + G λ on M_c in the coordinates z = x[coordinates]  [CEF (5.12); YM §4 with
/// the sources' jets u(t) = (V1(t), V1'(t), …)]: λ is free, so (F, f, S) are fixed modulo span(G).
template <class N>
struct Motion {
  std::vector<std::size_t> coordinates;     ///< variable indices
  Rows<N> f_matrix;                         ///< F
  std::vector<N> f;                         ///< f
  Rows<N> g;                                ///< G: its columns span the free directions (solution rank many)
  std::vector<std::string> source_columns;  ///< the names of u's entries (forced systems)
  Rows<N> s;                                ///< S (rows × source_columns)
};

/// A sparse matrix as its nonzero entries (row, column, value).
template <class N>
struct SparseBlock {
  long rows = 0, cols = 0;
  std::vector<std::tuple<long, long, N>> entries;
};

/// The state equations of an RLC circuit with sources at any size (dcad/reference/rlc_state.hpp):
/// the motion on M_c in node potentials and inductor currents, never on the 3n-dimensional bundle,
///   C_ww ẇ = −(G_ww w + G_wr ρ + L_w i + H_w σ + H_wd σ̇)
///   0      =  G_wrᵀ w + G_rr ρ + L_r i + H_r σ
///   0      =  L_e i + I_e σ
///   Φ i̇   =  L_wᵀ w + L_rᵀ ρ + L_eᵀ e + O_L σ
/// with C_ww, G_rr, Φ and L_e Φ⁻¹ L_eᵀ positive definite, so (ẇ, ρ, i̇, e) is unique at every state.
template <class N>
struct StateEquations {
  std::vector<std::string> w, i, r,
      e;  ///< names: potentials (differential), inductor currents, levels ρ, island levels e
  std::vector<std::string> sources;  ///< σ's names ("V1(t)"); σ̇ is the same list differentiated
  std::vector<std::pair<std::string, SparseBlock<N>>>
      blocks;  ///< C_ww, G_ww, G_wr, G_rr, L_w, L_r, L_e, Phi, H_w, H_wd, H_r, I_e, O_L
};

/// The constraints of M_c: r − 2s first class, 2s second class, and the Dirac bracket J*  [CEF Lemma 3.23].
template <class N>
struct Classes {
  long first_class = 0, second_class = 0;
  std::vector<Equation<N>> second_class_constraints;  ///< χ (exact routes)
  Rows<N> dirac_bracket;                              ///< J* (exact routes)
};

/// CEF Thm 3.28 / 7.4: the second class constraints adapted to the primary ones and the constraints of
/// the abridged total energy E_AT, in `variables` (N's, or T*TQ's for a `pontryagin` case, §7).
template <class N>
struct Adapted {
  std::string setting;  ///< "N" (constrained) or "T*TQ" (pontryagin, §7)
  std::vector<std::string> variables;
  long s_prime = 0, secondary_first_class = 0;
  std::vector<Equation<N>> chi, abridged;
};

/// M_c exactly: point + span of the rows of `basis` (what `dcad check` compares a claimed M_c with).
template <class N>
struct ExactSubspace {
  Rows<N> basis;
  std::vector<N> point;
};

/// How the answers were reached (the CONTRACT's `decisions`).
struct Decisions {
  long float_tests = 0;  ///< zero tests certified in floating point (balls), or fast's rank decisions (the Lagrangian
                         ///< form: its zeros that rest on the separation hypothesis)
  long exact_verifications = 0;  ///< settled by comparing exact input numbers; fast::solve: 1 if its answer was
                                 ///< confirmed by the certified tier
  long exact_recomputation = 0;  ///< 1 if recomputed exactly
  long machine_words = 0;        ///< 1 if the whole run was exact in 64- or 128-bit rationals
  int word_bits = 0;             ///< that run's word: 64, or 128 when a number outgrew 64 bits
};

/// The circuit's graph facts (CEF §6 Thms 6.4, 6.6, 6.8; YM §4's sources), by signed branch names.
struct CircuitFacts {
  long branches = 0, nodes = 0;  ///< nodes with ground
  long empty_loops = 0;          ///< dim of the cycle space of the empty branches (Thm 6.8)
  long kvlpc_graph = 0;          ///< Thm 6.4's count of KVL equations of purely capacitive loops
  bool physical = true;          ///< no negative L or C (Remark 6.7)
  bool has_empty_branch = false;
  std::vector<std::string> branch_names;  ///< LC decks: each branch
  std::vector<BranchKind> branch_kinds;   ///< and its kind: an inductor, a capacitor or empty (CEF §6)
  std::vector<std::vector<std::string>> pc_loop_branches, empty_loop_branches;
  /// with resistors, sources or couplings (YM §4): the element counts and the loops and cutsets that
  /// constrain the circuit — CV loops fix charges by the sources, LI cutsets currents
  bool forced = false;
  long inductors = 0, capacitors = 0, resistors = 0, voltage_sources = 0, current_sources = 0, wires = 0, couplings = 0;
  std::vector<std::vector<std::string>> cv_loops, source_loops, li_cutsets, source_cutsets;
};

/// A condition on the sources alone that the tower found (KVL of a loop of voltage sources, KCL of a
/// cutset of current sources): b + Σ c σ^(d)(t) = 0, decided against the waveforms.
struct SourceCondition {
  std::string text;       ///< "V1(t) - V2(t) = 0"
  Truth holds = unknown;  ///< for all t ≥ 0: yes, no, or unknown (different waveforms that agree where sampled)
  std::string evidence;   ///< why
};

/// The CAD of the expression form as formulas on a chart (CONTRACT "Formulas for nonlinear results";
/// built by fast/chart.hpp, its tower checked against the backend's).  Text in the case's names.
struct Formulas {
  std::vector<std::string> constraints;  ///< every M_k's constraints (formula = 0), with p = ∂L/∂v
  std::vector<long> levels;              ///< for each constraint, the k of the M_k it cuts out (1: the given ones)
  std::vector<std::pair<std::string, std::string>> equations;  ///< d/dt NAME = formula, for q and v
  std::vector<std::pair<std::string, std::string>> momenta;    ///< p_NAME = ∂L/∂v
  std::vector<std::string> free;          ///< velocities whose rate is free on M_c (0 in `equations`)
  std::vector<std::string> kept, solved;  ///< M_c's chart: coordinates kept, coordinates the constraints solve for
  std::vector<std::string> valid_where, valid_where_why;  ///< must not vanish; why each
  std::string decided;                                    ///< where the chart's decisions were made
};

/// The values at the user's own given point where the exact tiers could not run there (an irrational
/// point, decimals that miss M_c by their rounding): balls proved by Krawczyk's test on the chart's
/// constraints, the equations of motion evaluated on the proved box (certified/zero_enclosure.hpp).
struct AtGiven {
  struct Ball {
    std::string name;
    double mid = 0, rad = 0;  ///< the value lies in [mid − rad, mid + rad]
  };
  bool proved = false;
  std::string why;                  ///< not proved: which test failed
  std::vector<Ball> point;          ///< q, v, p
  std::vector<Ball> velocity;       ///< d/dt of q and v
  std::vector<std::string> solved;  ///< the coordinates the chart's constraints were solved for
  std::vector<std::string> moved;   ///< given values among them (their decimals miss M_c)
  std::string claim;                ///< what the balls prove, and what they take from the tower
};

/// The pointwise CAD of the expression form (reference/nonlinear/pointwise.hpp) at its point.
template <class N>
struct Pointwise {
  std::string route;  ///< "pointwise exact" or "pointwise double"
  bool regular = true;
  std::string why;        ///< inconsistent or singular: the reason
  std::string time_name;  ///< the time variable, if the system has one
  N time{};
  std::vector<N> point, velocity;              ///< x = (q, v, p) and one ẋ at the point
  Rows<N> gauge;                               ///< the other solutions' differences (solution rank many)
  std::vector<std::string> first_constraints;  ///< M_1 as formulas: p = ∂L/∂v and the constraints
  struct Tangent {
    std::string solved_for;
    std::vector<std::pair<std::string, N>> terms;  ///< Σ g_j s_j over the chart variables (q, v, t)
    N rhs{};
  };
  struct PivotValue {
    std::string row, column;
    N value{};
  };
  struct Step {
    long dim = 0;
    std::vector<Tangent> constraints;  ///< the tangent equations of M_{k+1} at the point (k ≥ 1)
    std::vector<PivotValue> pivots;    ///< of the system for (d/dt s, λ) on M_k
  };
  std::vector<Step> levels;  ///< levels[k] describes M_{k+1}
  long order = 0, checked_order = 0, moves = 0;
  /// Where the exact route ran when not at the given values (or the default point), one line each:
  /// the angles put on rational points of the circle, the constraints the positions were put on, the
  /// given values moved (pipeline/exact_place.hpp).  Empty: at the given values.
  std::vector<std::string> place;
  std::vector<std::pair<std::size_t, std::string>> point_text;  ///< values of `point` N cannot hold ("2*atan(1/3)")
  std::optional<Formulas> formulas;  ///< where a chart was found (consistent, regular results)
  std::string formulas_why;          ///< else why not
  std::optional<AtGiven> at_given;   ///< certified: balls at the given values where the point is not exact
};

template <class N>
struct Solution {
  Backend backend = Backend::reference;  ///< which twin answered (each twin's solve sets it)
  Truth certified = unknown;  ///< every decision behind the result exact or provably right: yes (each route sets it)
  bool exact = false;         ///< every number is exact (a row's absent entries are exact zeros)
  std::string file, name;     ///< the problem's
  std::vector<std::string> variables;  ///< x's names
  std::vector<std::string> jets;       ///< more columns of the tower's equations after x: the sources' jets (forced)
  std::vector<Level<N>> tower;         ///< M_0 … M_c, or M_0 … M_k with M_k = ∅
  long steps = 0;                      ///< c (or k of the empty M_k)
  bool consistent = true;
  std::optional<long> solution_rank;     ///< dim(ker ω_D ∩ T M_c)  [Thm 5.4(b)]; none when inconsistent or singular
  std::optional<bool> regular_pencil;    ///< a square linear DAE: det(sE − A) ≢ 0
  Algorithm algorithm = Algorithm::cad;  ///< Algorithm::implicit_equation for the DAE forms
  std::optional<std::vector<Equation<N>>> final_constraints;  ///< M_c = {a·x = b}
  std::optional<ExactSubspace<N>> final_exact;                ///< M_c as point + span (exact routes)
  std::optional<Motion<N>> motion;
  std::optional<StateEquations<N>> state;  ///< circuits on the graph route: the sparse state equations
  std::optional<Classes<N>> classes;
  std::optional<Adapted<N>> adapted;
  std::optional<CircuitFacts> circuit;
  std::vector<std::string> source_names;  ///< σ, in order (forced netlists)
  std::vector<SourceCondition> source_conditions;
  std::optional<Pointwise<N>> pointwise;  ///< the expression form
  Decisions decisions;
  /// Every decision behind the tower, in order, with its evidence (dcad/trace.hpp): fast's rank decisions (σ's,
  /// thresholds, gap) on its linear, circuit and DAE routes; one exact decision per level on the exact tiers.
  std::vector<Decision> trace;
  std::vector<std::string> warnings;  ///< the reader's (a netlist's ignored cards …)
  std::string note;                   ///< how the result was reached; why it is not certified

  /// The DAE's differentiation index (CONTRACT key `index`), none where there is none: a square linear DAE with a
  /// regular pencil and a consistent tower has index `steps` (Kronecker); the implicit form, where ẋ is unique on
  /// M_c, has Rabier–Rheinboldt's geometric index `steps`, the differentiation index there (CEF (1.6)).
  std::optional<long> index() const {
    if (regular_pencil) return *regular_pencil && consistent ? std::optional<long>(steps) : std::nullopt;
    if (algorithm == Algorithm::implicit_equation && consistent && solution_rank && *solution_rank == 0) return steps;
    return std::nullopt;
  }

  std::vector<long> dims() const {
    std::vector<long> d;
    for (const Level<N>& l : tower) d.push_back(l.dim);
    return d;
  }
  bool unique() const { return consistent && solution_rank && *solution_rank == 0; }
  /// The first invariant of a tower this answer breaks, in words, or none: CEF §5 (5.1)–(5.3) and (1.6) build
  /// M_{k+1} ⊆ M_k and stop at the first c with M_{c+1} = M_c, so dim M_0 > … > dim M_c, an empty M_k (−1)
  /// only last; c = steps; consistent iff M_c ≠ ∅; dim(ker ω_D ∩ T M_c) ≤ dim M_c (Thm 5.4(b)).  A singular
  /// point of the pointwise routes claims its dims only.  dcad::api refuses to print a broken answer (exit 4).
  std::optional<std::string> broken_invariant() const {
    const std::vector<long> d = dims();
    if (d.empty()) return std::string("no level M_0");
    const auto dim = [&](std::size_t k) { return "dim M_" + std::to_string(k) + " = " + std::to_string(d[k]); };
    for (std::size_t k = 0; k + 1 < d.size(); ++k) {
      if (d[k] < 0) return "M_" + std::to_string(k) + " is empty and the tower goes on";
      if (d[k + 1] >= d[k]) return dim(k + 1) + " is not below " + dim(k) + " (M_{k+1} ⊆ M_k, strictly until c)";
    }
    if (pointwise && !pointwise->regular) return std::nullopt;
    const std::size_t c = d.size() - 1;
    if (steps != static_cast<long>(c))
      return "steps = " + std::to_string(steps) + " beside the levels M_0 … M_" + std::to_string(c);
    if (consistent != (d[c] >= 0)) return std::string(consistent ? "consistent" : "inconsistent") + " with " + dim(c);
    if (solution_rank && (*solution_rank < 0 || *solution_rank > d[c]))
      return "solution rank " + std::to_string(*solution_rank) + " beside " + dim(c);
    return std::nullopt;
  }
  /// The names of the equations' columns: the variables, then the jets.
  std::vector<std::string> columns() const {
    std::vector<std::string> c = variables;
    c.insert(c.end(), jets.begin(), jets.end());
    return c;
  }
};

/// The same state equations with every number mapped by f.
template <class To, class From, class F>
StateEquations<To> map_state(const StateEquations<From>& s, F f) {
  StateEquations<To> q{s.w, s.i, s.r, s.e, s.sources, {}};
  for (const auto& [name, b] : s.blocks) {
    SparseBlock<To> t{b.rows, b.cols, {}};
    for (const auto& [i, j, v] : b.entries) t.entries.emplace_back(i, j, f(v));
    q.blocks.emplace_back(name, std::move(t));
  }
  return q;
}

/// Where the answer as a whole is not certified (a deck rounded to rationals, a condition on the sources decided in
/// double), no exact or graph entry of its trace says certain: they were exact for data other than the problem's.
template <class N>
void uncertain_exact_entries(Solution<N>& s) {
  if (s.certified.yes()) return;
  for (Decision& d : s.trace)
    if (d.by == DecidedBy::exact || d.by == DecidedBy::graph) {
      d.certain = unknown;
      d.evidence += "; the answer is not certified (its note says why)";
    }
}

/// The exact tiers' trace where a route left none: one decision per level M_1 … M_c (dcad/trace.hpp), decided
/// `by` exact zero tests or the graph's theorems in the tier `how` names; then uncertain_exact_entries.
template <class N>
void trace_exact_levels(Solution<N>& s, DecidedBy by, const std::string& how) {
  if (s.trace.empty()) s.trace = exact_trace(s.dims(), by, how);
  uncertain_exact_entries(s);
}

/// Drops what `parts` does not ask for (routes that compute everything keep only what was asked).
template <class N>
void keep_parts(Solution<N>& s, const Parts& parts) {
  if (!parts.final_constraints) {
    s.final_constraints.reset();
    s.final_exact.reset();
  }
  if (!parts.reduced) {
    s.motion.reset();
    s.state.reset();
  }
  if (!parts.classes) s.classes.reset();
  if (!parts.adapted) s.adapted.reset();
}

/// Every number of v mapped by f.
template <class To, class From, class F>
std::vector<To> map_vector(const std::vector<From>& v, F f) {
  std::vector<To> o;
  for (const From& x : v) o.push_back(f(x));
  return o;
}

/// Every number of the rows m mapped by f.
template <class To, class From, class F>
Rows<To> map_rows(const Rows<From>& m, F f) {
  Rows<To> o;
  for (const auto& r : m) o.push_back(map_vector<To>(r, f));
  return o;
}

/// The same pointwise result with every number mapped by f.
template <class To, class From, class F>
Pointwise<To> map_pointwise(const Pointwise<From>& p, F f) {
  Pointwise<To> q;
  q.route = p.route;
  q.regular = p.regular;
  q.why = p.why;
  q.time_name = p.time_name;
  q.time = f(p.time);
  q.point = map_vector<To>(p.point, f);
  q.velocity = map_vector<To>(p.velocity, f);
  q.gauge = map_rows<To>(p.gauge, f);
  q.first_constraints = p.first_constraints;
  for (const auto& l : p.levels) {
    typename Pointwise<To>::Step k;
    k.dim = l.dim;
    for (const auto& t : l.constraints) {
      typename Pointwise<To>::Tangent u;
      u.solved_for = t.solved_for;
      for (const auto& [name, g] : t.terms) u.terms.emplace_back(name, f(g));
      u.rhs = f(t.rhs);
      k.constraints.push_back(u);
    }
    for (const auto& pv : l.pivots) k.pivots.push_back({pv.row, pv.column, f(pv.value)});
    q.levels.push_back(k);
  }
  q.order = p.order;
  q.checked_order = p.checked_order;
  q.moves = p.moves;
  q.place = p.place;
  q.point_text = p.point_text;
  q.formulas = p.formulas;
  q.formulas_why = p.formulas_why;
  q.at_given = p.at_given;
  return q;
}

/// The same solution with every number mapped by f (e.g. a machine-word rational to mpq).
template <class To, class From, class F>
Solution<To> map_numbers(const Solution<From>& s, F f) {
  const auto eq = [&](const Equation<From>& e) {
    Equation<To> o;
    for (const auto& [j, a] : e.terms) o.terms.emplace_back(j, f(a));
    o.rhs = f(e.rhs);
    return o;
  };
  const auto eqs = [&](const std::vector<Equation<From>>& v) {
    std::vector<Equation<To>> o;
    for (const auto& e : v) o.push_back(eq(e));
    return o;
  };
  const auto vec = [&](const std::vector<From>& v) { return map_vector<To>(v, f); };
  const auto rows = [&](const Rows<From>& m) { return map_rows<To>(m, f); };
  Solution<To> o;
  o.backend = s.backend;
  o.certified = s.certified;
  o.exact = s.exact;
  o.file = s.file;
  o.name = s.name;
  o.variables = s.variables;
  o.jets = s.jets;
  for (const Level<From>& l : s.tower) o.tower.push_back({l.dim, eqs(l.constraints)});
  o.steps = s.steps;
  o.consistent = s.consistent;
  o.solution_rank = s.solution_rank;
  if (s.final_constraints) o.final_constraints = eqs(*s.final_constraints);
  if (s.final_exact) o.final_exact = ExactSubspace<To>{rows(s.final_exact->basis), vec(s.final_exact->point)};
  if (s.motion) {
    const Motion<From>& m = *s.motion;
    o.motion = Motion<To>{m.coordinates, rows(m.f_matrix), vec(m.f), rows(m.g), m.source_columns, rows(m.s)};
  }
  if (s.state) o.state = map_state<To>(*s.state, f);
  if (s.classes)
    o.classes = Classes<To>{s.classes->first_class, s.classes->second_class, eqs(s.classes->second_class_constraints),
                            rows(s.classes->dirac_bracket)};
  if (s.adapted)
    o.adapted =
        Adapted<To>{s.adapted->setting,  s.adapted->variables,    s.adapted->s_prime, s.adapted->secondary_first_class,
                    eqs(s.adapted->chi), eqs(s.adapted->abridged)};
  o.circuit = s.circuit;
  o.source_names = s.source_names;
  o.source_conditions = s.source_conditions;
  o.regular_pencil = s.regular_pencil;
  o.algorithm = s.algorithm;
  if (s.pointwise) o.pointwise = map_pointwise<To>(*s.pointwise, f);
  o.decisions = s.decisions;
  o.trace = s.trace;
  o.warnings = s.warnings;
  o.note = s.note;
  return o;
}

}  // namespace dcad
