#include "dcad/io/netlist.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace dcad::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

}  // namespace

bool is_netlist_file(const std::string& file) {
  const std::string f = lower(file);
  for (const std::string ext : {".cir", ".sp", ".net", ".spice", ".ckt"})
    if (f.size() > ext.size() && f.compare(f.size() - ext.size(), std::string::npos, ext) == 0) return true;
  return false;
}

namespace {
/// A value for a message: %g of its double.
std::string shown(const Rational& v) {
  std::ostringstream o;
  o << v.convert_to<double>();
  return o.str();
}
}  // namespace

Rational parse_spice_value(const std::string& text, std::string* ignored) {
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
  std::string rest = t.substr(i);
  for (char ch : rest)
    if (!std::isalpha(static_cast<unsigned char>(ch))) throw std::invalid_argument("expected a SPICE value such as 10u or 4.7nF, found \"" + text + "\"");
  // ngspice's scale factors (mil before m); `a` and `x` differ between SPICEs: refused, never guessed
  if (!rest.empty() && (rest[0] == 'a' || rest[0] == 'x'))
    throw std::invalid_argument(std::string("'") + rest[0] + "' is a scale factor in some SPICEs (" +
                                (rest[0] == 'a' ? "atto, 1e-18, in HSPICE and LTspice" : "mega, 1e6, in HSPICE") +
                                ") and none in ngspice (which reads \"" + text + "\" as " + t.substr(0, i) +
                                "): write the value without it, e.g. " + t.substr(0, i) + (rest[0] == 'a' ? "e-18" : "e6") + " or " + t.substr(0, i));
  static const std::vector<std::pair<std::string, Rational>> scales = {
      {"meg", Rational(1000000)},     {"mil", Rational(254, 10000000)}, {"f", Rational(1, 1000000000000000LL)},
      {"p", Rational(1, 1000000000000LL)}, {"n", Rational(1, 1000000000)},   {"u", Rational(1, 1000000)},
      {"m", Rational(1, 1000)},       {"k", Rational(1000)},            {"g", Rational(1000000000)},
      {"t", Rational(1000000000000LL)}};
  for (const auto& [s, factor] : scales)
    if (rest.compare(0, s.size(), s) == 0) {
      v *= factor;
      rest = rest.substr(s.size());
      break;
    }
  // what follows is a unit, which SPICE ignores; other letters are ignored too, and said so
  static const std::vector<std::string> units = {"",     "f",   "farad", "farads", "h",   "henry", "henries", "ohm", "ohms",
                                                 "v",    "volt", "volts", "a",     "amp", "amps",  "s",       "sec", "hz"};
  if (std::find(units.begin(), units.end(), rest) == units.end() && ignored) *ignored = rest;
  return v;
}

namespace {

/// A logical line of the deck (continuations joined, comments removed) and where it came from.
struct Line {
  std::string file;
  std::size_t number;
  std::string text;
  std::string where() const { return file + ":" + std::to_string(number); }
};

[[noreturn]] void fail(const Line& l, const std::string& expected, const std::string& found) {
  throw InputError(l.where() + ": expected " + expected + ", found " + found);
}

/// The words of a line, `NAME = VALUE` glued into `NAME=VALUE` (ngspice reads `IC = 0.5`, `IC= 0.5`
/// and `.ic V(a) = 2` as their unspaced forms).
std::vector<std::string> tokens(const std::string& text) {
  std::istringstream ss(text);
  std::vector<std::string> tok;
  for (std::string t; ss >> t;) {
    if (!tok.empty() && (t.front() == '=' || tok.back().back() == '=')) {
      tok.back() += t;
      continue;
    }
    tok.push_back(t);
  }
  return tok;
}

/// Text without an inline comment: `;` anywhere, `$` at the start or after white space (ngspice).
std::string strip_inline_comment(const std::string& text) {
  std::size_t cut = text.find(';');
  for (std::size_t i = 0; i < text.size() && i < cut; ++i)
    if (text[i] == '$' && (i == 0 || std::isspace(static_cast<unsigned char>(text[i - 1])))) cut = i;
  return cut == std::string::npos ? text : text.substr(0, cut);
}

std::string unquote(const std::string& s) {
  return s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front() ? s.substr(1, s.size() - 2) : s;
}

std::string beside(const std::string& deck, const std::string& name) {  // relative to the including deck
  if (!name.empty() && name[0] == '/') return name;
  const std::size_t slash = deck.rfind('/');
  return slash == std::string::npos ? name : deck.substr(0, slash + 1) + name;
}

/// The deck's logical lines: title dropped (top file only), comments and .control blocks removed,
/// `+` continuations joined, .include and .lib FILE SECTION read in place.  Stops at .end.
class Reader {
 public:
  std::string title;
  std::vector<Line> lines;
  std::vector<std::string> warnings;

