// Recursive descent over the grammar
//   sum     := product (('+' | '-') product)*
//   product := unary (('*' | '/') unary)*
//   unary   := ('+' | '-') unary | power
//   power   := atom ('^' integer)?          integer: [+-]?digits or '(' [+-]?digits ')'
//   atom    := number | name | function '(' sum ')' | '(' sum ')'
// so -x^2 = -(x^2) and 2^-1 is refused (write 2^(-1)); a^b^c is refused (ambiguous).
#include "expression_parse.hpp"

#include <algorithm>
#include <cctype>

namespace dcad::io {

namespace ex = reference::expr;

namespace {

constexpr std::size_t kMaxDepth = 200;        // nesting of parentheses and unary signs
constexpr long kMaxExponent = 64;             // x^k with |k| ≤ 64: larger ones only make huge derivatives
constexpr std::size_t kMaxLength = 10000000;  // 10⁷ characters (a check of 1.1·10⁶: 1.9 s, 0.22 GB)

class Parser {
 public:
  Parser(const std::string& text, const std::map<std::string, std::size_t>& vars,
         const std::map<std::string, Rational>& params, const Where& at)
      : t_(text), vars_(vars), params_(params), at_(at) {}

  ex::Expr parse() {
    if (t_.size() > kMaxLength)
      at_.fail("an expression of at most " + std::to_string(kMaxLength) + " characters", std::to_string(t_.size()));
    skip();
    if (i_ == t_.size()) fail("an expression", "an empty string");
    ex::Expr e = sum();
    skip();
    if (i_ != t_.size()) fail("an operator (+ - * / ^) or the end", quote_here());
    return e;
  }

 private:
  [[noreturn]] void fail(const std::string& expected, const std::string& found) const {
    throw InputError(at_.file + ": " + (at_.path.empty() ? std::string("/") : at_.path) + ": column " +
                     std::to_string(i_ + 1) + ": expected " + expected + ", found " + found);
  }
  std::string quote_here() const {
    if (i_ >= t_.size()) return "the end of the expression";
    std::string s = t_.substr(i_, 12);
    return "\"" + s + (i_ + 12 < t_.size() ? "..." : "") + "\"";
  }
  void skip() {
    while (i_ < t_.size() && std::isspace(static_cast<unsigned char>(t_[i_]))) ++i_;
  }
  bool eat(char c) {
    skip();
    if (i_ < t_.size() && t_[i_] == c) {
      ++i_;
      return true;
    }
    return false;
  }
  void enter() {
    if (++depth_ > kMaxDepth)
      fail("at most " + std::to_string(kMaxDepth) + " nested parentheses or signs", "deeper nesting");
  }

