// Reduced rational functions on FLINT's fmpq_mpoly (rational_functions.hpp).
#include "rational_functions.hpp"

#include <flint/fmpq.h>
#include <flint/fmpq_mpoly.h>

#include <cstdlib>
#include <map>
#include <stdexcept>

namespace dcad::reference {

namespace {
using expr::Expr;
using expr::ExprOp;
}  // namespace

struct RationalFunctions::Impl {
  /// N/D in lowest terms, D monic (leading coefficient 1 in the context's order).
  struct Fraction {
    fmpq_mpoly_t n, d;
  };
  std::size_t vars, slots;  ///< expression variables, and the context's (vars + atoms)
  std::size_t max_terms, max_atoms;
  fmpq_mpoly_ctx_t ctx;
  std::vector<std::unique_ptr<Fraction>> store;
  std::unordered_map<const expr::ExprNode*, Fraction*> memo;
  std::vector<Expr> keep;                        ///< memoized nodes stay alive: a freed node's address is never reused
  std::map<std::string, std::size_t> atom_slot;  ///< "sin(N/D)" → its variable
  std::vector<Expr> atom_expr;                   ///< the atom as an expression (slot − vars)
  std::vector<std::vector<bool>> atom_involves;  ///< which expression variables its argument involves

  Impl(std::size_t v, std::size_t terms, std::size_t atoms)
      : vars(v), slots(v + atoms), max_terms(terms), max_atoms(atoms) {
    fmpq_mpoly_ctx_init(ctx, static_cast<slong>(slots), ORD_LEX);
  }
  ~Impl() {
    for (auto& f : store) {
      fmpq_mpoly_clear(f->n, ctx);
      fmpq_mpoly_clear(f->d, ctx);
    }
    fmpq_mpoly_ctx_clear(ctx);
  }

  Fraction* fresh() {
    store.push_back(std::make_unique<Fraction>());
    Fraction* f = store.back().get();
    fmpq_mpoly_init(f->n, ctx);
    fmpq_mpoly_init(f->d, ctx);
    fmpq_mpoly_one(f->d, ctx);
    return f;
  }
  void check(const fmpq_mpoly_t p) const {
    if (static_cast<std::size_t>(fmpq_mpoly_length(p, ctx)) > max_terms)
      throw std::length_error("a rational function of more than " + std::to_string(max_terms) + " terms");
  }
  /// N/D to lowest terms, D monic; D = 0 is a division by an identically zero expression.
  void reduce(Fraction* f) {
    if (fmpq_mpoly_is_zero(f->d, ctx)) throw std::domain_error("division by an expression that is identically 0");
    if (fmpq_mpoly_is_zero(f->n, ctx)) {
      fmpq_mpoly_one(f->d, ctx);
      return;
    }
    if (!fmpq_mpoly_is_fmpq(f->d, ctx)) {
      fmpq_mpoly_t g;
      fmpq_mpoly_init(g, ctx);
      if (!fmpq_mpoly_gcd(g, f->n, f->d, ctx)) {
        fmpq_mpoly_clear(g, ctx);
        throw std::length_error("a polynomial gcd FLINT could not compute");
      }
      if (!fmpq_mpoly_is_one(g, ctx)) {
        fmpq_mpoly_divides(f->n, f->n, g, ctx);
        fmpq_mpoly_divides(f->d, f->d, g, ctx);
      }
      fmpq_mpoly_clear(g, ctx);
    }
    fmpq_t lc;
    fmpq_init(lc);
    fmpq_mpoly_get_term_coeff_fmpq(lc, f->d, 0, ctx);
    if (!fmpq_is_one(lc)) {
      fmpq_mpoly_scalar_div_fmpq(f->n, f->n, lc, ctx);
      fmpq_mpoly_scalar_div_fmpq(f->d, f->d, lc, ctx);
    }
    fmpq_clear(lc);
    check(f->n);
    check(f->d);
  }

  /// sin, cos, exp or sqrt of a fraction: a new generator per distinct argument (an atom), the same one again
  /// for an argument that reduces to the same fraction.
  void atom(const Expr& e, Fraction* r) {
    const Fraction* a = of(e->a);
    const char* op = e->op == ExprOp::Sin   ? "sin"
                     : e->op == ExprOp::Cos ? "cos"
                     : e->op == ExprOp::Exp ? "exp"
                                            : "sqrt";
    char* ns = fmpq_mpoly_get_str_pretty(a->n, nullptr, ctx);
    char* ds = fmpq_mpoly_get_str_pretty(a->d, nullptr, ctx);
    const std::string key = std::string(op) + "((" + ns + ")/(" + ds + "))";
    flint_free(ns);
    flint_free(ds);
    auto it = atom_slot.find(key);
    if (it == atom_slot.end()) {
      if (atom_expr.size() >= max_atoms)
        throw std::length_error("more than " + std::to_string(max_atoms) + " distinct sin, cos, exp or sqrt");
      it = atom_slot.emplace(key, vars + atom_expr.size()).first;
      atom_expr.push_back(e);
      atom_involves.push_back(involved(a));
    }
    fmpq_mpoly_gen(r->n, static_cast<slong>(it->second), ctx);
  }

