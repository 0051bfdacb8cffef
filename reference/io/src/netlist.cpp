#include "dcad/io/netlist.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <optional>
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

std::optional<Dialect> dialect_named(const std::string& name) {
  static const std::vector<std::pair<std::string, Dialect>> names = {
      {"strict", Dialect::strict}, {"ngspice", Dialect::ngspice}, {"ngspice39", Dialect::ngspice39},
      {"xyce", Dialect::xyce},     {"hspice", Dialect::hspice},   {"gnucap", Dialect::gnucap}};
  for (const auto& [n, d] : names)
    if (n == lower(name)) return d;
  return std::nullopt;
}

Rational parse_spice_value(const std::string& text, std::string* ignored, Dialect dialect) {
  const std::string t = lower(text);
  std::size_t i = 0;
  if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
  while (i < t.size() && (std::isdigit(static_cast<unsigned char>(t[i])) || t[i] == '.')) ++i;
  if (i < t.size() && t[i] == 'e' && i + 1 < t.size() &&
      (std::isdigit(static_cast<unsigned char>(t[i + 1])) ||
       ((t[i + 1] == '+' || t[i + 1] == '-') && i + 2 < t.size()))) {
    ++i;
    if (t[i] == '+' || t[i] == '-') ++i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
  }
  Rational v = reference::parse_rational(t.substr(0, i));
  std::string rest = t.substr(i);
  for (char ch : rest)
    if (!std::isalpha(static_cast<unsigned char>(ch)))
      throw std::invalid_argument("expected a SPICE value such as 10u or 4.7nF, found \"" + text + "\"");
  // ngspice's scale factors (mil before m); `a` and `x` differ between SPICEs (Dialect): read as the deck's
  // dialect reads them, refused in the strict one, never guessed.  Where `a` is atto it is atto before any
  // letters ("1amp" is 1e-18 and "mp" ignored, as gnucap's ap_convert.cc reads it); elsewhere it is a unit.
  const bool atto = dialect == Dialect::ngspice || dialect == Dialect::hspice || dialect == Dialect::gnucap;
  const bool mega = dialect == Dialect::xyce || dialect == Dialect::hspice;
  if (dialect != Dialect::strict && !rest.empty() && rest[0] == 'a') {
    if (atto) v /= Rational(1000000000000000000ULL);
    rest = rest.substr(atto ? 1 : 0);
  } else if (dialect != Dialect::strict && !rest.empty() && rest[0] == 'x') {
    if (mega) v *= 1000000;
    rest = rest.substr(1);
  } else if (!rest.empty() && (rest[0] == 'a' || rest[0] == 'x'))
    throw std::invalid_argument(
        std::string("'") + rest[0] + "' is " +
        (rest[0] == 'a'
             ? "atto (1e-18) in ngspice 40 and later, HSPICE and LTspice, and no scale factor in ngspice 39 and Xyce"
             : "mega (1e6) in HSPICE and no scale factor in ngspice") +
        " (which read \"" + text + "\" as " + t.substr(0, i) + "): write the value without it, e.g. " + t.substr(0, i) +
        (rest[0] == 'a' ? "e-18" : "e6") + " or " + t.substr(0, i) +
        ", or give the deck's dialect (--dialect ngspice, ngspice39, xyce, hspice or gnucap)");
  static const std::vector<std::pair<std::string, Rational>> scales = {{"meg", Rational(1000000)},
                                                                       {"mil", Rational(254, 10000000)},
                                                                       {"f", Rational(1, 1000000000000000LL)},
                                                                       {"p", Rational(1, 1000000000000LL)},
                                                                       {"n", Rational(1, 1000000000)},
                                                                       {"u", Rational(1, 1000000)},
                                                                       {"m", Rational(1, 1000)},
                                                                       {"k", Rational(1000)},
                                                                       {"g", Rational(1000000000)},
                                                                       {"t", Rational(1000000000000LL)}};
  for (const auto& [s, factor] : scales)
    if (rest.compare(0, s.size(), s) == 0) {
      v *= factor;
      rest = rest.substr(s.size());
      break;
    }
  // what follows is a unit, which SPICE ignores; other letters are ignored too, and said so
  static const std::vector<std::string> units = {"",        "f",   "farad", "farads", "h",    "henry",
                                                 "henries", "ohm", "ohms",  "v",      "volt", "volts",
                                                 "a",       "amp", "amps",  "s",      "sec",  "hz"};
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
/// and `.ic V(a) = 2` as their unspaced forms).  A braced expression `{a + 1}` is one word whatever its
/// spaces, and so is an HSPICE-quoted one `'a + 1'`, which becomes `{a + 1}`.
std::vector<std::string> tokens(const std::string& text) {
  std::vector<std::string> words;
  std::string t;
  int braces = 0;
  bool quote = false;
  for (char ch : text) {
    if (ch == '\'' && braces == 0) {
      quote = !quote;
      t += quote ? '{' : '}';
      continue;
    }
    if (!quote) braces += ch == '{' ? 1 : ch == '}' ? -1 : 0;
    if (braces < 0) braces = 0;
    if (!quote && braces == 0 && std::isspace(static_cast<unsigned char>(ch))) {
      if (!t.empty()) words.push_back(t);
      t.clear();
      continue;
    }
    t += ch;
  }
  if (!t.empty()) words.push_back(t);
  std::vector<std::string> tok;
  for (const std::string& w : words) {
    if (!tok.empty() && (w.front() == '=' || tok.back().back() == '=')) {
      tok.back() += w;
      continue;
    }
    tok.push_back(w);
  }
  return tok;
}

/// Text without an inline comment: `;` anywhere, `$` at the start or after white space (ngspice, HSPICE) — in
/// Xyce's dialect `$` is a character of names ("$N_0001", Xyce's INVALID_CHARS/valid_chars_device_node_names.cir).
std::string strip_inline_comment(const std::string& text, Dialect dialect) {
  std::size_t cut = text.find(';');
  for (std::size_t i = 0; dialect != Dialect::xyce && i < text.size() && i < cut; ++i)
    if (text[i] == '$' && (i == 0 || std::isspace(static_cast<unsigned char>(text[i - 1])))) cut = i;
  return cut == std::string::npos ? text : text.substr(0, cut);
}

std::string unquote(const std::string& s) {  // "file", 'file' (which tokens() made {file}) or {file}
  if (s.size() >= 2 && s.front() == '{' && s.back() == '}') return s.substr(1, s.size() - 2);
  return s.size() >= 2 && (s.front() == '"' || s.front() == '\'') && s.back() == s.front() ? s.substr(1, s.size() - 2)
                                                                                           : s;
}

std::string beside(const std::string& deck, const std::string& name) {  // relative to the including deck
  if (!name.empty() && name[0] == '/') return name;
  const std::size_t slash = deck.rfind('/');
  return slash == std::string::npos ? name : deck.substr(0, slash + 1) + name;
}

/// Xyce's "PWL FILE name [TD=…] [R=…]" (also "file", the name quoted or not): the file beside the deck holds
/// one "TIME VALUE" pair per line, separated by blanks or a comma (Xyce's .csv and text tables); the
/// specification becomes PWL(t1 v1 t2 v2 …) with the rest kept.  Other specifications are returned as
/// they are.  A file that is missing, or a line that is not two numbers, is an InputError naming file and line.
std::string pwl_from_file(const Line& l, const std::string& spec, Dialect dialect) {
  std::string low = spec;
  std::transform(low.begin(), low.end(), low.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::size_t pwl = low.find("pwl");
  if (pwl == std::string::npos) return spec;
  std::size_t i = low.find_first_not_of(" \t", pwl + 3);
  if (i == std::string::npos || low.compare(i, 4, "file") != 0 ||
      (i + 4 < low.size() && !std::isspace(static_cast<unsigned char>(low[i + 4]))))
    return spec;
  i = low.find_first_not_of(" \t", i + 4);
  if (i == std::string::npos) fail(l, "PWL FILE NAME", "no file name in \"" + spec + "\"");
  std::size_t end;
  std::string name;
  if (spec[i] == '"') {
    end = spec.find('"', i + 1);
    if (end == std::string::npos) fail(l, "a closing '\"' after PWL FILE", "\"" + spec + "\"");
    name = spec.substr(i + 1, end - i - 1);
    ++end;
  } else {
    end = spec.find_first_of(" \t", i);
    if (end == std::string::npos) end = spec.size();
    name = spec.substr(i, end - i);
  }
  const std::string path = beside(l.file, name);
  if (name.empty() || !std::filesystem::is_regular_file(path))
    fail(l, "a regular file of PWL points", "\"" + name + "\" (no such file)");
  std::ifstream in(path, std::ios::binary);
  std::string table, line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string t; words >> t;) w.push_back(t);
    if (w.empty()) continue;
    std::string shown = line.substr(0, 40);
    for (char& ch : shown)
      if (!std::isprint(static_cast<unsigned char>(ch))) ch = '?';
    if (w.size() != 2)
      throw InputError(path + ":" + std::to_string(number) + ": expected TIME VALUE (PWL FILE of " + l.where() +
                       "), found \"" + shown + "\"");
    for (const std::string& t : w) try {
        (void)parse_spice_value(t, nullptr, dialect);
      } catch (const std::exception&) {
        throw InputError(path + ":" + std::to_string(number) + ": expected TIME VALUE numbers (PWL FILE of " +
                         l.where() + "), found \"" + shown + "\"");
      }
    table += (table.empty() ? "" : " ") + w[0] + " " + w[1];
  }
  return spec.substr(0, pwl) + "PWL(" + table + ")" + spec.substr(end);
}

/// ngspice's .control script, read only for what it does to the circuit: an `alter` (or `altermod`,
/// `mc_source`, `source`) changes it, and is refused unless an analysis has run before it on the circuit
/// as written — outside any loop or branch (`tran`, `op`, `run`, … at the script's top level) — in which
/// case dcad's circuit is that first analysis' one, and a note says the script alters it afterwards.
struct ControlScript {
  int depth = 0;         ///< inside while/repeat/dowhile/foreach/if … end
  std::string analysed;  ///< the first analysis at the top level, "" before one
  bool noted = false;

  void line(const Line& l, const std::string& head, std::vector<std::string>& warnings) {
    static const std::set<std::string> blocks = {"while", "repeat", "dowhile", "foreach", "if"};
    static const std::set<std::string> analyses = {"tran", "op",   "run", "ac",    "dc", "noise",
                                                   "pz",   "sens", "tf",  "disto", "sp", "pss"};
    if (blocks.count(head))
      ++depth;
    else if (head == "end" && depth > 0)
      --depth;
    else if (depth == 0 && analysed.empty() && analyses.count(head))
      analysed = head;
    if (head != "alter" && head != "altermod" && head != "mc_source" && head != "source") return;
    if (analysed.empty())
      fail(l, "a .control block that leaves the circuit as written (dcad reads the circuit, not the script)",
           l.text.substr(0, l.text.find(' ')) +
               ", which changes it before any analysis at the script's top level runs: write the altered values in the "
               "deck");
    if (!noted)
      warnings.push_back(l.where() + ": the .control block's " + head +
                         " changes the circuit after its first analysis (" + analysed +
                         ") has run on it as written: dcad solves the circuit as written");
    noted = true;
  }
};

/// The deck's logical lines: title dropped (top file only), comments and .control blocks removed,
/// `+` continuations joined, .include and .lib FILE SECTION read in place.  Stops at .end.
class Reader {
 public:
  std::string title;
  std::vector<Line> lines;
  std::vector<std::string> warnings;
  std::string top_deck;  ///< the top deck's path (includes fall back to its directory)
  Dialect dialect = Dialect::strict;