  /// `text`: the top deck's contents (a deck given as a string, named `file` in messages; its
  /// includes are read relative to `directory`), else the file is opened.
  void read(const std::string& file, bool top, const std::string& section, int depth, const Line* from,
            std::istream* text = nullptr, const std::string& directory = "") {
    if (depth > 16) fail(*from, "includes nested at most 16 deep", "deeper (an include cycle?)");
    std::error_code ec;
    if (from && !std::filesystem::is_regular_file(file, ec))  // not a device or a pipe: never a hang
      fail(*from, "a regular file to include", "\"" + file + "\" (" + (std::filesystem::exists(file, ec) ? "not a regular file" : "no such file") + ")");
    std::ifstream opened;
    if (!text) {
      opened.open(file);
      if (!opened) {
        if (from) fail(*from, "a readable file to include", "\"" + file + "\" cannot be opened");
        throw InputError(file + ": cannot open the file for reading");
      }
    }
    std::istream& in = text ? *text : opened;
    // includes beside this deck (a deck given as text: in `directory`)
    const std::string beside_this = text ? (directory.empty() ? std::string("./") : directory + "/") + "deck" : file;
    std::string raw;
    std::size_t number = 0;
    bool first = top, in_control = false, in_section = section.empty();
    for (; std::getline(in, raw);) {
      ++number;
      if (!raw.empty() && raw.back() == '\r') raw.pop_back();
      if (first) {  // the title line
        title = raw;
        first = false;
        continue;
      }
      const std::size_t start = raw.find_first_not_of(" \t");
      if (start == std::string::npos || raw[start] == '*') continue;
      std::string text = strip_inline_comment(raw.substr(start));
      const std::vector<std::string> tok = tokens(text);
      if (tok.empty()) continue;  // white space of any kind (\f, \v too), or only a comment
      text = text.substr(text.find_first_not_of(" \t\n\v\f\r"));  // tok is not empty: the line has a word
      const Line here{file, number, text};
      const std::string head = lower(tok[0]);
      if (!in_section) {  // .lib FILE SECTION: only `.lib SECTION` … `.endl`
        if (head == ".lib" && tok.size() == 2 && lower(tok[1]) == lower(section)) in_section = true;
        continue;
      }
      if (!section.empty() && head == ".endl") return;
      if (in_control) {  // .control … .endc: ngspice's script, ignored as a whole
        if (head == ".endc") in_control = false;
        continue;
      }
      if (head == ".control") {
        in_control = true;
        warnings.push_back(here.where() + ": ignored .control block");
        continue;
      }
      if (text[0] == '+') {
        if (lines.empty() || lines.back().file != file) fail(here, "an element line before a continuation '+'", "'+' first");
        lines.back().text += " " + text.substr(1);
        continue;
      }
      if (head == ".end") {
        ended = true;
        return;
      }
      if (head == ".include" || head == ".inc") {
        if (tok.size() != 2) fail(here, ".include FILE", "\"" + text + "\"");
        read(beside(beside_this, unquote(tok[1])), false, "", depth + 1, &here);
        if (ended) return;
        continue;
      }
      if (head == ".lib" && tok.size() == 3) {
        read(beside(beside_this, unquote(tok[1])), false, tok[2], depth + 1, &here);
        continue;
      }
      if (head == ".lib") fail(here, ".lib FILE SECTION (a library section is read where it is named)", "\"" + text + "\"");
      lines.push_back(here);
    }
    if (!section.empty() && !in_section && from) fail(*from, "a section .lib " + section + " in " + file, "none");
  }
  bool ended = false;
};

/// Exact arithmetic on .param expressions: numbers (SPICE suffixes), parameters, + - * / ( ),
/// unary signs, ^ or ** with an integer exponent.
class Expression {
 public:
  Expression(const std::string& text, const std::map<std::string, Rational>& params) : s_(lower(text)), params_(params) {}
  Rational value() {
    const Rational v = sum();
    skip();
    if (i_ != s_.size()) throw std::invalid_argument("unexpected \"" + s_.substr(i_) + "\"");
    return v;
  }

