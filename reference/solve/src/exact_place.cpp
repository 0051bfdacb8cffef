// A rational place for the exact route (exact_place.hpp): angles on rational points of the circle,
// positions on the holonomic constraints.
#include "dcad/reference/pipeline/exact_place.hpp"

#include "dcad/reference/nonlinear/jet.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <unordered_map>

namespace dcad::reference::pipeline {

namespace {

using expr::Expr;
using expr::ExprNode;
using expr::ExprOp;

/// arg = k·x_i + (terms without x_i): k (any rational), or nullopt if x_i occurs otherwise.
std::optional<Rational> linear_coefficient(const Expr& arg, std::size_t i) {
  if (!expr::depends_on(arg, i)) return Rational(0);
  switch (arg->op) {
    case ExprOp::Variable: return Rational(1);
    case ExprOp::Add:
    case ExprOp::Sub: {
      const auto a = linear_coefficient(arg->a, i), b = linear_coefficient(arg->b, i);
      if (!a || !b) return std::nullopt;
      return arg->op == ExprOp::Add ? Rational(*a + *b) : Rational(*a - *b);
    }
    case ExprOp::Neg: {
      const auto a = linear_coefficient(arg->a, i);
      return a ? std::optional<Rational>(-*a) : std::nullopt;
    }
    case ExprOp::Mul: {
      const Expr& k = expr::is_number(arg->a) ? arg->a : arg->b;
      const Expr& x = expr::is_number(arg->a) ? arg->b : arg->a;
      if (!expr::is_number(k)) return std::nullopt;
      const auto a = linear_coefficient(x, i);
      return a ? std::optional<Rational>(k->value * *a) : std::nullopt;
    }
    case ExprOp::Div: {
      if (!expr::is_number(arg->b)) return std::nullopt;
      const auto a = linear_coefficient(arg->a, i);
      return a ? std::optional<Rational>(*a / arg->b->value) : std::nullopt;
    }
    default: return std::nullopt;
  }
}

bool is_integer(const Rational& r) { return denominator(r) == 1; }

/// x_i occurs in e only as k·x_i, k an integer, inside arguments of sin and cos.
bool only_in_trig(const Expr& e, std::size_t i, std::unordered_map<const ExprNode*, bool>& memo) {
  if (!expr::depends_on(e, i)) return true;
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  bool ok = false;
  if (e->op == ExprOp::Sin || e->op == ExprOp::Cos) {
    // |k| ≤ 64, as the parser's exponents: cos(kφ₀) is a power (c + i s)^k, whose size grows with k
    // (cos(1000000000*phi) ran for minutes)
    const auto k = linear_coefficient(e->a, i);
    ok = k && is_integer(*k) && abs(*k) <= 64;
  } else if (e->op != ExprOp::Variable) {
    ok = only_in_trig(e->a, i, memo) && (!e->b || only_in_trig(e->b, i, memo));
  }
  memo.emplace(e.get(), ok);
  return ok;
}

/// x_i occurs inside an argument of sin, cos or exp.
bool inside_function(const Expr& e, std::size_t i) {
  if (!expr::depends_on(e, i)) return false;
  if (e->op == ExprOp::Sin || e->op == ExprOp::Cos || e->op == ExprOp::Exp) return true;
  return e->a && (inside_function(e->a, i) || (e->b && inside_function(e->b, i)));
}

/// Every expression of the system.
std::vector<Expr> all_expressions(const LagrangianSystem& s) {
  std::vector<Expr> all{s.lagrangian};
  all.insert(all.end(), s.constraints.begin(), s.constraints.end());
  all.insert(all.end(), s.forces.begin(), s.forces.end());
  return all;
}

/// (cos, sin) of k·φ₀ from (cos φ₀, sin φ₀): (c + i s)^k, exactly.
std::pair<Rational, Rational> rotate(const Rational& c, const Rational& s, long k) {
  Rational rc = 1, rs = 0;
  const Rational sc = k < 0 ? -s : s;  // (c + i s)^{−1} = c − i s on the unit circle
  for (long j = 0; j < std::labs(k); ++j) {
    const Rational nc = rc * c - rs * sc, ns = rc * sc + rs * c;
    rc = nc;
    rs = ns;
  }
  return {rc, rs};
}

/// The rewrite of translate_angles, memoized on the DAG.
struct Translator {
  const std::vector<PlacedAngle>& angles;
  std::unordered_map<const ExprNode*, Expr> memo;

