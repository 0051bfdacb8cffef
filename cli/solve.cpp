#include "solve.hpp"

#include "dcad/certified/ball.hpp"
#include "dcad/reference/small_rational.hpp"

#include <functional>
#include <sstream>

namespace dcad::cli {

std::string equation_text(const Equation& e, const std::vector<std::string>& names) {
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

Equation row_equation(const io::QMatrix& rows, std::size_t i) {
  Equation e;
  for (std::size_t j = 0; j + 1 < rows.cols(); ++j)
    if (rows(i, j) != 0) e.terms.emplace_back(j, rows(i, j).str());
  e.rhs = rows(i, rows.cols() - 1).str();
  return e;
}

SolveReport certify(const std::function<SolveReport()>& small, const std::function<SolveReport(double&)>& ball,
                    const std::function<SolveReport()>& exact) {
  std::string overflow;
  if (small) {
    try {
      SolveReport r = small();
      r.backend = "certified";
      r.certified = true;
      r.decisions_machine_words = 1;
      r.note = (r.note.empty() ? "" : r.note + "; ") + "the reference algorithm in exact " + std::to_string(r.word_bits) +
               "-bit rationals (every number fitted in machine words" + (r.word_bits > 64 ? ", once 64 bits gave up)" : ")");
      return r;
    } catch (const reference::Overflow& e) {
      overflow = std::string("exact 128-bit rationals gave up (") + e.what() + "); ";
    }
  }
  certified::Ball::decisions() = 0;
  certified::Ball::verifications() = 0;
  try {
    double radius = 0;
    SolveReport r = ball(radius);
    r.backend = "certified";
    r.certified = true;
    r.decisions_float = certified::Ball::decisions();
    r.decisions_verified = certified::Ball::verifications();
    std::ostringstream o;
    o.precision(2);
    o << (r.note.empty() ? "" : r.note + "; ") << overflow << "the reference algorithm in ball arithmetic: " << r.decisions_float
      << " zero tests certified in floating point, " << r.decisions_verified
      << " by exact comparison of input numbers; numbers are ball midpoints, exact values within " << radius;
    r.note = o.str();
    return r;
  } catch (const certified::Uncertain& e) {
    const long done = certified::Ball::decisions();
    SolveReport out = exact();
    out.backend = "certified";
    out.decisions_float = done;
    out.decisions_verified = certified::Ball::verifications();
    out.decisions_exact = 1;
    out.note = (out.note.empty() ? "" : out.note + "; ") + overflow + "zero test " + std::to_string(done + 1) + " undecidable in floating point (" +
               e.what() + "): recomputed exactly from the exact input";
    return out;
  }
}

SolveReport solve_certified(const io::CaseFile& c, const Parts& parts) {
  std::function<SolveReport()> small;
  if (c.n <= reference::kSmallFirstUpTo) small = [&] { return solve_small(c, parts); };
  return certify(small, [&](double& radius) { return solve_ball(c, radius, parts); }, [&] { return solve_rational(c, parts); });
}

Parts parse_parts(const std::string& list) {
  if (list == "all") return {};
  Parts p{false, false, false, false};
  if (list == "none") return p;
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = list.find(',', start);
    const std::string w = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (w == "final") p.final_constraints = true;
    else if (w == "reduced") p.reduced = true;
    else if (w == "classes") p.classes = true;
    else if (w == "adapted") p.adapted = true;
    else
      throw std::invalid_argument("--with: expected all, none or a comma-separated list of final, reduced, classes, adapted; found '" +
                                  w + "'");
    if (comma == std::string::npos) return p;
    start = comma + 1;
  }
}

namespace {

std::string row_text(const std::vector<std::string>& coeff, const std::vector<std::string>& names, const std::string& constant) {
  Equation e;
  for (std::size_t j = 0; j < coeff.size(); ++j)
    if (!coeff[j].empty()) e.terms.emplace_back(j, coeff[j]);
  std::string lhs = equation_text(e, names);
  lhs = lhs.substr(0, lhs.size() - 3);  // drop " = "
  if (constant == "0" || constant == "0.0" || constant.empty()) return lhs;
  if (lhs == "0") return constant;
  return lhs + (constant[0] == '-' ? " - " + constant.substr(1) : " + " + constant);
}

}  // namespace

nlohmann::json to_json(const SolveReport& r, const io::CaseFile& c) {
  nlohmann::json j = {{"dcad", 1},        {"backend", r.backend},       {"certified", r.certified}, {"dims", r.dims},
                      {"steps", r.steps}, {"consistent", r.consistent}, {"variables", c.variables}};
  j["solution_rank"] = r.consistent ? nlohmann::json(r.solution_rank) : nlohmann::json(nullptr);
  j["unique"] = r.consistent ? nlohmann::json(r.solution_rank == 0) : nlohmann::json(nullptr);
  nlohmann::json tower = nlohmann::json::array();
  for (std::size_t k = 0; k < r.tower.size(); ++k) {
    nlohmann::json eqs = nlohmann::json::array();
    for (const Equation& e : r.tower[k].equations) eqs.push_back(equation_text(e, c.variables));
    tower.push_back({{"k", k}, {"dim", r.tower[k].dim}, {"new_constraints", eqs}});
  }
  j["tower"] = tower;
  if (r.has_final_constraints) {  // rows [a…, b] of M_c = {a·x = b}: what `dcad check` compares as a subspace
    nlohmann::json rows = nlohmann::json::array();
    for (const Equation& e : r.final_constraints) {
      // an absent term is an exact 0 only in an exact result (a ball's "absent" only contains 0)
      const bool exact = r.backend == "reference" || r.decisions_exact > 0;
      std::vector<std::string> row(c.variables.size(), exact ? "0" : "0.0");
      for (const auto& [var, coeff] : e.terms) row[var] = coeff;
      row.push_back(e.rhs);
      rows.push_back(row);
    }
    j["final_constraints"] = rows;
  }
  if (r.has_reduced) {
    std::vector<std::string> names;
    for (std::size_t i : r.coords) names.push_back(c.variables[i]);
    j["reduced"] = {{"coordinates", names}, {"F", r.f_matrix}, {"f", r.f}, {"G", r.g}};
  }
  if (r.second_class >= 0) {
    nlohmann::json chi = nlohmann::json::array();
    for (const Equation& e : r.second_class_constraints) chi.push_back(equation_text(e, c.variables));
    j["constraint_classes"] = {{"first_class", r.first_class}, {"second_class", r.second_class}};
    if (!chi.empty()) j["constraint_classes"]["second_class_constraints"] = chi;
    if (!r.dirac_bracket.empty()) j["dirac_bracket"] = r.dirac_bracket;
  }
  if (r.has_adapted) {
    nlohmann::json chi = nlohmann::json::array(), terms = nlohmann::json::array();
    for (const Equation& e : r.adapted_chi) chi.push_back(equation_text(e, r.adapted_variables));
    for (const Equation& e : r.abridged_terms) terms.push_back(equation_text(e, r.adapted_variables));
    j["adapted"] = {{"setting", r.adapted_setting},
                    {"variables", r.adapted_variables},
                    {"s_prime", r.s_prime},
                    {"second_class", chi},
                    {"abridged_total_energy_constraints", terms},
                    {"secondary_first_class", r.secondary_first_class}};
  }
  j["decisions"] = {{"float", r.decisions_float},
                    {"exact_verification", r.decisions_verified},
                    {"exact_recomputation", r.decisions_exact},
                    {"exact_machine_words", r.decisions_machine_words}};
  if (!r.note.empty()) j["note"] = r.note;
  return j;
}

std::string to_text(const SolveReport& r, const io::CaseFile& c) {
  std::ostringstream o;
  o << c.file << (c.name.empty() ? "" : " (" + c.name + ")") << ": CAD (CEF §5), backend " << r.backend
    << (r.certified ? ", certified" : ", NOT certified") << "\n";
  for (std::size_t k = 0; k < r.tower.size(); ++k) {
    o << "  M_" << k << ": " << (r.tower[k].dim < 0 ? std::string("empty") : "dim " + std::to_string(r.tower[k].dim)) << "\n";
    for (const Equation& e : r.tower[k].equations) o << "      " << equation_text(e, c.variables) << "\n";
  }
  if (!r.consistent) {
    o << "  inconsistent: M_" << r.steps << " is empty, the system has no solution\n";
  } else {
    o << "  final constraint submanifold M_c, c = " << r.steps << ", dim " << r.dims.back() << "\n";
    o << "  solution rank dim(ker omega_D ∩ T M_c) = " << r.solution_rank << (r.solution_rank == 0 ? " (unique)" : " (not unique)") << "\n";
  }
  if (r.second_class >= 0) {
    o << "  constraints of M_c (CEF §2.1, Lemma 3.23): " << r.first_class << " first class, " << r.second_class
      << " second class\n";
    for (const Equation& e : r.second_class_constraints) o << "      second class: " << equation_text(e, c.variables) << "\n";
  }
  if (r.has_adapted) {
    o << "  adapted to the primary constraints (CEF Thm 3.28" << (r.adapted_setting == "T*TQ" ? ", §7 on T*TQ" : "")
      << "): s' = " << r.s_prime << ", " << r.adapted_chi.size() << " second class\n";
    for (const Equation& e : r.adapted_chi) o << "      chi: " << equation_text(e, r.adapted_variables) << "\n";
    o << "    E_AT = E";
    for (std::size_t k = 0; k < r.abridged_terms.size(); ++k)
      o << " + lambda" << k + 1 << "*(" << equation_text(r.abridged_terms[k], r.adapted_variables) << ")";
    o << "   (E_E adds " << r.secondary_first_class << " secondary first class constraints)\n";
  }
  if (r.has_reduced) {
    std::vector<std::string> names;
    for (std::size_t i : r.coords) names.push_back(c.variables[i]);
    std::vector<std::string> lambdas;
    for (std::size_t k = 0; k < (r.g.empty() ? 0 : r.g[0].size()); ++k) lambdas.push_back("lambda" + std::to_string(k + 1));
    o << "  equations of motion on M_c (CEF (5.12)) in coordinates (" ;
    for (std::size_t i = 0; i < names.size(); ++i) o << (i ? ", " : "") << names[i];
    o << "):\n";
    for (std::size_t i = 0; i < names.size(); ++i) {
      std::vector<std::string> coeff = r.f_matrix[i];
      std::vector<std::string> all = names;
      for (std::size_t k = 0; k < r.extra_names.size(); ++k) {
        coeff.push_back(r.extra_terms[i][k]);
        all.push_back(r.extra_names[k]);
      }
      for (std::size_t k = 0; k < lambdas.size(); ++k) {
        coeff.push_back(r.g[i][k] == "0" || r.g[i][k] == "0.0" ? "" : r.g[i][k]);
        all.push_back(lambdas[k]);
      }
      for (std::string& x : coeff)
        if (x == "0" || x == "0.0") x = "";
      o << "    d/dt " << names[i] << " = " << row_text(coeff, all, r.f[i]) << "\n";
    }
  }
  if (!r.note.empty()) o << "  note: " << r.note << "\n";
  return o.str();
}

}  // namespace dcad::cli
