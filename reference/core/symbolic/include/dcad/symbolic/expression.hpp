// Expressions of the CONTRACT's expression form (Lagrangians, constraints, forces): exact rational
// numbers, variables, + − × ÷, integer powers, sin, cos, exp, sqrt.  Immutable DAGs; the builders
// fold numbers and drop neutral elements so that symbolic derivatives stay small.  Nothing here
// decides anything: evaluation is generic over the scalar (a number or a Jet, jet.hpp).
#pragma once

#include "dcad/symbolic/rational.hpp"

#include <memory>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

/// The builders (add, mul, sin, …) live in namespace expr, so that they never hide std::sin for doubles.
namespace dcad::symbolic::expr {

enum class ExprOp { Number, Variable, Add, Sub, Mul, Div, Neg, Pow, Sin, Cos, Exp, Sqrt };

struct ExprNode;
using Expr = std::shared_ptr<const ExprNode>;

struct ExprNode {
  ExprOp op = ExprOp::Number;
  Rational value = 0;   ///< Number
  std::size_t var = 0;  ///< Variable
  long exponent = 0;    ///< Pow
  Expr a, b;            ///< operands (b only for binary operations)
};

inline bool is_number(const Expr& e) { return e->op == ExprOp::Number; }
inline bool is_number(const Expr& e, long v) { return is_number(e) && e->value == v; }

inline Expr number(const Rational& v) {
  auto n = std::make_shared<ExprNode>();
  n->value = v;
  return n;
}
inline Expr variable(std::size_t i) {
  auto n = std::make_shared<ExprNode>();
  n->op = ExprOp::Variable;
  n->var = i;
  return n;
}
inline Expr make(ExprOp op, Expr a, Expr b = nullptr, long exponent = 0) {
  auto n = std::make_shared<ExprNode>();
  n->op = op;
  n->a = std::move(a);
  n->b = std::move(b);
  n->exponent = exponent;
  return n;
}

inline Expr sub(const Expr& a, const Expr& b);
inline Expr neg(const Expr& a) {
  if (is_number(a)) return number(-a->value);
  if (a->op == ExprOp::Neg) return a->a;
  if (a->op == ExprOp::Mul && is_number(a->a))  // −(c·x) = (−c)·x
    return a->a->value == -1 ? a->b : make(ExprOp::Mul, number(-a->a->value), a->b);
  if (a->op == ExprOp::Sub) return sub(a->b, a->a);  // −(x − y) = y − x (folded: −(−3 − x) prints x + 3, not x - -3)
  return make(ExprOp::Neg, a);
}
/// −b as a "positive" expression if b is visibly negative (−x, a negative number, c·x with c < 0), else
/// nullptr: a + (−x) is built as a − x, so that formulas print as people write them.
inline Expr negated(const Expr& b) {
  if (b->op == ExprOp::Neg) return b->a;
  if (is_number(b) && b->value < 0) return number(-b->value);
  if (b->op == ExprOp::Mul && is_number(b->a) && b->a->value < 0)
    return b->a->value == -1 ? b->b : make(ExprOp::Mul, number(-b->a->value), b->b);
  return nullptr;
}
Expr mul(const Expr& a, const Expr& b);
inline Expr add(const Expr& a, const Expr& b) {
  if (is_number(a) && is_number(b)) return number(a->value + b->value);
  if (is_number(a, 0)) return b;
  if (is_number(b, 0)) return a;
  if (a.get() == b.get()) return mul(number(2), a);  // x + x (one node: derivatives of products make these)
  if (const Expr nb = negated(b)) return make(ExprOp::Sub, a, nb);
  return make(ExprOp::Add, a, b);
}
inline Expr sub(const Expr& a, const Expr& b) {
  if (is_number(a) && is_number(b)) return number(a->value - b->value);
  if (is_number(b, 0)) return a;
  if (a.get() == b.get()) return number(0);  // x − x, one node
  if (is_number(a, 0)) return neg(b);
  if (const Expr nb = negated(b)) return make(ExprOp::Add, a, nb);
  return make(ExprOp::Sub, a, b);
}
inline Expr mul(const Expr& a, const Expr& b) {
  if (is_number(a) && is_number(b)) return number(a->value * b->value);
  if (is_number(b)) return mul(b, a);  // numbers first, so that c·(d·x) folds to (cd)·x
  if (is_number(a) && b->op == ExprOp::Mul && is_number(b->a)) return mul(number(a->value * b->a->value), b->b);
  if (is_number(a, 0) || is_number(b, 0)) return number(0);
  if (is_number(a, 1)) return b;
  if (is_number(b, 1)) return a;
  if (is_number(a, -1)) return neg(b);
  if (is_number(b, -1)) return neg(a);
  if (a->op == ExprOp::Neg) return neg(mul(a->a, b));  // signs and numbers move to the front
  if (b->op == ExprOp::Neg) return neg(mul(a, b->a));
  if (!is_number(a) && a->op == ExprOp::Mul && is_number(a->a)) return mul(a->a, mul(a->b, b));
  if (!is_number(a) && b->op == ExprOp::Mul && is_number(b->a)) return mul(b->a, mul(a, b->b));
  return make(ExprOp::Mul, a, b);
}
/// a / b; a division by the number 0 is std::invalid_argument.
inline Expr div(const Expr& a, const Expr& b) {
  if (is_number(b, 0)) throw std::invalid_argument("division by zero");
  if (is_number(a) && is_number(b)) return number(a->value / b->value);
  if (is_number(a, 0)) return number(0);
  if (is_number(b, 1)) return a;
  if (is_number(b)) return mul(number(1 / b->value), a);
  if (a->op == ExprOp::Neg) return neg(div(a->a, b));
  if (b->op == ExprOp::Neg) return neg(div(a, b->a));
  return make(ExprOp::Div, a, b);
}
/// a^k, k an integer; 0^k with k < 0 is std::invalid_argument.  (a^0 is 1: the parser refuses 0^0 in
/// the user's formulas, expression_parse.cpp.)
inline Expr pow(const Expr& a, long k) {
  if (k == 0) return number(1);
  if (k == 1) return a;
  if (is_number(a)) {
    if (a->value == 0 && k < 0) throw std::invalid_argument("division by zero (0 to a negative power)");
    Rational r = 1;
    for (long i = 0; i < (k < 0 ? -k : k); ++i) r *= a->value;
    return number(k < 0 ? Rational(1 / r) : r);
  }
  return make(ExprOp::Pow, a, nullptr, k);
}
inline Expr sin(const Expr& a) { return is_number(a, 0) ? number(0) : make(ExprOp::Sin, a); }
inline Expr cos(const Expr& a) { return is_number(a, 0) ? number(1) : make(ExprOp::Cos, a); }
inline Expr exp(const Expr& a) { return is_number(a, 0) ? number(1) : make(ExprOp::Exp, a); }
inline Expr sqrt(const Expr& a) { return make(ExprOp::Sqrt, a); }

/// e depends on variable i.
inline bool depends_on(const Expr& e, std::size_t i) {
  switch (e->op) {
    case ExprOp::Number: return false;
    case ExprOp::Variable: return e->var == i;
    default: return depends_on(e->a, i) || (e->b && depends_on(e->b, i));
  }
}

/// ∂e/∂x_i by the rules of calculus (sum, product, quotient, power and chain rules).
inline Expr diff(const Expr& e, std::size_t i) {
  if (!depends_on(e, i)) return number(0);
  const Expr& a = e->a;
  switch (e->op) {
    case ExprOp::Number: return number(0);
    case ExprOp::Variable: return number(1);
    case ExprOp::Add: return add(diff(a, i), diff(e->b, i));
    case ExprOp::Sub: return sub(diff(a, i), diff(e->b, i));
    case ExprOp::Neg: return neg(diff(a, i));
    case ExprOp::Mul: return add(mul(diff(a, i), e->b), mul(a, diff(e->b, i)));
    case ExprOp::Div: return div(sub(mul(diff(a, i), e->b), mul(a, diff(e->b, i))), pow(e->b, 2));
    case ExprOp::Pow: return mul(mul(number(e->exponent), pow(a, e->exponent - 1)), diff(a, i));
    case ExprOp::Sin: return mul(cos(a), diff(a, i));
    case ExprOp::Cos: return neg(mul(sin(a), diff(a, i)));
    case ExprOp::Exp: return mul(e, diff(a, i));
    case ExprOp::Sqrt: return div(diff(a, i), mul(number(2), e));
  }
  throw std::logic_error("diff: unknown operation");
}

/// e with variable i replaced by r.
inline Expr substitute(const Expr& e, std::size_t i, const Expr& r) {
  if (!depends_on(e, i)) return e;
  switch (e->op) {
    case ExprOp::Number: return e;
    case ExprOp::Variable: return r;
    case ExprOp::Add: return add(substitute(e->a, i, r), substitute(e->b, i, r));
    case ExprOp::Sub: return sub(substitute(e->a, i, r), substitute(e->b, i, r));
    case ExprOp::Neg: return neg(substitute(e->a, i, r));
    case ExprOp::Mul: return mul(substitute(e->a, i, r), substitute(e->b, i, r));
    case ExprOp::Div: return div(substitute(e->a, i, r), substitute(e->b, i, r));
    case ExprOp::Pow: return pow(substitute(e->a, i, r), e->exponent);
    case ExprOp::Sin: return sin(substitute(e->a, i, r));
    case ExprOp::Cos: return cos(substitute(e->a, i, r));
    case ExprOp::Exp: return exp(substitute(e->a, i, r));
    case ExprOp::Sqrt: return sqrt(substitute(e->a, i, r));
  }
  throw std::logic_error("substitute: unknown operation");
}

/// Polynomial degree of e in the variables with in_set(i); −1 if e is not a polynomial in them
/// (a division by, or a function of, an expression that contains them).  A conservative syntactic
/// test: v²/v has "no degree" although it equals v.
template <class InSet>
long degree_in(const Expr& e, const InSet& in_set) {
  switch (e->op) {
    case ExprOp::Number: return 0;
    case ExprOp::Variable: return in_set(e->var) ? 1 : 0;
    case ExprOp::Add:
    case ExprOp::Sub: {
      const long x = degree_in(e->a, in_set), y = degree_in(e->b, in_set);
      return x < 0 || y < 0 ? -1 : std::max(x, y);
    }
    case ExprOp::Neg: return degree_in(e->a, in_set);
    case ExprOp::Mul: {
      const long x = degree_in(e->a, in_set), y = degree_in(e->b, in_set);
      return x < 0 || y < 0 ? -1 : x + y;
    }
    case ExprOp::Div: {
      const long x = degree_in(e->a, in_set), y = degree_in(e->b, in_set);
      return x < 0 || y != 0 ? -1 : x;
    }
    case ExprOp::Pow: {
      const long x = degree_in(e->a, in_set);
      if (x < 0 || (x > 0 && e->exponent < 0)) return -1;
      return x * e->exponent;
    }
    default: return degree_in(e->a, in_set) == 0 ? 0 : -1;
  }
}

/// The value of e with x_i = vars[i], in any scalar S with + − × ÷, from_rational(S, q) (a constant),
/// pow_int(S, k), sin, cos, exp, sqrt (found by argument-dependent lookup).  Shared subexpressions
/// (derivatives share operands) are evaluated once.
template <class S, class FromRational>
S evaluate(const Expr& e, const std::vector<S>& vars, const FromRational& constant,
           std::unordered_map<const ExprNode*, S>& memo) {
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  const auto sub_value = [&](const Expr& x) { return evaluate(x, vars, constant, memo); };
  S r = [&]() -> S {
    switch (e->op) {
      case ExprOp::Number: return constant(e->value);
      case ExprOp::Variable:
        if (e->var >= vars.size()) throw std::logic_error("evaluate: variable index out of range");
        return vars[e->var];
      case ExprOp::Add: return sub_value(e->a) + sub_value(e->b);
      case ExprOp::Sub: return sub_value(e->a) - sub_value(e->b);
      case ExprOp::Neg: return -sub_value(e->a);
      case ExprOp::Mul: return sub_value(e->a) * sub_value(e->b);
      case ExprOp::Div: return sub_value(e->a) / sub_value(e->b);
      case ExprOp::Pow: return pow_int(sub_value(e->a), e->exponent);
      case ExprOp::Sin: return sin(sub_value(e->a));
      case ExprOp::Cos: return cos(sub_value(e->a));
      case ExprOp::Exp: return exp(sub_value(e->a));
      case ExprOp::Sqrt: return sqrt(sub_value(e->a));
    }
    throw std::logic_error("evaluate: unknown operation");
  }();
  memo.emplace(e.get(), r);
  return r;
}

template <class S, class FromRational>
S evaluate(const Expr& e, const std::vector<S>& vars, const FromRational& constant) {
  std::unordered_map<const ExprNode*, S> memo;
  return evaluate(e, vars, constant, memo);
}

/// e as text in the given variable names, with the fewest parentheses that keep its meaning.
inline std::string to_text(const Expr& e, const std::vector<std::string>& names, int outer = 0) {
  // precedence: 1 sum, 2 product, 3 unary minus, 4 power, 5 atom
  const auto wrap = [&](const std::string& s, int prec) { return prec < outer ? "(" + s + ")" : s; };
  switch (e->op) {
    case ExprOp::Number: {
      const std::string s = e->value.str();
      return e->value < 0 || s.find('/') != std::string::npos ? wrap(s, e->value < 0 ? 3 : 2) : s;
    }
    case ExprOp::Variable: return e->var < names.size() ? names[e->var] : "x" + std::to_string(e->var);
    case ExprOp::Add: return wrap(to_text(e->a, names, 1) + " + " + to_text(e->b, names, 1), 1);
    case ExprOp::Sub: return wrap(to_text(e->a, names, 1) + " - " + to_text(e->b, names, 2), 1);
    case ExprOp::Neg: return wrap("-" + to_text(e->a, names, 3), 3);
    case ExprOp::Mul: return wrap(to_text(e->a, names, 2) + "*" + to_text(e->b, names, 3), 2);
    case ExprOp::Div: return wrap(to_text(e->a, names, 2) + "/" + to_text(e->b, names, 3), 2);
    case ExprOp::Pow:
      return wrap(to_text(e->a, names, 5) + "^" +
                      (e->exponent < 0 ? "(" + std::to_string(e->exponent) + ")" : std::to_string(e->exponent)),
                  4);
    case ExprOp::Sin: return "sin(" + to_text(e->a, names) + ")";
    case ExprOp::Cos: return "cos(" + to_text(e->a, names) + ")";
    case ExprOp::Exp: return "exp(" + to_text(e->a, names) + ")";
    case ExprOp::Sqrt: return "sqrt(" + to_text(e->a, names) + ")";
  }
  throw std::logic_error("to_text: unknown operation");
}

}  // namespace dcad::symbolic::expr