  Expr operator()(const Expr& e) {
    if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
    Expr r = rewrite(e);
    memo.emplace(e.get(), r);
    return r;
  }

  Expr rewrite(const Expr& e) {
    switch (e->op) {
      case ExprOp::Number:
      case ExprOp::Variable: return e;
      case ExprOp::Sin:
      case ExprOp::Cos: {
        // arg(φ₀ + φ') = Θ + arg(φ'), Θ = Σ k_j φ₀_j: sin(Θ + a) = sin Θ cos a + cos Θ sin a, cos(Θ + a) = cos Θ cos a
        // − sin Θ sin a
        Rational c = 1, s = 0;
        for (const PlacedAngle& g : angles) {
          const auto k = linear_coefficient(e->a, g.q);
          if (!k || *k == 0) continue;
          const auto [kc, ks] = rotate(g.cos, g.sin, static_cast<long>(numerator(*k)));
          const Rational nc = c * kc - s * ks, ns = c * ks + s * kc;
          c = nc;
          s = ns;
        }
        const Expr a = (*this)(e->a);
        if (c == 1 && s == 0) return e->op == ExprOp::Sin ? expr::sin(a) : expr::cos(a);
        const Expr ca = expr::cos(a), sa = expr::sin(a);
        if (e->op == ExprOp::Sin) return expr::add(expr::mul(expr::number(s), ca), expr::mul(expr::number(c), sa));
        return expr::sub(expr::mul(expr::number(c), ca), expr::mul(expr::number(s), sa));
      }
      case ExprOp::Add: return expr::add((*this)(e->a), (*this)(e->b));
      case ExprOp::Sub: return expr::sub((*this)(e->a), (*this)(e->b));
      case ExprOp::Mul: return expr::mul((*this)(e->a), (*this)(e->b));
      case ExprOp::Div: return expr::div((*this)(e->a), (*this)(e->b));
      case ExprOp::Neg: return expr::neg((*this)(e->a));
      case ExprOp::Pow: return expr::pow((*this)(e->a), e->exponent);
      case ExprOp::Exp: return expr::exp((*this)(e->a));
      case ExprOp::Sqrt: return expr::sqrt((*this)(e->a));
    }
    throw std::logic_error("translate_angles: unknown operation");
  }
};

/// The exact value of e at x (NotExactHere where a function's value is irrational).
Rational value_at(const Expr& e, const std::vector<Rational>& x) {
  static const auto space = std::make_shared<const JetSpace>(0, 0);
  std::vector<Jet<Rational>> vars;
  vars.reserve(x.size());
  for (const Rational& v : x) vars.emplace_back(space, v);
  return expr::evaluate(e, vars, [](const Rational& q) { return Jet<Rational>(space, q); }).value();
}

/// A rational square root of r, if r is the square of a rational.
std::optional<Rational> rational_sqrt(const Rational& r) {
  if (r < 0) return std::nullopt;
  try {
    return JetFunctions<Rational>::sqrt(r);
  } catch (const NotExactHere&) {
    return std::nullopt;
  }
}

/// h affine in one of `vars`: one exact Newton step in it lands on h = 0.
bool affine_step(const Expr& h, const std::vector<std::size_t>& vars, std::vector<Rational>& x) {
  for (std::size_t z : vars) {
    if (expr::degree_in(h, [&](std::size_t i) { return i == z; }) != 1) continue;
    std::vector<Rational> y = x;
    const Rational a = value_at(expr::diff(h, z), y);
    if (a == 0) continue;
    y[z] -= value_at(h, y) / a;
    if (value_at(h, y) == 0) {
      x = y;
      return true;
    }
  }
  return false;
}

/// Candidate values for the coordinates not solved for: small numbers and the values at hand (the values
/// of the coordinates that stay: a circle about (x1, y1) has the point (x1 ± r, y1)), and the moving
/// coordinates' values simplified (x = 0.6000000000000001: 3/5, and y = ±4/5).
std::vector<Rational> candidate_values(const std::vector<std::size_t>& vars, const std::vector<Rational>& x) {
  std::vector<Rational> cand{0, 1, -1, 2, -2, Rational(1, 2), Rational(-1, 2), 3, -3};
  for (std::size_t i = 0; i < x.size(); ++i)
    if (std::find(vars.begin(), vars.end(), i) == vars.end() && std::find(cand.begin(), cand.end(), x[i]) == cand.end())
      cand.push_back(x[i]);
  for (std::size_t w : vars)
    for (long den = 10; den <= 1000000; den *= 10) {
      const Rational r = simplest_near(x[w], den);
      if (std::find(cand.begin(), cand.end(), r) == cand.end()) cand.push_back(r);
    }
  return cand;
}

/// The rational zeros of a polynomial of degree ≤ 2 given by its values at 0, 1 and −1.
std::vector<Rational> rational_roots(const Rational& f0, const Rational& f1, const Rational& fm) {
  const Rational qa = (f1 + fm) / 2 - f0, qb = (f1 - fm) / 2;
  std::vector<Rational> roots;
  if (qa == 0 && qb != 0) roots.push_back(-f0 / qb);
  if (qa != 0)
    if (const auto r = rational_sqrt(qb * qb - 4 * qa * f0)) {
      roots.push_back((-qb + *r) / (2 * qa));
      roots.push_back((-qb - *r) / (2 * qa));
    }
  return roots;
}

/// From a rational zero rp of the quadratic h, the line rp + s·d, d ≈ x − rp with its largest entry 1 and the
/// others' best approximations of denominator ≤ 10⁴ (the slopes of a stereographic projection: the point lands
/// within ~1e-8 with small denominators): g(s) = A s² + B s (g(0) = 0), its other zero s = −B/A, if rational
/// and a zero of h.
std::optional<std::vector<Rational>> second_intersection(const Expr& h, const std::vector<std::size_t>& vars,
                                                         const std::vector<Rational>& x,
                                                         const std::vector<Rational>& rp, long& budget) {
  std::size_t big = vars[0];
  for (std::size_t w : vars)
    if (abs(x[w] - rp[w]) > abs(x[big] - rp[big])) big = w;
  if (x[big] == rp[big]) return std::nullopt;
  std::map<std::size_t, Rational> d;
  for (std::size_t w : vars) d[w] = w == big ? Rational(1) : simplest_near((x[w] - rp[w]) / (x[big] - rp[big]), 10000);
  const auto g = [&](const Rational& s) {
    std::vector<Rational> p = x;
    for (std::size_t w : vars) p[w] = rp[w] + s * d[w];
    return p;
  };
  budget -= 3;
  const Rational g1 = value_at(h, g(1)), gm = value_at(h, g(-1));
  const Rational la = (g1 + gm) / 2, lb = (g1 - gm) / 2;
  if (la == 0) return std::nullopt;
  const std::vector<Rational> p = g(-lb / la);
  if (value_at(h, p) != 0) return std::nullopt;
  return p;
}

/// x moved towards {h = 0} along the coordinates of `vars` that are not `anchored` (least-norm Newton steps in
/// rationals, each rounded to a denominator ≤ 10¹²), where some are: the line from a rational point of the quadric
/// through it meets the quadric again beside it, so the anchored values move by ~1e-8 only (x1 = 1/2 given on the
/// unit circle: y1 = ±√3/2 has no rational value, and the line through (1/2, 0) landed far from x1 = 1/2).
std::vector<Rational> aimed(const Expr& h, const std::vector<std::size_t>& vars, const std::vector<char>& anchored,
                            const std::vector<Rational>& x) {
  std::vector<std::size_t> loose;
  for (std::size_t w : vars)
    if (!anchored[w]) loose.push_back(w);
  std::vector<Rational> aim = x;
  if (loose.empty() || loose.size() == vars.size()) return aim;
  for (int it = 0; it < 40; ++it) {
    const Rational f = value_at(h, aim);
    if (f == 0) break;
    const std::vector<Rational> g = exact_gradient(h, aim, aim.size());
    Rational nn = 0;
    for (std::size_t w : loose) nn += g[w] * g[w];
    for (std::size_t w : loose)  // at a critical point (y1 = 0 on the circle), a step off it first
      aim[w] = nn == 0 ? aim[w] + Rational(1, 2) : simplest_near(aim[w] - f * g[w] / nn, 1000000000000L);
  }
  return aim;
}

/// Puts x on {h = 0} by moving the coordinates in `vars` (h affine in one of them: solved for it; h
/// quadratic in them: the second intersection of the line from a rational point R of the quadric
/// through x; of the points found, the nearest to x in the `anchored` coordinates — the given ones —
/// or in all of `vars` if none is).  The result is checked exactly; false if none is found.
bool land(const Expr& h, const std::vector<std::size_t>& vars, const std::vector<char>& anchored,
          std::vector<Rational>& x) {
  std::vector<std::size_t> measured;
  for (std::size_t w : vars)
    if (anchored[w]) measured.push_back(w);
  if (measured.empty()) measured = vars;
  const auto distance = [&](const std::vector<Rational>& p) {
    double d = 0;
    for (std::size_t w : measured)
      d = std::max(d,
                   std::abs((p[w] - x[w]).convert_to<double>()) / std::max(1.0, std::abs(x[w].convert_to<double>())));
    return d;
  };
  if (affine_step(h, vars, x)) return true;
  if (expr::degree_in(h, [&](std::size_t i) { return std::find(vars.begin(), vars.end(), i) != vars.end(); }) != 2)
    return false;
  const std::vector<Rational> aim = aimed(h, vars, anchored, x);
  const std::vector<Rational> cand = candidate_values(vars, x);
  const std::size_t nc = cand.size();
  std::optional<std::vector<Rational>> best;
  double best_distance = HUGE_VAL;
  long budget = 20000;  // evaluations of h in the search
  for (std::size_t z : vars) {
    std::vector<std::size_t> others;
    for (std::size_t w : vars)
      if (w != z) others.push_back(w);
    std::vector<std::size_t> pick(others.size(), 0);
    while (budget > 0) {
      std::vector<Rational> y = x;
      for (std::size_t j = 0; j < others.size(); ++j) y[others[j]] = cand[pick[j]];
      const auto at = [&](const Rational& v) {
        y[z] = v;
        return value_at(h, y);
      };
      budget -= 3;
      const Rational f0 = at(0), f1 = at(1), fm = at(-1);
      for (const Rational& root : rational_roots(f0, f1, fm)) {
        std::vector<Rational> rp = y;
        rp[z] = root;
        if (value_at(h, rp) != 0) continue;
        const std::optional<std::vector<Rational>> p = second_intersection(h, vars, aim, rp, budget);
        if (p && distance(*p) < best_distance) {
          best = p;
          best_distance = distance(*p);
        }
      }
      if (best_distance <= 1e-12) break;  // as near as the given decimals
      std::size_t j = 0;                  // the next assignment of the others
      while (j < pick.size() && ++pick[j] == nc) pick[j++] = 0;
      if (j == pick.size()) break;
    }
    if (best_distance <= 1e-12) break;
  }
  if (!best) return false;
  x = *best;
  return true;
}

}  // namespace

std::vector<std::size_t> angle_coordinates(const LagrangianSystem& s) {
  std::vector<std::size_t> out;
  const std::vector<Expr> all = all_expressions(s);
  for (std::size_t i = 0; i < s.n; ++i) {
    std::unordered_map<const ExprNode*, bool> memo;
    bool occurs = false, ok = true;
    for (const Expr& e : all) {
      occurs = occurs || expr::depends_on(e, s.q(i));
      ok = ok && only_in_trig(e, s.q(i), memo);
    }
    if (occurs && ok) out.push_back(i);
  }
  return out;
}

LagrangianSystem translate_angles(const LagrangianSystem& s, const std::vector<PlacedAngle>& angles) {
  LagrangianSystem t = s;
  Translator tr{angles, {}};
  t.lagrangian = tr(s.lagrangian);
  for (Expr& c : t.constraints) c = tr(c);
  for (Expr& f : t.forces) f = tr(f);
  return t;
}

std::vector<expr::Expr> holonomic_constraints(const LagrangianSystem& s) {
  std::vector<Expr> out;
  const auto velocity_free = [&](const Expr& e) {
    for (std::size_t i = 0; i < s.n; ++i)
      if (expr::depends_on(e, s.v(i))) return false;
    return true;
  };
  for (std::size_t mu = 0; mu < s.n; ++mu) {
    bool multiplier = !expr::depends_on(s.lagrangian, s.v(mu));
    for (const Expr& c : s.constraints) multiplier = multiplier && !expr::depends_on(c, s.v(mu));
    if (!s.forces.empty()) multiplier = multiplier && expr::is_number(s.forces[mu], 0);
    if (!multiplier) continue;
    const Expr h = expr::diff(s.lagrangian, s.q(mu));
    if (!expr::is_number(h) && velocity_free(h) && !expr::depends_on(h, s.q(mu))) out.push_back(h);
  }
  for (const Expr& c : s.constraints)
    if (!expr::is_number(c) && velocity_free(c)) out.push_back(c);
  return out;
}

Rational exact_value(const expr::Expr& e, const std::vector<Rational>& x) { return value_at(e, x); }

std::vector<Rational> exact_gradient(const expr::Expr& e, const std::vector<Rational>& x, std::size_t width,
                                     Rational* value) {
  const auto space = std::make_shared<const JetSpace>(width, 1);
  std::vector<Jet<Rational>> vars;
  vars.reserve(x.size());
  for (std::size_t i = 0; i < x.size(); ++i)
    vars.push_back(i < width ? Jet<Rational>::variable(space, i, x[i]) : Jet<Rational>(space, x[i]));
  const Jet<Rational> j = expr::evaluate(e, vars, [&](const Rational& q) { return Jet<Rational>(space, q); });
  std::vector<Rational> out(width);
  for (std::size_t i = 0; i < width; ++i) out[i] = j.gradient(i);
  if (value) *value = j.value();
  return out;
}

Rational simplest_near(const Rational& x, long max_den) {
  using boost::multiprecision::mpz_int;
  // convergents h/k of the continued fraction of x, stopped before k exceeds max_den
  mpz_int n = numerator(x), d = denominator(x);
  mpz_int h0 = 0, h1 = 1, k0 = 1, k1 = 0;
  while (d != 0) {
    mpz_int a = n / d;
    if (n < 0 && a * d != n) a -= 1;  // floor
    const mpz_int h2 = a * h1 + h0, k2 = a * k1 + k0;
    if (k2 > max_den) break;
    h0 = h1;
    h1 = h2;
    k0 = k1;
    k1 = k2;
    const mpz_int r = n - a * d;
    n = d;
    d = r;
  }
  return k1 == 0 ? x : Rational(h1, k1);
}

namespace {

/// The given angle v of coordinate i placed at a rational point of the circle: φ = 2·atan(t) + 2πk with t the
/// simplest rational within 1e-9 (relative) of tan(φ/2), never 0 for φ ≠ 0 (a special point: sin φ = 0); dcad's
/// own default point (`given` false): 2·atan(v).  nullopt (with `why`) for |φ| ≥ 1e12.
std::optional<PlacedAngle> placed_angle(const LagrangianSystem& s, std::size_t i, const Rational& v, bool given,
                                        std::string& why) {
  PlacedAngle g;
  g.q = s.q(i);
  g.tan_half = v;
  if (given) {
    const double phi = v.convert_to<double>(), two_pi = 2 * std::acos(-1.0);
    if (!(std::abs(phi) < 1e12)) {  // whole turns beyond a long, and tan(φ/2) meaningless in double
      why = "the angle " + s.variable_names()[i] + " = " + v.str() + " is too large to place (|angle| ≥ 1e12)";
      return std::nullopt;
    }
    g.turns = static_cast<long>(std::llround(phi / two_pi));
    const double red = phi - two_pi * static_cast<double>(g.turns);
    for (long den = 100000;; den *= 100) {
      g.tan_half = simplest_near(Rational(std::tan(red / 2)), den);
      const double err = std::abs(2 * std::atan(g.tan_half.convert_to<double>()) - red);
      if ((g.tan_half != 0 && err <= 1e-9 * std::abs(red)) || den > 100000000000000L) break;
    }
  }
  return g;
}

/// A given coordinate inside sin, cos or exp that is not an angle keeps its given value, which makes them
/// irrational: the reason, or "" when there is none.
std::string not_exact_reason(const LagrangianSystem& s, const std::vector<Rational>& start) {
  const std::vector<std::size_t> ang = angle_coordinates(s);
  for (std::size_t i = 0; i < 2 * s.n; ++i) {
    if (start[i] == 0 || std::find(ang.begin(), ang.end(), i) != ang.end()) continue;
    for (const Expr& e : all_expressions(s))
      if (inside_function(e, i))
        return s.variable_names()[i] + " = " + start[i].str() +
               " occurs inside sin, cos or exp other than as an angle (" +
               (i < s.n ? "an angle occurs only as integer multiples, at most 64, inside sin and cos" : "a velocity") +
               "): no rational value near it makes them rational (they are irrational at every nonzero rational, "
               "Lindemann)";
  }
  return "";
}

/// dcad's own point: coordinates inside sin, cos, exp, sqrt (other than angles) at 0, with their velocities.
void default_zero_inside_functions(const LagrangianSystem& s, ExactPlace& pl) {
  const std::vector<std::size_t> ang = angle_coordinates(s);
  for (std::size_t i = 0; i < s.n; ++i) {
    if (std::find(ang.begin(), ang.end(), i) != ang.end()) continue;
    for (const Expr& e : all_expressions(pl.system))
      if (inside_function(e, s.q(i)) || inside_function(e, s.v(i))) {
        pl.start[s.q(i)] = 0;
        pl.start[s.v(i)] = 0;
      }
  }
}

/// Given values typed short (6 decimals or fewer) stay unless M_c then has no point (`loosen`); long ones —
/// rounded values of irrational ones, which may miss M_c at the place — are starting values, to 12 digits or so
/// (the CAD's values then keep readable denominators); landed positions and angles stay as placed.
void settle_given_values(const io::LagrangianCase& c, ExactPlace& pl) {
  for (std::size_t i = 0; i < 2 * c.system.n; ++i) {  // positions and velocities, not the time
    if (!c.initial[i] || pl.fixed[i]) continue;
    if (denominator(*c.initial[i]) <= 1000000) {
      pl.fixed[i] = true;
      pl.loosen.push_back(i);
    } else {
      pl.start[i] = simplest_near(pl.start[i], 1000000);
    }
  }
}

}  // namespace

std::optional<ExactPlace> exact_place(const io::LagrangianCase& c, const std::vector<Rational>& start, bool given,
                                      std::string& why) {
  const LagrangianSystem& s = c.system;
  ExactPlace pl;
  pl.start = start;
  pl.fixed.assign(start.size(), false);
  if (s.has_time) pl.fixed[s.t()] = c.initial[s.t()].has_value();
  for (std::size_t i : angle_coordinates(s)) {
    const Rational& v = start[s.q(i)];
    if (v == 0) continue;  // sin 0 and cos 0 are rational already
    std::optional<PlacedAngle> placed = placed_angle(s, i, v, given, why);
    if (!placed) return std::nullopt;
    PlacedAngle& g = *placed;
    const Rational t2 = g.tan_half * g.tan_half;
    g.cos = (1 - t2) / (1 + t2);
    g.sin = 2 * g.tan_half / (1 + t2);
    pl.angles.push_back(g);
    pl.start[g.q] = 0;
    pl.fixed[g.q] = true;
  }
  pl.system = translate_angles(s, pl.angles);
  if (given) pl.not_exact = not_exact_reason(s, start);
  if (!given) default_zero_inside_functions(s, pl);
  // positions onto the holonomic constraints, fewest coordinates first; each claims the ones it moves
  std::vector<Expr> hs = holonomic_constraints(pl.system);
  std::vector<Expr> shown = holonomic_constraints(s);  // as the case writes them (the same order)
  if (shown.size() != hs.size()) shown = hs;
  std::vector<std::vector<std::size_t>> vars(hs.size());
  for (std::size_t k = 0; k < hs.size(); ++k)
    for (std::size_t i = 0; i < s.n; ++i)
      if (expr::depends_on(hs[k], s.q(i))) vars[k].push_back(s.q(i));
  std::vector<std::size_t> order(hs.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return vars[a].size() < vars[b].size(); });
  const std::vector<std::string> names = s.variable_names();
  try {
    for (std::size_t k : order) {
      std::vector<std::size_t> movable, ungiven;  // coordinates not given move first (x = 3/5 given: y = ±4/5)
      for (std::size_t i : vars[k])
        if (!pl.fixed[i]) {
          movable.push_back(i);
          if (!given || !c.initial[i]) ungiven.push_back(i);
        }
      if (value_at(hs[k], pl.start) != 0) {
        std::vector<char> anchored(pl.start.size(), 0);
        for (std::size_t i = 0; i < 2 * s.n; ++i) anchored[i] = given && c.initial[i].has_value();
        const bool landed =
            (!ungiven.empty() && ungiven.size() < movable.size() && land(hs[k], ungiven, anchored, pl.start)) ||
            (!movable.empty() && land(hs[k], movable, anchored, pl.start));
        if (!landed) {
          why = "no rational point of " + expr::to_text(hs[k], names) + " = 0 was found near the " +
                (given ? "given" : "default") + " positions";
          return std::nullopt;
        }
        pl.landed.push_back(expr::to_text(shown[k], names) + " = 0");
      }
      // it claims the coordinates it pins (nonzero partial derivative): later ones move the others
      for (std::size_t i : vars[k])
        if (value_at(expr::diff(hs[k], i), pl.start) != 0) pl.fixed[i] = true;
    }
    for (const Expr& h : hs)  // a later landing may not undo an earlier one
      if (value_at(h, pl.start) != 0) {
        why = "no rational point of the holonomic constraints together was found (" + expr::to_text(h, names) +
              " = 0 moved off)";
        return std::nullopt;
      }
  } catch (const NotExactHere& e) {
    why = std::string("a holonomic constraint is irrational there (") + e.what() + ")";
    return std::nullopt;
  }
  if (given) settle_given_values(c, pl);
  return pl;
}

}  // namespace dcad::reference::pipeline
