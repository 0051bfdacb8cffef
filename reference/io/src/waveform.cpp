#include "dcad/io/waveform.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <optional>
#include <stdexcept>

namespace dcad::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

double d(const Rational& x) { return x.convert_to<double>(); }
double floor_of(double x) { return std::floor(x); }
Rational floor_of(const Rational& x) {
  using boost::multiprecision::mpz_int;
  const mpz_int n = boost::multiprecision::numerator(x), q = boost::multiprecision::denominator(x);
  mpz_int f = n / q;  // truncates toward zero
  if (f * q > n) f -= 1;
  return Rational(f);
}

constexpr double kPi = 3.141592653589793238462643383279502884;

}  // namespace

namespace {

/// The words of a source specification: commas and parentheses are separators, each parenthesis kept as
/// a word of its own; "KEY=VALUE" stays one word (the reader glued "KEY = VALUE").
std::vector<std::string> spec_words(const std::string& spec) {
  std::vector<std::string> out;
  std::string t;
  int depth = 0;  // inside {…}: one word
  for (char ch : spec) {
    if (ch == '{') ++depth;
    if (ch == '}') --depth;
    const bool sep =
        depth == 0 && (std::isspace(static_cast<unsigned char>(ch)) || ch == ',' || ch == '(' || ch == ')');
    if (!sep) {
      t += ch;
      continue;
    }
    if (!t.empty()) out.push_back(t);
    t.clear();
    if (ch == '(' || ch == ')') out.push_back(std::string(1, ch));
  }
  if (!t.empty()) out.push_back(t);
  return out;
}

bool is_function(const std::string& w) {
  static const std::vector<std::string> fns = {"sin",     "pulse",    "pwl", "exp",       "sffm", "am",
                                               "trnoise", "trrandom", "pat", "generator", "file", "sine"};
  return std::find(fns.begin(), fns.end(), w) != fns.end();
}

bool readable(const std::string& fn) {
  return fn == "sin" || fn == "pulse" || fn == "pwl" || fn == "exp" || fn == "sffm" || fn == "generator";
}

bool is_keyword(const std::string& w) {
  static const std::vector<std::string> kw = {"dc", "ac", "distof1", "distof2", "portnum", "z0", "pwr", "freq"};
  return std::find(kw.begin(), kw.end(), w) != kw.end() || is_function(w);
}

/// gnucap's keyword form of SIN, EXP and PULSE ("sin(freq=1k ampl=1 peak zero)", "exp iv=0 pv=1 td1=1n …",
/// gnucap's apps/bm_sin.cc, bm_exp.cc, bm_pulse.cc): true when the word after the function is one of its keys.
/// A key in braces' sense ("o{ffset}") is any prefix of the name at least as long as its mandatory part.
struct GnucapKey {
  const char* name;
  std::size_t least;  ///< the mandatory prefix's length
};
const std::vector<GnucapKey>& gnucap_keys(const std::string& fn) {
  static const std::vector<GnucapKey> sin = {{"offset", 1},  {"amplitude", 1}, {"frequency", 1}, {"delay", 2},
                                             {"damping", 2}, {"samples", 2},   {"zero", 2},      {"peak", 2},
                                             {"nozero", 6},  {"nopeak", 6}};
  static const std::vector<GnucapKey> exp = {{"iv", 2},  {"pv", 2},   {"td1", 3},   {"tau1", 4},
                                             {"td2", 3}, {"tau2", 4}, {"period", 6}};
  static const std::vector<GnucapKey> pulse = {{"iv", 2},   {"pv", 2},    {"delay", 5}, {"rise", 4},
                                               {"fall", 4}, {"width", 5}, {"period", 6}};
  static const std::vector<GnucapKey> sffm = {{"offset", 6}, {"amplitude", 9}, {"carrier", 7}, {"modindex", 8},
                                              {"signal", 6}, {"samples", 7},   {"zero", 4},    {"peak", 4},
                                              {"nozero", 6}, {"nopeak", 6}};
  static const std::vector<GnucapKey> none;
  return fn == "sin" ? sin : fn == "exp" ? exp : fn == "pulse" ? pulse : fn == "sffm" ? sffm : none;
}
std::optional<std::string> gnucap_key(const std::string& fn, const std::string& word) {
  const std::string key = lower(word.substr(0, word.find('=')));
  for (const GnucapKey& k : gnucap_keys(fn))
    if (key.size() >= k.least && std::string(k.name).compare(0, key.size(), key) == 0) return std::string(k.name);
  return std::nullopt;
}

/// gnucap's PULSE (bm_pulse.cc's tr_eval): IV up to DELAY, a ramp over RISE, PV for WIDTH, a ramp over FALL, IV
/// after, the whole repeated every PERIOD (fmod, as SPICE's PULSE); WIDTH or PERIOD 0 or missing is forever.
/// Without a period it is the PWL (0 IV) (DELAY IV) (DELAY+RISE PV) [(…+WIDTH PV) (…+FALL IV)]; with one, SPICE's
/// PULSE of the same values, which evaluates a period alike — a period that cuts the pulse short is a step
/// where the run reaches it, refused there (Waveform::breakpoints).  A RISE 0, or a FALL 0 that is reached, is
/// a step: two PWL points at one time, or a PULSE with TR or TF 0 (Waveform::step_at).
template <class Value, class Refuse>
void gnucap_pulse(std::string& fn, const Value& value, const Refuse& refuse, std::vector<Rational>& args) {
  if (!value("iv") || !value("pv")) refuse("no iv or pv (gnucap then takes a value of its own)", "iv=V1 pv=V2");
  const Rational iv = *value("iv"), pv = *value("pv");
  const Rational delay = value("delay").value_or(0), rise = value("rise").value_or(0);
  const Rational fall = value("fall").value_or(0), width = value("width").value_or(0);
  const Rational period = value("period").value_or(0);
  for (const Rational* x : {&delay, &rise, &fall, &width, &period})
    if (*x < 0) refuse("a negative time " + x->str(), "times >= 0");
  if (iv == pv) {  // a constant
    args = {0, iv};
    fn = "pwl";
    return;
  }
  const Rational held = width == 0 && period != 0 ? period : width;  // PV up to the period's end
  if (period != 0) {
    const bool falls = rise + held < period;  // else the period ends before the fall
    if (rise == 0 || (fall == 0 && falls))
      refuse("rise or fall 0 with period=" + period.str() + " (a step every period)", "rise and fall > 0");
    args = {iv, pv, delay, rise, fall == 0 && !falls ? rise : fall, held, period};  // a FALL 0 unreached: any
    return;
  }
  args = {0, iv};
  if (delay > 0) args.insert(args.end(), {delay, iv});
  args.insert(args.end(), {delay + rise, pv});
  if (width != 0) args.insert(args.end(), {delay + rise + width, pv, delay + rise + width + fall, iv});
  fn = "pwl";
}

/// gnucap's meaning of a SIN, EXP or PULSE whose values are `got` (KEY, VALUE), keyword or positional alike
/// (apps/bm_sin.cc, bm_exp.cc, bm_pulse.cc: parse_numlist fills the keys in their order, and the defaults are
/// gnucap's own — no TSTEP or TSTOP).  gnucap evaluates SIN as OFFSET + AMPLITUDE sin(2π FREQUENCY (t − DELAY))
/// e^{−(t−DELAY) DAMPING} after DELAY (OFFSET before) — SPICE's SIN with PHASE 0 — and EXP as SPICE's
/// EXP(IV PV TD1 TAU1 TD2 TAU2) when TD1 <= TD2 and no PERIOD.  PULSE is IV up to DELAY, then RISE, WIDTH, FALL
/// with RISE = FALL = 0 (a step) and WIDTH = PERIOD = forever by default, 0 meaning forever too: SPICE's PULSE
/// when every piece is finite, else the PWL it is.  Sets `fn` and `args` to the SPICE form; throws where gnucap's
/// meaning is not one dcad's exact flows take (a step, a repetition, a frequency taken from the analysis).
void gnucap_meaning(std::string& fn, const std::vector<std::pair<std::string, Rational>>& got, const std::string& spec,
                    std::vector<Rational>& args) {
  const auto value = [&](const char* key) -> std::optional<Rational> {
    for (const auto& g : got)
      if (g.first == key) return g.second;
    return std::nullopt;
  };
  const auto refuse = [&](const std::string& why, const std::string& instead) {
    throw std::invalid_argument("expected gnucap's " + fn + " in a form with an exact transient, found " + why +
                                " in \"" + spec + "\": write " + instead);
  };
  if (fn == "sin") {
    if (!value("frequency")) refuse("no frequency (gnucap then takes the analysis' frequency)", "frequency=F");
    args = {value("offset").value_or(0), value("amplitude").value_or(1), *value("frequency"),
            value("delay").value_or(0),  value("damping").value_or(0),   0};
    if (args[2] < 0)
      throw std::invalid_argument("expected frequency >= 0, found " + args[2].str() + " in \"" + spec + "\"");
  } else if (fn == "exp") {
    if (!value("iv") || !value("pv")) refuse("no iv= or pv= (gnucap then takes a value of its own)", "iv=V1 pv=V2");
    const Rational td1 = value("td1").value_or(0), td2 = value("td2").value_or(0);
    const Rational tau1 = value("tau1").value_or(0), tau2 = value("tau2").value_or(0);
    if (!(tau1 > 0) || !(tau2 > 0)) refuse("tau1 or tau2 not > 0 (a step)", "tau1 and tau2 > 0");
    if (td2 < td1) refuse("td2 < td1 (gnucap's second exponential starts first; SPICE's EXP does not)", "td2 >= td1");
    if (td1 < 0) refuse("td1 < 0", "td1 >= 0");
    args = {*value("iv"), *value("pv"), td1, tau1, td2, tau2};
    if (const std::optional<Rational> period = value("period")) {  // bm_exp.cc: started again every period, summed
      if (!(*period > 0)) refuse("period=" + period->str() + " (gnucap's sum over periods never ends)", "period > 0");
      args.push_back(*period);
    }
  } else if (fn ==
             "sffm") {  // bm_sffm.cc: offset + amplitude sin(2π carrier t + modindex sin(2π signal t)), SPICE's SFFM
    if (!value("carrier") || !value("modindex") || !value("signal"))
      refuse("no carrier=, modindex= or signal= (gnucap has no default)", "all three");
    args = {value("offset").value_or(0), value("amplitude").value_or(1), *value("carrier"), *value("modindex"),
            *value("signal")};
  } else {
    gnucap_pulse(fn, value, refuse, args);
  }
}

/// Reads gnucap's keyword form from words[from]: KEY=VALUE words (and SIN's flags ZERO, PEAK, SAMPLES=, which
/// steer gnucap's time steps, not the waveform) up to ')' or the end, and gives them gnucap's meaning
/// (gnucap_meaning).  Returns the index after the form.
std::size_t gnucap_form(std::string& fn, const std::vector<std::string>& words, std::size_t from,
                        const std::string& spec, const std::function<Rational(const std::string&)>& number,
                        std::vector<Rational>& args, std::vector<std::string>& noted) {
  std::vector<std::pair<std::string, Rational>> got;
  std::size_t j = from;
  for (; j < words.size() && words[j] != ")"; ++j) {
    if (words[j].find('=') == std::string::npos && is_keyword(lower(words[j]))) break;  // "… ac 1" after the form
    const std::optional<std::string> key = gnucap_key(fn, words[j]);
    const std::size_t eq = words[j].find('=');
    if (!key)
      throw std::invalid_argument("expected gnucap's " + fn + " keys (" +
                                  [&] {
                                    std::string all;
                                    for (const GnucapKey& k : gnucap_keys(fn))
                                      all += (all.empty() ? "" : " ") + std::string(k.name);
                                    return all;
                                  }() +
                                  "), found \"" + words[j] + "\" in \"" + spec + "\"");
    if (*key == "zero" || *key == "peak" || *key == "samples" || *key == "nozero" ||
        *key == "nopeak") {  // gnucap's time-step hints
      noted.push_back(words[j] + " (gnucap's time-step hint)");
      continue;
    }
    std::string text = eq == std::string::npos ? "" : words[j].substr(eq + 1);
    if (eq + 1 == words[j].size() && j + 1 < words.size() && words[j + 1] != ")")
      text = words[++j];  // "offset= 0." as spaced
    if (text.empty())
      throw std::invalid_argument("expected " + *key + "=VALUE, found \"" + words[j] + "\" in \"" + spec + "\"");
    for (const auto& g : got)
      if (g.first == *key)
        throw std::invalid_argument("expected " + *key + " once, found it twice in \"" + spec + "\"");
    got.emplace_back(*key, number(text));
  }
  gnucap_meaning(fn, got, spec, args);
  return j;
}

/// gnucap's positional form (bm_*.cc parse_numlist): the values fill the keys in gnucap's order — SIN's
/// offset amplitude frequency delay damping, EXP's iv pv td1 tau1 td2 tau2 period, PULSE's iv pv delay rise fall
/// width period — with gnucap's defaults after them, not SPICE's.
void gnucap_positional(std::string& fn, std::vector<Rational>& args, const std::string& spec) {
  const std::vector<GnucapKey>& keys = gnucap_keys(fn);
  const std::size_t n = fn == "sin" ? 5 : 7;  // SIN's keys after damping are time-step hints
  if (args.size() > n)
    throw std::invalid_argument("expected at most " + std::to_string(n) + " values in gnucap's " + fn + " (" +
                                [&] {
                                  std::string all;
                                  for (std::size_t k = 0; k < n; ++k) all += (k ? " " : "") + std::string(keys[k].name);
                                  return all;
                                }() +
                                "), found " + std::to_string(args.size()) + " in \"" + spec + "\"");
  std::vector<std::pair<std::string, Rational>> got;
  for (std::size_t k = 0; k < args.size(); ++k) got.emplace_back(keys[k].name, args[k]);
  gnucap_meaning(fn, got, spec, args);
}

}  // namespace

