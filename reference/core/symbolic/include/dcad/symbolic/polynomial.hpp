// A canonical form of expressions (expression.hpp) as polynomials with rational coefficients over atoms:
// the variables, and sin, cos, exp, sqrt of a canonical argument and 1/(a canonical sum) as opaque
// atoms (atoms may carry negative exponents: x·x⁻¹ cancels).  Two expressions with the same canonical
// form are equal as functions (expansion and collection of like terms are identities); the converse
// does not hold (sin² + cos² is not 1 here).  Used to decide that a constraint is affine in the
// velocities after simplification — (v+1)² − v² − 2v is the constant 1 — not by its syntax alone.
#pragma once

#include "dcad/symbolic/expression.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace dcad::symbolic::expr {

class Canonical {
 public:
  using Mono = std::vector<std::pair<std::string, long>>;  ///< atoms (by key, sorted) and exponents
  using Poly = std::map<Mono, Rational>;                   ///< nonzero coefficients only

  /// The canonical form of e; std::length_error beyond `max_terms` terms (an expansion too large to decide).
  /// A node shared in the DAG (derivatives share their operands) is expanded once.
  Poly of(const Expr& e) {
    if (e->op == ExprOp::Number || e->op == ExprOp::Variable) return expand(e);
    if (const auto it = memo_.find(e.get()); it != memo_.end()) return it->second;
    Poly p = expand(e);
    keep_.push_back(e);  // the key stays alive: a freed node's address is never reused while cached
    return memo_.emplace(e.get(), std::move(p)).first->second;
  }

 private:
  Poly expand(const Expr& e) {
    switch (e->op) {
      case ExprOp::Number: return constant(e->value);
      case ExprOp::Variable: return atom("x" + std::to_string(e->var), e);
      case ExprOp::Add: return plus(of(e->a), of(e->b), 1);
      case ExprOp::Sub: return plus(of(e->a), of(e->b), -1);
      case ExprOp::Neg: return plus(Poly{}, of(e->a), -1);
      case ExprOp::Mul: return times(of(e->a), of(e->b));
      case ExprOp::Div: return times(of(e->a), inverse(of(e->b)));
      case ExprOp::Pow: {
        const Poly base = of(e->a);
        Poly r = constant(1), b = e->exponent < 0 ? inverse(base) : base;
        for (long k = 0; k < (e->exponent < 0 ? -e->exponent : e->exponent); ++k) r = times(r, b);
        return r;
      }
      case ExprOp::Sin: return function("sin", e->a);
      case ExprOp::Cos: return function("cos", e->a);
      case ExprOp::Exp: return function("exp", e->a);
      case ExprOp::Sqrt: return function("sqrt", e->a);
    }
    throw std::logic_error("Canonical: unknown operation");
  }

 public:
  /// Canonical text of a form (equal forms, equal texts).
  static std::string key(const Poly& p) {
    std::string s;
    for (const auto& [m, c] : p) {
      s += "+" + c.str();
      for (const auto& [a, k] : m) s += "*" + a + "^" + std::to_string(k);
    }
    return s.empty() ? "0" : s;
  }

  /// An expression for a form (built with expression.hpp's folding builders).
  Expr expr(const Poly& p) const {
    Expr sum = number(0);
    for (const auto& [m, c] : p) {
      Expr term = number(c);
      for (const auto& [a, k] : m) term = mul(term, pow(atoms_.at(a), k));
      sum = add(sum, term);
    }
    return sum;
  }
  const Expr& atom_expr(const std::string& key) const { return atoms_.at(key); }

  std::size_t max_terms = 4096;
  std::size_t max_key = 20000;

 private:
  std::map<std::string, Expr> atoms_;
  std::unordered_map<const ExprNode*, Poly> memo_;
  std::vector<Expr> keep_;

