#include "dcad/io/waveform.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace dcad::io {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return s;
}

double d(const Rational& x) { return x.convert_to<double>(); }

constexpr double kPi = 3.141592653589793238462643383279502884;

}  // namespace

Waveform parse_waveform(const std::string& spec, const std::function<Rational(const std::string&)>& number) {
  std::string s = spec;
  for (char& ch : s)
    if (ch == ',') ch = ' ';
  Waveform w;
  w.text = spec;
  const std::string l = lower(s);
  const std::size_t open = l.find('(');
  std::string head = l.substr(0, open == std::string::npos ? l.size() : open);
  std::vector<std::string> pre;
  {
    std::string t;
    for (std::size_t i = 0; i <= head.size(); ++i) {
      if (i == head.size() || std::isspace(static_cast<unsigned char>(head[i]))) {
        if (!t.empty()) pre.push_back(t);
        t.clear();
      } else {
        t += s[i];
      }
    }
  }
  if (open == std::string::npos) {  // [DC] value
    if (!pre.empty() && lower(pre[0]) == "dc") pre.erase(pre.begin());
    if (pre.size() != 1) throw std::invalid_argument("expected [DC] VALUE, SIN(...), PULSE(...) or PWL(...), found \"" + spec + "\"");
    w.p = {number(pre[0])};
    return w;
  }
  // "DC v" before a transient function is the operating-point value: the transient uses the function
  if (pre.size() >= 2 && lower(pre[0]) == "dc") pre.erase(pre.begin(), pre.begin() + 2);
  if (pre.size() != 1) throw std::invalid_argument("expected one of SIN(...), PULSE(...), PWL(...), found \"" + spec + "\"");
  const std::string fn = lower(pre[0]);
  const std::size_t close = l.rfind(')');
  if (close == std::string::npos || close < open) throw std::invalid_argument("expected a closing ')' in \"" + spec + "\"");
  for (std::size_t i = close + 1; i < l.size(); ++i)
    if (!std::isspace(static_cast<unsigned char>(l[i])))
      throw std::invalid_argument("expected nothing after " + pre[0] + "(...), found \"" + spec.substr(i) + "\"");
  std::vector<Rational> a;
  {
    std::string t;
    const std::string inner = s.substr(open + 1, close - open - 1);
    for (std::size_t i = 0; i <= inner.size(); ++i) {
      if (i == inner.size() || std::isspace(static_cast<unsigned char>(inner[i]))) {
        if (!t.empty()) a.push_back(number(t));
        t.clear();
      } else {
        t += inner[i];
      }
    }
  }
  if (fn == "sin") {
    if (a.size() < 3 || a.size() > 6)
      throw std::invalid_argument("expected SIN(VO VA FREQ [TD [THETA [PHASE]]]) with FREQ given, found " + std::to_string(a.size()) + " values");
    a.resize(6, Rational(0));
    if (a[3] < 0 || a[2] < 0) throw std::invalid_argument("expected FREQ >= 0 and TD >= 0 in SIN, found a negative one");
    w.kind = Waveform::Kind::sin;
  } else if (fn == "pulse") {
    if (a.size() != 7)
      throw std::invalid_argument("expected PULSE(V1 V2 TD TR TF PW PER) with all seven values (dcad has no TSTEP/TSTOP defaults), found " +
                                  std::to_string(a.size()));
    if (a[2] < 0 || a[3] <= 0 || a[4] <= 0 || a[5] < 0 || a[6] < a[3] + a[4] + a[5])
      throw std::invalid_argument("expected PULSE with TD >= 0, TR > 0, TF > 0, PW >= 0 and PER >= TR + PW + TF, found TD = " + a[2].str() +
                                  ", TR = " + a[3].str() + ", TF = " + a[4].str() + ", PW = " + a[5].str() + ", PER = " + a[6].str());
    w.kind = Waveform::Kind::pulse;
  } else if (fn == "pwl") {
    if (a.size() < 2 || a.size() % 2 != 0) throw std::invalid_argument("expected PWL(t1 v1 t2 v2 ...) with pairs, found " + std::to_string(a.size()) + " values");
    for (std::size_t i = 2; i < a.size(); i += 2)
      if (!(a[i] > a[i - 2])) throw std::invalid_argument("expected increasing PWL times, found " + a[i - 2].str() + " then " + a[i].str());
    if (a[0] < 0) throw std::invalid_argument("expected PWL times >= 0, found " + a[0].str());
    w.kind = Waveform::Kind::pwl;
  } else {
    throw std::invalid_argument("expected SIN, PULSE or PWL, found \"" + pre[0] + "\" (EXP, SFFM, AM are not supported)");
  }
  w.p = a;
  return w;
}

bool Waveform::constant() const {
  if (kind == Kind::dc) return true;
  if (kind == Kind::sin) return p[1] == 0 || p[2] == 0 && p[5] == 0;
  return false;
}

double Waveform::horizon() const {
  switch (kind) {
    case Kind::dc: return 0;
    case Kind::sin: return d(p[3]) + (p[2] != 0 ? 4 / d(p[2]) : 1.0);
    case Kind::pulse: return d(p[2]) + 2 * d(p[6]);
    default: return 2 * d(p[p.size() - 2]);
  }
}

double Waveform::decay() const { return kind == Kind::sin ? -d(p[4]) : 0.0; }
double Waveform::omega() const { return kind == Kind::sin ? 2 * kPi * d(p[2]) : 0.0; }