bool Generator::set(const std::string& key_in, const Rational& value) {
  const std::string key = lower(key_in);
  // gnucap's order (c_genrat.cc's ONE_OF): "f" is frequency, "fa" fall; a key is a prefix at least as long as the
  // mandatory part
  const std::vector<std::pair<GnucapKey, Rational Generator::*>> keys = {
      {{"frequency", 1}, &Generator::freq}, {{"amplitude", 1}, &Generator::ampl}, {{"phase", 1}, &Generator::phase},
      {{"max", 2}, &Generator::max},        {{"min", 2}, &Generator::min},        {{"offset", 1}, &Generator::offset},
      {{"initial", 1}, &Generator::init},   {{"rise", 1}, &Generator::rise},      {{"fall", 1}, &Generator::fall},
      {{"delay", 1}, &Generator::delay},    {{"width", 1}, &Generator::width},    {{"period", 2}, &Generator::period}};
  for (const auto& [k, member] : keys)
    if (key.size() >= k.least && std::string(k.name).compare(0, key.size(), key) == 0) {
      this->*member = value;
      return true;
    }
  return false;
}

std::vector<Rational> Generator::pwl(std::optional<Rational>* repeat) const {
  const auto refuse = [](const std::string& found) {
    throw std::invalid_argument(
        "expected gnucap's generator as a continuous pulse (.generator freq=0, rise and fall > 0, period >= "
        "rise + width + fall), found " +
        found + ": write the waveform as PWL(t1 v1 t2 v2 …)");
  };
  if (freq != 0) refuse("freq=" + freq.str() + " (a sine times the pulse)");
  for (const Rational* x : {&rise, &fall, &delay, &width, &period})
    if (*x < 0) refuse("a negative time " + x->str());
  if (rise == 0) refuse("rise=0 (a step)");
  const Rational hi = max * ampl + offset, lo = min * ampl + offset;
  std::vector<Rational> p;
  const auto point = [&](const Rational& t, const Rational& v) {
    if (!p.empty() && p[p.size() - 2] == t) return;  // a zero-length piece (delay = 0, a pulse that fills its period)
    p.push_back(t);
    p.push_back(v);
  };
  point(0, init);
  point(delay, init);
  point(delay + rise, hi);
  if (width == 0) {  // on for ever; with a period it steps from max back to min where each period ends
    if (period > 0 && hi != lo)
      refuse("width=0 with period=" + period.str() + " (on until the period ends, then a step to min)");
    return p;
  }
  if (fall == 0) refuse("fall=0 (a step)");
  if (period > 0 && rise + width + fall > period)
    refuse("period=" + period.str() + " < rise + width + fall (the pulse is cut: a step)");
  for (int k = 0; k < (period > 0 ? 2 : 1); ++k) {  // the first pulse rises from init, the repeated ones from min
    const Rational t0 = delay + k * period;
    if (k == 1) {
      *repeat = t0;
      point(t0 + rise, hi);
    }
    point(t0 + rise + width, hi);
    point(t0 + rise + width + fall, lo);
    if (period > 0) point(t0 + period, lo);
  }
  return p;
}

