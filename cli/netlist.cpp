#include "netlist.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace dcad::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

struct Line {
  std::size_t number;
  std::string text;
};

[[noreturn]] void fail(const std::string& file, std::size_t line, const std::string& expected, const std::string& found) {
  throw InputError(file + ":" + std::to_string(line) + ": expected " + expected + ", found " + found);
}

}  // namespace

bool is_netlist_file(const std::string& file) {
  const std::string f = lower(file);
  for (const char* ext : {".cir", ".sp", ".net"})
    if (f.size() > std::string(ext).size() && f.compare(f.size() - std::string(ext).size(), std::string::npos, ext) == 0) return true;
  return false;
}

Rational parse_spice_value(const std::string& text) {
  const std::string t = lower(text);
  std::size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  while (i < t.size() && (std::isdigit(static_cast<unsigned char>(t[i])) || t[i] == '.')) ++i;
  if (i < t.size() && t[i] == 'e' && i + 1 < t.size() &&
      (std::isdigit(static_cast<unsigned char>(t[i + 1])) || ((t[i + 1] == '+' || t[i + 1] == '-') && i + 2 < t.size()))) {
    ++i;
    if (t[i] == '+' || t[i] == '-') ++i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
  }
  Rational v = reference::parse_rational(t.substr(0, i));
  const std::string rest = t.substr(i);
  static const std::vector<std::pair<std::string, int>> suffixes = {{"meg", 6}, {"f", -15}, {"p", -12}, {"n", -9}, {"u", -6},
                                                                    {"m", -3},  {"k", 3},   {"g", 9},   {"t", 12}};
  for (const auto& [s, e] : suffixes)
    if (rest.compare(0, s.size(), s) == 0) {
      const Rational ten(10);
      for (int k = 0; k < std::abs(e); ++k) {
        if (e > 0) v *= ten; else v /= ten;
      }
      return v;
    }
  for (char ch : rest)
    if (!std::isalpha(static_cast<unsigned char>(ch))) throw std::invalid_argument("expected a SPICE value such as 10u or 4.7nF, found \"" + text + "\"");
  return v;  // plain number, possibly with unit letters ("2H")
}

Netlist read_netlist(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot open the file for reading");
  Netlist out;
  out.file = file;
  std::vector<Line> lines;
  std::string raw;
  std::size_t number = 0;
  bool first = true, in_control = false;
  while (std::getline(in, raw)) {
    ++number;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    if (first) {  // the title line
      out.title = raw;
      first = false;
      continue;
    }
    const std::size_t start = raw.find_first_not_of(" \t");
    if (start == std::string::npos) continue;
    std::string text = raw.substr(start);
    const std::string low = lower(text);
    if (in_control) {  // .control … .endc: ngspice's script, ignored as a whole
      if (low.compare(0, 5, ".endc") == 0) in_control = false;
      continue;
    }
    if (low.compare(0, 8, ".control") == 0) {
      in_control = true;
      out.warnings.push_back(file + ":" + std::to_string(number) + ": ignored .control block");
      continue;
    }
    if (text[0] == '*') continue;
    if (text[0] == '+') {
      if (lines.empty()) fail(file, number, "an element line before a continuation '+'", "'+' first");
      lines.back().text += " " + text.substr(1);
      continue;
    }
    lines.push_back({number, text});
  }
  if (first) throw InputError(file + ":1: expected a title line and LC elements, found an empty file");
  std::map<std::string, std::size_t> names, nodes;
  for (const Line& l : lines) {
    std::istringstream ss(l.text);
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    const std::string head = lower(tok[0]);
    if (head[0] == '.') {
      if (head == ".end") break;
      out.warnings.push_back(file + ":" + std::to_string(l.number) + ": ignored " + tok[0]);
      continue;
    }
    const char kind = head[0];
    if (kind == 'r')
      fail(file, l.number, "an L, C or zero-volt V element (an LC circuit has no resistors; CEF §6)", "resistor " + tok[0]);
    if (kind != 'l' && kind != 'c' && kind != 'v')
      fail(file, l.number, "an L, C or zero-volt V element", "element " + tok[0]);
    if (tok.size() < 4) fail(file, l.number, "NAME NODE+ NODE- VALUE", "\"" + l.text + "\"");
    if (names.count(head)) fail(file, l.number, "a new element name", "duplicate " + tok[0] + " (first on line " + std::to_string(names[head]) + ")");
    names[head] = l.number;
    reference::Branch<Rational> b;
    b.name = tok[0];
    const auto node = [&](const std::string& t) -> long {
      const std::string s = lower(t);
      if (s == "0" || s == "gnd") return -1;
      if (!nodes.count(s)) {
        nodes[s] = out.node_names.size();
        out.node_names.push_back(t);
      }
      return static_cast<long>(nodes[s]);
    };
    b.from = node(tok[1]);
    b.to = node(tok[2]);
    std::size_t vi = 3;
    if (kind == 'v' && lower(tok[3]) == "dc" && tok.size() > 4) vi = 4;  // "V1 a b DC 0"
    Rational value;
    try {
      value = parse_spice_value(tok[vi]);
    } catch (const std::invalid_argument& e) {
      fail(file, l.number, "a value (number with optional SPICE suffix)", "\"" + tok[vi] + "\" (" + e.what() + ")");
    }
    std::optional<Rational> ic;
    for (std::size_t k = vi + 1; k < tok.size(); ++k) {
      const std::string t = lower(tok[k]);
      if (t.compare(0, 3, "ic=") == 0) {
        try {
          ic = parse_spice_value(tok[k].substr(3));
        } catch (const std::invalid_argument& e) {
          fail(file, l.number, "IC=value", "\"" + tok[k] + "\"");
        }
      } else {
        fail(file, l.number, "nothing or IC=value after the value", "\"" + tok[k] + "\"");
      }
    }
    if (kind == 'v') {
      if (value != 0) fail(file, l.number, "a zero-volt source (a wire, an empty branch)", "V = " + value.str());
      b.kind = reference::BranchKind::empty;
    } else if (kind == 'l') {
      b.kind = reference::BranchKind::inductor;
      b.value = value;
      if (value < 0) out.warnings.push_back(file + ":" + std::to_string(l.number) + ": negative inductance " + tok[0] + " is not physical (CEF Remark 6.7)");
    } else {
      if (value == 0) fail(file, l.number, "a nonzero capacitance (C = 0 is an open branch, CEF §6)", "C = 0 for " + tok[0]);
      b.kind = reference::BranchKind::capacitor;
      b.value = value;
      if (value < 0) out.warnings.push_back(file + ":" + std::to_string(l.number) + ": negative capacitance " + tok[0] + " is not physical (CEF Remark 6.7)");
    }
    if (kind == 'l' && value == 0) b.kind = reference::BranchKind::empty;  // L = 0: a wire
    out.circuit.branches.push_back(b);
    out.initial.push_back(ic);
  }
  if (out.circuit.branches.empty()) throw InputError(file + ":" + std::to_string(number) + ": expected at least one L, C or V element, found none");
  out.circuit.nodes = out.node_names.size();
  return out;
}

