// Text and JSON, written once for every backend and problem kind (issue 26): a Solution's numbers are
// printed by the twin's own number printer (printed()), then the CONTRACT's result JSON and the report
// for people are formatted here.  Exact numbers print as "p/q"; floating-point ones as %.17g that
// round-trips, always as a float ("1.0", never "1" or "-0": `dcad check` reads integer and fraction
// strings as exact).
#pragma once

#include "dcad/inspection.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/solution.hpp"

#include <string>
#include <vector>

namespace dcad::io {

/// A solution whose numbers are their printed text.
using Printed = Solution<std::string>;

/// x as %.17g (round-trips), always as a float: "1.0", never "1" (an exact integer string) or "-0".
std::string float_text(double x);
/// The radius to print beside `mid` for a ball mid ± rad of an exact value (issue 45 §6): wide enough that
/// the *printed* decimals contain it — rad plus one ulp of mid (any decimal that reads back as mid, the
/// shortest or 17 digits, lies within half an ulp of it), rounded up twice so that even the shortest
/// decimal of the result is not below the sum.  Infinite or NaN radii are returned as they are.
double printed_radius(double mid, double rad);
inline std::string number_text(double x) { return float_text(x); }
inline std::string number_text(const reference::Rational& q) { return q.str(); }

/// The solution with its numbers printed (number_text of N, found by argument-dependent lookup for a
/// twin's own number type).
template <class N>
Printed printed(const Solution<N>& s) {
  return map_numbers<std::string>(s, [](const N& x) { return number_text(x); });
}

template <class N>
Equation<std::string> printed_equation(const Equation<N>& e) {
  Equation<std::string> o;
  for (const auto& [j, a] : e.terms) o.terms.emplace_back(j, number_text(a));
  o.rhs = number_text(e.rhs);
  return o;
}

/// "2*x1 - 1/3*x2 = 5" in the given column names.
std::string equation_text(const Equation<std::string>& e, const std::vector<std::string>& names);

/// The CONTRACT's result JSON (`dcad solve --json`), indented by `indent` (−1: one line).
std::string result_json(const Printed& s, int indent = 2);
/// The same as one line with "file" first (`dcad solve --jsonl`).
std::string result_json_line(const Printed& s, const std::string& file);
/// `{"file", "error", "exit"}` on one line: a file of `dcad solve --jsonl` that is bad input.
std::string error_json_line(const std::string& file, const std::string& message, int exit_code);
/// The report for people (`dcad solve`).
std::string report_text(const Printed& s);

std::string inspection_json(const Inspection& r);
std::string inspection_text(const Inspection& r);

}  // namespace dcad::io
