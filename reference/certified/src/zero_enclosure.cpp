// Krawczyk's test in Arb's balls (zero_enclosure.hpp).
#include "dcad/certified/zero_enclosure.hpp"

#include "balls.hpp"

#include <arb.h>
#include <arb_mat.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>

namespace dcad::certified {

namespace {

namespace ex = reference::expr;
using ex::ExprOp;
using namespace detail;

/// Formulas evaluated in balls at the balls `vars`: every node once (the DAG's sharing kept).
class Evaluator {
 public:
  Evaluator(const std::deque<Ball>& vars, slong prec) : vars_(vars), prec_(prec) {}
  const arb_struct* operator()(const ex::Expr& e) {
    const auto found = memo_.find(e.get());
    if (found != memo_.end()) return found->second;
    Ball& out = store_.emplace_back();
    switch (e->op) {
      case ExprOp::Number: set_q(out.v, e->value, prec_); break;
      case ExprOp::Variable: arb_set(out.v, vars_.at(e->var).v); break;
      case ExprOp::Add: arb_add(out.v, (*this)(e->a), (*this)(e->b), prec_); break;
      case ExprOp::Sub: arb_sub(out.v, (*this)(e->a), (*this)(e->b), prec_); break;
      case ExprOp::Mul: arb_mul(out.v, (*this)(e->a), (*this)(e->b), prec_); break;
      case ExprOp::Div: arb_div(out.v, (*this)(e->a), (*this)(e->b), prec_); break;
      case ExprOp::Neg: arb_neg(out.v, (*this)(e->a)); break;
      case ExprOp::Pow: {
        const arb_struct* a = (*this)(e->a);
        arb_pow_ui(out.v, a, static_cast<ulong>(e->exponent < 0 ? -e->exponent : e->exponent), prec_);
        if (e->exponent < 0) arb_inv(out.v, out.v, prec_);
        break;
      }
      case ExprOp::Sin: arb_sin(out.v, (*this)(e->a), prec_); break;
      case ExprOp::Cos: arb_cos(out.v, (*this)(e->a), prec_); break;
      case ExprOp::Exp: arb_exp(out.v, (*this)(e->a), prec_); break;
      case ExprOp::Sqrt: arb_sqrt(out.v, (*this)(e->a), prec_); break;
    }
    memo_.emplace(e.get(), out.v);
    return out.v;
  }