namespace {

/// A source specification's words, read: its DC value, its transient function with the values as written
/// and what the transient does not use.
struct SourceWords {
  std::optional<Rational> dc;
  std::string fn;  ///< "" (DC), sin, pulse, pwl, exp, sffm, generator, or one dcad refuses
  std::vector<Rational> args;
  std::vector<std::string> ignored;
  std::optional<Rational> pwl_td, pwl_r;
  bool literal = false;                   ///< gnucap's keyword form: every value given, no SPICE defaults
  std::string pat_data;                   ///< PAT's bits ("1010", of 0, 1 and M), without the leading b
  std::optional<Rational> pat_r, pat_rb;  ///< PAT's R= (repetitions; -1 for ever) and RB= (the bit they start at)
};

/// PAT's words from words[j] (HSPICE, Xyce): "(VHI VLO TD TR TF TSAMPLE bDATA [R=n] [RB=k])" or the same without
/// parentheses to the end of the specification; R= and RB= may also follow the ')'.  Returns the index after them.
std::size_t read_pat(SourceWords& r, const std::vector<std::string>& words, std::size_t j, const std::string& spec,
                     const std::function<Rational(const std::string&)>& number) {
  const bool parens = j < words.size() && words[j] == "(";
  for (j += parens ? 1 : 0; j < words.size() && words[j] != ")"; ++j) {
    const std::string w = lower(words[j]);
    if (w.rfind("r=", 0) == 0 || w.rfind("rb=", 0) == 0) {
      (w[1] == '=' ? r.pat_r : r.pat_rb) = number(w.substr(w.find('=') + 1));
    } else if (r.args.size() == 6 && r.pat_data.empty()) {
      if (w.size() < 2 || w[0] != 'b' || w.find_first_not_of("01m", 1) != std::string::npos)
        throw std::invalid_argument("expected PAT's data as a b-string of 0, 1 and M (b1010), found \"" + words[j] +
                                    "\" in \"" + spec + "\"");
      r.pat_data = w.substr(1);
    } else if (r.args.size() < 6) {
      r.args.push_back(number(words[j]));
    } else {
      throw std::invalid_argument("expected PAT(VHI VLO TD TR TF TSAMPLE bDATA [R=n] [RB=k]), found \"" + words[j] +
                                  "\" after the data in \"" + spec + "\"");
    }
  }
  if (parens && j == words.size()) throw std::invalid_argument("expected a closing ')' in \"" + spec + "\"");
  return parens ? j + 1 : j;
}

/// The transient function at words[i] and its values — in parentheses, as SPICE3's bare list, or as gnucap's
/// keys — read into r.  Returns the index after them, or words.size() for a function dcad does not read (its
/// values need not be numbers; waveform_of says it).  `values` reads bare numbers up to a keyword.
std::size_t read_function(SourceWords& r, const std::vector<std::string>& words, std::size_t i, const std::string& spec,
                          const std::function<Rational(const std::string&)>& number,
                          const std::function<std::size_t(std::size_t, std::size_t, std::vector<Rational>*)>& values) {
  std::string& fn = r.fn;
  const std::string word = lower(words[i]);
  if (!fn.empty())
    throw std::invalid_argument("expected one transient function, found " + fn + " and " + words[i] + " in \"" + spec +
                                "\"");
  fn = word == "sine" ? "sin" : word;
  std::size_t j = i + 1;
  const std::size_t first = j < words.size() && words[j] == "(" ? j + 1 : j;
  if (first < words.size() && words[first].find('=') != std::string::npos &&
      gnucap_key(fn, words[first])) {  // gnucap's keyword form
    j = gnucap_form(fn, words, first, spec, number, r.args, r.ignored);
    if (first > i + 1) {  // "(…)"
      if (j == words.size() || words[j] != ")")
        throw std::invalid_argument("expected a closing ')' in \"" + spec + "\"");
      ++j;
    }
    r.literal = true;
    return j;
  }
  if (fn == "pat") return read_pat(r, words, j, spec, number);
  if (!readable(fn)) return words.size();
  if (j == words.size() || words[j] != "(") return values(j, words.size(), &r.args);  // SPICE3: no parentheses
  for (++j; j < words.size() && words[j] != ")"; ++j) {
    if (words[j] == "(")
      throw std::invalid_argument("expected " + words[i] + "(values), found a nested '(' in \"" + spec + "\"");
    r.args.push_back(number(words[j]));
  }
  if (j == words.size())  // "SIN(0 1 1k" at the end of the line: Xyce and ngspice read it to the end (SENS/vsin.cir)
    r.ignored.push_back("the missing ')' of " + words[i] + "(…) (its values read to the end of the line)");
  return j == words.size() ? j : j + 1;
}

/// KEY=VALUE at words[i] where the key is PWL's TD= or R= (ngspice, Xyce) or DC=, AC=, ACMAG=, ACPHASE=, a
/// port's PORTNUM=, Z0=, PWR=, FREQ= (recorded as ignored): true when read.
bool read_key_value(SourceWords& r, const std::string& word, const std::string& spec,
                    const std::function<Rational(const std::string&)>& number) {
  const std::size_t eq = word.find('=');
  if (eq == std::string::npos) return false;
  const std::string key = lower(word.substr(0, eq));
  const bool pwl = r.fn == "pwl" && (key == "td" || key == "r");
  if (r.fn == "pat" && (key == "r" || key == "rb")) {
    (key == "r" ? r.pat_r : r.pat_rb) = number(word.substr(eq + 1));
    return true;
  }
  if (!pwl && key != "dc" && key != "ac" && key != "acmag" && key != "acphase" && key != "portnum" && key != "z0" &&
      key != "pwr" && key != "freq")
    return false;
  const std::string value = word.substr(eq + 1);
  if (value.empty()) throw std::invalid_argument("expected a value after " + word + ", found none in \"" + spec + "\"");
  const Rational v = number(value);
  if (pwl)
    (key == "td" ? r.pwl_td : r.pwl_r) = v;
  else if (key == "dc" && r.dc)  // "dc 1 dc=2": one rule for both spellings (read_dc_or_ignored)
    throw std::invalid_argument("expected one DC value, found a second one, " + word + ", in \"" + spec + "\"");
  else if (key == "dc")
    r.dc = v;
  else
    r.ignored.push_back(word);
  return true;
}

/// DC VALUE, or AC [MAG [PHASE]], DISTOF1/2, PORTNUM, Z0, PWR, FREQ and their values (recorded as ignored), at
/// words[i]: the index after them, or i when words[i] is none of these.
std::size_t read_dc_or_ignored(
    SourceWords& r, const std::vector<std::string>& words, std::size_t i, const std::string& spec,
    const std::function<std::size_t(std::size_t, std::size_t, std::vector<Rational>*)>& values) {
  const std::string word = lower(words[i]);
  if (word == "dc") {
    std::vector<Rational> v;
    const std::size_t j = values(i + 1, 1, &v);
    if (v.empty()) {  // "DC" before a function or AC with no value of its own: the operating point's 0
      if (j < words.size() && is_keyword(lower(words[j]))) {
        r.ignored.push_back("DC without a value");
        return j;
      }
      throw std::invalid_argument("expected a value after DC, found none in \"" + spec + "\"");
    }
    if (r.dc)  // Xyce's ISSUE_455 "dc 1.0 dc 0.0": Xyce refuses it; which one would the transient take?
      throw std::invalid_argument("expected one DC value, found a second one, DC " + v[0].str() + ", in \"" + spec +
                                  "\"");
    r.dc = v[0];
    return j;
  }
  if (word != "ac" && word != "distof1" && word != "distof2" && word != "portnum" && word != "z0" && word != "pwr" &&
      word != "freq")
    return i;
  const std::size_t j = values(i + 1, word == "ac" || word == "distof1" || word == "distof2" ? 2 : 1, nullptr);
  if (j == i + 1 && word != "ac")
    throw std::invalid_argument("expected a value after " + words[i] + ", found none in \"" + spec + "\"");
  std::string said = words[i];
  for (std::size_t k = i + 1; k < j; ++k) said += " " + words[k];
  r.ignored.push_back(said);
  return j;
}

SourceWords read_source_words(const std::string& spec, const std::function<Rational(const std::string&)>& number,
                              bool gnucap) {
  SourceWords r;
  const std::vector<std::string> words = spec_words(spec);
  // the values after a keyword: at most `most`, while they are not keywords, KEY=VALUE words (HSPICE's bare
  // "PWL 0 0, 2 3 R=7 TD=1", Xyce_Regression's VPWL) or parentheses
  const auto key_value = [](const std::string& w) {
    const std::size_t eq = w.find('=');
    if (eq == std::string::npos || eq == 0 || !std::isalpha(static_cast<unsigned char>(w[0]))) return false;
    return std::all_of(w.begin(), w.begin() + static_cast<std::ptrdiff_t>(eq),
                       [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
  };
  const auto values = [&](std::size_t from, std::size_t most, std::vector<Rational>* into) {
    std::size_t j = from;
    for (; j < words.size() && j - from < most && words[j] != "(" && words[j] != ")" && !is_keyword(lower(words[j])) &&
           !key_value(words[j]);
         ++j) {
      const Rational v = number(words[j]);
      if (into) into->push_back(v);
    }
    return j;
  };
  for (std::size_t i = 0; i < words.size();) {
    const std::string word = lower(words[i]);
    if (read_key_value(r, words[i], spec, number)) {
      ++i;
      continue;
    }
    if (const std::size_t j = read_dc_or_ignored(r, words, i, spec, values); j != i) {
      i = j;
      continue;
    }
    if (is_function(word)) {
      i = read_function(r, words, i, spec, number, values);
      continue;
    }
    if (words[i] == "(" || words[i] == ")")
      throw std::invalid_argument("expected a value or a keyword, found '" + words[i] + "' in \"" + spec + "\"");
    const bool keyword = word.find('=') != std::string::npos;
    if (!r.fn.empty() && !r.dc && !keyword && i > 0 &&
        words[i - 1] == ")") {  // "pwl(…) 7": ngspice-39 ignores it (not even the DC)
      number(words[i]);
      r.ignored.push_back(words[i] + " after " + r.fn + "(…) (ngspice ignores a value after the function)");
      ++i;
      continue;
    }
    if (r.dc || !r.fn.empty()) {  // a second bare value
      if (keyword)
        throw std::invalid_argument("expected DC, AC or a transient function, found \"" + words[i] +
                                    "\" (a keyword dcad does not read) in \"" + spec + "\"");
      throw std::invalid_argument("expected one DC value, found another one, \"" + words[i] + "\", in \"" + spec +
                                  "\"");
    }
    r.dc = number(words[i]);  // "[DC] value": DC is optional before the first value
    ++i;
  }
  if (gnucap && !r.literal && (r.fn == "sin" || r.fn == "exp" || r.fn == "pulse")) {
    gnucap_positional(r.fn, r.args, spec);  // gnucap's order and defaults, not SPICE's
    r.literal = true;
  }
  return r;
}

/// PWL's points (t1 v1 t2 v2 …) checked, shifted by TD= and repeated from R= as ngspice does (R = -1: none).
/// `steps`: two points may share a time (gnucap's PULSE with RISE or FALL 0, read as its PWL), a step there.
void shape_pwl(Waveform& w, std::vector<Rational>& a, const std::optional<Rational>& pwl_td,
               const std::optional<Rational>& pwl_r, bool steps) {
  if (a.size() < 2 || a.size() % 2 != 0)
    throw std::invalid_argument("expected PWL(t1 v1 t2 v2 ...) with pairs, found " + std::to_string(a.size()) +
                                " values");
  if (pwl_td)
    for (std::size_t i = 0; i < a.size(); i += 2) a[i] += *pwl_td;  // TD= shifts the whole waveform
  for (std::size_t i = 2; i < a.size(); i += 2)
    if (!(a[i] > a[i - 2]) && !(steps && a[i] == a[i - 2]))
      throw std::invalid_argument("expected increasing PWL times, found " + a[i - 2].str() + " then " + a[i].str());
  if (a[0] < 0) throw std::invalid_argument("expected PWL times >= 0, found " + a[0].str());
  w.kind = Waveform::Kind::pwl;
  bool constant = true;
  for (std::size_t i = 3; i < a.size(); i += 2) constant = constant && a[i] == a[1];
  if (pwl_r && *pwl_r >= 0 && constant) {  // Xyce's BUG_630 "PWL (1.0 1.0) R=0": any repetition is the same constant
    w.ignored += std::string(w.ignored.empty() ? "" : ", ") + "R=" + pwl_r->str() + " (a constant PWL repeats itself)";
  } else if (pwl_r && *pwl_r >= 0) {  // R = -1: no repetition (ngspice); else a time point before the last
    const Rational r = *pwl_r + (pwl_td ? *pwl_td : Rational(0));
    bool point = false;
    for (std::size_t i = 0; i < a.size(); i += 2) point = point || a[i] == r;
    if (!(r < a[a.size() - 2]) || !point)
      throw std::invalid_argument("expected PWL's R= at one of its time points before the last (ngspice), found R = " +
                                  pwl_r->str());
    w.repeat = r;  // a part that does not start where it ends steps at each repetition (step_at)
  }
}

/// PAT(VHI VLO TD TR TF TSAMPLE bDATA R= RB=) as the PWL that draws it (HSPICE's pattern source as Xyce reads it,
/// checked against Xyce_Regression's VPAT/vpat.cir output): bit k holds from TD + k·TSAMPLE, the first also
/// through the delay; a change of level ramps over TR (rising) or TF (falling) centred on the bit boundary; M is
/// (VHI + VLO)/2.  After the data, R >= 1 repeats bits RB… R times, R = -1 for ever (a PWL repeated from the
/// middle of bit RB), R = 0 — and R < -1, as Xyce's output holds it — plays it once; the last bit then holds.
/// Points before t = 0 (TD < 0) are cut at the value there.  TR or TF 0 is a step (two points at one time).
std::vector<Rational> pat_pwl(const SourceWords& r, const std::string& spec, std::optional<Rational>& repeat) {
  const auto refuse = [&](const std::string& what) {
    throw std::invalid_argument("expected PAT(VHI VLO TD TR TF TSAMPLE bDATA [R=n] [RB=k]) " + what + " in \"" + spec +
                                "\"");
  };
  if (r.args.size() != 6 || r.pat_data.empty()) refuse("with its six values and a b-string");
  const Rational &hi = r.args[0], &lo = r.args[1], &td = r.args[2], &tr = r.args[3], &tf = r.args[4];
  const Rational& ts = r.args[5];
  if (tr < 0 || tf < 0 || !(ts > 0)) refuse("with TR, TF >= 0 and TSAMPLE > 0");
  if (tr > ts || tf > ts) refuse("with TR, TF <= TSAMPLE (the ramps of neighbouring bits would overlap)");
  const long n = static_cast<long>(r.pat_data.size());
  const Rational rr = r.pat_r.value_or(0), rb = r.pat_rb.value_or(1);
  if (rb != floor_of(rb) || rb < 1 || rb > n) refuse("with RB= a bit of the data, 1 to " + std::to_string(n));
  if (rr != floor_of(rr)) refuse("with R= a whole number of repetitions");
  const long first = static_cast<long>(d(rb)) - 1;
  const long period = n - first;
  const bool forever = rr == -1;
  const long times = rr > 0 ? static_cast<long>(d(rr)) : 0;
  if (times > 1000000 / period) refuse("with at most 10^6 repeated bits");
  const auto bit = [&](long k) { return r.pat_data[static_cast<std::size_t>(k < n ? k : first + (k - n) % period)]; };
  const auto level = [&](char b) { return b == '1' ? hi : b == '0' ? lo : Rational((hi + lo) / 2); };
  // forever: the PWL repeats from the middle of bit `first` + m·period (m making it >= 0) over one period
  Rational from = td + (Rational(first) + Rational(1, 2)) * ts;
  if (forever && from < 0) from += ts * period * floor_of(Rational(-from / (ts * period)) + 1);
  const Rational until = forever ? Rational(from + ts * period) : Rational(0);
  const long bits = forever ? static_cast<long>(d(floor_of(Rational((until - td) / ts)))) + 2 : n + times * period;
  std::vector<std::pair<Rational, Rational>> pts{{td, level(bit(0))}};
  for (long k = 1; k < bits; ++k) {
    const Rational before = level(bit(k - 1)), after = level(bit(k));
    if (before == after) continue;
    const Rational edge = td + ts * k, half = (after > before ? tr : tf) / 2;
    pts.push_back({edge - half, before});
    pts.push_back({edge + half, after});
  }
  const auto at = [&](const Rational& t) {  // the drawn value at t
    if (t <= pts.front().first) return pts.front().second;
    for (std::size_t i = 1; i < pts.size(); ++i)
      if (t < pts[i].first)
        return Rational(pts[i - 1].second + (pts[i].second - pts[i - 1].second) * (t - pts[i - 1].first) /
                                                (pts[i].first - pts[i - 1].first));
    return pts.back().second;
  };
  std::vector<std::pair<Rational, Rational>> cut{{0, at(0)}};
  if (forever) cut.push_back({from, at(from)});
  for (const auto& q : pts)
    if (q.first > 0 && (!forever || q.first < until)) cut.push_back(q);  // the bits before `from` too
  if (forever) cut.push_back({until, at(until)});
  std::stable_sort(cut.begin(), cut.end(),  // a step's two points share a time: their order is the step's
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Rational> out;
  for (std::size_t i = 0; i < cut.size(); ++i)
    if (i == 0 || cut[i] != cut[i - 1]) out.insert(out.end(), {cut[i].first, cut[i].second});
  if (forever) repeat = from;
  return out;
}

/// PAT's waveform: the PWL pat_pwl draws, with what the transient does not use noted.
Waveform pat_waveform(const SourceWords& r, const std::string& spec) {
  Waveform w;
  w.text = spec;
  w.p = pat_pwl(r, spec, w.repeat);
  w.kind = Waveform::Kind::pwl;
  w.given = w.p.size();
  w.literal = true;
  for (std::size_t k = 0; k < r.ignored.size(); ++k) w.ignored += (k ? ", " : "") + r.ignored[k];
  return w;
}

/// SFFM's values: all five (the defaults and a 6th value differ between ngspice versions), FC, FS > 0, MDI >= 0.
void check_sffm(const std::vector<Rational>& a) {
  if (a.size() != 5)
    throw std::invalid_argument(
        "expected SFFM(VO VA FC MDI FS) with the five values SPICE3, ngspice 39, ngspice 46 on and Xyce read alike "
        "(their defaults for missing ones differ between ngspice versions, a 6th value is PHASEC in ngspice 39 and "
        "TD in ngspice 43 on), found " +
        std::to_string(a.size()) + " values: write the five");
  if (!(a[2] > 0) || !(a[4] > 0) || a[3] < 0)
    throw std::invalid_argument("expected SFFM's FC > 0, FS > 0 and MDI >= 0, found FC = " + a[2].str() +
                                ", MDI = " + a[3].str() + ", FS = " + a[4].str());
}

/// The waveform the words stand for: each kind's count and ranges checked, PWL's TD= and R= applied.
Waveform waveform_of(SourceWords r, const std::string& spec, const Generator& generator) {
  Waveform w;
  w.text = spec;
  if (r.fn == "pat") return pat_waveform(r, spec);
  if (r.fn == "am" || r.fn == "trnoise" || r.fn == "trrandom" || r.fn == "file")
    throw std::invalid_argument("expected DC, SIN, PULSE, PWL or EXP for the transient, found " + r.fn +
                                (r.fn == "trnoise" || r.fn == "trrandom"
                                     ? " (a random source: no exact transient exists)"
                                 : r.fn == "file" ? " (values from outside the deck)"
                                                  : " (not read by dcad yet)") +
                                ": write the waveform as PWL(t1 v1 t2 v2 …)");
  for (std::size_t k = 0; k < r.ignored.size(); ++k) w.ignored += (k ? ", " : "") + r.ignored[k];
  if (r.fn.empty()) {
    w.p = {r.dc ? *r.dc : Rational(0)};  // AC alone: DC 0 in the transient, as ngspice
    w.given = 1;
    return w;
  }
  if (r.dc)
    w.ignored += std::string(w.ignored.empty() ? "" : ", ") + "DC " + r.dc->str() +
                 " (the operating point's value; the transient uses " + r.fn + ")";
  if (r.fn == "generator") {  // bm_generator.cc: SCALE (default 1) times the generator's value
    if (r.args.size() > 1)
      throw std::invalid_argument("expected generator or generator(SCALE), found " + std::to_string(r.args.size()) +
                                  " values in \"" + spec + "\"");
    const Rational scale = r.args.empty() ? Rational(1) : r.args[0];
    w.p = generator.pwl(&w.repeat);
    for (std::size_t i = 1; i < w.p.size(); i += 2) w.p[i] *= scale;
    w.kind = Waveform::Kind::pwl;
    w.given = w.p.size();
    w.literal = true;
    return w;
  }
  std::vector<Rational>& a = r.args;
  w.given = a.size();
  if (r.fn == "sin") {
    if (a.size() < 2 || a.size() > 6)
      throw std::invalid_argument("expected SIN(VO VA [FREQ [TD [THETA [PHASE]]]]), found " + std::to_string(a.size()) +
                                  " values");
    if (a.size() > 2 && a[2] < 0) throw std::invalid_argument("expected FREQ >= 0 in SIN, found " + a[2].str());
    w.kind = Waveform::Kind::sin;
  } else if (r.fn == "pulse") {
    if (a.size() < 2 || a.size() > 8)
      throw std::invalid_argument("expected PULSE(V1 V2 [TD [TR [TF [PW [PER [NP]]]]]]), found " +
                                  std::to_string(a.size()) + " values");
    if (a.size() > 2 && a[2] < 0) throw std::invalid_argument("expected TD >= 0 in PULSE, found " + a[2].str());
    if (a.size() == 8) {
      if (a[7] < 0 || boost::multiprecision::denominator(a[7]) != 1 || a[7] > 1000000)
        throw std::invalid_argument("expected PULSE's NP (number of pulses) a whole number in 0 … 10^6, found " +
                                    a[7].str());
      w.pulses = static_cast<long>(boost::multiprecision::numerator(a[7]).convert_to<long>());
      a.pop_back();
    }
    w.kind = Waveform::Kind::pulse;
  } else if (r.fn == "sffm") {
    check_sffm(a);
    w.kind = Waveform::Kind::sffm;
  } else if (r.fn == "exp") {
    if (r.literal && a.size() == 7) {  // gnucap's period= (gnucap_meaning)
      w.period = a[6];
      a.pop_back();
    }
    if (a.size() < 2 || a.size() > 6)
      throw std::invalid_argument("expected EXP(V1 V2 [TD1 [TAU1 [TD2 [TAU2]]]]), found " + std::to_string(a.size()) +
                                  " values");
    w.kind = Waveform::Kind::exp;
  } else {
    shape_pwl(w, a, r.pwl_td, r.pwl_r, r.literal);  // literal: gnucap's PULSE as its PWL
  }
  if ((r.pwl_td || r.pwl_r) && r.fn != "pwl")
    throw std::invalid_argument("expected TD= and R= after PWL only, found them after " + r.fn);
  w.p = a;
  w.literal = r.literal;
  if (w.kind == Waveform::Kind::pwl) w.given = a.size();
  if (w.kind == Waveform::Kind::sin && a.size() > 2 && a[2] != 0)
    w.p.resize(6, Rational(0));  // FREQ given: complete already
  return w;
}

}  // namespace

Waveform parse_waveform(const std::string& spec, const std::function<Rational(const std::string&)>& number,
                        const Generator& generator, bool gnucap) {
  return waveform_of(read_source_words(spec, number, gnucap), spec, generator);
}

void Waveform::complete(const std::optional<Rational>& tstep, const std::optional<Rational>& tstop) {
  const auto need = [&](const std::optional<Rational>& x, const char* what, const char* why) -> Rational {
    if (!x || *x <= 0)
      throw std::invalid_argument(std::string("expected a .tran card with ") + what + " for " + text +
                                  " (ngspice takes " + why + "), found none: give .tran or the value");
    return *x;
  };
  if (literal) return;  // gnucap's keyword form: its own defaults, already applied
  if (kind == Kind::sin) {
    const bool has_freq = p.size() > 2 && p[2] != 0;
    if (!has_freq) {
      const Rational stop = need(tstop, "TSTOP", "FREQ = 1/TSTOP where FREQ is 0 or missing");
      if (p.size() < 3) p.resize(3, Rational(0));
      p[2] = Rational(1) / stop;
    }
    p.resize(6, Rational(0));
  } else if (kind == Kind::exp) {  // vsrcload.c: TD1, TAU1 = TSTEP where 0 or missing, TD2 = TD1 + TSTEP, TAU2 = TSTEP
    const std::size_t n = given;
    p.resize(6, Rational(0));
    if (n < 3 || p[2] == 0) p[2] = need(tstep, "TSTEP", "TD1 = TSTEP where TD1 is 0 or missing");
    if (n < 4 || p[3] == 0) p[3] = need(tstep, "TSTEP", "TAU1 = TSTEP where TAU1 is 0 or missing");
    if (n < 5 || p[4] == 0) p[4] = p[2] + need(tstep, "TSTEP", "TD2 = TD1 + TSTEP where TD2 is 0 or missing");
    if (n < 6 || p[5] == 0) p[5] = need(tstep, "TSTEP", "TAU2 = TSTEP where TAU2 is 0 or missing");
    if (p[4] < p[2] && p[0] != p[1])  // vsrcload.c: V1 up to TD1, then the third piece at once — a step there
      throw std::invalid_argument(
          "expected EXP's TD2 >= TD1 in " + text + ", found TD2 = " + p[4].str() + " < TD1 = " + p[2].str() +
          ": ngspice's EXP then steps at TD1 (V1 before it, V1 + (V1 - V2)(1 - e^(-(TD1-TD2)/TAU2)) after); "
          "dcad's exact flows take continuous sources");
  } else if (kind == Kind::pulse) {
    const std::size_t n = given > 7 ? 7 : given;
    p.resize(7, Rational(0));
    if (n < 4 || p[3] <= 0) p[3] = need(tstep, "TSTEP", "TR = TSTEP where TR is missing or <= 0");
    if (n < 5 || p[4] <= 0) p[4] = need(tstep, "TSTEP", "TF = TSTEP where TF is missing or <= 0");
    if (n == 5)
      p[5] = 0;
    else if (n < 6 || p[5] < 0)
      p[5] = need(tstop, "TSTOP", "PW = TSTOP where PW is missing or < 0");
    if (n < 7 || p[6] <= 0) p[6] = need(tstop, "TSTOP", "PER = TSTOP where PER is missing or <= 0");
  }
}

bool Waveform::constant() const {
  if (kind == Kind::dc) return true;
  if (kind == Kind::sin) return p[1] == 0;
  if (kind == Kind::exp) return p[0] == p[1];
  if (kind == Kind::sffm) return p[1] == 0;
  return false;
}

double Waveform::horizon() const {
  switch (kind) {
    case Kind::dc: return 0;
    case Kind::sin: return d(p[3]) + (p[2] != 0 ? 4 / d(p[2]) : 1.0);
    case Kind::pulse: return d(p[2]) + 2 * d(p[6]);
    case Kind::exp: return std::max(d(p[2]), d(p[4])) + 5 * (std::abs(d(p[3])) + std::abs(d(p[5]))) + 2 * d(period);
    case Kind::sffm: return 2 / std::min(d(p[2]), d(p[4]));  // two periods of the slower of carrier and modulation
    default: return 2 * d(p[p.size() - 2]);
  }
}

std::optional<double> Waveform::corner_jump(double tb, int order) const {
  if (kind == Kind::sffm) return 0.0;  // analytic everywhere: no corners
  if (kind != Kind::exp && kind != Kind::sin) return std::nullopt;
  if (order == 0) return 0.0;
  if (kind == Kind::sin) return tb == d(p[3]) ? value(tb, order) : 0.0;  // value at TD is the right limit
  double jump = 0;
  if (tb == d(p[2])) jump += (d(p[0]) - d(p[1])) * std::pow(rate1(), order);
  if (tb == d(p[4])) jump += (d(p[1]) - d(p[0])) * std::pow(rate2(), order);
  return jump;
}

double Waveform::decay() const { return kind == Kind::sin ? -d(p[4]) : 0.0; }
double Waveform::omega() const { return kind == Kind::sin ? 2 * kPi * d(p[2]) : 0.0; }
double Waveform::rate1() const { return kind == Kind::exp ? -1 / d(p[3]) : 0.0; }
double Waveform::rate2() const { return kind == Kind::exp ? -1 / d(p[5]) : 0.0; }

namespace {
/// EXP's exosystem state (c, e1, e2) at t (right limit), as ngspice's pieces (vsrcload.c): V1 up to TD1;
/// then V2 + (V1 − V2) e^{-(t-TD1)/TAU1} up to TD2; then V1 + (V1 − V2) e^{-(t-TD1)/TAU1} + (V2 − V1)
/// e^{-(t-TD2)/TAU2}.
void exp_state(const Waveform& w, double t, long double* x) {
  const auto ld = [&](std::size_t i) {
    return w.p[i].convert_to<long double>();
  };  // from the exact values: a long-double shadow sees double's roundings
  const long double v1 = ld(0), v2 = ld(1), td1 = ld(2), tau1 = ld(3), td2 = ld(4), tau2 = ld(5);
  x[0] = v1, x[1] = 0, x[2] = 0;
  if (t < td1) return;  // at TD1 itself the right limit: the decay has started (σ' = (V2 − V1)/TAU1 there)
  x[1] = (v1 - v2) * std::exp(-(static_cast<long double>(t) - td1) / tau1);
  if (t < td2) {
    x[0] = v2;
    return;
  }
  x[2] = (v2 - v1) * std::exp(-(static_cast<long double>(t) - td2) / tau2);
}

/// gnucap's periodic EXP (bm_exp.cc tr_eval): IV + Σ over the m >= 0 with t − m·P > TD (>= here: right limits) of (PV −
/// IV)(1 − e^{−(t − m·P − TD1)/TAU1}) and (IV − PV)(1 − e^{−(t − m·P − TD2)/TAU2}); the N terms started of each with
/// the geometric sum of their exponentials in closed form: e^{−s/TAU} (1 − r^N)/(1 − r), r = e^{−P/TAU}, s the
/// youngest's age.
double periodic_exp(const Waveform& w, double t, int order) {
  const long double v1 = w.p[0].convert_to<long double>(), v2 = w.p[1].convert_to<long double>();
  const long double period = w.period.convert_to<long double>();
  const auto started = [&](std::size_t td_at, std::size_t tau_at, long double sign) -> long double {
    const long double td = w.p[td_at].convert_to<long double>(), tau = w.p[tau_at].convert_to<long double>();
    if (static_cast<long double>(t) < td) return 0;  // at a restart its right limit: the new term has started
    const long double n = std::floor((static_cast<long double>(t) - td) / period) + 1;  // t − m·P >= TD for m < n
    const long double s = static_cast<long double>(t) - td - (n - 1) * period;
    const long double r = std::exp(-period / tau);
    const long double sum = std::exp(-s / tau) * (r < 1 ? -std::expm1(n * std::log(r)) / (1 - r) : n);
    const long double terms = order == 0 ? n - sum : -sum * std::pow(-1 / tau, order);
    return sign * (v2 - v1) * terms;
  };
  return static_cast<double>((order == 0 ? v1 : 0) + started(2, 3, 1) + started(4, 5, -1));
}
}  // namespace

namespace {

/// Piecewise-linear pieces (t_i, v_i) of PULSE (one period, shifted) or PWL at t: value and slope.
double as(double, const Rational& x) { return d(x); }
Rational as(const Rational&, const Rational& x) { return x; }
double as_double(double x) { return x; }
double as_double(const Rational& x) { return x.convert_to<double>(); }

/// The period k >= k_min that t lies in: origin + period·k <= t < origin + period·(k + 1), each bound
/// computed as breakpoints() computes its corners (in double, a row an ulp from a corner takes the side of
/// it the flow's breakpoints put it on; exactly, the same).
template <class T>
long period_of(const T& t, const T& origin, const T& period, long k_min) {
  const auto start = [&](long k) { return T(origin + period * static_cast<T>(k)); };
  const double q = as_double(floor_of(T((t - origin) / period)));
  if (!(q < 1e15)) return static_cast<long>(1e15);  // corners beyond double's resolution of the period (and NaN)
  long k = std::max<long>(k_min, static_cast<long>(q));
  // a few steps from the rounded quotient; more only where PERIOD is below the resolution of ORIGIN + PERIOD·k
  // (its corners then coincide in double, and which of them t is past is moot): bounded, never a hang
  for (int n = 0; n < 64 && k > k_min && t < start(k); ++n) --k;
  for (int n = 0; n < 64 && !(t < start(k + 1)); ++n) ++k;
  return k;
}

/// PULSE and PWL: the value and slope at t (right limit), in double or exactly (T = Rational).  The pieces
/// are bounded by the corners exactly as Waveform::breakpoints() writes them — PULSE's TD + PER·k (+ TR,
/// + PW, + TF), a repeated PWL's LAST + PERIOD·(k − 1) and t_i + PERIOD·k — so that the double flow, which
/// stops at those corners, and the jets it reads at a row agree on the side of a corner the row is on.
template <class T>
void linear_at(const Waveform& w, const T& t, T& v, T& slope) {
  const auto p = [&](std::size_t i) { return as(t, w.p[i]); };
  slope = 0;
  if (w.kind == Waveform::Kind::pulse) {
    const T v1 = p(0), v2 = p(1), td = p(2), tr = p(3), tf = p(4), pw = p(5), per = p(6);
    if (t < td) {
      v = v1;
      return;
    }
    // right limits: at TD + k·PER the next period (ngspice's value there is the same)
    const long k = per > 0 ? period_of(t, td, per, 0) : 0;
    if (w.pulses > 0 && k >= w.pulses) {  // after NP pulses: V1 (ngspice)
      v = v1;
      return;
    }
    const T base = per > 0 ? T(td + per * static_cast<T>(k)) : td;
    if (t < T(base + tr)) {
      slope = (v2 - v1) / tr;
      v = v1 + slope * (t - base);
    } else if (t < T(base + tr + pw)) {
      v = v2;
    } else if (t < T(base + tr + pw + tf)) {
      slope = (v1 - v2) / tf;
      v = v2 + slope * (t - T(base + tr + pw));
    } else {
      v = v1;
    }
    return;
  }
  const std::size_t n = w.p.size() / 2;
  if (t < p(0)) {
    v = p(1);
    return;
  }
  std::size_t first = 0;  // the pieces from point `first` on, their times shifted by `shift`, the first from `from`
  T shift = 0, from = p(0);
  if (w.repeat && !(t < p(2 * n - 2))) {  // R=: from the repeat point to the last, period after period (ngspice)
    const T r = as(t, *w.repeat), last = p(2 * n - 2), period = last - r;
    const long k = period_of(t, last, period, 0) + 1;  // repetition k: from LAST + PERIOD·(k − 1)
    shift = period * static_cast<T>(k);
    from = last + period * static_cast<T>(k - 1);
    while (p(2 * first) != r) ++first;
  }
  for (std::size_t i = first; i + 1 < n; ++i) {
    const T t0 = i == first ? from : T(p(2 * i) + shift), t1 = p(2 * i + 2) + shift;
    if (t < t1) {
      const T v0 = p(2 * i + 1), v1 = p(2 * i + 3);
      slope = (v1 - v0) / (p(2 * i + 2) - p(2 * i));
      v = v0 + slope * (t - t0);
      return;
    }
  }
  v = p(2 * n - 1);
  slope = T(0);  // held after the last point
}

}  // namespace

namespace {
/// SFFM's σ^{(order)}(t) = VA · order! · [τ^order] sin(φ(t + τ)), φ(t) = 2π FC t + MDI sin(2π FS t): the Taylor
/// coefficients a_k of φ at t (a_k = MDI ωs^k sin(ωs t + kπ/2)/k! for k ≥ 2) composed with sin and cos by
/// s_k = (1/k) Σ j a_j c_{k−j}, c_k = −(1/k) Σ j a_j s_{k−j}.
double sffm_value(const Waveform& w, double t, int order) {
  const double vo = d(w.p[0]), va = d(w.p[1]), wc = 2 * kPi * d(w.p[2]), mdi = d(w.p[3]), ws = 2 * kPi * d(w.p[4]);
  const auto n = static_cast<std::size_t>(order);
  std::vector<double> a(n + 1), sn(n + 1), cs(n + 1);
  double fact = 1, wk = 1;
  for (std::size_t k = 0; k <= n; ++k, wk *= ws, fact *= static_cast<double>(std::max<std::size_t>(k, 1)))
    a[k] = mdi * wk * std::sin(ws * t + static_cast<double>(k) * kPi / 2) / fact + (k == 0   ? wc * t
                                                                                    : k == 1 ? wc
                                                                                             : 0.0);
  sn[0] = std::sin(a[0]), cs[0] = std::cos(a[0]);
  for (std::size_t k = 1; k <= n; ++k) {
    double s = 0, c = 0;
    for (std::size_t j = 1; j <= k; ++j) {
      s += static_cast<double>(j) * a[j] * cs[k - j];
      c -= static_cast<double>(j) * a[j] * sn[k - j];
    }
    sn[k] = s / static_cast<double>(k), cs[k] = c / static_cast<double>(k);
  }
  double factorial = 1;
  for (std::size_t k = 2; k <= n; ++k) factorial *= static_cast<double>(k);
  return (order == 0 ? vo : 0.0) + va * factorial * sn[n];
}
}  // namespace

double Waveform::value(double t, int order) const {
  switch (kind) {
    case Kind::sffm: return sffm_value(*this, t, order);
    case Kind::dc: return order == 0 ? d(p[0]) : 0.0;
    case Kind::sin: {
      const double vo = d(p[0]), va = d(p[1]), td = d(p[3]), phi = d(p[5]) * kPi / 180;
      if (t < td) return order == 0 ? vo + va * std::sin(phi) : 0.0;  // ngspice: VO + VA sin(PHASE) before TD
      // Im(VA s^order e^{s τ + iφ}) with s = −θ + iω
      const std::complex<double> s(decay(), omega());
      const std::complex<double> z = va * std::pow(s, order) * std::exp(s * (t - td) + std::complex<double>(0, phi));
      return (order == 0 ? vo : 0.0) + z.imag();
    }
    case Kind::exp: {
      if (period > 0) return periodic_exp(*this, t, order);
      long double x[3];
      exp_state(*this, t, x);
      if (order == 0) return static_cast<double>(x[0] + x[1] + x[2]);
      return static_cast<double>(x[1] * std::pow(static_cast<long double>(rate1()), order) +
                                 x[2] * std::pow(static_cast<long double>(rate2()), order));
    }
    default: {
      double v, slope;
      linear_at(*this, t, v, slope);
      return order == 0 ? v : order == 1 ? slope : 0.0;
    }
  }
}

std::optional<Rational> Waveform::exact_at_zero(int order) const {
  switch (kind) {
    case Kind::sffm:  // VO + VA sin(0); its derivatives involve π
      if (p[1] == 0) return order == 0 ? p[0] : Rational(0);
      if (order == 0) return p[0];
      return std::nullopt;
    case Kind::dc: return order == 0 ? p[0] : Rational(0);
    case Kind::sin: {
      if (p[1] == 0) return order == 0 ? p[0] : Rational(0);  // no sine: VO
      if (order > 0) {
        if (p[3] > 0) return Rational(0);  // before TD the value is constant
        return std::nullopt;               // VA (−θ + iω)^order …: ω = 2π FREQ
      }
      // VO + VA sin(2π FREQ lag + φ) e^{−θ lag}, lag = −TD the time the sine has run at t = 0 when TD < 0, else 0
      // (ngspice holds VO + VA sin φ before TD): rational at quarter turns where the damping has not acted
      const Rational lag = p[3] < 0 ? Rational(-p[3]) : Rational(0), turns = p[5] + 360 * p[2] * lag;
      const Rational phase = turns - 360 * floor_of(Rational(turns / 360));
      if (phase == 0 || phase == 180) return p[0];
      if (lag > 0 && p[4] != 0) return std::nullopt;  // e^{−θ lag}: irrational
      if (phase == 90) return p[0] + p[1];
      if (phase == 270) return p[0] - p[1];
      return std::nullopt;
    }
    case Kind::exp:  // V1 up to TD1 > 0 (ngspice's default TD1 is TSTEP): constant at 0
      if (p[2] > 0) return order == 0 ? p[0] : Rational(0);
      return std::nullopt;
    default: {
      Rational v, slope;
      linear_at(*this, Rational(0), v, slope);
      return order == 0 ? v : order == 1 ? slope : Rational(0);
    }
  }
}

namespace {
/// PULSE cut by a PER shorter than TR + PW + TF (ngspice): the value just before each period's start, where
/// it returns to V1 — a step unless it is V1 already.  nullopt when the pulse is not cut or lands at V1.
std::optional<Rational> pulse_step(const Waveform& w) {
  if (w.kind != Waveform::Kind::pulse || w.p.size() < 7) return std::nullopt;
  const Rational &v1 = w.p[0], &v2 = w.p[1], &tr = w.p[3], &tf = w.p[4], &pw = w.p[5], &per = w.p[6];
  if (!(per < tr + pw + tf)) return std::nullopt;
  const Rational end = per <= tr        ? Rational(v1 + (v2 - v1) * per / tr)
                       : per <= tr + pw ? v2
                                        : Rational(v2 + (v1 - v2) * (per - tr - pw) / tf);
  if (end == v1) return std::nullopt;
  return end;
}
[[noreturn]] void refuse_step(const Waveform& w, const Rational& from, double at) {
  throw std::invalid_argument(w.element + ": " + w.text + " steps from " + from.str() + " to V1 = " + w.p[0].str() +
                              " at t = " + std::to_string(at) +
                              " s (PER < TR + PW + TF cuts the pulse): dcad's exact flows take continuous sources; "
                              "lengthen PER or end the run before it");
}
}  // namespace

std::vector<double> Waveform::breakpoints(double tstop) const {
  std::vector<double> out;
  if (const std::optional<Rational> step =
          pulse_step(*this)) {  // a step inside the run: refused where the run reaches it
    const double first = d(p[2]) + d(p[6]);
    if (first < tstop && (pulses == 0 || pulses > 1)) refuse_step(*this, *step, first);
  }
  if (kind == Kind::sin) {
    if (d(p[3]) > 0 && d(p[3]) <= tstop) out.push_back(d(p[3]));
  } else if (kind == Kind::exp) {
    for (double c : {d(p[2]), d(p[4])})
      for (long k = 0; period > 0 || k == 0; ++k) {  // gnucap's period=: each restart's corners
        const double at = c + (period > 0 ? d(period) * static_cast<double>(k) : 0.0);
        if (at > tstop) break;
        if (k >= kMaxPeriods)
          throw std::invalid_argument(element + ": " + text + " has more than " + std::to_string(kMaxPeriods) +
                                      " periods before " + std::to_string(tstop) + " s");
        if (at > 0) out.push_back(at);
        if (!(period > 0)) break;
      }
  } else if (kind == Kind::pwl) {
    for (std::size_t i = 0; i < p.size(); i += 2)
      if (d(p[i]) > 0 && d(p[i]) <= tstop) out.push_back(d(p[i]));
    if (repeat) {  // the repeated part's points, period after period
      const double r = d(*repeat), end = d(p[p.size() - 2]), period = end - r;
      for (long k = 1;; ++k) {
        if (end + period * static_cast<double>(k - 1) > tstop) break;
        if (k >= kMaxPeriods)
          throw std::invalid_argument(element + ": " + text + " repeats more than " + std::to_string(kMaxPeriods) +
                                      " times before " + std::to_string(tstop) + " s");
        for (std::size_t i = 0; i < p.size(); i += 2)
          if (p[i] > *repeat) {  // the repeat point itself is the previous period's last corner, LAST + PERIOD·(k − 1)
            const double c = d(p[i]) + period * static_cast<double>(k);
            if (c > 0 && c <= tstop) out.push_back(c);
          }
      }
    }
  } else if (kind == Kind::pulse) {
    const double td = d(p[2]), tr = d(p[3]), tf = d(p[4]), pw = d(p[5]), per = d(p[6]);
    for (long k = 0;; ++k) {
      const double base = td + (per > 0 ? per * static_cast<double>(k) : 0.0);
      if (base > tstop) break;
      if (pulses > 0 && k >= pulses) {  // NP pulses done: V1 from here on
        if (base > 0) out.push_back(base);
        break;
      }
      if (k >= kMaxPeriods)
        throw std::invalid_argument(element + ": " + text + " has more than " + std::to_string(kMaxPeriods) +
                                    " periods before " + std::to_string(tstop) +
                                    " s (each is four breakpoints of the exact integration)");
      for (double c : {base, base + tr, base + tr + pw, base + tr + pw + tf})
        if (c > 0 && c <= tstop) out.push_back(c);
      if (per <= 0) break;
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void Waveform::exo_state(double t, long double* w) const {
  if (kind == Kind::sffm) throw std::invalid_argument(element + ": an SFFM source has no finite exosystem");
  if (period > 0) throw std::invalid_argument(element + ": a periodic EXP has no exosystem of three states");
  w[0] = w[1] = w[2] = 0;
  if (kind == Kind::sin) {
    const double td = d(p[3]), phi = d(p[5]) * kPi / 180;
    w[0] = d(p[0]);
    if (t < td) {  // ngspice holds VO + VA sin(PHASE) before TD
      w[0] += static_cast<long double>(d(p[1])) * std::sin(static_cast<long double>(phi));
      return;
    }
    const std::complex<long double> s(decay(), omega());
    const std::complex<long double> z =
        static_cast<long double>(d(p[1])) *
        std::exp(s * static_cast<long double>(t - td) + std::complex<long double>(0, phi));
    w[1] = z.real();
    w[2] = z.imag();
    return;
  }
  if (kind == Kind::exp) {
    exp_state(*this, t, w);
    return;
  }
  w[0] = value(t, 0);
  w[1] = value(t, 1);
}

}  // namespace dcad::io

namespace dcad::io {

void Waveform::exact_piece(const Rational& t, Rational& v, Rational& slope) const {
  if (kind == Kind::sin || kind == Kind::exp || kind == Kind::sffm)
    throw std::invalid_argument(element + ": exact_piece of a SIN, EXP or SFFM source");
  if (kind == Kind::dc) {
    v = p[0];
    slope = 0;
    return;
  }
  linear_at(*this, t, v, slope);
}

std::optional<std::string> without_exact_flow(const std::vector<Waveform>& waveforms) {
  for (const Waveform& w : waveforms) {
    if (w.is_sffm()) return w.element + " (" + w.text + "), frequency modulated: no finite exosystem";
    if (w.period > 0)
      return w.element + " (" + w.text + "), a periodic EXP (gnucap's period=: a new exponential every period)";
    if (const std::optional<Rational> t = w.step_at())
      return w.element + " (" + w.text + "), a step at t = " + t->str() + " s";
  }
  return std::nullopt;
}

std::optional<Rational> Waveform::step_at() const {
  if (kind == Kind::pulse) {
    if (p.size() < 7 || p[0] == p[1]) return std::nullopt;
    const Rational &td = p[2], &tr = p[3], &tf = p[4], &pw = p[5], &per = p[6];
    if (tr == 0) return td;
    if (tf == 0 && (per == 0 || tr + pw < per)) return td + tr + pw;  // the fall is reached
    return std::nullopt;  // a PULSE cut by its PER: refused where a run reaches it (breakpoints)
  }
  if (kind != Kind::pwl) return std::nullopt;
  for (std::size_t i = 2; i + 1 < p.size(); i += 2)
    if (p[i] == p[i - 2] && p[i + 1] != p[i - 1]) return p[i];
  if (repeat) {
    for (std::size_t i = 0; i + 1 < p.size(); i += 2)
      if (p[i] == *repeat && p[i + 1] != p.back()) return p[p.size() - 2];
  }
  return std::nullopt;
}

std::optional<Rational> Waveform::next_corner(const Rational& t) const {
  std::optional<Rational> best;
  const auto consider = [&](const Rational& c) {
    if (c > t && c > 0 && (!best || c < *best)) best = c;
  };
  if (kind == Kind::sin) {
    consider(p[3]);
  } else if (kind == Kind::exp) {
    consider(p[2]);
    consider(p[4]);
  } else if (kind == Kind::pwl) {
    for (std::size_t i = 0; i < p.size(); i += 2) consider(p[i]);
    if (repeat && t >= p[p.size() - 2]) {
      const Rational period = p[p.size() - 2] - *repeat, k = floor_of(Rational((t - *repeat) / period));
      for (const Rational& shift : {Rational(k * period), Rational((k + 1) * period)})
        for (std::size_t i = 0; i < p.size(); i += 2)
          if (p[i] >= *repeat) consider(p[i] + shift);
    }
  } else if (kind == Kind::pulse) {
    const Rational &td = p[2], &tr = p[3], &tf = p[4], &pw = p[5], &per = p[6];
    Rational k0 = 0;
    if (per > 0 && t > td) k0 = floor_of(Rational((t - td) / per));
    for (Rational k = k0; k <= k0 + 1; k += 1) {
      const Rational base = td + (per > 0 ? per * k : Rational(0));
      if (pulses > 0 && k >= pulses) {  // NP pulses done: the last corner is the end of the last period
        consider(td + per * pulses);
        break;
      }
      if (k >= 1 && base > t && pulse_step(*this)) refuse_step(*this, *pulse_step(*this), d(base));
      for (const Rational& c : {base, Rational(base + tr), Rational(base + tr + pw), Rational(base + tr + pw + tf)})
        consider(c);
      if (per <= 0) break;
    }
  }
  return best;
}

}  // namespace dcad::io