  /// .data … .enddata (skipped with a note), .if (refused), .control (its script watched for changes): true if
  /// `head` is one of them.
  bool block_card(const Line& here, const std::string& head, bool& in_control, ControlScript& control) {
    if (head == ".data") {
      skip_until = ".enddata";
      warnings.push_back(
          here.where() +
          ": ignored .data block (a table for sweeps: dcad solves the circuit at the values as written)");
      return true;
    }
    if (head == ".if") fail(here, "a netlist without conditionals (write the branch that applies)", ".if");
    if (head == ".control") {
      in_control = true;
      control = ControlScript{};
      warnings.push_back(here.where() + ": ignored .control block");
      return true;
    }
    return false;
  }
  /// An include's path: beside the including file, else beside the top deck (Xyce's fallback, its
  /// Certification_Tests/BUG_1325_SON: "paths relative to the directory of the top-level netlist").
  std::string locate_include(const std::string& beside_this, const std::string& name) const {
    const std::string here_path = beside(beside_this, name);
    std::error_code ec;
    if (std::filesystem::exists(here_path, ec) || top_deck.empty()) return here_path;
    const std::string top_path = beside(top_deck, name);
    return std::filesystem::exists(top_path, ec) ? top_path : here_path;
  }
  enum class IncludeCard { none, read_on, stop_if_ended };
  /// .include/.inc/.incl FILE, .lib FILE SECTION, .lib FILE (the whole file) and .lib SECTION (skipped here).
  template <class Locate>
  IncludeCard include_card(const Line& here, const std::string& head, const std::vector<std::string>& tok,
                           const std::string& text, int depth, const Locate& locate) {
    if (head == ".include" || head == ".inc" || head == ".incl") {  // Xyce takes all three
      if (tok.size() != 2)
        fail(here, ".include FILE",
             "\"" + text + "\"" +
                 (tok.size() < 2 ? " (no file named: write the file's path after it)"
                                 : " (more than one word: quote a path with spaces)"));
      read(locate(unquote(tok[1])), false, "", depth + 1, &here);
      return IncludeCard::stop_if_ended;
    }
    if (head == ".lib" && tok.size() == 3) {
      read(locate(unquote(tok[1])), false, tok[2], depth + 1, &here);
      return IncludeCard::read_on;
    }
    if (head == ".lib" && tok.size() == 2) {
      std::error_code ec;
      const std::string whole = locate(unquote(tok[1]));
      if (std::filesystem::is_regular_file(
              whole,
              ec)) {  // .lib FILE: the whole file, as .include (Xyce, HSPICE without a section)
        read(whole, false, "", depth + 1, &here);
        return IncludeCard::stop_if_ended;
      }
      skip_until = ".endl";  // .lib SECTION … .endl defined here and not asked for: skipped, as ngspice does
      return IncludeCard::read_on;
    }
    if (head == ".lib")
      fail(here, ".lib FILE SECTION (a library section is read where it is named)", "\"" + text + "\"");
    return IncludeCard::none;
  }
  /// `text`: the top deck's contents (a deck given as a string, named `file` in messages; its
  /// includes are read relative to `directory`), else the file is opened.
  void read(const std::string& file, bool top, const std::string& section, int depth, const Line* from,
            std::istream* text = nullptr, const std::string& directory = "") {
    if (depth > 16) fail(*from, "includes nested at most 16 deep", "deeper (an include cycle?)");
    std::error_code ec;
    if (from && !std::filesystem::is_regular_file(file, ec))  // not a device or a pipe: never a hang
      fail(*from, "a regular file to include",
           "\"" + file + "\" (" + (std::filesystem::exists(file, ec) ? "not a regular file" : "no such file") + ")");
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
    if (top) top_deck = beside_this;
    const auto locate = [&](const std::string& name) { return locate_include(beside_this, name); };
    std::string raw;
    std::size_t number = 0;
    bool first = top, in_control = false, in_section = section.empty();
    ControlScript control;
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
      std::string text = strip_inline_comment(raw.substr(start), dialect);
      const std::vector<std::string> tok = tokens(text);
      if (tok.empty()) continue;  // white space of any kind (\f, \v too), or only a comment
      text = text.substr(text.find_first_not_of(" \t\n\v\f\r"));  // tok is not empty: the line has a word
      std::string head = lower(tok[0]);
      if (head == ".macro" || head == ".eom") {  // HSPICE's names of .subckt and .ends
        text = (head == ".macro" ? ".subckt" : ".ends") + text.substr(tok[0].size());
        head = head == ".macro" ? ".subckt" : ".ends";
      }
      const Line here{file, number, text};
      if (!in_section) {  // .lib FILE SECTION: only `.lib SECTION` … `.endl`
        if (head == ".lib" && tok.size() == 2 && lower(tok[1]) == lower(section)) in_section = true;
        continue;
      }
      if (!section.empty() && head == ".endl") return;
      if (in_control) {  // .control … .endc: ngspice's script, ignored as a whole — unless it alters the circuit
        if (head == ".endc") in_control = false;
        control.line(here, head, warnings);
        continue;
      }
      if (!skip_until.empty()) {  // .data … .enddata, a .lib section not asked for, .if blocks
        if (head == skip_until) skip_until.clear();
        continue;
      }
      if (block_card(here, head, in_control, control)) continue;
      if (text[0] == '+') {
        if (lines.empty() || lines.back().file != file)
          fail(here, "an element line before a continuation '+'", "'+' first");
        lines.back().text += " " + text.substr(1);
        continue;
      }
      if (head == ".end") {
        ended = true;
        return;
      }
      if (const IncludeCard c = include_card(here, head, tok, text, depth, locate); c != IncludeCard::none) {
        if (c == IncludeCard::stop_if_ended && ended) return;
        continue;
      }
      lines.push_back(here);
    }
    if (!section.empty() && !in_section && from) fail(*from, "a section .lib " + section + " in " + file, "none");
  }
  bool ended = false;
  std::string skip_until;  ///< lines are skipped up to this card
};

/// A user function of the deck: `.func NAME(a, b) {body}` or `.param NAME(a, b) = {body}`.
struct UserFunction {
  std::vector<std::string> args;
  std::string body;
};

/// What evaluating the deck's expressions noted: values that are irrational (rounded to 80 significant
/// digits) and statistical functions read at their nominal value.
struct ExpressionNotes {
  bool rounded = false;              ///< the last value read was rounded (irrational)
  std::vector<std::string> nominal;  ///< "agauss(…)" read as its nominal value
  std::vector<std::string> letters;  ///< "10x": letters after a number that are neither scale nor unit, ignored
};

/// Arithmetic on .param expressions as ngspice's numparam and Xyce read them: numbers (SPICE suffixes),
/// parameters, + - * / ( ), unary signs, ^ or ** (exact for an integer exponent), comparisons, && || !,
/// c ? a : b, pi, and the functions decks use (sqrt abs exp log ln log10 pow pwr min max sin cos tan asin
/// acos atan arctan atan2 sinh cosh tanh asinh acosh atanh sqr int floor ceil nint round sign if ternary_fcn), the
/// user's .func functions, and the statistical ones (agauss gauss aunif unif limit) at their nominal value.  Exact
/// where the value is rational; an irrational value (sqrt(2), exp(1), pi) is rounded to 80 significant digits and says
/// so.
class Expression {
 public:
  using Functions = std::map<std::string, UserFunction>;
  Expression(const std::string& text, const std::map<std::string, Rational>& params,
             const Functions* functions = nullptr, ExpressionNotes* notes = nullptr, int depth = 0,
             Dialect dialect = Dialect::strict)
      : s_(lower(text)), params_(params), functions_(functions), notes_(notes), depth_(depth), dialect_(dialect) {}
  Rational value() {
    if (depth_ > 32) throw std::invalid_argument("user functions nested more than 32 deep (a recursive .func?)");
    const Rational v = ternary();
    skip();
    if (i_ != s_.size()) throw std::invalid_argument("unexpected \"" + s_.substr(i_) + "\"");
    return v;
  }