  Fraction* of(const Expr& e) {
    if (const auto it = memo.find(e.get()); it != memo.end()) return it->second;
    Fraction* r = fresh();
    switch (e->op) {
      case ExprOp::Number: {
        fmpq_t c;
        fmpq_init(c);
        fmpq_set_mpq(c, e->value.backend().data());
        fmpq_mpoly_set_fmpq(r->n, c, ctx);
        fmpq_clear(c);
        break;
      }
      case ExprOp::Variable:
        if (e->var >= vars) throw std::logic_error("RationalFunctions: variable index out of range");
        fmpq_mpoly_gen(r->n, static_cast<slong>(e->var), ctx);
        break;
      case ExprOp::Add:
      case ExprOp::Sub: {
        const Fraction *a = of(e->a), *b = of(e->b);
        fmpq_mpoly_t t;
        fmpq_mpoly_init(t, ctx);
        fmpq_mpoly_mul(r->n, a->n, b->d, ctx);
        fmpq_mpoly_mul(t, b->n, a->d, ctx);
        if (e->op == ExprOp::Add)
          fmpq_mpoly_add(r->n, r->n, t, ctx);
        else
          fmpq_mpoly_sub(r->n, r->n, t, ctx);
        fmpq_mpoly_mul(r->d, a->d, b->d, ctx);
        fmpq_mpoly_clear(t, ctx);
        reduce(r);
        break;
      }
      case ExprOp::Neg: {
        const Fraction* a = of(e->a);
        fmpq_mpoly_neg(r->n, a->n, ctx);
        fmpq_mpoly_set(r->d, a->d, ctx);
        break;
      }
      case ExprOp::Mul:
      case ExprOp::Div: {
        const Fraction *a = of(e->a), *b = of(e->b);
        const bool div = e->op == ExprOp::Div;
        fmpq_mpoly_mul(r->n, a->n, div ? b->d : b->n, ctx);
        fmpq_mpoly_mul(r->d, a->d, div ? b->n : b->d, ctx);
        reduce(r);
        break;
      }
      case ExprOp::Pow: {
        const Fraction* a = of(e->a);
        const long k = e->exponent;
        const ulong u = static_cast<ulong>(k < 0 ? -k : k);
        if (u > 1000) throw std::length_error("a power above 1000");
        fmpq_mpoly_pow_ui(r->n, k < 0 ? a->d : a->n, u, ctx);
        fmpq_mpoly_pow_ui(r->d, k < 0 ? a->n : a->d, u, ctx);
        reduce(r);
        break;
      }
      case ExprOp::Sin:
      case ExprOp::Cos:
      case ExprOp::Exp:
      case ExprOp::Sqrt: atom(e, r); break;
    }
    keep.push_back(e);
    memo.emplace(e.get(), r);
    return r;
  }

  /// The expression variables a fraction involves, through its atoms too.
  std::vector<bool> involved(const Fraction* f) const {
    std::vector<bool> out(vars, false);
    for (const auto* p : {&f->n, &f->d})
      for (std::size_t s = 0; s < slots; ++s) {
        if (fmpq_mpoly_degree_si(*p, static_cast<slong>(s), ctx) <= 0) continue;
        if (s < vars) {
          out[s] = true;
        } else {
          const std::vector<bool>& a = atom_involves[s - vars];
          for (std::size_t i = 0; i < vars; ++i) out[i] = out[i] || a[i];
        }
      }
    return out;
  }

  /// A polynomial as an expression (its atoms as the expressions they stand for).
  Expr expression(const fmpq_mpoly_t p) const {
    Expr sum = expr::number(0);
    std::vector<ulong> exps(slots);
    fmpq_t c;
    fmpq_init(c);
    for (slong i = 0; i < fmpq_mpoly_length(p, ctx); ++i) {
      fmpq_mpoly_get_term_coeff_fmpq(c, p, i, ctx);
      Rational q;
      fmpq_get_mpq(q.backend().data(), c);
      fmpq_mpoly_get_term_exp_ui(exps.data(), p, i, ctx);
      Expr term = expr::number(q);
      for (std::size_t s = 0; s < slots; ++s)
        if (exps[s] > 0)
          term = expr::mul(term,
                           expr::pow(s < vars ? expr::variable(s) : atom_expr[s - vars], static_cast<long>(exps[s])));
      sum = expr::add(sum, term);
    }
    fmpq_clear(c);
    return sum;
  }
};

RationalFunctions::RationalFunctions(std::size_t variables) : p_(std::make_unique<Impl>(variables, 20000, 64)) {}
RationalFunctions::~RationalFunctions() = default;

bool RationalFunctions::zero(const Expr& e) {
  if (expr::is_number(e)) return e->value == 0;
  try {
    return fmpq_mpoly_is_zero(p_->of(e)->n, p_->ctx);
  } catch (const std::length_error&) {
    return false;
  } catch (const std::domain_error&) {
    return false;
  }
}

std::optional<Expr> RationalFunctions::reduced(const Expr& e, std::vector<bool>* involves, bool* atoms) {
  try {
    const Impl::Fraction* f = p_->of(e);
    if (involves) *involves = p_->involved(f);
    if (atoms) {
      *atoms = false;
      for (const auto* q : {&f->n, &f->d})
        for (std::size_t s = p_->vars; s < p_->slots; ++s)
          *atoms = *atoms || fmpq_mpoly_degree_si(*q, static_cast<slong>(s), p_->ctx) > 0;
    }
    const Expr n = p_->expression(f->n);
    return fmpq_mpoly_is_one(f->d, p_->ctx) ? n : expr::div(n, p_->expression(f->d));
  } catch (const std::length_error&) {
    return std::nullopt;
  } catch (const std::domain_error&) {
    return std::nullopt;
  }
}

}  // namespace dcad::reference