 private:
  const std::deque<Ball>& vars_;
  slong prec_;
  std::deque<Ball> store_;
  std::unordered_map<const ex::ExprNode*, const arb_struct*> memo_;
};

/// K columns of the K×m matrix `j` (doubles), one per row by elimination: the largest remaining entry
/// among the columns not `held`, or where none is above 1e-10 of the matrix's size, among the held
/// ones (`moved` then says so); empty if some row has none.
std::vector<std::size_t> pivot_columns(std::vector<std::vector<double>> j, const std::vector<bool>& held, bool& moved) {
  for (std::size_t c = 0; c < held.size();
       ++c) {  // columns scaled to max-norm 1: rank is invariant, a small coordinate's column is not "zero"
    double big = 0;
    for (const auto& row : j) big = std::max(big, std::abs(row[c]));
    if (big > 0)
      for (auto& row : j) row[c] /= big;
  }
  double size = 0;
  for (const auto& row : j)
    for (double x : row) size = std::max(size, std::abs(x));
  std::vector<std::size_t> chosen;
  std::vector<bool> used(held.size(), false);
  for (std::size_t r = 0; r < j.size(); ++r) {
    std::size_t best = 0;
    double big = -1;
    for (int pass = 0; pass < 2 && !(big > 1e-10 * size); ++pass) {
      big = -1;
      for (std::size_t c = 0; c < held.size(); ++c)
        if (!used[c] && held[c] == (pass == 1) && std::abs(j[r][c]) > big) big = std::abs(j[r][c]), best = c;
      if (pass == 1 && big > 1e-10 * size) moved = true;
    }
    if (!(big > 1e-10 * size)) return {};
    used[best] = true;
    chosen.push_back(best);
    for (std::size_t s = r + 1; s < j.size(); ++s) {
      const double f = j[s][best] / j[r][best];
      for (std::size_t c = 0; c < j[s].size(); ++c) j[s][c] -= f * j[r][c];
    }
  }
  return chosen;
}

}  // namespace

ZeroEnclosure enclose_zero(const ZeroProblem& p, long precision) {
  const slong prec = precision;
  const std::size_t m = p.approx.size(), k = p.equations.size();
  ZeroEnclosure out;
  std::deque<Ball> vars(m);
  for (std::size_t i = 0; i < m; ++i) {
    if (!std::isfinite(p.approx[i])) {
      out.why = "the approximate point is not finite";
      return out;
    }
    if (p.given[i])
      set_q(vars[i].v, *p.given[i], prec);
    else
      arb_set_d(vars[i].v, p.approx[i]);
  }
  // The unknowns: coordinates that were not given, where the Jacobian at the approximate point allows;
  // else any (the given values alone miss the zero set: their rounding).
  std::vector<std::vector<double>> jd(k, std::vector<double>(m, 0));
  {
    std::deque<Ball> at(m);
    for (std::size_t i = 0; i < m; ++i) arb_set_d(at[i].v, p.approx[i]);
    Evaluator ev(at, prec);
    for (std::size_t r = 0; r < k; ++r)
      for (std::size_t c = 0; c < m; ++c) jd[r][c] = arf_get_d(arb_midref(ev(p.gradients[r][c])), ARF_RND_NEAR);
  }
  std::vector<bool> held(m);
  for (std::size_t i = 0; i < m; ++i) held[i] = p.given[i].has_value();
  out.solved = pivot_columns(jd, held, out.given_moved);
  for (std::size_t i : out.solved) arb_set_d(vars[i].v, p.approx[i]);
  if (out.solved.size() != k) {
    out.why = "the constraints' Jacobian is not of full rank at the approximate point";
    return out;
  }
  const slong kk = static_cast<slong>(k);
  const auto residual_and_jacobian = [&](BallMat& f, BallMat& jac) {
    Evaluator ev(vars, prec);
    for (std::size_t r = 0; r < k; ++r) {
      arb_set(f.at(static_cast<slong>(r), 0), ev(p.equations[r]));
      for (std::size_t c = 0; c < k; ++c)
        arb_set(jac.at(static_cast<slong>(r), static_cast<slong>(c)), ev(p.gradients[r][out.solved[c]]));
    }
  };
  // Newton in the balls' midpoints at full precision: s̃ close enough that the box can be tiny.
  std::vector<Ball> mid(k);
  BallMat f(kk, 1), jac(kk, kk), y(kk, kk), step(kk, 1);
  for (int it = 0; it < 8 && k > 0; ++it) {
    residual_and_jacobian(f, jac);
    for (slong r = 0; r < kk; ++r) {
      arb_get_mid_arb(f.at(r, 0), f.at(r, 0));
      for (slong c = 0; c < kk; ++c) arb_get_mid_arb(jac.at(r, c), jac.at(r, c));
    }
    if (!arb_mat_approx_solve(step.m, jac.m, f.m, prec)) break;
    for (std::size_t c = 0; c < k; ++c) {
      Ball& s = vars[out.solved[c]];
      arb_sub(s.v, s.v, step.at(static_cast<slong>(c), 0), prec);
      arb_get_mid_arb(s.v, s.v);
    }
  }
  for (std::size_t c = 0; c < k; ++c) arb_set(mid[c].v, vars[out.solved[c]].v);
  // Krawczyk: Y ≈ F'(s̃)⁻¹, X = s̃ ± r grown until K(X) ⊂ int X.
  bool inside = k == 0;
  if (k > 0) {
    residual_and_jacobian(f, jac);
    BallMat jm(kk, kk);
    for (slong r = 0; r < kk; ++r)
      for (slong c = 0; c < kk; ++c) arb_get_mid_arb(jm.at(r, c), jac.at(r, c));
    if (!arb_mat_approx_inv(y.m, jm.m, prec)) {
      out.why = "the constraints' Jacobian on the unknowns is singular at the approximate point";
      return out;
    }
    BallMat yf(kk, 1);
    arb_mat_mul(yf.m, y.m, f.m, prec);
    std::vector<double> rad(k);
    double size = 0;  // the unknowns' common scale: a zero that is exactly 0 still gets a box of that scale's rounding
    for (std::size_t c = 0; c < k; ++c) size = std::max(size, std::abs(arf_get_d(arb_midref(mid[c].v), ARF_RND_NEAR)));
    for (std::size_t c = 0; c < k; ++c) {
      const double yfc = enclosure_of(yf.at(static_cast<slong>(c), 0)).mid,
                   s = std::abs(arf_get_d(arb_midref(mid[c].v), ARF_RND_NEAR));
      rad[c] = 4 * std::abs(yfc) + std::ldexp(s + 1e-12 * size, -static_cast<int>(prec) / 2) + 1e-300;
    }
    BallMat x(kk, 1), kx(kk, 1), ya(kk, kk), dx(kk, 1);
    for (int attempt = 0; attempt < 40 && !inside; ++attempt) {
      for (std::size_t c = 0; c < k; ++c) {  // X = s̃ ± rad, X − s̃ = 0 ± rad
        const slong i = static_cast<slong>(c);
        Ball err;
        arb_set_d(err.v, rad[c]);
        arb_zero(dx.at(i, 0));
        arb_add_error(dx.at(i, 0), err.v);
        arb_add(x.at(i, 0), mid[c].v, dx.at(i, 0), prec);
        arb_set(vars[out.solved[c]].v, x.at(i, 0));
      }
      {
        Evaluator ev(vars, prec);
        for (std::size_t r = 0; r < k; ++r)
          for (std::size_t c = 0; c < k; ++c)
            arb_set(jac.at(static_cast<slong>(r), static_cast<slong>(c)), ev(p.gradients[r][out.solved[c]]));
      }
      arb_mat_mul(ya.m, y.m, jac.m, prec);  // I − Y F'(X)
      arb_mat_neg(ya.m, ya.m);
      for (slong c = 0; c < kk; ++c) arb_add_si(ya.at(c, c), ya.at(c, c), 1, prec);
      arb_mat_mul(kx.m, ya.m, dx.m, prec);
      inside = true;
      for (std::size_t c = 0; c < k; ++c) {
        arb_ptr kc = kx.at(static_cast<slong>(c), 0);
        arb_add(kc, kc, mid[c].v, prec);
        arb_sub(kc, kc, yf.at(static_cast<slong>(c), 0), prec);
        if (!arb_is_finite(kc) || !arb_contains_interior(x.at(static_cast<slong>(c), 0), kc)) inside = false;
      }
      if (inside) {
        for (std::size_t c = 0; c < k; ++c) arb_set(vars[out.solved[c]].v, kx.at(static_cast<slong>(c), 0));
        break;
      }
      for (std::size_t c = 0; c < k; ++c) {  // grow: at least twice, at least to cover K(X)
        const Enclosure e = enclosure_of(kx.at(static_cast<slong>(c), 0));
        const double reach = std::abs(e.mid - arf_get_d(arb_midref(mid[c].v), ARF_RND_NEAR)) + e.rad;
        rad[c] = std::isfinite(reach) ? std::max(2 * rad[c], 2 * reach) : 2 * rad[c];
      }
    }
  }
  out.values.resize(m);
  for (std::size_t i = 0; i < m; ++i) out.values[i] = enclosure_of(vars[i].v);
  if (!inside) {
    out.why =
        "Krawczyk's test failed: no box around the approximate point was proved to hold a unique zero of the "
        "constraints";
    return out;
  }
  Evaluator ev(vars, prec);
  for (const ex::Expr& e : p.outputs) out.outputs.push_back(enclosure_of(ev(e)));
  for (std::size_t i = 0; i < p.nonzero.size(); ++i)
    if (arb_contains_zero(ev(p.nonzero[i]))) {
      out.why = "condition " + std::to_string(i + 1) + " of the chart was not proved nonzero at the point";
      return out;
    }
  for (const Enclosure& e : out.outputs)
    if (!std::isfinite(e.mid) || !std::isfinite(e.rad)) {
      out.why = "an output is not finite at the point";
      return out;
    }
  out.proved = true;
  return out;
}

}  // namespace dcad::certified