namespace {

/// Piecewise-linear pieces (t_i, v_i) of PULSE (one period, shifted) or PWL at t: value and slope.
double floor_of(double x) { return std::floor(x); }
Rational floor_of(const Rational& x) {
  using boost::multiprecision::mpz_int;
  const mpz_int n = boost::multiprecision::numerator(x), q = boost::multiprecision::denominator(x);
  mpz_int f = n / q;  // truncates toward zero
  if (f * q > n) f -= 1;
  return Rational(f);
}
double as(double, const Rational& x) { return d(x); }
Rational as(const Rational&, const Rational& x) { return x; }

/// PULSE and PWL: the value and slope at t (right limit), in double or exactly (T = Rational).
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
    T tau = t - td;
    if (per > 0) tau -= per * floor_of(T(tau / per));
    if (tau < tr) {
      slope = (v2 - v1) / tr;
      v = v1 + slope * tau;
    } else if (tau < tr + pw) {
      v = v2;
    } else if (tau < tr + pw + tf) {
      slope = (v1 - v2) / tf;
      v = v2 + slope * (tau - tr - pw);
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
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const T t0 = p(2 * i), t1 = p(2 * i + 2);
    if (t < t1) {
      const T v0 = p(2 * i + 1), v1 = p(2 * i + 3);
      slope = (v1 - v0) / (t1 - t0);
      v = v0 + slope * (t - t0);
      return;
    }
  }
  v = p(2 * n - 1);
}

}  // namespace

double Waveform::value(double t, int order) const {
  switch (kind) {
    case Kind::dc:
      return order == 0 ? d(p[0]) : 0.0;
    case Kind::sin: {
      const double vo = d(p[0]), va = d(p[1]), td = d(p[3]), phi = d(p[5]) * kPi / 180;
      if (t < td) return order == 0 ? vo + va * std::sin(phi) : 0.0;  // ngspice: VO + VA sin(PHASE) before TD
      // Im(VA s^order e^{s τ + iφ}) with s = −θ + iω
      const std::complex<double> s(decay(), omega());
      const std::complex<double> z = va * std::pow(s, order) * std::exp(s * (t - td) + std::complex<double>(0, phi));
      return (order == 0 ? vo : 0.0) + z.imag();
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
    case Kind::dc:
      return order == 0 ? p[0] : Rational(0);
    case Kind::sin: {
      if (p[1] == 0) return order == 0 ? p[0] : Rational(0);  // no sine: VO
      if (order > 0) {
        if (p[3] > 0) return Rational(0);  // before TD the value is constant
        return std::nullopt;               // VA (−θ + iω)^order …: ω = 2π FREQ
      }
      const Rational phase = p[5] - 360 * floor_of(Rational(p[5] / 360));         // VO + VA sin φ, rational at quarter turns
      // VO + VA sin φ, at t = 0 whether or not TD > 0 (ngspice holds it before TD)
      if (phase == 0 || phase == 180) return p[0];
      if (phase == 90) return p[0] + p[1];
      if (phase == 270) return p[0] - p[1];
      return std::nullopt;
    }
    default: {
      Rational v, slope;
      linear_at(*this, Rational(0), v, slope);
      return order == 0 ? v : order == 1 ? slope : Rational(0);
    }
  }
}

std::vector<double> Waveform::breakpoints(double tstop) const {
  std::vector<double> out;
  if (kind == Kind::sin) {
    if (d(p[3]) > 0 && d(p[3]) <= tstop) out.push_back(d(p[3]));
  } else if (kind == Kind::pwl) {
    for (std::size_t i = 0; i < p.size(); i += 2)
      if (d(p[i]) > 0 && d(p[i]) <= tstop) out.push_back(d(p[i]));
  } else if (kind == Kind::pulse) {
    const double td = d(p[2]), tr = d(p[3]), tf = d(p[4]), pw = d(p[5]), per = d(p[6]);
    for (long k = 0;; ++k) {
      const double base = td + (per > 0 ? per * static_cast<double>(k) : 0.0);
      if (base > tstop) break;
      if (k >= kMaxPeriods)
        throw std::invalid_argument(element + ": " + text + " has more than " + std::to_string(kMaxPeriods) + " periods before " +
                                    std::to_string(tstop) + " s (each is four breakpoints of the exact integration)");
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
        static_cast<long double>(d(p[1])) * std::exp(s * static_cast<long double>(t - td) + std::complex<long double>(0, phi));
    w[1] = z.real();
    w[2] = z.imag();
    return;
  }
  w[0] = value(t, 0);
  w[1] = value(t, 1);
}

}  // namespace dcad::io

namespace dcad::io {

void Waveform::exact_piece(const Rational& t, Rational& v, Rational& slope) const {
  if (kind == Kind::sin) throw std::invalid_argument(element + ": exact_piece of a SIN source");
  if (kind == Kind::dc) {
    v = p[0];
    slope = 0;
    return;
  }
  linear_at(*this, t, v, slope);
}

std::optional<Rational> Waveform::next_corner(const Rational& t) const {
  std::optional<Rational> best;
  const auto consider = [&](const Rational& c) {
    if (c > t && c > 0 && (!best || c < *best)) best = c;
  };
  if (kind == Kind::sin) {
    consider(p[3]);
  } else if (kind == Kind::pwl) {
    for (std::size_t i = 0; i < p.size(); i += 2) consider(p[i]);
  } else if (kind == Kind::pulse) {
    const Rational &td = p[2], &tr = p[3], &tf = p[4], &pw = p[5], &per = p[6];
    Rational k0 = 0;
    if (per > 0 && t > td) k0 = floor_of(Rational((t - td) / per));
    for (Rational k = k0; k <= k0 + 1; k += 1) {
      const Rational base = td + (per > 0 ? per * k : Rational(0));
      for (const Rational& c : {base, Rational(base + tr), Rational(base + tr + pw), Rational(base + tr + pw + tf)}) consider(c);
      if (per <= 0) break;
    }
  }
  return best;
}

}  // namespace dcad::io