 private:
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(const std::string& op) {
    skip();
    if (s_.compare(i_, op.size(), op) != 0) return false;
    i_ += op.size();
    return true;
  }
  Rational sum() {
    Rational v = product();
    for (;;) {
      if (eat("+")) v += product();
      else if (eat("-")) v -= product();
      else return v;
    }
  }
  Rational product() {
    Rational v = power();
    for (;;) {
      if (s_.compare(i_, 2, "**") != 0 && eat("*")) {
        v *= power();
      } else if (eat("/")) {
        const Rational d = power();
        if (d == 0) throw std::invalid_argument("division by zero");
        v /= d;
      } else {
        return v;
      }
    }
  }
  Rational power() {
    const Rational base = unary();
    if (!eat("^") && !eat("**")) return base;
    const Rational e = unary();
    if (boost::multiprecision::denominator(e) != 1 || boost::multiprecision::abs(e) > 64)
      throw std::invalid_argument("expected an integer exponent of at most 64, found " + e.str());
    Rational r(1);
    for (long k = 0; k < boost::multiprecision::abs(e); ++k) {
      r *= base;
      if (boost::multiprecision::msb(boost::multiprecision::abs(boost::multiprecision::numerator(r)) + 1) > 20000 ||
          boost::multiprecision::msb(boost::multiprecision::denominator(r)) > 20000)
        throw std::invalid_argument("a power beyond 20000 bits");
    }
    if (e < 0) {
      if (r == 0) throw std::invalid_argument("division by zero");
      r = Rational(1) / r;
    }
    return r;
  }
  Rational unary() {
    if (eat("-")) return -unary();
    if (eat("+")) return unary();
    if (eat("(")) {
      const Rational v = sum();
      if (!eat(")")) throw std::invalid_argument("expected ')'");
      return v;
    }
    skip();
    const std::size_t start = i_;
    if (i_ < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) {
      while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) ++i_;
      const std::string name = s_.substr(start, i_ - start);
      const auto it = params_.find(name);
      if (it == params_.end()) throw std::invalid_argument("unknown parameter \"" + name + "\"");
      return it->second;
    }
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.' ||
                              ((s_[i_] == '+' || s_[i_] == '-') && i_ > start && s_[i_ - 1] == 'e' &&
                               std::isdigit(static_cast<unsigned char>(s_[start])))))
      ++i_;
    if (i_ == start) throw std::invalid_argument("expected a number, a parameter or '('");
    return parse_spice_value(s_.substr(start, i_ - start));
  }
  std::string s_;
  std::size_t i_ = 0;
  const std::map<std::string, Rational>& params_;
};

/// name=value pairs of a .param line or a subcircuit's params: list ("a=1 b={2*a}", spaces around
/// '=' allowed), evaluated in order into `into`.
void read_params(const std::vector<std::string>& tok, std::size_t from, const Line& l, std::map<std::string, Rational>& into) {
  std::string joined;
  for (std::size_t k = from; k < tok.size(); ++k) joined += tok[k] + " ";
  std::size_t i = 0;
  while (true) {
    while (i < joined.size() && std::isspace(static_cast<unsigned char>(joined[i]))) ++i;
    if (i >= joined.size()) return;
    const std::size_t eq = joined.find('=', i);
    if (eq == std::string::npos) fail(l, "NAME=VALUE", "\"" + joined.substr(i) + "\"");
    std::string name = lower(joined.substr(i, eq - i));
    name.erase(name.find_last_not_of(" \t") + 1);
    std::size_t j = joined.find_first_not_of(" \t", eq + 1);
    if (name.empty() || j == std::string::npos) fail(l, "NAME=VALUE", "\"" + joined.substr(i) + "\"");
    std::size_t end;
    if (joined[j] == '{') {
      end = joined.find('}', j);
      if (end == std::string::npos) fail(l, "a closing '}'", "\"" + joined.substr(j) + "\"");
      ++end;
    } else {
      end = joined.find_first_of(" \t", j);
    }
    std::string expr = joined.substr(j, end - j);
    if (expr.front() == '{') expr = expr.substr(1, expr.size() - 2);
    try {
      into[name] = Expression(expr, into).value();
    } catch (const std::invalid_argument& e) {
      fail(l, "a parameter value (exact: numbers, parameters, + - * / ^, parentheses)", "\"" + expr + "\" (" + e.what() + ")");
    }
    i = end;
  }
}

