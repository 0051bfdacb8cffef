#include "dcad/io/report.hpp"

#include <nlohmann/json.hpp>

#include <initializer_list>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace dcad::io {

using nlohmann::json;
using Eq = Equation<std::string>;

std::string float_text(double x) {
  if (x == 0) return "0.0";  // never "-0"
  std::ostringstream o;
  o.precision(17);
  o << x;
  std::string s = o.str();
  // a rounded value must not read as an exact integer string ("-1" for -1.000000000000000000001):
  // `dcad check` compares integer and fraction strings exactly
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

double printed_radius(double mid, double rad) {
  if (!std::isfinite(rad) || !std::isfinite(mid)) return rad;
  // how far the decimals that print mid (the shortest, as std::to_chars and the JSON writer give them,
  // and 17 significant digits, as float_text) lie from it, exactly
  using reference::Rational;
  Rational off(0);
  const Rational m(mid);
  char buf[64];
  const std::string shortest(buf, std::to_chars(buf, buf + sizeof buf, mid).ptr);
  for (const std::string& text : {shortest, json(mid).dump(), float_text(mid)}) {
    const Rational d = boost::multiprecision::abs(reference::parse_rational(text == "0.0" ? "0" : text) - m);
    if (d > off) off = d;
  }
  if (rad == 0 && off == 0) return 0.0;  // an exact value printed exactly
  const double o = std::nextafter(off.convert_to<double>(), HUGE_VAL);
  const double r = std::nextafter(std::nextafter(rad + o, HUGE_VAL), HUGE_VAL);
  return std::max(r, std::numeric_limits<double>::min());  // never subnormal: readers (strtod, stod) refuse those
}

std::string equation_text(const Eq& e, const std::vector<std::string>& names) {
  std::string s;
  for (const auto& [j, coeff] : e.terms) {
    std::string c = coeff;
    const bool neg = c[0] == '-';
    if (neg) c = c.substr(1);
    s += s.empty() ? (neg ? "-" : "") : (neg ? " - " : " + ");
    s += (c == "1" || c == "1.0" ? "" : c + "*") + names[j];
  }
  return (s.empty() ? "0" : s) + " = " + e.rhs;
}

namespace {

bool is_zero_text(const std::string& x) { return x == "0" || x == "0.0"; }

/// Σ coeff_j · name_j + constant, with empty coefficients left out (a row of the equations of motion).
std::string row_text(const std::vector<std::string>& coeff, const std::vector<std::string>& names,
                     const std::string& constant) {
  Eq e;
  for (std::size_t j = 0; j < coeff.size(); ++j)
    if (!coeff[j].empty()) e.terms.emplace_back(j, coeff[j]);
  std::string lhs = equation_text(e, names);
  lhs = lhs.substr(0, lhs.size() - 3);  // drop " = "
  if (constant == "0" || constant == "0.0" || constant.empty()) return lhs;
  if (lhs == "0") return constant;
  return lhs + (constant[0] == '-' ? " - " + constant.substr(1) : " + " + constant);
}

std::string negated(const std::string& c) { return c.empty() ? c : c[0] == '-' ? c.substr(1) : "-" + c; }

/// The state equations (dcad/solution.hpp) as JSON: names, the four equations' form, and each block's
/// nonzero entries [row, column, value].
json state_json(const StateEquations<std::string>& q) {
  json blocks = json::object();
  for (const auto& [name, b] : q.blocks) {
    json entries = json::array();
    for (const auto& [i, j, v] : b.entries) entries.push_back({i, j, v});
    blocks[name] = {{"rows", b.rows}, {"cols", b.cols}, {"entries", entries}};
  }
  std::vector<std::string> ds;
  for (const std::string& x : q.sources) ds.push_back(x.substr(0, x.size() - 3) + "'(t)");
  return {{"form",
           "circuit state equations on M_c (dcad/reference/rlc_state.hpp): x = (w, i) differential, r and e algebraic; "
           "the charges of the branches that are not capacitors are the integrals of their currents"},
          {"equations",
           {"C_ww d/dt w = -(G_ww w + G_wr r + L_w i + H_w s + H_wd ds)", "0 = G_wr^T w + G_rr r + L_r i + H_r s",
            "0 = L_e i + I_e s", "Phi d/dt i = L_w^T w + L_r^T r + L_e^T e + O_L s"}},
          {"w", q.w},
          {"i", q.i},
          {"r", q.r},
          {"e", q.e},
          {"s", q.sources},
          {"ds", ds},
          {"blocks", blocks}};
}

/// Largest number of state-equation rows the text report prints (beyond: where the JSON has them).
constexpr std::size_t kStateRowsPrinted = 40;

void state_text(const StateEquations<std::string>& q, std::ostream& o) {
  const std::size_t rows = q.w.size() + q.i.size() + q.r.size() + q.e.size();
  o << "  state equations on M_c (dcad/reference/rlc_state.hpp): " << q.w.size() << " potential(s) and " << q.i.size()
    << " inductor current(s) differential, " << q.r.size() + q.e.size() << " level(s) algebraic";
  if (rows > kStateRowsPrinted) {
    o << "; " << rows << " rows: see --json, key state_equations\n";
    return;
  }
  o << ":\n";
  std::vector<std::string> ds;
  for (const std::string& x : q.sources) ds.push_back("d/dt " + x);
  std::vector<std::string> dw, di;
  for (const std::string& x : q.w) dw.push_back("d/dt " + (x.find('-') == std::string::npos ? x : "(" + x + ")"));
  for (const std::string& x : q.i) di.push_back("d/dt " + x);
  const auto find = [&](const char* name) -> const SparseBlock<std::string>& {
    for (const auto& [n, b] : q.blocks)
      if (n == name) return b;
    throw std::logic_error(std::string("state equations without block ") + name);
  };
  // one row: Σ coefficient·name over (block, row or column k, names, transposed, negated)
  struct Use {
    const char* block;
    const std::vector<std::string>* names;
    bool transposed, negative;
  };
  const auto row = [&](long k, std::initializer_list<Use> uses) {
    Eq e;
    std::vector<std::string> names;
    for (const Use& u : uses)
      for (const auto& [i, j, v] : find(u.block).entries) {
        if ((u.transposed ? j : i) != k) continue;
        names.push_back((*u.names)[static_cast<std::size_t>(u.transposed ? i : j)]);
        e.terms.emplace_back(names.size() - 1, u.negative ? negated(v) : v);
      }
    e.rhs = "0";
    return equation_text(e, names);
  };
  for (std::size_t k = 0; k < q.w.size(); ++k)
    o << "    "
      << row(static_cast<long>(k), {{"C_ww", &dw, false, false},
                                    {"G_ww", &q.w, false, false},
                                    {"G_wr", &q.r, false, false},
                                    {"L_w", &q.i, false, false},
                                    {"H_w", &q.sources, false, false},
                                    {"H_wd", &ds, false, false}})
      << "\n";
  for (std::size_t k = 0; k < q.r.size(); ++k)
    o << "    "
      << row(static_cast<long>(k), {{"G_wr", &q.w, true, false},
                                    {"G_rr", &q.r, false, false},
                                    {"L_r", &q.i, false, false},
                                    {"H_r", &q.sources, false, false}})
      << "\n";
  for (std::size_t k = 0; k < q.e.size(); ++k)
    o << "    " << row(static_cast<long>(k), {{"L_e", &q.i, false, false}, {"I_e", &q.sources, false, false}}) << "\n";
  for (std::size_t k = 0; k < q.i.size(); ++k)
    o << "    "
      << row(static_cast<long>(k), {{"Phi", &di, false, false},
                                    {"L_w", &q.w, true, true},
                                    {"L_r", &q.r, true, true},
                                    {"L_e", &q.e, true, true},
                                    {"O_L", &q.sources, false, true}})
      << "\n";
}

/// codim M_2 in M_1: the KVLPC equations that constrain q (CONTRACT `pc_loops`, CEF Thm 6.4).
long pc_loops(const Printed& s) {
  const std::vector<long> d = s.dims();
  return s.consistent && d.size() > 2 ? d[1] - d[2] : 0;
}

std::string joined(const std::vector<std::string>& names) {
  std::string t;
  for (const std::string& x : names) t += (t.empty() ? "" : " ") + x;
  return t;
}

std::string holds_text(Truth t) {
  return t.yes() ? "holds" : t.no() ? "FAILS — the circuit is inconsistent" : "UNDECIDED";
}

json circuit_json(const Printed& s) {
  const CircuitFacts& f = *s.circuit;
  if (!f.forced)
    return {{"branches", f.branches},
            {"nodes", f.nodes},
            {"pc_loops", pc_loops(s)},
            {"empty_loops", f.empty_loops},
            {"kvlpc_graph", f.kvlpc_graph},
            {"physical", f.physical},
            {"pc_loop_branches", f.pc_loop_branches},
            {"empty_loop_branches", f.empty_loop_branches}};
  return {{"branches", f.branches},
          {"nodes", f.nodes},
          {"pc_loops", pc_loops(s)},
          {"empty_loops", f.empty_loops},
          {"inductors", f.inductors},
          {"capacitors", f.capacitors},
          {"resistors", f.resistors},
          {"voltage_sources", f.voltage_sources},
          {"current_sources", f.current_sources},
          {"wires", f.wires},
          {"couplings", f.couplings},
          {"cv_loops", f.cv_loops},
          {"source_loops", f.source_loops},
          {"li_cutsets", f.li_cutsets},
          {"source_cutsets", f.source_cutsets}};
}

const char* kind_text(BranchKind k) {
  return k == BranchKind::inductor ? "inductive" : k == BranchKind::capacitor ? "capacitive" : "empty";
}

std::string circuit_text(const Printed& s, const std::vector<std::string>& branch_names,
                         const std::vector<BranchKind>& branch_kinds) {
  const CircuitFacts& f = *s.circuit;
  std::ostringstream o;
  if (f.forced) {
    o << "  circuit \"" << s.name << "\": " << f.branches << " branches, " << f.nodes << " nodes (ground included); "
      << f.inductors << " L, " << f.capacitors << " C, " << f.resistors << " R, " << f.voltage_sources << " V, "
      << f.current_sources << " I, " << f.couplings << " K\n";
    for (const auto& l : f.cv_loops)
      o << "    CV loop " << joined(l)
        << ": KVL fixes its capacitor charges by the sources (Σ ±q/C = Σ ±V on M_2, the currents on M_3)\n";
    for (const auto& l : f.source_loops)
      o << "    loop of voltage sources " << joined(l) << ": KVL is a condition on the sources alone (Σ ±V(t) = 0)\n";
    for (const auto& c : f.li_cutsets)
      o << "    LI cutset " << joined(c)
        << ": KCL fixes its inductor currents by the current sources (Σ ±v_L = Σ ±I on M_1)\n";
    for (const auto& c : f.source_cutsets)
      o << "    cutset of current sources " << joined(c) << ": KCL is a condition on the sources alone (Σ ±I(t) = 0)\n";
    for (const SourceCondition& v : s.source_conditions)
      o << "    source condition " << v.text << ": " << holds_text(v.holds) << " (" << v.evidence << ")\n";
    for (const std::string& w : s.warnings) o << "    warning: " << w << "\n";
    return o.str();
  }
  o << "  circuit \"" << s.name << "\": " << f.branches << " branches, " << f.nodes
    << " nodes (ground included)\n    branches:";
  for (std::size_t b = 0; b < branch_names.size(); ++b)
    o << " " << branch_names[b] << " (" << kind_text(branch_kinds[b]) << ")";
  o << "\n    purely capacitive loops: " << pc_loops(s)
    << " independent KVLPC equation(s) on q (the M_2 constraints, CEF Thm 6.4)"
    << "; graph count " << f.kvlpc_graph << "\n";
  for (std::size_t i = 0; i < f.pc_loop_branches.size(); ++i)
    o << "      KVL loop " << i + 1 << ": " << joined(f.pc_loop_branches[i])
      << "  (sum of ±q/C over its capacitors = 0 on M_2, ±v/C on M_3)\n";
  o << "    empty loops: " << f.empty_loops
    << (f.empty_loops ? " (their loop currents are free: non-uniqueness, CEF Thm 6.8)" : "") << "\n";
  for (std::size_t i = 0; i < f.empty_loop_branches.size(); ++i)
    o << "      empty loop " << i + 1 << ": " << joined(f.empty_loop_branches[i]) << "\n";
  if (f.physical && !f.has_empty_branch)
    o << "    CEF Thm 6.6 (L, C > 0, no empty branch): c ∈ {1, 3}, c = 3 iff a purely capacitive loop exists — here c "
         "= "
      << s.steps << "\n";
  if (f.physical)
    o << "    CEF Thm 6.8 (L ≥ 0, C > 0): the leaves x + W_c are symplectic iff there are no empty loops — here "
      << (f.empty_loops ? "not symplectic" : "symplectic") << "\n";
  else
    o << "    negative L or C: not physical (CEF Remark 6.7), no theorem bounds c\n";
  for (const std::string& w : s.warnings) o << "    warning: " << w << "\n";
  return o.str();
}

/// A radius with two significant digits, rounded up (never printed smaller than the bound).
std::string radius_text(double r) {
  if (r == 0 || !std::isfinite(r)) return float_text(r);
  const int e = static_cast<int>(std::floor(std::log10(r)));
  long m = static_cast<long>(std::ceil(r / std::pow(10.0, e - 1) * (1 + 1e-12)));  // 10…100
  int ex = e;
  if (m >= 100) m = 10, ++ex;
  return std::to_string(m / 10) + "." + std::to_string(m % 10) + "e" + std::to_string(ex);
}

namespace {
/// M_c's rows in the result: {a·x = b} as rows [a…, b] ("final_constraints", what `dcad check` compares as a
/// subspace), or E and A's sparse encoding beyond 2·10⁶ entries ("final_constraints_sparse").
void final_constraints_json(const std::vector<Eq>& rows_of_mc, const std::vector<std::string>& names, bool exact,
                            json& j) {
  // M_c's rows beyond 2·10⁶ entries (5,000 constraints of a 10⁴-node circuit: 5·10⁷ strings, 6 GB of JSON) go
  // in E and A's sparse encoding instead, {rows, columns, entries: [[row, column, value]], rhs}
  const std::size_t dense_entries = rows_of_mc.size() * (names.size() + 1);
  if (dense_entries > 2'000'000) {
    json entries = json::array(), rhs = json::array();
    for (std::size_t i = 0; i < rows_of_mc.size(); ++i) {
      const Eq& e = rows_of_mc[i];
      for (const auto& [var, coeff] : e.terms) entries.push_back(json::array({i, var, coeff}));
      rhs.push_back(e.rhs);
    }
    j["final_constraints_sparse"] = {
        {"rows", rows_of_mc.size()}, {"columns", names}, {"entries", entries}, {"rhs", rhs}};
  } else {  // rows [a…, b] of M_c = {a·x = b}: what `dcad check` compares as a subspace
    json rows = json::array();
    for (const Eq& e : rows_of_mc) {
      // an absent term is an exact 0 only in an exact result (a ball's "absent" only contains 0)
      std::vector<std::string> row(names.size(),
                                   exact ? "0" : "0.0");  // the variables, then the sources' jets (if any)
      for (const auto& [var, coeff] : e.terms) row[var] = coeff;
      row.push_back(e.rhs);
      rows.push_back(row);
    }
    j["final_constraints"] = rows;
  }
}

/// How the answers were reached (CONTRACT `decisions`), for every form.
json decisions_json(const Decisions& d) {
  return {{"float", d.float_tests},
          {"exact_verification", d.exact_verifications},
          {"exact_recomputation", d.exact_recomputation},
          {"exact_machine_words", d.machine_words}};
}
}  // namespace

json cad_json(const Printed& r) {
  const std::vector<std::string> names = r.columns();
  json j = {
      {"dcad", 1},        {"backend", backend_name(r.backend)}, {"certified", r.certified.yes()}, {"dims", r.dims()},
      {"steps", r.steps}, {"consistent", r.consistent},         {"variables", r.variables}};
  j["solution_rank"] = r.solution_rank ? json(*r.solution_rank) : json(nullptr);
  j["unique"] = r.solution_rank ? json(*r.solution_rank == 0) : json(nullptr);
  if (r.regular_pencil) {  // a square linear DAE: for a regular pencil, steps is the differentiation index
    j["regular_pencil"] = *r.regular_pencil;
    j["index"] = r.index() ? json(*r.index()) : json(nullptr);
  }
  if (!r.jets.empty()) j["source_jets"] = r.jets;  // the columns after the variables in final_constraints
  json tower = json::array();
  for (std::size_t k = 0; k < r.tower.size(); ++k) {
    json eqs = json::array();
    for (const Eq& e : r.tower[k].constraints) eqs.push_back(equation_text(e, names));
    tower.push_back({{"k", k}, {"dim", r.tower[k].dim}, {"new_constraints", eqs}});
  }
  j["tower"] = tower;
  if (r.final_constraints) final_constraints_json(*r.final_constraints, names, r.exact, j);
  if (r.motion) {
    std::vector<std::string> coords;
    for (std::size_t i : r.motion->coordinates) coords.push_back(r.variables[i]);
    j["reduced"] = {{"coordinates", coords}, {"F", r.motion->f_matrix}, {"f", r.motion->f}, {"G", r.motion->g}};
    if (!r.motion->source_columns.empty())
      j["reduced"]["sources"] = {{"columns", r.motion->source_columns}, {"S", r.motion->s}};
  }
  if (r.state) j["state_equations"] = state_json(*r.state);
  if (r.classes) {
    json chi = json::array();
    for (const Eq& e : r.classes->second_class_constraints) chi.push_back(equation_text(e, names));
    j["constraint_classes"] = {{"first_class", r.classes->first_class}, {"second_class", r.classes->second_class}};
    if (!chi.empty()) j["constraint_classes"]["second_class_constraints"] = chi;
    if (!r.classes->dirac_bracket.empty()) j["dirac_bracket"] = r.classes->dirac_bracket;
  }
  if (r.adapted) {
    json chi = json::array(), terms = json::array();
    for (const Eq& e : r.adapted->chi) chi.push_back(equation_text(e, r.adapted->variables));
    for (const Eq& e : r.adapted->abridged) terms.push_back(equation_text(e, r.adapted->variables));
    j["adapted"] = {{"setting", r.adapted->setting},
                    {"variables", r.adapted->variables},
                    {"s_prime", r.adapted->s_prime},
                    {"second_class", chi},
                    {"abridged_total_energy_constraints", terms},
                    {"secondary_first_class", r.adapted->secondary_first_class}};
  }
  j["decisions"] = decisions_json(r.decisions);
  if (!r.note.empty()) j["note"] = r.note;
  if (r.circuit) j["circuit"] = circuit_json(r);
  json conds = json::array();
  for (const SourceCondition& v : r.source_conditions)
    conds.push_back({{"condition", v.text},
                     {"holds", v.holds.yes()  ? json(true)
                               : v.holds.no() ? json(false)
                                              : json(nullptr)},
                     {"evidence", v.evidence}});
  if (!r.source_names.empty() || !conds.empty()) j["sources"] = {{"names", r.source_names}, {"conditions", conds}};
  return j;
}

namespace {

/// The text of adapted constraints (CEF Thm 3.28; §7 on T*TQ): s', the second class chi, E_AT.
void adapted_text(const Adapted<std::string>& a, std::ostream& o) {
  o << "  adapted to the primary constraints (CEF Thm 3.28" << (a.setting == "T*TQ" ? ", §7 on T*TQ" : "")
    << "): s' = " << a.s_prime << ", " << a.chi.size() << " second class\n";
  for (const Eq& e : a.chi) o << "      chi: " << equation_text(e, a.variables) << "\n";
  o << "    E_AT = E";
  for (std::size_t k = 0; k < a.abridged.size(); ++k)
    o << " + lambda" << k + 1 << "*(" << equation_text(a.abridged[k], a.variables) << ")";
  o << "   (E_E adds " << a.secondary_first_class << " secondary first class constraints)\n";
}

/// The text of the equations of motion on M_c (CEF (5.12)), or of the velocities of a DAE (`ide`).
void motion_text(const Printed& r, bool ide, std::ostream& o) {
  const Motion<std::string>& m = *r.motion;
  std::vector<std::string> coords;
  for (std::size_t i : m.coordinates) coords.push_back(r.variables[i]);
  std::vector<std::string> lambdas;
  for (std::size_t k = 0; k < (m.g.empty() ? 0 : m.g[0].size()); ++k)
    lambdas.push_back("lambda" + std::to_string(k + 1));
  o << (ide ? "  velocities on M_c (E v = A x + f, v tangent to M_c) in coordinates ("
            : "  equations of motion on M_c (CEF (5.12)) in coordinates (");
  for (std::size_t i = 0; i < coords.size(); ++i) o << (i ? ", " : "") << coords[i];
  o << "):\n";
  for (std::size_t i = 0; i < coords.size(); ++i) {
    std::vector<std::string> coeff = m.f_matrix[i];
    std::vector<std::string> all = coords;
    for (std::size_t k = 0; k < m.source_columns.size(); ++k) {
      coeff.push_back(m.s[i][k]);
      all.push_back(m.source_columns[k]);
    }
    for (std::size_t k = 0; k < lambdas.size(); ++k) {
      coeff.push_back(is_zero_text(m.g[i][k]) ? "" : m.g[i][k]);
      all.push_back(lambdas[k]);
    }
    for (std::string& x : coeff)
      if (is_zero_text(x)) x = "";
    o << "    d/dt " << coords[i] << " = " << row_text(coeff, all, m.f[i]) << "\n";
  }
}

}  // namespace

std::string cad_text(const Printed& r) {
  const std::vector<std::string> names = r.columns();
  std::ostringstream o;
  const bool ide = r.regular_pencil.has_value() ||
                   r.algorithm == Algorithm::implicit_equation;  // a DAE: the implicit-equation algorithm
  o << r.file << (r.name.empty() ? "" : " (" + r.name + ")")
    << (ide ? ": the constraint algorithm of CEF (1.6)" : ": CAD (CEF §5)") << ", backend " << backend_name(r.backend)
    << (r.certified.yes() ? ", certified" : ", NOT certified") << "\n";
  for (std::size_t k = 0; k < r.tower.size(); ++k) {
    o << "  M_" << k << ": " << (r.tower[k].dim < 0 ? std::string("empty") : "dim " + std::to_string(r.tower[k].dim))
      << "\n";
    for (const Eq& e : r.tower[k].constraints) o << "      " << equation_text(e, names) << "\n";
  }
  if (!r.consistent) {
    o << "  inconsistent: M_" << r.steps << " is empty, the system has no solution\n";
  } else {
    const long rank = r.solution_rank.value_or(0);
    o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << r.tower.back().dim << "\n";
    o << (ide ? "  solution rank dim{v in T M_c : E v = A x + f} = " : "  solution rank dim(ker omega_D ∩ T M_c) = ")
      << rank << (rank == 0 ? " (unique)" : " (not unique)") << "\n";
  }
  if (r.regular_pencil)
    o << "  pencil sE - A" << (r.certified.yes() ? "" : " (uncertain, as this result)") << ": "
      << (*r.regular_pencil ? "regular (det(sE - A) is not identically 0)" +
                                  std::string(r.consistent ? "; differentiation index " + std::to_string(r.steps) : "")
                            : std::string("singular (det(sE - A) = 0 for every s): no unique solution for every f"))
      << "\n";
  if (ide)
    for (const std::string& f : r.source_names) o << "  source " << f << "\n";
  if (!r.circuit)
    for (const SourceCondition& v : r.source_conditions)
      o << "  condition on the sources " << v.text << ": "
        << (v.holds.yes()  ? "holds"
            : v.holds.no() ? "FAILS for generic t (an empty M_k)"
                           : "UNDECIDED")
        << " (" << v.evidence << ")\n";
  if (r.classes) {
    o << "  constraints of M_c (CEF §2.1, Lemma 3.23): " << r.classes->first_class << " first class, "
      << r.classes->second_class << " second class\n";
    for (const Eq& e : r.classes->second_class_constraints)
      o << "      second class: " << equation_text(e, names) << "\n";
  }
  if (r.adapted) adapted_text(*r.adapted, o);
  if (r.motion) motion_text(r, ide, o);
  if (r.state) state_text(*r.state, o);
  if (!r.note.empty()) o << "  note: " << r.note << "\n";
  return o.str();
}

namespace {
/// The pointwise tower: M_0, then each level's constraints (formulas, or tangent equations at the point with what
/// they are solved for) and the pivots of its linear system, and an empty last level where M_c is empty.
json pointwise_tower_json(const Printed& r, const Pointwise<std::string>& p, const std::vector<long>& dims) {
  json tower = json::array();
  tower.push_back({{"k", 0}, {"dim", dims[0]}, {"new_constraints", json::array()}});
  for (std::size_t k = 0; k < p.levels.size(); ++k) {
    const auto& l = p.levels[k];
    json cs = json::array(), solved = json::array(), ps = json::array();
    const bool formula = k == 0 && !p.first_constraints.empty();  // the implicit form's M_1 is a tangent equation too
    if (formula) {
      cs = p.first_constraints;
    } else {
      for (const auto& con : l.constraints) {
        Eq e;
        std::vector<std::string> names;
        for (const auto& [name, g] : con.terms) {
          e.terms.emplace_back(names.size(), g);
          names.push_back(name);
        }
        e.rhs = con.rhs;
        cs.push_back(equation_text(e, names));
        solved.push_back(con.solved_for);
      }
    }
    for (const auto& pv : l.pivots) ps.push_back({{"row", pv.row}, {"column", pv.column}, {"value", pv.value}});
    json step = {{"k", k + 1}, {"dim", k + 1 < dims.size() ? dims[k + 1] : l.dim}, {"new_constraints", cs}};
    step["form"] = formula ? "formula" : "tangent at the point";
    if (!formula) step["solved_for"] = solved;
    step["pivots"] = ps;  // of the linear system for (d/dt s, lambda) on this M_k
    tower.push_back(step);
  }
  if (!r.consistent) tower.push_back({{"k", dims.size() - 1}, {"dim", -1}, {"new_constraints", json::array({p.why})}});
  return tower;
}
}  // namespace

json pointwise_json(const Printed& r) {
  const Pointwise<std::string>& p = *r.pointwise;
  const std::vector<long> dims = r.dims();
  json j;
  j["dcad"] = 1;
  j["backend"] = backend_name(r.backend);
  j["certified"] = r.certified.yes();
  j["dims"] = dims;
  j["steps"] = r.steps;
  // at a singular point the tower is not decided: consistency is unknown (null), never a regular-looking true
  j["consistent"] = p.regular || !r.consistent ? json(r.consistent) : json(nullptr);
  j["solution_rank"] = r.solution_rank ? json(*r.solution_rank) : json(nullptr);
  j["unique"] = r.solution_rank ? json(*r.solution_rank == 0) : json(nullptr);
  // the implicit form: where ẋ is unique on M_c, steps is the index (Rabier–Rheinboldt's geometric
  // index, which is the differentiation index there); else none
  if (r.algorithm == Algorithm::implicit_equation) j["index"] = r.index() ? json(*r.index()) : json(nullptr);
  if (!r.name.empty()) j["name"] = r.name;
  j["variables"] = r.variables;
  j["route"] = p.route;
  j["regular"] = p.regular;
  j["decisions"] = decisions_json(r.decisions);
  if (!p.why.empty()) j["why"] = p.why;
  json pt = json::object();
  if (!p.time_name.empty()) pt[p.time_name] = p.time;
  for (std::size_t i = 0; i < p.point.size(); ++i) pt[r.variables[i]] = p.point[i];
  for (const auto& [i, text] : p.point_text) pt[r.variables[i]] = text;
  j["point"] = pt;
  if (!p.place.empty()) j["place"] = p.place;
  j["tower"] = pointwise_tower_json(r, p, dims);
  if (!p.velocity.empty()) {
    json v = json::object();
    for (std::size_t i = 0; i < p.velocity.size(); ++i) v[r.variables[i]] = p.velocity[i];
    j["velocity"] = v;
    j["gauge"] = p.gauge;
  }
  if (p.checked_order < 0)  // the implicit form's formula route: no jets, every zero test an identity of the formulas
    j["zero_tests"] = {{"by", "identities of the formulas (their canonical polynomial forms)"}, {"moves", p.moves}};
  else
    j["jets"] = {{"order", p.order}, {"checked_order", p.checked_order}, {"moves", p.moves}};
  if (p.formulas) {
    const Formulas& f = *p.formulas;
    json eq = json::object(), mo = json::object();
    for (const auto& [name, e] : f.equations) eq[name] = e;
    for (const auto& [name, e] : f.momenta) mo[name] = e;
    j["formulas"] = {{"constraints", f.constraints},
                     {"levels", f.levels},
                     {"equations", eq},
                     {"momenta", mo},
                     {"free", f.free},
                     {"chart", {{"kept", f.kept}, {"solved", f.solved}}},
                     {"valid_where", f.valid_where},
                     {"valid_where_why", f.valid_where_why},
                     {"decided", f.decided}};
  } else if (!p.formulas_why.empty()) {
    j["formulas"] = nullptr;
    j["formulas_why"] = p.formulas_why;
  }
  if (p.at_given) {
    const AtGiven& a = *p.at_given;
    const auto balls = [](const std::vector<AtGiven::Ball>& bs) {
      json o = json::object();
      for (const AtGiven::Ball& b : bs) o[b.name] = {{"mid", b.mid}, {"rad", printed_radius(b.mid, b.rad)}};
      return o;
    };
    json at = {{"certified", a.proved},  {"point", balls(a.point)}, {"velocity", balls(a.velocity)},
               {"solved_for", a.solved}, {"moved", a.moved},        {"claim", a.claim}};
    if (!a.why.empty()) at["why"] = a.why;
    j["at_given"] = at;
  }
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

std::string tangent_text(const Pointwise<std::string>::Tangent& t) {
  Eq e;
  std::vector<std::string> names;
  for (const auto& [name, g] : t.terms) {
    e.terms.emplace_back(names.size(), g);
    names.push_back(name);
  }
  e.rhs = t.rhs;
  return equation_text(e, names);
}

namespace {
/// The pointwise result's formulas on a chart (or why there are none) and its values at the given point in balls.
void pointwise_extras_text(const Pointwise<std::string>& p, std::ostream& o) {
  if (p.formulas) {
    const Formulas& f = *p.formulas;
    const auto shown = [](const std::string& e) {
      return e.size() <= 400 ? e : "(a formula of " + std::to_string(e.size()) + " characters: see --json)";
    };
    o << "  formulas on a chart (kept:";
    for (const std::string& k : f.kept) o << " " << k;
    o << "):\n";
    for (std::size_t i = 0; i < f.constraints.size(); ++i)
      o << "      M_" << f.levels[i] << ": " << shown(f.constraints[i]) << " = 0\n";
    for (const auto& [name, e] : f.equations) o << "      d/dt " << name << " = " << shown(e) << "\n";
    for (std::size_t i = 0; i < f.valid_where.size(); ++i)
      o << "      valid where " << shown(f.valid_where[i]) << " != 0   (" << f.valid_where_why[i] << ")\n";
  } else if (!p.formulas_why.empty()) {
    o << "  no formulas: " << p.formulas_why << "\n";
  }
  if (p.at_given) {
    const AtGiven& a = *p.at_given;
    o << "  at the given values, in balls (" << (a.proved ? "proved" : "NOT proved: " + a.why) << "):";
    const auto show = [&o](const std::string& pre, const std::vector<AtGiven::Ball>& bs) {
      for (std::size_t i = 0; i < bs.size(); ++i)
        o << (i % 3 == 0 ? "\n     " : "") << " " << pre << bs[i].name << " = " << float_text(bs[i].mid) << " ± "
          << radius_text(printed_radius(bs[i].mid, bs[i].rad)) << (i + 1 < bs.size() ? "," : "");
    };
    show("", a.point);
    show("d/dt ", a.velocity);
    if (!a.solved.empty()) o << "\n      solved for: " << joined(a.solved);
    if (!a.moved.empty()) o << "\n      given values moved (their decimals miss M_c): " << joined(a.moved);
    o << "\n      " << a.claim << "\n";
  }
}
}  // namespace

std::string pointwise_text(const Printed& r) {
  const Pointwise<std::string>& p = *r.pointwise;
  const std::vector<long> dims = r.dims();
  const std::vector<std::string>& st = r.variables;
  std::ostringstream o;
  const bool ide = r.algorithm == Algorithm::implicit_equation;
  o << r.file << (r.name.empty() ? "" : " (" + r.name + ")")
    << (ide ? ": the constraint algorithm of CEF (1.6) at a point, " : ": CAD (CEF §5) at a point, ") << p.route
    << ", backend " << backend_name(r.backend) << ", " << (r.certified.yes() ? "certified" : "NOT certified") << "\n";
  o << "  point" << (!p.time_name.empty() ? " at " + p.time_name + " = " + p.time : "") << ":";
  std::vector<std::string> shown = p.point;
  for (const auto& [i, text] : p.point_text) shown[i] = text;
  for (std::size_t i = 0; i < shown.size(); ++i)
    o << (i % 6 == 0 ? "\n     " : "") << " " << st[i] << " = " << shown[i] << (i + 1 < shown.size() ? "," : "");
  o << "\n";
  if (!p.place.empty()) {
    o << "  the exact route ran at a rational place, not at the given values:\n";
    for (const std::string& l : p.place) o << "      " << l << "\n";
  }
  if (p.moves > 0)
    o << "  (the given values were completed onto M_c by " << p.moves << " Newton step" << (p.moves > 1 ? "s" : "")
      << ")\n";
  o << "  M_0: dim " << dims[0] << "\n";
  for (std::size_t k = 0; k < p.levels.size() && k + 1 < dims.size(); ++k) {
    o << "  M_" << k + 1 << ": dim " << dims[k + 1] << "\n";
    if (k == 0)
      for (const std::string& f : p.first_constraints) o << "      " << f << "\n";
    for (const auto& cs : p.levels[k].constraints)
      o << "      " << tangent_text(cs) << "   (tangent at the point; solved for " << cs.solved_for << ")\n";
  }
  if (!r.consistent) o << "  M_" << dims.size() - 1 << " is empty: " << p.why << "\n";
  if (!p.regular) o << "  SINGULAR POINT: " << p.why << " (the tower is not decided here; try another point)\n";
  if (r.consistent && p.regular) {
    const long rank = r.solution_rank.value_or(0);
    if (p.route.rfind("derivative array", 0) == 0)
      o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << dims.back()
        << " (ranks of the derivative array F_" << p.order << " at a zero of it)\n";
    else if (p.checked_order < 0)  // the formula route: every zero test an identity
      o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << dims.back()
        << " (regular at the point; every zero test an "
        << "identity of the formulas)\n";
    else
      o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << dims.back()
        << " (regular at the point; the last step's "
        << "constraints vanish on M_c to order " << p.checked_order << ")\n";
    o << (ide ? "  solution rank dim{v in T M_c : phi(t, x, v) = 0} = " : "  solution rank dim(ker omega_D ∩ T M_c) = ")
      << rank << (rank == 0 ? " (unique)" : "") << (ide && rank == 0 ? "; index " + std::to_string(r.steps) : "")
      << "\n";
    o << "  velocity at the point (one solution" << (rank ? " of a " + std::to_string(rank) + "-parameter family" : "")
      << "):";
    for (std::size_t i = 0; i < p.velocity.size(); ++i)
      o << (i % 4 == 0 ? "\n     " : "") << " d/dt " << st[i] << " = " << p.velocity[i]
        << (i + 1 < p.velocity.size() ? "," : "");
    o << "\n";
  }
  pointwise_extras_text(p, o);
  if (!r.note.empty()) o << "  note: " << r.note << "\n";
  return o.str();
}

json solution_json(const Printed& s) { return s.pointwise ? pointwise_json(s) : cad_json(s); }

}  // namespace

std::string result_json(const Printed& s, int indent) { return solution_json(s).dump(indent); }

std::string result_json_line(const Printed& s, const std::string& file) {
  json j = {{"file", file}};
  j.update(solution_json(s));
  return j.dump();
}

std::string error_json_line(const std::string& file, const std::string& message, int exit_code) {
  return json({{"file", file}, {"error", message}, {"exit", exit_code}}).dump();
}

std::string report_text(const Printed& s) {
  if (s.pointwise) return pointwise_text(s);
  std::string t = cad_text(s);
  if (s.circuit) t += circuit_text(s, s.circuit->branch_names, s.circuit->branch_kinds);
  return t;
}

std::string inspection_json(const Inspection& r) {
  json j = {{"dcad", 1},
            {"backend", backend_name(r.backend)},
            {"certified", r.certified.yes()},
            {"n", r.n},
            {"form", r.form},
            {"valid", r.valid}};
  if (!r.valid) {
    j["why"] = r.why;
    return j.dump(2);
  }
  j["dim_E_D"] = r.dim_e;
  j["rank_omega_D"] = r.rank_omega;
  j["dim_ker_omega_D"] = r.dim_ker_omega;
  j["presymplectic"] = r.presymplectic;
  j["poisson"] = r.poisson;
  if (!r.uncertain.empty()) {
    j["uncertain"] = r.uncertain;
    j["evidence"] = r.evidence;
  }
  return j.dump(2);
}

std::string inspection_text(const Inspection& r) {
  std::ostringstream o;
  const auto yes_no = [](bool b) { return b ? "yes" : "no"; };
  o << r.file << (r.name.empty() ? "" : " (" + r.name + ")") << ": D on R^" << r.n << " given as `" << r.form
    << "`, backend " << backend_name(r.backend) << "\n";
  o << "  Dirac structure (CEF Lemma 4.1): " << yes_no(r.valid) << (r.valid ? "" : " -- " + r.why) << "\n";
  if (r.valid) {
    o << "  dim E_D          = " << r.dim_e << "\n";
    o << "  rank omega_D     = " << r.rank_omega << "\n";
    o << "  dim ker omega_D  = " << r.dim_ker_omega << "\n";
    o << "  from a presymplectic form (E_D = R^" << r.n << "): " << yes_no(r.presymplectic) << "\n";
    o << "  from a Poisson bivector (D meets V+0 in 0): " << yes_no(r.poisson) << "\n";
  }
  o << "  certified: " << yes_no(r.certified.yes()) << "\n";
  for (const std::string& e : r.evidence) o << "  uncertain " << e << "\n";
  return o.str();
}

}  // namespace dcad::io