 private:
  using Float = boost::multiprecision::cpp_bin_float_100;
  void skip() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  bool eat(const std::string& op) {
    skip();
    if (s_.compare(i_, op.size(), op) != 0) return false;
    i_ += op.size();
    return true;
  }
  bool peek(const std::string& op) {
    skip();
    return s_.compare(i_, op.size(), op) == 0;
  }
  /// An irrational value, rounded: 80 significant digits of its 100-digit float, noted.
  Rational rounded(const Float& x) {
    if (!boost::multiprecision::isfinite(x))
      throw std::invalid_argument("a value that is not finite (a function outside its real domain, or an overflow)");
    if (notes_) notes_->rounded = true;
    if (x == 0) return Rational(0);
    int e = 0;
    const Float m = boost::multiprecision::frexp(x, &e);  // x = m 2^e, |m| in [1/2, 1)
    const boost::multiprecision::mpz_int n =
        boost::multiprecision::ldexp(m, 266).convert_to<boost::multiprecision::mpz_int>();  // 80 digits
    Rational r(n);
    const int shift = e - 266;
    const Rational two = shift >= 0 ? Rational(boost::multiprecision::mpz_int(1) << shift)
                                    : Rational(1, boost::multiprecision::mpz_int(1) << -shift);
    return r * two;
  }
  static Float as_float(const Rational& x) {
    return Float(boost::multiprecision::numerator(x).str()) / Float(boost::multiprecision::denominator(x).str());
  }
  static bool whole(const Rational& x) { return boost::multiprecision::denominator(x) == 1; }
  /// x^e for an integer e, exactly (bounded).
  static Rational ipow(const Rational& base, const Rational& e) {
    if (boost::multiprecision::abs(e) > 64)
      throw std::invalid_argument("expected an integer exponent of at most 64, found " + e.str());
    Rational r(1);
    for (long k = 0; k < boost::multiprecision::abs(e); ++k) r *= base;
    if (e < 0) {
      if (r == 0) throw std::invalid_argument("division by zero");
      r = Rational(1) / r;
    }
    return r;
  }
  /// The exact square root of x if it is rational.
  static std::optional<Rational> exact_sqrt(const Rational& x) {
    using boost::multiprecision::mpz_int;
    const mpz_int n = boost::multiprecision::numerator(x), d = boost::multiprecision::denominator(x);
    const mpz_int rn = boost::multiprecision::sqrt(n), rd = boost::multiprecision::sqrt(d);
    if (rn * rn == n && rd * rd == d) return Rational(rn, rd);
    return std::nullopt;
  }
  Rational ternary() {
    const Rational c = logical_or();
    if (!eat("?")) return c;
    const Rational a = ternary();
    if (!eat(":")) throw std::invalid_argument("expected ':' of c ? a : b");
    const Rational b = ternary();
    return c != 0 ? a : b;
  }
  Rational logical_or() {
    Rational v = logical_and();
    while (eat("||") || eat("|")) {  // Xyce writes | and & for || and &&
      const Rational w = logical_and();
      v = (v != 0 || w != 0) ? 1 : 0;
    }
    return v;
  }
  Rational logical_and() {
    Rational v = comparison();
    while (eat("&&") || eat("&")) {
      const Rational w = comparison();
      v = (v != 0 && w != 0) ? 1 : 0;
    }
    return v;
  }
  Rational comparison() {
    Rational v = sum();
    for (;;) {
      if (eat("=="))
        v = v == sum() ? 1 : 0;
      else if (eat("!="))
        v = v != sum() ? 1 : 0;
      else if (eat("<="))
        v = v <= sum() ? 1 : 0;
      else if (eat(">="))
        v = v >= sum() ? 1 : 0;
      else if (eat("<"))
        v = v < sum() ? 1 : 0;
      else if (eat(">"))
        v = v > sum() ? 1 : 0;
      else
        return v;
    }
  }
  Rational sum() {
    Rational v = product();
    for (;;) {
      if (eat("+"))
        v += product();
      else if (eat("-"))
        v -= product();
      else
        return v;
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
    return pow_of(base, unary());
  }
  Rational pow_of(const Rational& base, const Rational& e) {
    if (whole(e)) {
      const Rational r = ipow(base, e);
      if (boost::multiprecision::msb(boost::multiprecision::abs(boost::multiprecision::numerator(r)) + 1) > 20000 ||
          boost::multiprecision::msb(boost::multiprecision::denominator(r)) > 20000)
        throw std::invalid_argument("a power beyond 20000 bits");
      return r;
    }
    if (base < 0) throw std::invalid_argument("a negative number to a fractional power");
    if (boost::multiprecision::denominator(e) == 2)
      if (const auto r = exact_sqrt(base)) return ipow(*r, Rational(boost::multiprecision::numerator(e)));
    if (base == 0) return Rational(0);
    return rounded(boost::multiprecision::pow(as_float(base), as_float(e)));
  }
  Rational unary() {
    if (eat("-")) return -unary();
    if (eat("+")) return unary();
    if (peek("!=")) throw std::invalid_argument("expected a value before '!='");
    if (eat("!")) return unary() == 0 ? 1 : 0;
    if (eat("(")) {
      const Rational v = ternary();
      if (!eat(")")) throw std::invalid_argument("expected ')'");
      return v;
    }
    skip();
    const std::size_t start = i_;
    if (i_ < s_.size() && (std::isalpha(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_')) {
      while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '_' || s_[i_] == '.'))
        ++i_;
      const std::string name = s_.substr(start, i_ - start);
      if (peek("(")) return call(name);
      const auto it = params_.find(name);
      if (it != params_.end()) return it->second;
      if (name == "pi") return rounded(boost::math::constants::pi<Float>());
      if (name == "exp") return rounded(boost::math::constants::e<Float>());  // Xyce: exp alone is e
      if (name == "temper" || name == "temp") return Rational(27);            // ngspice's nominal temperature, °C
      throw std::invalid_argument("unknown parameter \"" + name + "\"");
    }
    while (i_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[i_])) || s_[i_] == '.' ||
                              ((s_[i_] == '+' || s_[i_] == '-') && i_ > start && s_[i_ - 1] == 'e' &&
                               std::isdigit(static_cast<unsigned char>(s_[start])))))
      ++i_;
    if (i_ == start) throw std::invalid_argument("expected a number, a parameter or '('");
    const std::string number = s_.substr(start, i_ - start);
    if (std::tolower(static_cast<unsigned char>(number.back())) == 'j' &&
        std::isdigit(static_cast<unsigned char>(number[number.size() > 1 ? number.size() - 2 : 0])))
      throw std::invalid_argument("\"" + number +
                                  "\" is an imaginary number (Xyce's J suffix): complex values are "
                                  "AC-only");
    std::string ignored;
    const Rational v = parse_spice_value(number, &ignored, dialect_);
    if (!ignored.empty() && notes_) notes_->letters.push_back("\"" + number + "\" read as " + v.str());
    return v;
  }
  std::vector<Rational> arguments(const std::string& name) {
    eat("(");
    std::vector<Rational> a;
    if (eat(")")) return a;
    for (;;) {
      a.push_back(ternary());
      if (eat(")")) return a;
      if (!eat(",")) throw std::invalid_argument("expected ',' or ')' in the arguments of " + name);
    }
  }
  static void want_arguments(const std::string& name, const std::vector<Rational>& a, std::size_t lo, std::size_t hi) {
    if (a.size() < lo || a.size() > hi)
      throw std::invalid_argument(name + ": expected " + std::to_string(lo) +
                                  (hi > lo ? " to " + std::to_string(hi) : "") + " arguments, found " +
                                  std::to_string(a.size()));
  }
  /// sqrt, abs, exp, log, pow, min, max and the trigonometric and hyperbolic functions: exact where the value
  /// is rational at a rational argument, else rounded (and noted); nullopt for another name.
  std::optional<Rational> analytic(const std::string& name, const std::vector<Rational>& a) {
    const auto want = [&](std::size_t lo, std::size_t hi) { want_arguments(name, a, lo, hi); };
    const auto transcendental = [&](Float (*fn)(const Float&), const Rational& at_zero_arg,
                                    const Rational& at_zero_value) -> Rational {
      want(1, 1);
      if (a[0] == at_zero_arg) return at_zero_value;
      return rounded(fn(as_float(a[0])));
    };
    if (name == "sqrt") {
      want(1, 1);
      if (a[0] < 0) throw std::invalid_argument("sqrt of a negative number");
      if (const auto r = exact_sqrt(a[0])) return *r;
      return rounded(boost::multiprecision::sqrt(as_float(a[0])));
    }
    if (name == "abs") return want(1, 1), boost::multiprecision::abs(a[0]);
    if (name == "exp") return transcendental([](const Float& x) { return Float(boost::multiprecision::exp(x)); }, 0, 1);
    if (name == "log" || name == "ln" || name == "log10") {
      want(1, 1);
      if (a[0] <= 0) throw std::invalid_argument(name + " of a number <= 0");
      if (a[0] == 1) return Rational(0);
      if (name == "log10") {  // exact at powers of ten
        for (int k = -64; k <= 64; ++k)
          if (a[0] == ipow(Rational(10), Rational(k))) return Rational(k);
        return rounded(boost::multiprecision::log10(as_float(a[0])));
      }
      return rounded(boost::multiprecision::log(as_float(a[0])));
    }
    if (name == "pow" || name == "pwr") return want(2, 2), pow_of(a[0], a[1]);
    if (name == "min") return want(2, 2), std::min(a[0], a[1]);
    if (name == "max") return want(2, 2), std::max(a[0], a[1]);
    if (name == "sin") return transcendental([](const Float& x) { return Float(boost::multiprecision::sin(x)); }, 0, 0);
    if (name == "cos") return transcendental([](const Float& x) { return Float(boost::multiprecision::cos(x)); }, 0, 1);
    if (name == "tan") return transcendental([](const Float& x) { return Float(boost::multiprecision::tan(x)); }, 0, 0);
    if ((name == "asin" || name == "acos") && a.size() == 1 && (a[0] < -1 || a[0] > 1))
      throw std::invalid_argument(name + " outside its real domain");
    if (name == "asin")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::asin(x)); }, 0, 0);
    if (name == "acos")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::acos(x)); }, 1, 0);
    if (name == "atan" || name == "arctan")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::atan(x)); }, 0, 0);
    if (name == "asinh")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::asinh(x)); }, 0, 0);
    if (name == "acosh" || name == "atanh") {  // ngspice's numparam functions (xpressn.c), real only
      want(1, 1);
      if (name == "acosh" ? a[0] < 1 : a[0] <= -1 || a[0] >= 1)
        throw std::invalid_argument(name + " outside its real domain");
      if (a[0] == (name == "acosh" ? 1 : 0)) return Rational(0);
      return rounded(name == "acosh" ? Float(boost::multiprecision::acosh(as_float(a[0])))
                                     : Float(boost::multiprecision::atanh(as_float(a[0]))));
    }
    if (name == "sqr") return want(1, 1), a[0] * a[0];  // ngspice: x², not the square root
    if (name == "sinh")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::sinh(x)); }, 0, 0);
    if (name == "cosh")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::cosh(x)); }, 0, 1);
    if (name == "tanh")
      return transcendental([](const Float& x) { return Float(boost::multiprecision::tanh(x)); }, 0, 0);
    if (name == "atan2") {
      want(2, 2);
      if (a[0] == 0 && a[1] > 0) return Rational(0);
      return rounded(boost::multiprecision::atan2(as_float(a[0]), as_float(a[1])));
    }
    return std::nullopt;
  }
  /// floor, ceil, int, nint/round, sign/sgn and if: exact; nullopt for another name.
  static std::optional<Rational> piecewise(const std::string& name, const std::vector<Rational>& a) {
    const auto want = [&](std::size_t lo, std::size_t hi) { want_arguments(name, a, lo, hi); };
    using boost::multiprecision::mpz_int;
    const auto floor_q = [](const Rational& x) {
      const mpz_int n = boost::multiprecision::numerator(x), d = boost::multiprecision::denominator(x);
      mpz_int f = n / d;
      if (f * d > n) f -= 1;
      return Rational(f);
    };
    if (name == "floor") return want(1, 1), floor_q(a[0]);
    if (name == "ceil") return want(1, 1), -floor_q(-a[0]);
    if (name == "int") return want(1, 1), a[0] >= 0 ? floor_q(a[0]) : -floor_q(-a[0]);  // toward zero
    if (name == "nint" || name == "round")
      return want(1, 1), a[0] >= 0 ? floor_q(a[0] + Rational(1, 2)) : -floor_q(-a[0] + Rational(1, 2));
    if ((name == "sign" || name == "sgn") && a.size() == 2)  // Xyce and HSPICE: sign(x, y) = sgn(y) |x|
      return a[1] > 0   ? Rational(boost::multiprecision::abs(a[0]))
             : a[1] < 0 ? Rational(-boost::multiprecision::abs(a[0]))
                        : Rational(0);
    if (name == "sign" || name == "sgn") return want(1, 1), Rational(a[0] > 0 ? 1 : a[0] < 0 ? -1 : 0);
    if (name == "if" || name == "ternary_fcn") return want(3, 3), a[0] != 0 ? a[1] : a[2];
    return std::nullopt;
  }
  Rational call(const std::string& name) {
    if (functions_) {
      const auto f = functions_->find(name);
      if (f != functions_->end()) {
        const std::vector<Rational> a = arguments(name);
        if (a.size() != f->second.args.size())
          throw std::invalid_argument(name + ": expected " + std::to_string(f->second.args.size()) +
                                      " arguments, found " + std::to_string(a.size()));
        std::map<std::string, Rational> local = params_;
        for (std::size_t k = 0; k < a.size(); ++k) local[f->second.args[k]] = a[k];
        return Expression(f->second.body, local, functions_, notes_, depth_ + 1, dialect_).value();
      }
    }
    const std::size_t at = i_;
    const std::vector<Rational> a = arguments(name);
    const auto want = [&](std::size_t lo, std::size_t hi) { want_arguments(name, a, lo, hi); };
    if (const std::optional<Rational> r = analytic(name, a)) return *r;
    if (const std::optional<Rational> r = piecewise(name, a)) return *r;
    if (name == "agauss" || name == "gauss" || name == "aunif" || name == "unif" || name == "limit") {
      want(1, 4);
      if (notes_) notes_->nominal.push_back(name + s_.substr(at, i_ - at));
      return a[0];  // the nominal value (Xyce outside sampling analyses; ngspice draws a random one)
    }
    throw std::invalid_argument("unknown function \"" + name + "\"" +
                                (name == "rand" || name == "trrandom" ? " (random: no exact transient)" : ""));
  }
  std::string s_;
  std::size_t i_ = 0;
  const std::map<std::string, Rational>& params_;
  const Functions* functions_;
  ExpressionNotes* notes_;
  int depth_;
  Dialect dialect_;
};

