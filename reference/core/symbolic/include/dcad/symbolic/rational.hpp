// dcad::symbolic — the exact algebra both twins and the readers share (issue 47: "shared algebra lives in core
// under a name that says so"): rationals, expression DAGs and their calculus, jets, Lagrangian systems as
// formulas.  It decides nothing; the reference's algorithms and fast's routes are built on it.
//
// The exact field and exact reading of numbers (CONTRACT "Numbers").
#pragma once

#include <boost/multiprecision/gmp.hpp>

#include <cctype>
#include <stdexcept>
#include <string>

namespace dcad::symbolic {

using Rational = boost::multiprecision::mpq_rational;

/// Reads "3", "-2/7", "0.125", "1e-3", "-1.5E+2" exactly.  Throws std::invalid_argument
/// "expected …, found …" on anything else (including a zero denominator).
inline Rational parse_rational(const std::string& text) {
  using boost::multiprecision::mpz_int;
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("expected an exact number such as \"3\", \"-2/7\", \"0.125\" or \"1e-3\", found \"" +
                                 text + "\"" + (why.empty() ? "" : " (" + why + ")"));
  };
  std::size_t i = 0;
  const auto digits = [&](std::string& out) {
    const std::size_t start = i;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) out += text[i++];
    return i > start;
  };
  bool neg = false;
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) neg = text[i++] == '-';
  std::string whole, frac;
  const bool has_whole = digits(whole);
  bool has_frac = false;
  if (i < text.size() && text[i] == '.') {
    ++i;
    has_frac = digits(frac);
  }
  if (!has_whole && !has_frac) throw bad("");
  // digits in base 10: Boost's mpz_int("010") reads a leading 0 as octal (8), so "0.010" was 1/125
  const auto decimal = [](const std::string& d) {
    const std::size_t first = d.find_first_not_of('0');
    return mpz_int(first == std::string::npos ? std::string("0") : d.substr(first));
  };
  Rational value(decimal(whole) * pow(mpz_int(10), frac.size()) + decimal(frac), pow(mpz_int(10), frac.size()));
  if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) eneg = text[i++] == '-';
    std::string ex;
    // |exponent| ≤ 999: far beyond double (1e308) and any physical value, while 10^999999 would
    // make every later exact operation on a million-digit number (a hang, not an answer)
    if (!digits(ex) || ex.size() > 3) throw bad("an exponent of at most 3 digits");
    const mpz_int scale = pow(mpz_int(10), static_cast<unsigned>(std::stoul(ex)));
    value = eneg ? value / Rational(scale) : value * Rational(scale);
  } else if (i < text.size() && text[i] == '/') {
    ++i;
    std::string den;
    if (!has_whole || has_frac || !digits(den)) throw bad("a fraction is integer/integer");
    if (decimal(den) == 0) throw bad("zero denominator");
    value /= Rational(decimal(den));
  }
  if (i != text.size()) throw bad("");
  return neg ? Rational(-value) : value;
}

inline std::string to_string(const Rational& q) { return q.str(); }

}  // namespace dcad::symbolic