struct Subcircuit {
  std::string name;
  std::vector<std::string> ports;
  std::map<std::string, Rational> defaults;
  std::vector<Line> body;
  Line where;
};

/// Flattens the deck: .param, .subckt … .ends, X instances (hierarchical names as ngspice makes them:
/// element L1 of instance X1 is l.x1.l1, internal node n of X1 is x1.n), .ic v(node)=value.
class Flattener {
 public:
  Netlist& out;
  std::map<std::string, std::size_t> names, nodes;
  std::map<std::string, Subcircuit> subckts;
  std::map<std::string, Rational> node_ic;
  struct Coupling {
    Line line;
    std::string name, a, b;
    Rational k;
  };
  std::vector<Coupling> couplings;  ///< K elements, resolved once every inductor is known

  explicit Flattener(Netlist& n) : out(n) {}

  void run(const std::vector<Line>& lines) {
    std::map<std::string, Rational> params;
    std::vector<Line> top;
    for (std::size_t i = 0; i < lines.size(); ++i) {  // definitions first: ngspice allows use before definition
      const std::vector<std::string> tok = tokens(lines[i].text);
      const std::string head = lower(tok[0]);
      if (head == ".subckt") {
        i = define(lines, i);
      } else if (head == ".ends") {
        fail(lines[i], ".ends after a .subckt", ".ends without .subckt");
      } else if (head == ".param") {
        read_params(tok, 1, lines[i], params);
      } else {
        top.push_back(lines[i]);
      }
    }
    expand(top, "", {}, params, 0);
  }

 private:
  std::size_t define(const std::vector<Line>& lines, std::size_t i) {
    const Line& l = lines[i];
    const std::vector<std::string> tok = tokens(l.text);
    if (tok.size() < 2) fail(l, ".subckt NAME PORT…", "\"" + l.text + "\"");
    Subcircuit s{lower(tok[1]), {}, {}, {}, l};
    std::size_t k = 2;
    for (; k < tok.size() && lower(tok[k]) != "params:" && tok[k].find('=') == std::string::npos; ++k) s.ports.push_back(lower(tok[k]));
    if (k < tok.size()) read_params(tok, lower(tok[k]) == "params:" ? k + 1 : k, l, s.defaults);
    if (subckts.count(s.name)) fail(l, "a new subcircuit name", "a second .subckt " + tok[1]);
    for (++i; i < lines.size(); ++i) {
      const std::string head = lower(tokens(lines[i].text)[0]);
      if (head == ".ends") {
        subckts[s.name] = s;
        return i;
      }
      if (head == ".subckt") fail(lines[i], ".ends of " + tok[1] + " (nested .subckt definitions are not supported)", ".subckt");
      s.body.push_back(lines[i]);
    }
    fail(l, ".ends for .subckt " + tok[1], "the end of the deck");
  }

  /// node name in an instance: ground is global, ports map to the caller's nodes, others get the prefix
  std::string node_in(const std::string& n, const std::string& prefix, const std::map<std::string, std::string>& ports) const {
    const std::string s = lower(n);
    if (s == "0" || s == "gnd") return "0";
    const auto p = ports.find(s);
    if (p != ports.end()) return p->second;
    return prefix + s;
  }

  void expand(const std::vector<Line>& body, const std::string& prefix, const std::map<std::string, std::string>& ports,
              const std::map<std::string, Rational>& params, int depth) {
    for (const Line& l : body) {
      std::vector<std::string> tok = tokens(l.text);
      const std::string head = lower(tok[0]);
      if (head[0] == '.') {
        dot_card(l, tok, prefix, ports, params);
        continue;
      }
      if (head[0] == 'x') {
        instance(l, tok, prefix, ports, params, depth);
        continue;
      }
      element(l, tok, prefix, ports, params);
    }
  }