/// name=value pairs of a .param line or a subcircuit's params: list ("a=1 b={2*a}", spaces around
/// '=' allowed), as written (the value's text without braces).  A name with arguments, f(x, y), is a
/// user function (ngspice's `.param f(x) = {…}`).
std::vector<std::pair<std::string, std::string>> param_pairs(const std::vector<std::string>& tok, std::size_t from,
                                                             const Line& l) {
  std::string joined;
  for (std::size_t k = from; k < tok.size(); ++k) joined += tok[k] + " ";
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t i = 0;
  while (true) {
    while (i < joined.size() &&
           (std::isspace(static_cast<unsigned char>(joined[i])) || (joined[i] == ',' && !out.empty())))
      ++i;  // Xyce: "a=1, b=2"
    if (i >= joined.size()) return out;
    const std::size_t eq = joined.find('=', i);
    if (eq == std::string::npos) fail(l, "NAME=VALUE", "\"" + joined.substr(i) + "\"");
    std::string name = lower(joined.substr(i, eq - i));
    name.erase(name.find_last_not_of(" \t") + 1);
    std::size_t j = joined.find_first_not_of(" \t", eq + 1);
    if (name.empty() || j == std::string::npos) fail(l, "NAME=VALUE", "\"" + joined.substr(i) + "\"");
    std::size_t end;
    if (joined[j] == '{') {
      int depth = 0;
      for (end = j; end < joined.size(); ++end) {
        depth += joined[end] == '{' ? 1 : joined[end] == '}' ? -1 : 0;
        if (depth == 0) break;
      }
      if (end >= joined.size()) fail(l, "a closing '}'", "\"" + joined.substr(j) + "\"");
      ++end;
    } else {
      end = joined.find_first_of(" \t", j);
    }
    std::string expr = joined.substr(j, end - j);
    if (expr.front() == '{')
      expr = expr.substr(1, expr.size() - 2);
    else if (expr.size() > 1 && expr.back() == ',' &&
             std::count(expr.begin(), expr.end(), '(') == std::count(expr.begin(), expr.end(), ')'))
      expr.pop_back();  // the comma between two assignments, not an argument's
    out.emplace_back(name, expr);
    i = end;
  }
}

struct Subcircuit {
  std::string name;
  std::vector<std::string> ports;
  std::vector<std::pair<std::string, std::string>> defaults;  ///< params: as written, evaluated per instance
  std::vector<Line> body;
  Line where;
  std::string key;  ///< its definition's path, "/sub1/sub": a nested .subckt is local to its parent (ngspice)
};

/// Xyce's hierarchical separator ':' (x1:mid, x1:x2:l1) as ngspice's '.' (x1.mid), which dcad's names use.
static std::string hierarchical(std::string n) {
  std::replace(n.begin(), n.end(), ':', '.');
  return n;
}

/// Flattens the deck: .param (global and inside .subckt, scoped), .func, .global, .subckt … .ends (nested
/// ones too), X instances (hierarchical names as ngspice makes them: element L1 of instance X1 is
/// l.x1.l1, internal node n of X1 is x1.n), .ic / .dcvolt v(node)=value.
class Flattener {
 public:
  Netlist& out;
  std::map<std::string, std::size_t> names, nodes;
  std::map<std::string, Subcircuit> subckts;  ///< by definition path (Subcircuit::key)
  std::map<std::string, Rational> node_ic;
  std::map<std::string, std::string> node_ic_where;  ///< the .ic line that set it
  std::set<std::string> globals;                     ///< .global nodes: the same node in every instance
  Expression::Functions functions;
  struct Coupling {
    Line line;
    std::string name, a, b;
    Rational k;
  };
  std::vector<Coupling> couplings;      ///< K elements, resolved once every inductor is known
  std::optional<Rational> temperature;  ///< .temp or .options temp=, if the deck sets one (read before the elements)
  Rational tnom = 27;                   ///< .options tnom=
  bool replace_ground = false;  ///< Xyce's `.preprocess replaceground true`: gnd!, ground, ground! are node 0 too
  Generator generator;          ///< gnucap's `.generator` settings, read by generator(SCALE) sources
  Dialect dialect;              ///< how `a` and `x` after a number are read

  Flattener(Netlist& n, Dialect d) : out(n), dialect(d) {}

  void run(const std::vector<Line>& lines) {
    std::map<std::string, Rational> params;
    std::vector<Line> top, param_lines, temperature_lines, generator_lines;
    const Line* tran = nullptr;
    for (std::size_t i = 0; i < lines.size(); ++i) {  // definitions first: ngspice allows use before definition
      const std::vector<std::string> tok = tokens(lines[i].text);
      const std::string head = lower(tok[0]);
      if (head == ".tran" && !tran) tran = &lines[i];
      if (head.size() >= 4 &&
          std::string(".generator").compare(0, head.size(), head) == 0) {  // gnucap's command, in its order
        if (tran && tok.size() > 1)
          fail(lines[i],
               "gnucap's .generator settings before the deck's first .tran (" + tran->where() +
                   ", whose circuit dcad solves)",
               tok[0] + " after it");
        generator_lines.push_back(lines[i]);
        out.warnings.push_back(lines[i].where() + ": " + tok[0] +
                               ": read for the generator(SCALE) sources (gnucap's signal generator)");
      } else if (head == ".subckt") {
        i = define(lines, i, "");
      } else if (head == ".ends") {
        fail(lines[i], ".ends after a .subckt", ".ends without .subckt");
      } else if (is_param_card(head) || head == ".func") {
        param_lines.push_back(lines[i]);
      } else if (head == ".global") {
        for (std::size_t k = 1; k < tok.size(); ++k) globals.insert(lower(tok[k]));
      } else if (head == ".temp" || head == ".options" || head == ".option" ||
                 head == ".opt") {  // before any element reads it
        top.push_back(lines[i]);
        temperature_lines.push_back(lines[i]);
      } else if (head == ".preprocess" && tok.size() == 3 &&
                 lower(tok[1]) == "replaceground") {  // names, not devices: read
        replace_ground = lower(tok[2]) == "true" || tok[2] == "1";
        out.warnings.push_back(lines[i].where() + ": .preprocess replaceground " + tok[2] +
                               ": GND!, GROUND and GROUND! are " + (replace_ground ? "" : "not ") +
                               "node 0 (GND and 0 always are, as in ngspice)");
      } else {
        top.push_back(lines[i]);
      }
    }
    for (const Line& l : param_lines) read_params(l, params, nullptr);
    for (const Line& l : temperature_lines) read_temperatures(l, tokens(l.text), params);
    for (const Line& l : generator_lines) read_generator(l, tokens(l.text), params);
    expand(top, "", {}, params, 0, "");
  }

 private:
  static bool is_param_card(const std::string& head) {
    return head == ".param" || head == ".params" || head == ".global_param" || head == ".parameter" ||
           head == ".parameters" || head == ".csparam";
  }

  /// .temp T [T2 …] (the first: a list is a sweep) and .options temp=T tnom=T.
  void read_temperatures(const Line& l, const std::vector<std::string>& tok,
                         const std::map<std::string, Rational>& params) {
    const auto value = [&](const std::string& t, const std::string& what) { return card_value(l, t, params, what); };
    if (lower(tok[0]) == ".temp") {
      if (tok.size() < 2) fail(l, ".temp TEMPERATURE", "none");
      temperature = value(tok[1], "a temperature in C");
      return;
    }
    for (std::size_t k = 1; k < tok.size(); ++k) {
      const std::string t = lower(tok[k]);
      if (t.rfind("temp=", 0) == 0) temperature = value(t.substr(5), "temp=TEMPERATURE");
      if (t.rfind("tnom=", 0) == 0) tnom = value(t.substr(5), "tnom=TEMPERATURE");
    }
  }

  /// gnucap's conditional values (lib/bm_cond.cc): "r1 1 2 ac 1k dc 2k", a value per analysis.
  static bool gnucap_mode(const std::string& word) {
    static const std::set<std::string> modes = {"ac",     "op",      "dc",       "tran",      "trans",
                                                "transi", "transie", "transien", "transient", "four",
                                                "fouri",  "fourie",  "fourier",  "else",      "all"};
    return modes.count(lower(word)) > 0;
  }
  /// The element's words with its conditional values replaced by the transient's, as gnucap picks it: TRAN,
  /// else the unconditioned (ELSE, ALL), else DC, else OP.  Refused where the operating point's value (DC,
  /// else OP) differs from the transient's: dcad's transient starts on the circuit it integrates.
  std::vector<std::string> transient_value(const Line& l, const std::vector<std::string>& tok, const std::string& name,
                                           const std::function<Rational(const std::string&)>& number) {
    std::map<std::string, std::string> by_mode;
    std::size_t k = 3;
    for (; k + 1 < tok.size() && gnucap_mode(tok[k]); k += 2) {
      std::string mode = lower(tok[k]);
      mode = mode.rfind("tran", 0) == 0   ? "tran"
             : mode.rfind("four", 0) == 0 ? "fourier"
             : mode == "all"              ? "else"
                                          : mode;
      if (by_mode.count(mode))
        fail(l, "one value per analysis (gnucap's conditional form)", "a second " + tok[k] + " for " + name);
      by_mode[mode] = tok[k + 1];
    }
    const auto first = [&](std::initializer_list<const char*> modes) -> std::optional<std::string> {
      for (const char* m : modes)
        if (by_mode.count(m)) return by_mode[m];
      return std::nullopt;
    };
    const std::optional<std::string> tran = first({"tran", "else", "dc", "op"}),
                                     op = first({"op", "dc", "else", "tran"});
    if (!tran)
      fail(l, "a value for the transient (gnucap's TRAN, ELSE, DC or OP)",
           "only " + tok[3] + " " + tok[4] + " for " + name + " (gnucap then takes 0)");
    if (number(*tran) != number(*op))
      fail(l, "one value for the operating point and the transient",
           *op + " at the operating point and " + *tran + " in the transient for " + name);
    std::vector<std::string> out_tok(tok.begin(), tok.begin() + 3);
    out_tok.push_back(*tran);
    out_tok.insert(out_tok.end(), tok.begin() + static_cast<std::ptrdiff_t>(k), tok.end());
    std::string rest;
    for (const auto& [mode, value] : by_mode)
      if (value != *tran) rest += (rest.empty() ? "" : ", ") + mode + " " + value;
    out.warnings.push_back(l.where() + ": " + name + ": gnucap's conditional value read as " + *tran +
                           " (the transient's)" + (rest.empty() ? "" : "; ignored " + rest + " (other analyses)"));
    return out_tok;
  }

  /// gnucap's `.generator KEY=VALUE …` (or `KEY VALUE`, as gnucap's Get reads it): settings that persist.
  void read_generator(const Line& l, const std::vector<std::string>& tok,
                      const std::map<std::string, Rational>& params) {
    for (std::size_t k = 1; k < tok.size(); ++k) {
      const std::size_t eq = tok[k].find('=');
      const std::string key = tok[k].substr(0, eq);
      std::string value = eq == std::string::npos ? "" : tok[k].substr(eq + 1);
      if (eq == std::string::npos && k + 1 < tok.size()) value = tok[++k];
      if (value.empty()) fail(l, "KEY=VALUE after " + tok[0], "\"" + tok[k] + "\"");
      const Rational v = card_value(l, value, params, key + "=VALUE");
      if (!generator.set(key, v))
        fail(l, "gnucap's generator keys (freq ampl phase max min offset init rise fall delay width period)",
             "\"" + key + "\" in " + tok[0]);
    }
  }
  /// A value on a card (.temp, .options, .generator): `{expression}` over the deck's parameters, or a SPICE number.
  Rational card_value(const Line& l, const std::string& t, const std::map<std::string, Rational>& params,
                      const std::string& what) {
    if (t.size() > 1 && t.front() == '{') return evaluate(l, t.substr(1, t.size() - 2), params, what);
    try {
      return parse_spice_value(t, nullptr, dialect);
    } catch (const std::invalid_argument& e) {
      fail(l, what, "\"" + t + "\" (" + e.what() + ")");
    }
  }