namespace {

Rational pow10(int e) {
  Rational r(1);
  for (int k = 0; k < std::abs(e); ++k) r *= 10;
  return e >= 0 ? r : Rational(1) / r;
}

/// log10 |x| for an exact x ≠ 0 that may lie outside double's range: numerator and denominator
/// shifted into range apart.
double log10_abs(const Rational& x) {
  const auto part = [](auto z) {
    z = boost::multiprecision::abs(z);
    const long k = std::max(0L, static_cast<long>(boost::multiprecision::msb(z)) - 60);
    z >>= k;
    return std::log10(z.template convert_to<double>()) + static_cast<double>(k) * std::log10(2.0);
  };
  return part(boost::multiprecision::numerator(x)) - part(boost::multiprecision::denominator(x));
}

/// Nearest integer to the mean of log10 |value| over the branches of that kind (0 if none).
int mean_exponent(const Netlist& n, reference::BranchKind kind) {
  double sum = 0;
  long count = 0;
  for (const auto& b : n.circuit.branches)
    if (b.kind == kind && b.value != 0) {
      sum += log10_abs(b.value);
      ++count;
    }
  return count ? static_cast<int>(std::lround(sum / count)) : 0;
}

}  // namespace

Netlist dimensionless(const Netlist& n, Units& u) {
  u.a = mean_exponent(n, reference::BranchKind::inductor);
  u.b = mean_exponent(n, reference::BranchKind::capacitor);
  if ((u.a + u.b) % 2 != 0) ++u.b;
  Netlist out = n;
  const Rational l0 = pow10(u.a), c0 = pow10(u.b);
  for (auto& b : out.circuit.branches) {
    if (b.kind == reference::BranchKind::inductor) b.value /= l0;
    if (b.kind == reference::BranchKind::capacitor) b.value /= c0;
  }
  return out;
}

CaseFile netlist_case(const Netlist& n, bool dense) {
  CaseFile c;
  c.file = n.file;
  c.name = n.title;
  c.description = "LC netlist " + n.file;
  if (!dense) {
    c.n = 3 * n.circuit.branches.size();
    for (const char* s : {"q_", "v_", "p_"})
      for (const auto& b : n.circuit.branches) c.variables.push_back(s + b.name);
    return c;
  }
  c.has_pontryagin = true;
  const reference::PontryaginInput<Rational> p = reference::circuit_lagrangian(n.circuit);
  c.pontryagin = PontryaginInput{p.n, p.k, p.vv, p.qv, p.qq, p.q, p.v};
  c.n = 3 * p.n;
  for (const char* s : {"q_", "v_", "p_"})
    for (const auto& b : n.circuit.branches) c.variables.push_back(s + b.name);
  c.energy.hessian = QMatrix(c.n, c.n);
  c.energy.gradient.assign(c.n, 0);
  return c;
}

}  // namespace dcad::io