  /// Up to kChain operands a chain a ± b ± c … (a * b / c …) is folded from the left, as written; beyond,
  /// into a balanced tree of the same value — sympy's unsimplified output runs to 10⁵ terms, and every later
  /// pass over a formula recurses along its depth (a left fold of them overflowed the stack).
  static constexpr std::size_t kChain = 64;
  template <class Op>
  static ex::Expr balanced(const std::vector<ex::Expr>& v, std::size_t lo, std::size_t hi, const Op& op) {
    if (hi - lo == 1) return v[lo];
    const std::size_t mid = lo + (hi - lo) / 2;
    return op(balanced(v, lo, mid, op), balanced(v, mid, hi, op));
  }
  ex::Expr sum() {
    std::vector<std::pair<bool, ex::Expr>> terms{{false, product()}};  // (subtracted, term)
    for (;;) {
      if (eat('+'))
        terms.emplace_back(false, product());
      else if (eat('-'))
        terms.emplace_back(true, product());
      else
        break;
    }
    if (terms.size() <= kChain) {
      ex::Expr e = terms[0].second;
      for (std::size_t k = 1; k < terms.size(); ++k)
        e = terms[k].first ? ex::sub(e, terms[k].second) : ex::add(e, terms[k].second);
      return e;
    }
    std::vector<ex::Expr> signed_terms;
    for (const auto& [minus, t] : terms) signed_terms.push_back(minus ? ex::neg(t) : t);
    return balanced(signed_terms, 0, signed_terms.size(),
                    [](const ex::Expr& a, const ex::Expr& b) { return ex::add(a, b); });
  }
  ex::Expr product() {
    std::vector<std::pair<bool, ex::Expr>> factors{{false, unary()}};  // (divisor, factor)
    for (;;) {
      if (eat('*')) {
        factors.emplace_back(false, unary());
      } else if (eat('/')) {
        const std::size_t at = i_;
        ex::Expr d = unary();
        if (ex::is_number(d, 0)) {
          i_ = at;
          fail("a nonzero divisor", "division by zero");
        }
        factors.emplace_back(true, d);
      } else {
        break;
      }
    }
    if (factors.size() <= kChain) {
      ex::Expr e = factors[0].second;
      for (std::size_t k = 1; k < factors.size(); ++k)
        e = factors[k].first ? ex::div(e, factors[k].second) : ex::mul(e, factors[k].second);
      return e;
    }
    std::vector<ex::Expr> seq;  // in the order written, a divisor d as 1/d: neighbours x/x still meet first (in
                                // double, x^40/x^40 overflows where the product of the pairs does not)
    for (const auto& [divisor, f] : factors) seq.push_back(divisor ? ex::div(ex::number(1), f) : f);
    return balanced(seq, 0, seq.size(), [](const ex::Expr& a, const ex::Expr& b) { return ex::mul(a, b); });
  }
  ex::Expr unary() {
    skip();
    if (eat('-')) {
      enter();
      ex::Expr e = ex::neg(unary());
      --depth_;
      return e;
    }
    if (eat('+')) {
      enter();
      ex::Expr e = unary();
      --depth_;
      return e;
    }
    return power();
  }
  ex::Expr power() {
    ex::Expr base = atom();
    if (!eat('^')) return base;
    skip();
    const bool paren = eat('(');
    skip();
    bool neg = false;
    if (i_ < t_.size() && (t_[i_] == '-' || t_[i_] == '+')) {
      if (!paren) fail("an integer exponent (a negative one in parentheses: x^(-2))", quote_here());
      neg = t_[i_++] == '-';
    }
    const std::size_t start = i_;
    while (i_ < t_.size() && std::isdigit(static_cast<unsigned char>(t_[i_]))) ++i_;
    if (i_ == start) fail("an integer exponent", quote_here());
    if (i_ - start > 3 || std::stol(t_.substr(start, i_ - start)) > kMaxExponent) {
      i_ = start;
      fail("an exponent of at most " + std::to_string(kMaxExponent), quote_here());
    }
    long k = std::stol(t_.substr(start, i_ - start));
    if (neg) k = -k;
    if (paren && !eat(')')) fail("')' closing the exponent", quote_here());
    skip();
    if (i_ < t_.size() && t_[i_] == '^') fail("an operator other than a second ^ (write (a^b)^c)", quote_here());
    if (ex::is_number(base, 0) && k < 0) fail("a nonzero base for a negative power", "0^(" + std::to_string(k) + ")");
    if (ex::is_number(base, 0) && k == 0)
      fail("a nonzero base for the power 0 (0^0 is undefined: dcad does not read it as 1)", "0^0");
    return ex::pow(base, k);
  }
  ex::Expr atom() {
    skip();
    if (i_ >= t_.size()) fail("a number, a name or '('", "the end of the expression");
    const char c = t_[i_];
    if (c == '(') {
      ++i_;
      enter();
      ex::Expr e = sum();
      --depth_;
      if (!eat(')')) fail("')'", quote_here());
      return e;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') return name();
    fail("a number, a name or '('", quote_here());
  }
  ex::Expr number() {
    const std::size_t start = i_;
    while (i_ < t_.size() && (std::isdigit(static_cast<unsigned char>(t_[i_])) || t_[i_] == '.')) ++i_;
    if (i_ < t_.size() && (t_[i_] == 'e' || t_[i_] == 'E')) {
      std::size_t j = i_ + 1;
      if (j < t_.size() && (t_[j] == '+' || t_[j] == '-')) ++j;
      if (j < t_.size() && std::isdigit(static_cast<unsigned char>(t_[j]))) {
        i_ = j;
        while (i_ < t_.size() && std::isdigit(static_cast<unsigned char>(t_[i_]))) ++i_;
      }
    }
    const std::string text = t_.substr(start, i_ - start);
    try {
      return ex::number(reference::parse_rational(text));
    } catch (const std::invalid_argument& e) {
      i_ = start;
      fail("a number such as 3, 0.125 or 1e-3", "\"" + text + "\"");
    }
  }
  ex::Expr name() {
    const std::size_t start = i_;
    while (i_ < t_.size() && (std::isalnum(static_cast<unsigned char>(t_[i_])) || t_[i_] == '_')) ++i_;
    const std::string id = t_.substr(start, i_ - start);
    const auto& fns = expression_functions();
    if (std::find(fns.begin(), fns.end(), id) != fns.end()) {
      if (!eat('(')) fail("'(' after the function " + id, quote_here());
      enter();
      ex::Expr arg = sum();
      --depth_;
      if (!eat(')')) fail("')' closing " + id + "(", quote_here());
      if (id == "sin") return ex::sin(arg);
      if (id == "cos") return ex::cos(arg);
      if (id == "exp") return ex::exp(arg);
      return ex::sqrt(arg);
    }
    if (const auto v = vars_.find(id); v != vars_.end()) return ex::variable(v->second);
    if (const auto p = params_.find(id); p != params_.end()) return ex::number(p->second);
    std::vector<std::string> known(fns);
    for (const auto& [k, v] : vars_) known.push_back(k);
    for (const auto& [k, v] : params_) known.push_back(k);
    const std::string best = nearest_name(id, known);
    i_ = start;
    std::string list;
    for (const auto& [k, v] : vars_) list += (list.empty() ? "" : ", ") + k;
    fail("a variable (" + list + "), a parameter or a function (sin, cos, exp, sqrt)",
         "unknown name \"" + id + "\"" + (best.empty() ? "" : " (did you mean \"" + best + "\"?)"));
  }

  const std::string& t_;
  const std::map<std::string, std::size_t>& vars_;
  const std::map<std::string, Rational>& params_;
  const Where& at_;
  std::size_t i_ = 0, depth_ = 0;
};

}  // namespace

const std::vector<std::string>& expression_functions() {
  static const std::vector<std::string> f{"sin", "cos", "exp", "sqrt"};
  return f;
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

ex::Expr parse_expression(const std::string& text, const std::map<std::string, std::size_t>& variables,
                          const std::map<std::string, Rational>& parameters, const Where& at) {
  return Parser(text, variables, parameters, at).parse();
}

}  // namespace dcad::io