  /// A .param-like or .func line into `params` (functions into `functions`), in order; names in `keep`
  /// are not overwritten (an instance's overrides beat its subcircuit's own .param).
  void read_params(const Line& l, std::map<std::string, Rational>& params, const std::set<std::string>* keep) {
    const std::vector<std::string> tok = tokens(l.text);
    const std::string head = lower(tok[0]);
    if (head == ".func") {  // .func NAME(args) {body}  or  .func NAME(args) = {body}
      std::string rest;
      for (std::size_t k = 1; k < tok.size(); ++k) rest += tok[k] + " ";
      const std::size_t open = rest.find('('), close = rest.find(')');
      if (open == std::string::npos || close == std::string::npos || close < open)
        fail(l, ".func NAME(ARGS) {EXPRESSION}", "\"" + l.text + "\"");
      std::string body = rest.substr(close + 1);
      body.erase(0, body.find_first_not_of(" \t="));
      body.erase(body.find_last_not_of(" \t") + 1);
      if (body.size() >= 2 && body.front() == '{' && body.back() == '}') body = body.substr(1, body.size() - 2);
      define_function(l, lower(rest.substr(0, open)), rest.substr(open + 1, close - open - 1), body);
      return;
    }
    for (const auto& [name, expr] : param_pairs(tok, 1, l)) {
      const std::size_t open = name.find('(');
      if (open != std::string::npos) {  // .param f(x, y) = {…}
        const std::size_t close = name.find(')', open);
        if (close == std::string::npos) fail(l, "NAME(ARGS)={EXPRESSION}", "\"" + name + "\"");
        define_function(l, name.substr(0, open), name.substr(open + 1, close - open - 1), expr);
        continue;
      }
      if (keep && keep->count(name)) continue;
      try {
        params[name] = evaluate(l, expr, params, "a parameter value");
      } catch (const InputError& e) {      // Xyce's COMPLEX_NUM: a value dcad does not read (complex), unused, changes
        const std::string why = e.what();  // nothing; a name no card defines is the deck's error (Xyce: BUG_864)
        if (name == "pi" || name == "exp" || name == "temp" || name == "temper" ||  // else the built-in stands in
            (why.find("(unknown parameter \"") != std::string::npos &&
             why.find(": its .param has no value") == std::string::npos) ||
            why.find("(unknown function \"") != std::string::npos)
          throw;
        params.erase(name);  // never an earlier value in its place
        unevaluated[name] = e.what();
        out.warnings.push_back(l.where() + ": .param " + name + " has no value dcad reads (" + e.what() +
                               "): a card that uses it is refused");
      }
    }
  }

  void define_function(const Line& l, std::string name, const std::string& args, const std::string& body) {
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    UserFunction f;
    std::string a;
    for (char ch : args + ",") {
      if (ch == ',') {
        a.erase(0, a.find_first_not_of(" \t"));
        a.erase(a.find_last_not_of(" \t") + 1);
        if (!a.empty()) f.args.push_back(lower(a));
        a.clear();
      } else {
        a += ch;
      }
    }
    if (name.empty() || body.empty()) fail(l, ".func NAME(ARGS) {EXPRESSION}", "\"" + l.text + "\"");
    f.body = body;
    functions[lower(name)] = f;
  }

