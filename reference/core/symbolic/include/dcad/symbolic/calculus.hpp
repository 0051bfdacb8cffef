// Calculus on expression DAGs (expression.hpp) with shared subexpressions handled once: ∂e/∂x_i and
// "e depends on x_i", memoized per (node, variable).  expr::diff and expr::depends_on recurse without
// memory, which is exponential on a DAG whose nodes are shared (a derivative of a derivative); every
// route that differentiates repeatedly (the charts of fast/chart.hpp, the reference's CEF (1.6) on
// formulas) uses this one.  Nothing here decides anything.
#pragma once

#include "dcad/symbolic/expression.hpp"

#include <algorithm>
#include <functional>
#include <unordered_map>
#include <vector>

namespace dcad::symbolic::expr {

/// ∂e/∂x_i with shared subexpressions differentiated once (the DAG's sharing kept in the result).
class Differentiator {
 public:
  Expr operator()(const Expr& e, std::size_t i) {
    if (!depends(e, i)) return number(0);
    if (e->op == ExprOp::Variable) return number(1);
    const Key k{e.get(), i};
    if (const auto it = d_.find(k); it != d_.end()) return it->second;
    const Expr& a = e->a;
    const auto d = [&](const Expr& x) { return (*this)(x, i); };
    Expr r;
    switch (e->op) {
      case ExprOp::Add: r = add(d(a), d(e->b)); break;
      case ExprOp::Sub: r = sub(d(a), d(e->b)); break;
      case ExprOp::Neg: r = neg(d(a)); break;
      case ExprOp::Mul: r = add(mul(d(a), e->b), mul(a, d(e->b))); break;
      case ExprOp::Div: {  // (a/b)' = a'/b − (a/b)·b'/b: the quotient itself is shared
        const Expr db = d(e->b);
        r = sub(div(d(a), e->b), div(mul(e, db), e->b));
        break;
      }
      case ExprOp::Pow: r = mul(mul(number(e->exponent), pow(a, e->exponent - 1)), d(a)); break;
      case ExprOp::Sin: r = mul(cos(a), d(a)); break;
      case ExprOp::Cos: r = neg(mul(sin(a), d(a))); break;
      case ExprOp::Exp: r = mul(e, d(a)); break;
      case ExprOp::Sqrt: r = div(d(a), mul(number(2), e)); break;
      default: throw std::logic_error("diff: unknown operation");
    }
    keep_.push_back(e);
    d_.emplace(k, r);
    return r;
  }
  bool depends(const Expr& e, std::size_t i) {
    if (e->op == ExprOp::Number) return false;
    if (e->op == ExprOp::Variable) return e->var == i;
    const Key k{e.get(), i};
    if (const auto it = dep_.find(k); it != dep_.end()) return it->second;
    const bool r = depends(e->a, i) || (e->b && depends(e->b, i));
    keep_.push_back(e);
    dep_.emplace(k, r);
    return r;
  }
  std::size_t size() const { return d_.size(); }  ///< derivatives cached

 private:
  struct Key {
    const ExprNode* node;
    std::size_t var;
    bool operator==(const Key& o) const { return node == o.node && var == o.var; }
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return std::hash<const void*>()(k.node) ^ (k.var * 0x9e3779b97f4a7c15ULL);
    }
  };
  std::vector<Expr> keep_;  ///< keys stay alive: a freed node's address is never reused while cached
  std::unordered_map<Key, Expr, Hash> d_;
  std::unordered_map<Key, bool, Hash> dep_;
};

/// The size of e as a tree (its DAG unshared, saturating at `cap`): what symbolic differentiation without
/// sharing walks, and what to_text prints.
inline double tree_size(const Expr& e, std::unordered_map<const ExprNode*, double>& memo, double cap) {
  if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
  double n = 1;
  if (e->a) n += tree_size(e->a, memo, cap);
  if (e->b) n += tree_size(e->b, memo, cap);
  n = std::min(n, cap);
  memo.emplace(e.get(), n);
  return n;
}

}  // namespace dcad::symbolic::expr