  void dot_card(const Line& l, const std::vector<std::string>& tok, const std::string& prefix,
                const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params) {
    const std::string head = lower(tok[0]);
    static const std::vector<std::string> analysis = {".tran", ".ac", ".dc", ".op", ".options", ".option", ".opt", ".print",
                                                      ".plot", ".probe", ".save", ".meas", ".measure", ".four", ".width",
                                                      ".title", ".temp", ".nodeset", ".noise", ".disto", ".pz", ".sens", ".tf"};
    if (head == ".ic") {
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string t = lower(tok[k]);
        const std::size_t eq = t.find('=');
        if (t.compare(0, 2, "v(") != 0 || eq == std::string::npos || t[eq - 1] != ')')
          fail(l, ".ic V(NODE)=VALUE …", "\"" + tok[k] + "\"");
        std::string value = t.substr(eq + 1);
        if (!value.empty() && value.front() == '{') value = value.substr(1, value.size() - 2);
        try {
          node_ic[node_in(t.substr(2, eq - 3), prefix, ports)] = Expression(value, params).value();
        } catch (const std::invalid_argument& e) {
          fail(l, "V(NODE)=VALUE", "\"" + tok[k] + "\" (" + e.what() + ")");
        }
      }
      return;
    }
    if (head == ".tran") {  // read for its uic (the initial state of simulate and check), the rest ignored
      bool uic = false;
      for (std::size_t k = 1; k < tok.size(); ++k) uic = uic || lower(tok[k]) == "uic";
      out.tran = uic ? Netlist::Transient::uic : Netlist::Transient::op;
      out.tran_where = l.where();
      std::vector<std::string> times;  // .tran TSTEP TSTOP [TSTART [TMAX]] [UIC]
      for (std::size_t k = 1; k < tok.size(); ++k)
        if (lower(tok[k]) != "uic") times.push_back(tok[k]);
      try {
        if (times.size() >= 2) {
          out.tran_step = parse_spice_value(times[0]);
          out.tran_stop = parse_spice_value(times[1]);
        }
      } catch (const std::invalid_argument&) {  // a parameter expression: not needed by the circuit
      }
    }
    if (std::find(analysis.begin(), analysis.end(), head) != analysis.end()) {
      out.warnings.push_back(l.where() + ": ignored " + tok[0] + " (analysis or output card: the circuit is unchanged" +
                             (head == ".tran" ? "; simulate reads its uic for the initial state)" : ")"));
      return;
    }
    fail(l, "an R, L, C, V, I, K or X element, or a supported dot-card (.param, .subckt, .include, .lib, .ic, analysis cards)",
         "unsupported " + tok[0] + " (it would change the circuit)");
  }

  void instance(const Line& l, const std::vector<std::string>& tok, const std::string& prefix,
                const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params, int depth) {
    if (depth >= 32) fail(l, "subcircuits nested at most 32 deep", "deeper (a recursive .subckt?)");
    std::size_t k = tok.size();
    while (k > 1 && tok[k - 1].find('=') != std::string::npos) --k;  // trailing name=value overrides
    if (k > 1 && lower(tok[k - 1]) == "params:") --k;
    if (k < 2) fail(l, "XNAME NODE… SUBCKT", "\"" + l.text + "\"");
    const std::string sub = lower(tok[k - 1]);
    const auto it = subckts.find(sub);
    if (it == subckts.end()) fail(l, "a subcircuit defined by .subckt", "unknown subcircuit \"" + tok[k - 1] + "\" in " + tok[0]);
    const Subcircuit& s = it->second;
    if (k - 2 != s.ports.size())
      fail(l, std::to_string(s.ports.size()) + " nodes for " + tok[k - 1] + " (" + s.where.where() + ")",
           std::to_string(k - 2) + " in " + tok[0]);
    std::map<std::string, std::string> inner;
    for (std::size_t p = 0; p < s.ports.size(); ++p) inner[s.ports[p]] = node_in(tok[1 + p], prefix, ports);
    std::map<std::string, Rational> local = params;  // global .params, then the defaults, then the overrides
    for (const auto& [name, value] : s.defaults) local[name] = value;
    std::size_t first_override = k;
    if (first_override < tok.size() && lower(tok[first_override]) == "params:") ++first_override;
    read_params(tok, first_override, l, local);
    expand(s.body, prefix + lower(tok[0]) + ".", inner, local, depth + 1);
  }

  void element(const Line& l, std::vector<std::string> tok, const std::string& prefix,
               const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params) {
    const std::string head = lower(tok[0]);
    const char kind = head[0];
    if (std::string("lcvrik").find(kind) == std::string::npos)
      fail(l, "an L, C, R, V, I, K or X element", "element " + tok[0] + " (not supported)");
    if (tok.size() < 4) fail(l, "NAME NODE+ NODE- VALUE", "\"" + l.text + "\"");
    // ngspice's hierarchical name: kind letter, instance path, element name (l.x1.l1)
    const auto hier = [&](const std::string& t) { return prefix.empty() ? t : std::string(1, t[0]) + "." + prefix + lower(t); };
    const std::string name = hier(tok[0]);
    const std::string key = lower(name);
    if (names.count(key)) fail(l, "a new element name", "duplicate " + name + " (first at " + out_lines[names[key]] + ")");
    const auto number = [&](const std::string& text, const std::string& what) {
      try {
        if (!text.empty() && text.front() == '{') {
          if (text.back() != '}') throw std::invalid_argument("no closing '}'");
          return Expression(text.substr(1, text.size() - 2), params).value();
        }
        std::string ignored;
        const Rational v = parse_spice_value(text, &ignored);
        if (!ignored.empty())
          out.warnings.push_back(l.where() + ": " + name + ": \"" + text + "\" read as " + shown(v) + " (the letters \"" + ignored +
                                 "\" are neither a scale factor nor a unit; ngspice ignores them too)");
        return v;
      } catch (const std::invalid_argument& e) {
        fail(l, what, "\"" + text + "\" (" + e.what() + ")");
      }
    };
    if (kind == 'k') {
      if (tok.size() != 4) fail(l, "KNAME LX LY COUPLING", "\"" + l.text + "\"");
      const Rational k = number(tok[3], "a coupling coefficient");
      if (k < -1 || k > 1) fail(l, "a coupling coefficient with |k| <= 1", tok[3]);
      couplings.push_back({l, name, lower(hier(tok[1])), lower(hier(tok[2])), k});
      names[key] = out_lines.size();
      out_lines.push_back(l.where());
      return;
    }
    names[key] = out_lines.size();
    out_lines.push_back(l.where());
    reference::Branch<Rational> b;
    b.name = name;
    const auto node = [&](const std::string& t) -> long {
      const std::string s = node_in(t, prefix, ports);
      if (s == "0") return -1;
      if (!nodes.count(s)) {
        nodes[s] = out.node_names.size();
        out.node_names.push_back(s);
      }
      return static_cast<long>(nodes[s]);
    };
    b.from = node(tok[1]);
    b.to = node(tok[2]);
    reference::RlcBranch<Rational> rb{name, reference::RlcKind::wire, b.from, b.to, Rational(0), 0};
    if (kind == 'v' || kind == 'i') {
      std::string spec;
      for (std::size_t k = 3; k < tok.size(); ++k) spec += (k > 3 ? " " : "") + tok[k];
      Waveform w;
      try {
        w = parse_waveform(spec, [&](const std::string& t) { return number(t, "a source value"); });
      } catch (const std::invalid_argument& e) {
        throw InputError(l.where() + ": " + name + ": " + e.what());  // the parser's own "expected …, found …"
      }
      w.element = name;
      b.kind = reference::BranchKind::empty;
      if (kind == 'v' && w.kind == Waveform::Kind::dc && w.p[0] == 0) {
        rb.kind = reference::RlcKind::wire;  // a zero-volt source is a wire (an ammeter)
      } else {
        rb.kind = kind == 'v' ? reference::RlcKind::voltage : reference::RlcKind::current;
        rb.source = out.waveforms.size();
        out.waveforms.push_back(w);
        out.forced = true;
      }
      out.circuit.branches.push_back(b);
      out.rlc.branches.push_back(rb);
      out.initial.push_back(std::nullopt);
      out.where.push_back(l.where());
      return;
    }
    const Rational value = number(tok[3], "a value (number with optional SPICE suffix, or {expression})");
    std::optional<Rational> ic;
    for (std::size_t k = 4; k < tok.size(); ++k) {
      const std::string t = lower(tok[k]);
      if (t.compare(0, 3, "ic=") == 0 && kind != 'r') ic = number(tok[k].substr(3), "IC=value");
      else fail(l, kind == 'r' ? "nothing after the resistance" : "nothing or IC=value after the value", "\"" + tok[k] + "\"");
    }
    rb.value = value;
    if (kind == 'r') {
      if (value < 0) out.warnings.push_back(l.where() + ": negative resistance " + name + " is not physical (it supplies energy)");
      if (value == 0)  // a wire has another index class than a resistor: neither is guessed
        fail(l, "a nonzero resistance (ngspice replaces R = 0 by 1 mOhm, a resistor; a wire is a 0-volt V source)",
             "R = 0 for " + name);
      rb.kind = reference::RlcKind::resistor;
      out.forced = true;
      b.kind = reference::BranchKind::empty;
    } else if (kind == 'l') {
      b.kind = reference::BranchKind::inductor;
      b.value = value;
      rb.kind = reference::RlcKind::inductor;
      if (value < 0) out.warnings.push_back(l.where() + ": negative inductance " + name + " is not physical (CEF Remark 6.7)");
    } else {
      if (value == 0) fail(l, "a nonzero capacitance (C = 0 is an open branch, CEF §6)", "C = 0 for " + name);
      b.kind = reference::BranchKind::capacitor;
      b.value = value;
      rb.kind = reference::RlcKind::capacitor;
      if (value < 0) out.warnings.push_back(l.where() + ": negative capacitance " + name + " is not physical (CEF Remark 6.7)");
    }
    if (kind == 'l' && value == 0) {
      b.kind = reference::BranchKind::empty;  // L = 0: a wire
      rb.kind = reference::RlcKind::wire;
    }
    out.circuit.branches.push_back(b);
    out.rlc.branches.push_back(rb);
    out.initial.push_back(ic);
    out.where.push_back(l.where());
  }

 public:
  std::vector<std::string> out_lines;  ///< file:line of each branch
};

}  // namespace