  /// An element's value that is neither a number nor a parameter: refused, saying what it is — gnucap's nonlinear
  /// PWL/FIT/TABLE/POLY value, a name no .param defines (a value set from outside the deck), or not a number.
  [[noreturn]] void refuse_value(const Line& l, const std::string& what, const std::string& text,
                                 const std::string& why) {
    const std::string t = lower(text);
    if (t == "pwl" || t == "fit" || t == "table" || t == "poly")  // gnucap's d_res tests
      fail(l, what,
           "\"" + text + "\" (a nonlinear element: gnucap's " + t +
               " gives the value as a function of the element's voltage or current; dcad reads linear R, L and C)");
    const bool word = !t.empty() && std::all_of(t.begin(), t.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.';
    });
    if (word && (std::isalpha(static_cast<unsigned char>(t[0])) || t[0] == '_'))
      fail(l, what,
           "\"" + text + "\" (a name no .param defines" +
               (unevaluated.count(t) ? ": its .param has no value, " + unevaluated.at(t)
                                     : std::string("; a value set from outside the deck — Xyce's -prf parameter "
                                                   "file, Dakota — is not read: define it with .param")) +
               ")");
    fail(l, what, "\"" + text + "\" (" + why + ")");
  }

  /// .param names whose value could not be read (the reason, with its line): refused where a card uses them.
  std::map<std::string, std::string> unevaluated;

  /// An expression's value; an irrational one is recorded (rounded: the certified tier does not claim it).
  Rational evaluate(const Line& l, const std::string& expr, const std::map<std::string, Rational>& params,
                    const std::string& what) {
    ExpressionNotes notes;
    Rational v;
    try {
      v = Expression(expr, params, &functions, &notes, 0, dialect).value();
    } catch (const std::invalid_argument& e) {
      std::string why = e.what();
      const std::string unknown = "unknown parameter \"";
      if (why.rfind(unknown, 0) == 0) {  // one whose .param had no value: say why
        const auto it = unevaluated.find(why.substr(unknown.size(), why.find('"', unknown.size()) - unknown.size()));
        if (it != unevaluated.end()) why += ": its .param has no value, " + it->second;
      }
      fail(l, what + " (numbers, parameters, + - * / ^, comparisons, ?:, pi, sqrt, exp, log, trig, min, max, .func)",
           "\"" + expr + "\" (" + why + ")");
    }
    if (notes.rounded)
      out.rounded.push_back(l.where() + ": {" + expr + "} is irrational: used to 80 significant digits");
    for (const std::string& n : notes.nominal)
      out.warnings.push_back(l.where() + ": " + n +
                             " read as its nominal value (a statistical function: dcad solves the nominal circuit)");
    for (const std::string& n : notes.letters)
      out.warnings.push_back(l.where() + ": " + n + " in {" + expr +
                             "} (letters that are neither a scale factor nor a unit, ignored)");
    return v;
  }

  /// The .subckt at lines[i] and the definitions nested in it, under the definition path `scope`.
  std::size_t define(const std::vector<Line>& lines, std::size_t i, const std::string& scope) {
    const Line& l = lines[i];
    const std::vector<std::string> tok = tokens(l.text);
    if (tok.size() < 2) fail(l, ".subckt NAME PORT…", "\"" + l.text + "\"");
    Subcircuit s{lower(tok[1]), {}, {}, {}, l, scope + "/" + lower(tok[1])};
    std::size_t k = 2;
    for (; k < tok.size() && lower(tok[k]) != "params:" && tok[k].find('=') == std::string::npos; ++k) {
      std::string port = lower(tok[k]);
      if (!port.empty() && port.front() == '(') port.erase(0, 1);
      if (!port.empty() && port.back() == ')') port.pop_back();
      if (!port.empty()) s.ports.push_back(port);  // a name twice: the instance must join the same node (below)
    }
    if (k < tok.size()) s.defaults = param_pairs(tok, lower(tok[k]) == "params:" ? k + 1 : k, l);
    if (subckts.count(s.key))
      fail(l, "a new subcircuit name in its scope",
           "a second .subckt " + tok[1] + (scope.empty() ? "" : " in .subckt " + scope.substr(scope.rfind('/') + 1)));
    for (++i; i < lines.size(); ++i) {
      const std::string head = lower(tokens(lines[i].text)[0]);
      if (head == ".ends") {
        subckts[s.key] = s;
        return i;
      }
      if (head == ".subckt") {  // a nested definition, seen only inside this one (ngspice scopes it)
        i = define(lines, i, s.key);
        continue;
      }
      s.body.push_back(lines[i]);
    }
    fail(l, ".ends for .subckt " + tok[1], "the end of the deck");
  }

  /// node name in an instance: ground and .global nodes are global, ports map to the caller's nodes,
  /// others get the prefix
  std::string node_in(const std::string& n, const std::string& prefix,
                      const std::map<std::string, std::string>& ports) const {
    const std::string s = lower(n);
    if (s == "0" || s == "gnd") return "0";
    if (replace_ground && (s == "gnd!" || s == "ground" || s == "ground!"))
      return "0";  // Xyce's .preprocess replaceground true
    const auto p = ports.find(s);
    if (p != ports.end()) return p->second;
    if (globals.count(s)) return s;
    return prefix + s;
  }

  void expand(const std::vector<Line>& body, const std::string& prefix, const std::map<std::string, std::string>& ports,
              const std::map<std::string, Rational>& params, int depth, const std::string& scope) {
    for (const Line& l : body) {
      std::vector<std::string> tok = tokens(l.text);
      const std::string head = lower(tok[0]);
      if (is_param_card(head) || head == ".func" || head == ".global") continue;  // read before (run, instance)
      if (head[0] == '.') {
        dot_card(l, tok, prefix, ports, params);
        continue;
      }
      if (head[0] == 'x') {
        instance(l, tok, prefix, ports, params, depth, scope);
        continue;
      }
      element(l, tok, prefix, ports, params);
    }
  }

  /// Cards of analyses and output: they do not change the circuit, and are skipped with a note.
  static bool analysis_card(const std::string& head) {
    static const std::set<std::string> cards = {
        ".tran",    ".ac",          ".dc",     ".op",      ".options",   ".option",   ".opt",     ".print",
        ".plot",    ".probe",       ".save",   ".meas",    ".measure",   ".four",     ".fourier", ".width",
        ".title",   ".nodeset",     ".noise",  ".disto",   ".pz",        ".sens",     ".tf",      ".fft",
        ".hb",      ".list",        ".mor",    ".status",  ".dcop",      ".tr",       ".result",  ".mpde",
        ".lin",     ".sp",          ".pss",    ".shoot",   ".objective", ".endl",     ".end",     ".alter",
        ".graph",   ".nodelist",    ".nolist", ".protect", ".unprotect", ".csvprint", ".mem",     ".tsave",
        ".store",   ".fanout",         // gnucap: waveforms kept for .measure, a listing of node connections
        ".probe64", ".autoconverge"};  // PSpice: 64-bit probe data, convergence options
    return cards.count(head) > 0;
  }
  /// Sweeps and sampling: analyses run on the circuit at other values; dcad solves it as written.
  static bool sweep_card(const std::string& head) {
    static const std::set<std::string> cards = {
        ".step", ".sampling", ".embeddedsampling", ".pce", ".rol", ".data", ".mc", ".monte", ".sweep", ".stat"};
    return cards.count(head) > 0;
  }

  /// .ic V(NODE)=VALUE … (or Xyce's .IC NODE VALUE …, and .dcvolt): node voltages at the start.
  void initial_conditions(const Line& l, const std::vector<std::string>& tok, const std::string& prefix,
                          const std::map<std::string, std::string>& ports,
                          const std::map<std::string, Rational>& params) {
    for (std::size_t k = 1; k < tok.size(); ++k) {
      std::string t = lower(tok[k]);
      while (t.compare(0, 2, "v(") == 0 && t.find(')') == std::string::npos && k + 1 < tok.size())
        t += lower(tok[++k]);  // "V(mid )=1"
      const std::size_t eq = t.find('=');
      std::string node, value;
      if (t.compare(0, 2, "v(") == 0 && eq != std::string::npos && t[eq - 1] == ')') {
        node = t.substr(2, eq - 3), value = t.substr(eq + 1);
      } else if (t.find_first_of("()=") == std::string::npos && k + 1 < tok.size()) {  // Xyce's ".IC NODE VALUE …"
        node = t, value = lower(tok[++k]);
      } else {
        fail(l, tok[0] + " V(NODE)=VALUE … (or Xyce's NODE VALUE …)", "\"" + tok[k] + "\"");
      }
      if (!value.empty() && value.front() == '{') value = value.substr(1, value.size() - 2);
      const std::string at = node_in(hierarchical(node), prefix, ports);
      node_ic[at] = evaluate(l, value, params, "V(NODE)=VALUE");
      node_ic_where[at] = l.where();
    }
  }

  /// .tran TSTEP TSTOP [TSTART [TMAX]] [UIC]: read for its uic (the initial state of simulate and check) and the
  /// times sources' defaults take; the rest ignored.
  void transient_card(const Line& l, const std::vector<std::string>& tok,
                      const std::map<std::string, Rational>& params) {
    bool uic = false;
    for (std::size_t k = 1; k < tok.size(); ++k) uic = uic || lower(tok[k]) == "uic";
    out.tran = uic ? Netlist::Transient::uic : Netlist::Transient::op;
    out.tran_where = l.where();
    std::vector<std::string> times;  // .tran TSTEP TSTOP [TSTART [TMAX]] [UIC]
    for (std::size_t k = 1; k < tok.size(); ++k)
      if (lower(tok[k]) != "uic") times.push_back(tok[k]);
    try {
      const auto time = [&](const std::string& t) {
        return t.size() > 1 && t.front() == '{'
                   ? Expression(t.substr(1, t.size() - 2), params, &functions, nullptr, 0, dialect).value()
                   : parse_spice_value(t, nullptr, dialect);
      };
      if (times.size() >= 2) {
        out.tran_step = time(times[0]);
        out.tran_stop = time(times[1]);
      }
    } catch (
        const std::invalid_argument&) {  // not needed by the circuit (only by sources' defaults, which then say so)
    }
  }

  void dot_card(const Line& l, const std::vector<std::string>& tok, const std::string& prefix,
                const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params) {
    const std::string head = lower(tok[0]);
    if (head == ".ic" || head == ".dcvolt") {
      initial_conditions(l, tok, prefix, ports, params);
      return;
    }
    if (head == ".tran") transient_card(l, tok, params);
    if (head == ".temp" || ((head == ".options" || head == ".option" || head == ".opt") && !prefix.empty() &&
                            std::any_of(tok.begin(), tok.end(), [](const std::string& t) {
                              return lower(t).rfind("temp=", 0) == 0 || lower(t).rfind("tnom=", 0) == 0;
                            }))) {
      if (!prefix.empty())  // read_temperatures sees the top level only: the circuit's temperature is global
        fail(l, "the circuit's temperature (.temp, .options temp= tnom=) at the deck's top level",
             tok[0] + " inside a .subckt");
    }
    if (head == ".temp") {
      out.warnings.push_back(
          l.where() + ": " + tok[0] +
          ": read for the elements' TC1, TC2 (dcad's elements have no temperature dependence otherwise)" +
          (tok.size() > 2 ? ": a list of temperatures (a sweep): dcad solves at the first" : ""));
      return;
    }
    if (analysis_card(head)) {
      const bool temps = (head == ".options" || head == ".option" || head == ".opt") &&
                         std::any_of(tok.begin(), tok.end(), [](const std::string& t) {
                           return lower(t).rfind("temp=", 0) == 0 || lower(t).rfind("tnom=", 0) == 0;
                         });
      out.warnings.push_back(l.where() + ": ignored " + tok[0] + " (analysis or output card: the circuit is unchanged" +
                             (head == ".tran" ? "; simulate reads its uic for the initial state)"
                              : temps         ? "; its temp= and tnom= are read for TC1, TC2)"
                                              : ")"));
      return;
    }
    if (sweep_card(head)) {
      out.warnings.push_back(l.where() + ": ignored " + tok[0] +
                             " (a sweep or sampling analysis: dcad solves the circuit at the values as written)");
      return;
    }
    if (head == ".model") {  // no element dcad reads takes a model; an element that names one is refused where it is
      out.warnings.push_back(l.where() + ": ignored .model " + (tok.size() > 1 ? tok[1] : std::string()) +
                             " (no R, L, C, K, V or I element uses it)");
      return;
    }
    if (head == ".delete" || head == ".del" || head == ".modify" || head == ".mod" || head == ".fault" ||
        head == ".unfault")
      fail(l, "the circuit as written", tok[0] + " (a command that changes the circuit; write the circuit it leaves)");
    if (head == ".preprocess")
      fail(l, "cards that leave the circuit as written",
           ".preprocess (Xyce: it may add resistors or remove devices; write the circuit as it should be solved)");
    if (head == ".lib")
      fail(l, ".lib FILE SECTION", "\"" + l.text + "\" (a library section is read where it is named)");
    fail(l,
         "an R, L, C, V, I, K or X element, or a card dcad reads (.param, .func, .subckt, .include, .lib, .ic, "
         ".global, analysis and output cards)",
         "unknown card " + tok[0] + " (dcad cannot tell whether it changes the circuit: remove it if it does not)");
  }

  void instance(const Line& l, const std::vector<std::string>& tok_in, const std::string& prefix,
                const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params,
                int depth, const std::string& scope) {
    if (depth >= 32) fail(l, "subcircuits nested at most 32 deep", "deeper (a recursive .subckt?)");
    std::vector<std::string> tok;
    for (const std::string& t : tok_in) {  // "(a b)" node lists as gnucap writes them
      std::string u = t;
      if (&t != &tok_in.front() && !u.empty() && u.front() == '(') u.erase(0, 1);
      if (!u.empty() && u.back() == ')' && u.find('(') == std::string::npos && u.find('{') == std::string::npos)
        u.pop_back();
      if (!u.empty()) tok.push_back(u);
    }
    std::size_t k = tok.size();
    while (k > 1 && tok[k - 1].find('=') != std::string::npos) --k;  // trailing name=value overrides
    if (k > 1 && lower(tok[k - 1]) == "params:") --k;
    if (k < 2) fail(l, "XNAME NODE… SUBCKT", "\"" + l.text + "\"");
    const std::string sub = lower(tok[k - 1]);
    auto it = subckts.end();  // the innermost definition visible from `scope`: its own nested ones, then its parents'
    for (std::string sc = scope;; sc.erase(sc.rfind('/'))) {
      it = subckts.find(sc + "/" + sub);
      if (it != subckts.end() || sc.empty()) break;
    }
    if (it == subckts.end())
      fail(l, "a subcircuit defined by .subckt",
           "unknown subcircuit \"" + tok[k - 1] + "\" in " + tok[0] +
               " (define it with .subckt … .ends, or .include the file that does)");
    const Subcircuit& s = it->second;
    if (k - 2 != s.ports.size())
      fail(l, std::to_string(s.ports.size()) + " nodes for " + tok[k - 1] + " (" + s.where.where() + ")",
           std::to_string(k - 2) + " in " + tok[0]);
    std::map<std::string, std::string> inner;
    for (std::size_t p = 0; p < s.ports.size(); ++p) {
      const std::string node = node_in(tok[1 + p], prefix, ports);
      const auto [at, fresh] = inner.emplace(s.ports[p], node);
      if (!fresh && at->second != node) {  // Xyce: "Duplicate nodes in .subckt … point to different nodes" (BUG_784)
        const std::size_t q =
            static_cast<std::size_t>(std::find(s.ports.begin(), s.ports.end(), s.ports[p]) - s.ports.begin());
        fail(l, "one node for port " + s.ports[p] + ", named twice in .subckt " + s.name + " (" + s.where.where() + ")",
             "nodes " + tok[1 + q] + " and " + tok[1 + p] + " in " + tok[0]);
      }
    }
    // the caller's parameters, then the subcircuit's defaults (which may use them), then this instance's
    // overrides (in the caller's scope), then the subcircuit's own .param lines but for overridden names
    std::map<std::string, Rational> local = params;
    for (const auto& [name, expr] : s.defaults) local[name] = evaluate(s.where, expr, local, "a parameter default");
    std::size_t first_override = k;
    if (first_override < tok.size() && lower(tok[first_override]) == "params:") ++first_override;
    std::set<std::string> overridden;
    for (const auto& [name, expr] : param_pairs(tok, first_override, l)) {
      local[name] = evaluate(l, expr, params_with(params, local), "a parameter value");
      overridden.insert(name);
    }
    for (const Line& b : s.body)
      if (is_param_card(lower(tokens(b.text)[0])) || lower(tokens(b.text)[0]) == ".func")
        read_params(b, local, &overridden);
    for (const Line& b : s.body)
      if (lower(tokens(b.text)[0]) == ".global")
        for (const std::string& g : tokens(b.text))
          if (g[0] != '.') globals.insert(lower(g));
    expand(s.body, prefix + lower(tok[0]) + ".", inner, local, depth + 1, s.key);
  }

  /// An instance's overrides are written in the caller's scope; the subcircuit's defaults are visible too
  /// (ngspice evaluates `X1 … w={2*w0}` with the caller's parameters first).
  static std::map<std::string, Rational> params_with(const std::map<std::string, Rational>& caller,
                                                     const std::map<std::string, Rational>& local) {
    std::map<std::string, Rational> m = local;
    for (const auto& [k, v] : caller) m[k] = v;
    return m;
  }

  /// gnucap evaluates a value written without braces as an expression over the parameters (`r2 2 0 c+1`,
  /// `td1=delay/10`); ngspice refuses it (it wants `{c+1}`), so reading it never changes a deck ngspice
  /// reads.  Only text that starts with a name (ngspice reads "2*p" as 2: refused as before) and has an
  /// operator, every name a parameter or a function; said in a note.
  std::optional<Rational> bare_expression(const Line& l, const std::string& text,
                                          const std::map<std::string, Rational>& params, const std::string& name) {
    if (text.empty() || !(std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_') ||
        text.find_first_of("+-*/^()") == std::string::npos || text.find_first_of("\"'{}") != std::string::npos)
      return std::nullopt;
    try {
      Expression(text, params, &functions, nullptr, 0, dialect).value();
    } catch (const std::invalid_argument&) {
      return std::nullopt;
    }
    const Rational v = evaluate(l, text, params, "a value");  // its notes (irrational, nominal) as for {…}
    out.warnings.push_back(l.where() + ": " + name + ": \"" + text + "\" read as the expression {" + text +
                           "} = " + shown(v) + " (gnucap's value without braces; ngspice wants {…})");
    return v;
  }

  /// ngspice's restemp.c, captemp.c, indtemp.c (and Xyce's): the value at the device's temperature is
  /// V0 (1 + TC1 ΔT + TC2 ΔT²), ΔT = T − TNOM; T is the instance's TEMP=, else the circuit's (.temp, .options
  /// temp=; 27 °C) plus DTEMP=; TNOM the instance's, else .options tnom= (27 °C).  Exact; said in a note.
  Rational temperature_factor(const Line& l, const std::string& name, const std::optional<Rational>& tc1,
                              const std::optional<Rational>& tc2, const std::optional<Rational>& device_temp,
                              const std::optional<Rational>& dtemp, const std::optional<Rational>& device_tnom) {
    const Rational t = device_temp ? *device_temp : temperature.value_or(Rational(27)) + dtemp.value_or(Rational(0));
    if (device_temp && dtemp)  // ngspice's restemp.c: "Instance temperature specified, dtemp ignored"
      out.warnings.push_back(l.where() + ": " + name + ": DTEMP= ignored where TEMP= is given (as ngspice)");
    const Rational dt = t - device_tnom.value_or(tnom);
    const Rational factor = 1 + tc1.value_or(Rational(0)) * dt + tc2.value_or(Rational(0)) * dt * dt;
    if (factor <= 0)
      fail(l, "a positive temperature factor 1 + TC1 dT + TC2 dT^2 for " + name,
           shown(factor) + " at dT = " + shown(dt) + " C");
    out.warnings.push_back(l.where() + ": " + name + ": at " + shown(t) + " C (TNOM " + shown(t - dt) +
                           " C) its temperature coefficients " +
                           (dt == 0 ? "change nothing" : "scale its value by " + shown(factor)));
    return factor;
  }

  /// gnucap writes the nodes in parentheses, "(a b)" or "( a b )": ngspice reads them as separators too.
  static std::vector<std::string> without_node_parentheses(const std::vector<std::string>& tok) {
    std::vector<std::string> t{tok[0]};
    std::size_t k = 1;
    for (std::size_t got = 0; k < tok.size() && got < 2; ++k) {
      std::string u = tok[k];
      if (got == 0 && !u.empty() && u.front() == '(') u.erase(0, 1);
      if (got == 1 && !u.empty() && u.back() == ')' && u.find('(') == std::string::npos) u.pop_back();
      if (u.empty() || u == ")") continue;
      t.push_back(u);
      ++got;
    }
    if (k < tok.size() && tok[k] == ")") ++k;
    t.insert(t.end(), tok.begin() + static_cast<long>(k), tok.end());
    return t;
  }

  using Number = std::function<Rational(const std::string&, const std::string&)>;
  /// K L1 L2 … k: a coupling of every pair of the listed inductors (Xyce; two of them as in ngspice), |k| <= 1.
  void coupling_element(const Line& l, const std::vector<std::string>& tok, const std::string& name,
                        const std::string& prefix, const std::vector<std::string>& inductors, const Number& number) {
    if (tok.size() < 4) fail(l, "KNAME LX LY COUPLING", "\"" + l.text + "\"");
    const Rational k = number(tok.back(), "a coupling coefficient");
    if (k < -1 || k > 1)
      fail(l,
           "a coupling coefficient with |k| <= 1 for " + name +
               (prefix.empty() ? "" : " (instance " + prefix.substr(0, prefix.size() - 1) + ")"),
           "k = " + shown(k) + (tok.back().front() == '{' ? " from " + tok.back() : std::string()));
    for (std::size_t a = 0; a < inductors.size(); ++a)
      for (std::size_t b = a + 1; b < inductors.size(); ++b)
        couplings.push_back({l, name, inductors[a], inductors[b], k});
  }
  /// A V or I element: its waveform (the source's own words after the nodes), a 0-volt V a wire.
  void source_element(const Line& l, const std::vector<std::string>& tok, char kind, const std::string& name,
                      const Number& number, reference::Branch<Rational>& b, reference::RlcBranch<Rational>& rb) {
    std::string spec;
    for (std::size_t k = 3; k < tok.size(); ++k) spec += (k > 3 ? " " : "") + tok[k];
    Waveform w;
    try {
      w = parse_waveform(
          pwl_from_file(l, spec, dialect), [&](const std::string& t) { return number(t, "a source value"); }, generator,
          dialect == Dialect::gnucap);
    } catch (const std::invalid_argument& e) {
      throw InputError(l.where() + ": " + name + ": " + e.what());  // the parser's own "expected …, found …"
    }
    w.element = name;
    if (!w.ignored.empty())
      out.warnings.push_back(l.where() + ": " + name + ": not part of the transient, ignored: " + w.ignored);
    if (w.is_sffm())  // SPICE3's VO + VA sin(2π FC t + MDI sin(2π FS t)); ngspice 43 on holds 0 up to TD = 0 and
                      // limits MDI
      out.warnings.push_back(
          l.where() + ": " + name +
          ": SFFM read as SPICE3, ngspice 39 and Xyce read it (VO + VA sin(2 pi FC t + MDI sin(2 pi FS t)))" +
          (w.p[0] != 0 ? "; ngspice 43 on has 0, not VO, at t = 0 (its operating point differs)" : "") +
          (w.p[3] > w.p[2] / w.p[4] ? "; ngspice 43 on limits MDI to FC/FS" : "") +
          "; simulate and check refuse it (no finite exosystem)");
    b.kind = reference::BranchKind::empty;
    if (kind == 'v' && w.kind == Waveform::Kind::dc && w.p[0] == 0) {
      rb.kind = reference::RlcKind::wire;  // a zero-volt source is a wire (an ammeter)
    } else {
      rb.kind = kind == 'v' ? reference::RlcKind::voltage : reference::RlcKind::current;
      rb.source = out.waveforms.size();
      out.waveforms.push_back(w);
      source_lines.push_back(l);
      out.forced = true;
    }
    out.circuit.branches.push_back(b);
    out.rlc.branches.push_back(rb);
    out.initial.push_back(std::nullopt);
    out.where.push_back(l.where());
  }

  /// An R, L or C element's value: positional or a keyword (r=, c=, l=, value=), then IC=, a multiplier M= and
  /// temperature coefficients (which change nothing at the nominal temperature); `ic` set from IC=.
  Rational passive_value(const Line& l, std::vector<std::string> tok, char kind, const std::string& name,
                         const Number& number, std::optional<Rational>& ic) {
    if (tok.size() > 4 && gnucap_mode(tok[3]))
      tok = transient_value(l, tok, name, [&](const std::string& t) { return number(t, "a value"); });
    // the value: positional, or as a keyword (r=, c=, l=, value=); then IC=, a multiplier M= and temperature
    // coefficients, which change nothing at the nominal temperature
    const std::string value_key = kind == 'r' ? "r=" : kind == 'c' ? "c=" : "l=";
    std::optional<Rational> value;
    std::optional<Rational> multiplier;
    std::optional<Rational> tc1, tc2, device_temp, dtemp,
        device_tnom;  // ngspice's and Xyce's instance temperature parameters
    for (std::size_t k = 3; k < tok.size(); ++k) {
      const std::string t = lower(tok[k]);
      const std::size_t eq = t.find('=');
      const std::string key = eq == std::string::npos ? "" : t.substr(0, eq + 1);
      if (key.empty() && !value && k == 3) {
        value = number(tok[k], "a value (number with optional SPICE suffix, or {expression})");
      } else if ((key == value_key || key == "value=") && !value) {
        value = number(tok[k].substr(eq + 1), "a value");
      } else if (key == "ic=" && kind != 'r') {
        ic = number(tok[k].substr(3), "IC=value");
      } else if (key == "m=") {
        multiplier = number(tok[k].substr(2), "M=multiplier");
        if (*multiplier <= 0) fail(l, "a multiplier M > 0", "M = " + shown(*multiplier));
      } else if (key == "tc=") {  // TC=TC1 (Xyce) or TC=TC1,TC2 (PSpice)
        const std::string list = tok[k].substr(eq + 1);
        const std::size_t comma = list.find(',');
        tc1 = number(list.substr(0, comma), "TC=TC1[,TC2]");
        if (comma != std::string::npos) tc2 = number(list.substr(comma + 1), "TC=TC1[,TC2]");
      } else if (key == "tc1=" || key == "tc2=" || key == "temp=" || key == "dtemp=" || key == "tnom=") {
        std::optional<Rational>& slot = key == "tc1="     ? tc1
                                        : key == "tc2="   ? tc2
                                        : key == "temp="  ? device_temp
                                        : key == "dtemp=" ? dtemp
                                                          : device_tnom;
        slot = number(tok[k].substr(eq + 1), tok[k].substr(0, eq + 1) + "value");
      } else if (kind == 'r' &&
                 (key == "ac=" || key == "noisy=")) {  // ngspice: the AC analysis' resistance, the noise switch
        number(tok[k].substr(eq + 1), key == "ac=" ? "AC=resistance" : "NOISY=0 or 1");
        out.warnings.push_back(l.where() + ": " + name + ": " + tok[k] +
                               " ignored (ngspice uses it in .ac or .noise only, not in the transient)");
      } else {
        fail(l,
             kind == 'r' ? "nothing, M=, TC1=, TC2=, AC=, NOISY= after the resistance"
                         : "nothing, IC=, M= after the value",
             "\"" + tok[k] + "\"");
      }
    }
    if (!value) fail(l, "a value (positional or " + value_key + "VALUE)", "none in \"" + l.text + "\"");
    Rational v = *value;
    if (multiplier) v = kind == 'c' ? Rational(v * *multiplier) : Rational(v / *multiplier);  // M parallel copies
    if (tc1 || tc2) v *= temperature_factor(l, name, tc1, tc2, device_temp, dtemp, device_tnom);
    return v;
  }

  /// An R, L or C branch of value `value_` in both graphs (R: empty in D_Δ's, L = 0 a wire), with its warnings.
  void passive_kind(const Line& l, char kind, const std::string& name, const Rational& value_,
                    reference::Branch<Rational>& b, reference::RlcBranch<Rational>& rb) {
    rb.value = value_;
    if (kind == 'r') {
      if (value_ < 0)
        out.warnings.push_back(l.where() + ": negative resistance " + name + " is not physical (it supplies energy)");
      if (boost::multiprecision::abs(value_) <
          Rational(1, 1000000000000LL)) {  // as ngspice reads it (resparam.c: RESMIN)
        const Rational floor_value = value_ < 0 ? Rational(-1, 1000000000000LL) : Rational(1, 1000000000000LL);
        out.warnings.push_back(l.where() + ": " + name + ": R = " + shown(value_) + " read as " + shown(floor_value) +
                               " Ohm, as ngspice sets a resistance below 1e-12 (a resistor, not a wire: write a 0-volt "
                               "V source for a wire)");
        rb.value = floor_value;
      }
      rb.kind = reference::RlcKind::resistor;
      out.forced = true;
      b.kind = reference::BranchKind::empty;
    } else if (kind == 'l') {
      b.kind = reference::BranchKind::inductor;
      b.value = value_;
      rb.kind = reference::RlcKind::inductor;
      if (value_ < 0)
        out.warnings.push_back(l.where() + ": negative inductance " + name + " is not physical (CEF Remark 6.7)");
    } else {
      if (value_ == 0)
        fail(l, "a nonzero capacitance (C = 0 is an open branch, CEF §6)",
             "C = 0 for " + name + " (remove it: an open branch carries no current)");
      b.kind = reference::BranchKind::capacitor;
      b.value = value_;
      rb.kind = reference::RlcKind::capacitor;
      if (value_ < 0)
        out.warnings.push_back(l.where() + ": negative capacitance " + name + " is not physical (CEF Remark 6.7)");
    }
    if (kind == 'l' && value_ == 0) {
      b.kind = reference::BranchKind::empty;  // L = 0: a wire
      rb.kind = reference::RlcKind::wire;
    }
  }

  void element(const Line& l, std::vector<std::string> tok, const std::string& prefix,
               const std::map<std::string, std::string>& ports, const std::map<std::string, Rational>& params) {
    const std::string head = lower(tok[0]);
    const char kind = head[0];
    if (std::string("lcvrik").find(kind) == std::string::npos)
      fail(l, "an L, C, R, V, I, K or X element", "element " + tok[0] + " (not supported)");
    if (kind != 'k' && tok.size() >= 3) tok = without_node_parentheses(tok);
    if (tok.size() < 3 || (tok.size() < 4 && !(kind == 'v' || kind == 'i')))
      fail(l, "NAME NODE+ NODE- VALUE", "\"" + l.text + "\"" + (tok.size() == 3 ? " (no value after the nodes)" : ""));
    // ngspice's tokenizer (INPgetTok, INPgetNetTok) ends a name at , ( ) = and reads quotes and braces as
    // syntax: "v2, 2 0 1" is V2 there, "v4 , 0 1" a different source.  Such a name is refused, not guessed.
    for (std::size_t k = 0; k < (kind == 'k' ? 1u : 3u); ++k)
      if (tok[k].find_first_of(",()=\"'{}") != std::string::npos)
        fail(l, k == 0 ? "an element name without , ( ) = \" ' { }" : "a node name without , ( ) = \" ' { }",
             "\"" + tok[k] + "\" (ngspice reads these characters as separators or syntax: rename it)");
    // ngspice's hierarchical name: kind letter, instance path, element name (l.x1.l1)
    const auto hier = [&](const std::string& t) {
      return prefix.empty() ? t : std::string(1, t[0]) + "." + prefix + lower(t);
    };
    const std::string name = hier(tok[0]);
    const std::string key = lower(name);
    if (names.count(key))
      fail(l, "a new element name", "duplicate " + name + " (first at " + out_lines[names[key]] + ")");
    const auto number = [&](const std::string& text, const std::string& what) {
      if (!text.empty() && text.front() == '{') {
        if (text.back() != '}') fail(l, what, "\"" + text + "\" (no closing '}')");
        return evaluate(l, text.substr(1, text.size() - 2), params, what);
      }
      const std::string t = lower(text);
      if (!t.empty() && (std::isalpha(static_cast<unsigned char>(t[0])) || t[0] == '_') && params.count(t))
        return params.at(t);  // a parameter's name without braces (Xyce, and ngspice's numparam)
      try {
        std::string ignored;
        const Rational v = parse_spice_value(text, &ignored, dialect);
        if (!ignored.empty())
          out.warnings.push_back(l.where() + ": " + name + ": \"" + text + "\" read as " + shown(v) +
                                 " (the letters \"" + ignored +
                                 "\" are neither a scale factor nor a unit; ngspice ignores them too)");
        return v;
      } catch (const std::invalid_argument& e) {
        if (const auto v = bare_expression(l, text, params, name)) return *v;
        refuse_value(l, what, text, e.what());
      }
    };
    if (kind == 'k') {
      std::vector<std::string> inductors;
      for (std::size_t a = 1; a + 1 < tok.size(); ++a) inductors.push_back(lower(hier(tok[a])));
      coupling_element(l, tok, name, prefix, inductors, number);
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
      source_element(l, tok, kind, name, number, b, rb);
      return;
    }
    std::optional<Rational> ic;
    passive_kind(l, kind, name, passive_value(l, tok, kind, name, number, ic), b, rb);
    out.circuit.branches.push_back(b);
    out.rlc.branches.push_back(rb);
    out.initial.push_back(ic);
    out.where.push_back(l.where());
  }

 public:
  std::vector<Line> source_lines;      ///< the line of each waveform (for completing its defaults)
  std::vector<std::string> out_lines;  ///< file:line of each branch
};

}  // namespace