  static Poly constant(const Rational& v) {
    Poly p;
    if (v != 0) p[{}] = v;
    return p;
  }
  Poly atom(const std::string& key, const Expr& e) {
    // an atom's key holds its argument's canonical text: nested quotients (1/(… 1/(…) …)) grow it
    // geometrically, so a large one is "too large to decide", like a large expansion
    if (key.size() > max_key)
      throw std::length_error("an atom of more than " + std::to_string(max_key) + " characters");
    atoms_.emplace(key, e);
    return Poly{{Mono{{key, 1}}, Rational(1)}};
  }
  Poly plus(Poly a, const Poly& b, int sign) {
    for (const auto& [m, c] : b) {
      Rational& x = a[m];
      x += sign > 0 ? c : Rational(-c);
      if (x == 0) a.erase(m);
    }
    return a;
  }
  Poly times(const Poly& a, const Poly& b) {
    Poly r;
    for (const auto& [ma, ca] : a)
      for (const auto& [mb, cb] : b) {
        Mono m = ma;
        for (const auto& [atom, k] : mb) {
          auto it = std::lower_bound(m.begin(), m.end(), atom,
                                     [](const auto& x, const std::string& y) { return x.first < y; });
          if (it != m.end() && it->first == atom) {
            it->second += k;
            if (it->second == 0) m.erase(it);
          } else {
            m.insert(it, {atom, k});
          }
        }
        Rational& x = r[m];
        x += ca * cb;
        if (x == 0) r.erase(m);
        if (r.size() > max_terms) throw std::length_error("more than " + std::to_string(max_terms) + " terms");
      }
    return r;
  }
  /// 1/p: a monomial is inverted (its atoms' exponents negated), anything else is the atom 1/(p).
  Poly inverse(const Poly& p) {
    if (p.empty()) throw std::domain_error("division by an expression that is identically 0");
    if (p.size() == 1) {
      Mono m = p.begin()->first;
      for (auto& [a, k] : m) k = -k;
      return Poly{{m, Rational(1 / p.begin()->second)}};
    }
    return atom("1/(" + key(p) + ")", div(number(1), expr(p)));
  }
  Poly function(const char* name, const Expr& arg) {
    const Poly a = of(arg);
    const Expr inner = expr(a);
    const std::string op(name);
    const Expr e = op == "sin" ? sin(inner) : op == "cos" ? cos(inner) : op == "exp" ? exp(inner) : sqrt(inner);
    if (is_number(e)) return constant(e->value);  // sin(0), cos(0), exp(0)
    return atom(op + "(" + key(a) + ")", e);
  }
};

/// e as a(t, q)·v + b(t, q) after simplification (Canonical): the coefficients of the variables with
/// is_v (in order `vs`) and the rest, or nothing when e is not affine in them (a square of a velocity
/// that does not cancel, a velocity inside a function or a denominator) or too large to expand.
template <class IsV>
std::optional<std::pair<std::vector<Expr>, Expr>> affine_form(const Expr& e, const std::vector<std::size_t>& vs,
                                                              const IsV& is_v) {
  Canonical c;
  Canonical::Poly p;
  try {
    p = c.of(e);
  } catch (const std::length_error&) {
    return std::nullopt;
  } catch (const std::domain_error&) {
    return std::nullopt;
  }
  std::vector<Canonical::Poly> a(vs.size());
  Canonical::Poly b;
  for (const auto& [m, coef] : p) {
    long degree = 0;
    std::size_t which = 0;
    Canonical::Mono rest;
    for (const auto& [atom, k] : m) {
      const Expr& x = c.atom_expr(atom);
      const bool v_atom = x->op == ExprOp::Variable && is_v(x->var);
      if (!v_atom) {
        for (std::size_t v : vs)
          if (depends_on(x, v)) return std::nullopt;  // a velocity inside a function or a denominator
        rest.push_back({atom, k});
        continue;
      }
      if (k < 0) return std::nullopt;
      degree += k;
      which = static_cast<std::size_t>(std::find(vs.begin(), vs.end(), x->var) - vs.begin());
    }
    if (degree > 1) return std::nullopt;
    (degree == 0 ? b : a[which])[rest] = coef;
  }
  std::vector<Expr> coefficients;
  for (const auto& ai : a) coefficients.push_back(c.expr(ai));
  return std::make_pair(coefficients, c.expr(b));
}

}  // namespace dcad::symbolic::expr