/// K elements: M = k √(L_a L_b), exact when k² L_a L_b is the square of a rational, otherwise
/// truncated to 80 decimal places (with a warning).
static void resolve_couplings(Netlist& out, const Flattener& f) {
  for (const auto& c : f.couplings) {
    const auto find = [&](const std::string& n) -> std::size_t {
      for (std::size_t i = 0; i < out.rlc.branches.size(); ++i)
        if (lower(out.rlc.branches[i].name) == n) {
          if (out.rlc.branches[i].kind != reference::RlcKind::inductor)
            throw InputError(c.line.where() + ": expected an inductor for " + c.name + ", found " + out.rlc.branches[i].name);
          return i;
        }
      throw InputError(c.line.where() + ": expected an inductor of the circuit for " + c.name + ", found \"" + n + "\"");
    };
    const std::size_t a = find(c.a), b = find(c.b);
    if (a == b) throw InputError(c.line.where() + ": expected two different inductors for " + c.name + ", found one twice");
    const Rational sq = c.k * c.k * out.rlc.branches[a].value * out.rlc.branches[b].value;
    using boost::multiprecision::mpz_int;
    const mpz_int num = boost::multiprecision::numerator(sq), den = boost::multiprecision::denominator(sq);
    const mpz_int rn = boost::multiprecision::sqrt(num), rd = boost::multiprecision::sqrt(den);
    Rational m;
    bool rounded = false;
    if (rn * rn == num && rd * rd == den) {
      m = Rational(rn, rd);
    } else {
      const mpz_int scale = boost::multiprecision::pow(mpz_int(10), 80);
      m = Rational(boost::multiprecision::sqrt(mpz_int(num * scale * scale / den)), scale);  // 80 digits after the point, truncated
      out.warnings.push_back(c.line.where() + ": " + c.name + ": M = k*sqrt(Lx*Ly) is irrational; used it to 80 decimal places");
      rounded = true;
    }
    if (c.k < 0) m = -m;
    bool dup = false;
    for (auto& mu : out.rlc.mutuals)
      if ((mu.a == a && mu.b == b) || (mu.a == b && mu.b == a)) dup = true;
    if (dup) throw InputError(c.line.where() + ": expected one coupling per pair of inductors, found a second one (" + c.name + ")");
    out.rlc.mutuals.push_back({a, b, m, c.k, rounded});
    out.forced = true;
  }
}