/// det of a square matrix of rationals, by elimination with row exchanges.
static Rational determinant(std::vector<std::vector<Rational>> a) {
  const std::size_t n = a.size();
  Rational det = 1;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t p = i;
    while (p < n && a[p][i] == 0) ++p;
    if (p == n) return 0;
    if (p != i) std::swap(a[p], a[i]), det = -det;
    det *= a[i][i];
    for (std::size_t r = i + 1; r < n; ++r)
      if (a[r][i] != 0) {
        const Rational m = a[r][i] / a[i][i];
        for (std::size_t c = i; c < n; ++c) a[r][c] -= m * a[i][c];
      }
  }
  return det;
}

static Rational product_of_values(const Netlist& out, const std::vector<std::size_t>& members) {
  Rational p = 1;
  for (std::size_t i : members) p *= out.rlc.branches[i].value;
  return p;
}

/// Every group of coupled inductors (all L > 0) has a positive semidefinite inductance matrix, decided
/// exactly: Φ = D K D with D = diag(√L_i) and K the coupling coefficients (1 on the diagonal), so Φ is
/// semidefinite iff K is — symmetric elimination on K in rationals, a zero pivot allowed only with a zero
/// row (k = 1 is a perfect transformer).  Every |k| < 1 does not suffice (three inductors with k12 = 0.75,
/// k13 = 0.8, k23 = 0: det K = -0.2025).  A group that is not is recorded (Netlist::indefinite_inductance) and warned
/// about: its energy ½ iᵀ Φ i is unbounded below, so `simulate` and `check` refuse it.
static void check_inductance(Netlist& out, const Flattener& f) {
  const std::size_t nb = out.rlc.branches.size();
  std::vector<std::size_t> group(nb);
  for (std::size_t i = 0; i < nb; ++i) group[i] = i;
  const auto root = [&](std::size_t i) {
    while (group[i] != i) i = group[i] = group[group[i]];
    return i;
  };
  for (const auto& mu : out.rlc.mutuals) group[root(mu.a)] = root(mu.b);
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (const auto& mu : out.rlc.mutuals) groups[root(mu.a)];
  for (std::size_t i = 0; i < nb; ++i)
    if (groups.count(root(i))) groups[root(i)].push_back(i);
  for (const auto& [r, members] : groups) {
    bool positive = true;
    for (std::size_t i : members) positive = positive && out.rlc.branches[i].value > 0;
    if (!positive) continue;  // a negative L is warned about as such (CEF Remark 6.7)
    const std::size_t g = members.size();
    std::vector<std::vector<Rational>> k(g, std::vector<Rational>(g, Rational(0)));
    std::vector<std::string> pairs;
    for (std::size_t i = 0; i < g; ++i) k[i][i] = 1;
    for (std::size_t c = 0; c < out.rlc.mutuals.size(); ++c) {
      const auto& mu = out.rlc.mutuals[c];
      const auto ia = std::find(members.begin(), members.end(), mu.a),
                 ib = std::find(members.begin(), members.end(), mu.b);
      if (ia == members.end() || !mu.k) continue;
      const std::size_t a = static_cast<std::size_t>(ia - members.begin()),
                        b = static_cast<std::size_t>(ib - members.begin());
      k[a][b] = k[b][a] = *mu.k;
      pairs.push_back(f.couplings[c].name + " = " + shown(*mu.k));
    }
    const std::vector<std::vector<Rational>> k0 = k;
    bool semidefinite = true;
    for (std::size_t i = 0; i < g && semidefinite; ++i) {
      const Rational d = k[i][i];
      if (d < 0) semidefinite = false;
      if (d <= 0) {
        for (std::size_t j = i + 1; j < g; ++j) semidefinite = semidefinite && k[i][j] == 0;
        continue;
      }
      for (std::size_t r2 = i + 1; r2 < g; ++r2)
        if (k[r2][i] != 0) {
          const Rational m = k[r2][i] / d;
          for (std::size_t c2 = i; c2 < g; ++c2) k[r2][c2] -= m * k[i][c2];
        }
    }
    if (semidefinite) continue;
    const Rational det = determinant(k0);
    std::string names;
    for (std::size_t i : members) names += (names.empty() ? "" : ", ") + out.rlc.branches[i].name;
    std::string couplings;
    for (const std::string& p : pairs) couplings += (couplings.empty() ? "" : ", ") + p;
    const std::string what = "the coupled inductors " + names +
                             " have an inductance matrix that is not positive semidefinite (" + couplings +
                             ": every |k| <= 1, yet the matrix of coupling coefficients has a negative eigenvalue" +
                             ", its determinant " + shown(det) + ", the inductance matrix's " +
                             shown(det * product_of_values(out, members)) +
                             "): the magnetic energy is unbounded below, no physical transformer has these couplings";
    out.warnings.push_back(out.where[members.front()] + ": " + what);
    if (out.indefinite_inductance.empty()) out.indefinite_inductance = out.where[members.front()] + ": " + what;
  }
}

/// K elements: M = k √(L_a L_b), exact when k² L_a L_b is the square of a rational, otherwise
/// truncated to 80 decimal places (with a warning).
static void resolve_couplings(Netlist& out, const Flattener& f) {
  for (const auto& c : f.couplings) {
    const auto find = [&](const std::string& written) -> std::size_t {
      std::string n = written;
      const std::size_t colon = n.rfind(':');  // Xyce's x1:l1 (x1:x2:l1): element l1 of instance x1, named l.x1.l1
      if (colon != std::string::npos && colon + 1 < n.size())
        n = n.substr(colon + 1, 1) + "." + hierarchical(n.substr(0, colon)) + "." + n.substr(colon + 1);
      for (std::size_t i = 0; i < out.rlc.branches.size(); ++i)
        if (lower(out.rlc.branches[i].name) == n) {
          if (out.rlc.branches[i].kind != reference::RlcKind::inductor)
            throw InputError(c.line.where() + ": expected an inductor for " + c.name + ", found " +
                             out.rlc.branches[i].name);
          return i;
        }
      throw InputError(c.line.where() + ": expected an inductor of the circuit for " + c.name + ", found \"" + written +
                       "\"");
    };
    const std::size_t a = find(c.a), b = find(c.b);
    if (a == b)
      throw InputError(c.line.where() + ": expected two different inductors for " + c.name + ", found one twice");
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
      m = Rational(boost::multiprecision::sqrt(mpz_int(num * scale * scale / den)),
                   scale);  // 80 digits after the point, truncated
      out.warnings.push_back(c.line.where() + ": " + c.name +
                             ": M = k*sqrt(Lx*Ly) is irrational; used it to 80 decimal places");
      rounded = true;
    }
    if (c.k < 0) m = -m;
    bool dup = false;
    for (auto& mu : out.rlc.mutuals)
      if ((mu.a == a && mu.b == b) || (mu.a == b && mu.b == a)) dup = true;
    if (dup)
      throw InputError(c.line.where() + ": expected one coupling per pair of inductors, found a second one (" + c.name +
                       ")");
    out.rlc.mutuals.push_back({a, b, m, c.k, rounded});
    out.forced = true;
  }
  check_inductance(out, f);
}

namespace {

Netlist flatten(const std::string& file, Reader& reader, Dialect dialect);

}  // namespace

Netlist read_netlist(const std::string& file, const ReadOptions& options) {
  Reader reader;
  reader.dialect = options.dialect;
  reader.read(file, true, "", 0, nullptr);
  if (reader.title.empty() && reader.lines.empty()) {
    std::ifstream probe(file);
    if (probe.peek() == std::ifstream::traits_type::eof())
      throw InputError(file + ":1: expected a title line and LC elements, found an empty file");
  }
  return flatten(file, reader, options.dialect);
}

Netlist read_netlist_text(const std::string& text, const std::string& name, const std::string& directory,
                          const ReadOptions& options) {
  if (text.empty()) throw InputError(name + ":1: expected a title line and LC elements, found an empty deck");
  std::istringstream in(text);
  Reader reader;
  reader.dialect = options.dialect;
  reader.read(name, true, "", 0, nullptr, &in, directory);
  return flatten(name, reader, options.dialect);
}

namespace {

Netlist flatten(const std::string& file, Reader& reader, Dialect dialect) {
  Netlist out;
  out.file = file;
  out.title = reader.title;
  out.warnings = reader.warnings;
  Flattener f(out, dialect);
  f.run(reader.lines);
  if (out.circuit.branches.empty())
    throw InputError(file + ":" +
                     (reader.lines.empty() ? std::string("1") : reader.lines.back().where().substr(file.size() + 1)) +
                     ": expected at least one L, C or V element, found none");
  out.circuit.nodes = out.node_names.size();
  out.rlc.nodes = out.circuit.nodes;
  out.rlc.sources = out.waveforms.size();
  for (std::size_t j = 0; j < out.waveforms.size(); ++j) try {  // ngspice's defaults from .tran's TSTEP and TSTOP
      out.waveforms[j].complete(out.tran_step, out.tran_stop);
    } catch (const std::invalid_argument& e) {
      throw InputError(f.source_lines[j].where() + ": " + out.waveforms[j].element + ": " + e.what());
    }
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
    if (node != "0" &&
        at == out.node_names.end()) {  // ngspice: "IC on non-existent node - bleem, ignored"; Xyce warns too
      out.warnings.push_back(f.node_ic_where.at(node) + ": .ic v(" + node +
                             ") ignored: no such node in the circuit (ngspice and Xyce ignore it too)");
      continue;
    }
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
  return Units::nearest(mean_exponent(n, reference::BranchKind::inductor),
                        mean_exponent(n, reference::BranchKind::capacitor));
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