namespace {

Netlist flatten(const std::string& file, Reader& reader);

}  // namespace

Netlist read_netlist(const std::string& file) {
  Reader reader;
  reader.read(file, true, "", 0, nullptr);
  if (reader.title.empty() && reader.lines.empty()) {
    std::ifstream probe(file);
    if (probe.peek() == std::ifstream::traits_type::eof())
      throw InputError(file + ":1: expected a title line and LC elements, found an empty file");
  }
  return flatten(file, reader);
}

Netlist read_netlist_text(const std::string& text, const std::string& name, const std::string& directory) {
  if (text.empty()) throw InputError(name + ":1: expected a title line and LC elements, found an empty deck");
  std::istringstream in(text);
  Reader reader;
  reader.read(name, true, "", 0, nullptr, &in, directory);
  return flatten(name, reader);
}

namespace {

Netlist flatten(const std::string& file, Reader& reader) {
  Netlist out;
  out.file = file;
  out.title = reader.title;
  out.warnings = reader.warnings;
  Flattener f(out);
  f.run(reader.lines);
  if (out.circuit.branches.empty())
    throw InputError(file + ":" + (reader.lines.empty() ? std::string("1") : reader.lines.back().where().substr(file.size() + 1)) +
                     ": expected at least one L, C or V element, found none");
  out.circuit.nodes = out.node_names.size();
  out.rlc.nodes = out.circuit.nodes;
  out.rlc.sources = out.waveforms.size();
  resolve_couplings(out, f);
  // .ic v(node)=…: a capacitor without IC= starts at the difference of its nodes' voltages
  for (std::size_t i = 0; i < out.circuit.branches.size(); ++i) {
    const auto& b = out.circuit.branches[i];
    if (b.kind != reference::BranchKind::capacitor || out.initial[i]) continue;
    const auto volt = [&](long n) -> std::optional<Rational> {
      if (n < 0) return Rational(0);
      const auto it = f.node_ic.find(out.node_names[n]);
      return it == f.node_ic.end() ? std::nullopt : std::optional<Rational>(it->second);
    };
    const auto a = volt(b.from), c = volt(b.to);
    if (a && c && !f.node_ic.empty()) out.initial[i] = *a - *c;
  }
  for (const auto& [node, v] : f.node_ic) {
    const auto at = std::find(out.node_names.begin(), out.node_names.end(), node);
    if (node != "0" && at == out.node_names.end()) throw InputError(file + ": .ic: expected a node of the circuit, found v(" + node + ")");
    if (node != "0") out.node_ic.emplace_back(static_cast<long>(at - out.node_names.begin()), v);
  }
  return out;
}

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

/// Mean of log10 |value| over the branches of that kind (0 if none).
double mean_exponent(const Netlist& n, reference::BranchKind kind) {
  double sum = 0;
  long count = 0;
  for (const auto& b : n.circuit.branches)
    if (b.kind == kind && b.value != 0) {
      sum += log10_abs(b.value);
      ++count;
    }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace

Units units_of(const Netlist& n) {
  return Units::nearest(mean_exponent(n, reference::BranchKind::inductor), mean_exponent(n, reference::BranchKind::capacitor));
}

Netlist dimensionless(const Netlist& n, const Units& u) {
  Netlist out = n;
  const Rational l0 = pow10(u.a), c0 = pow10(u.b), r0 = pow10(u.r());
  for (auto& b : out.circuit.branches) {
    if (b.kind == reference::BranchKind::inductor) b.value /= l0;
    if (b.kind == reference::BranchKind::capacitor) b.value /= c0;
  }
  for (auto& b : out.rlc.branches) {
    if (b.kind == reference::RlcKind::inductor) b.value /= l0;
    if (b.kind == reference::RlcKind::capacitor) b.value /= c0;
    if (b.kind == reference::RlcKind::resistor) b.value /= r0;
  }
  for (auto& mu : out.rlc.mutuals) mu.m /= l0;
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
