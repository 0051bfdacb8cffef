// CEF (1.6) for the implicit form on formulas, exactly at a point (ide_formulas.hpp: the algorithm and why
// each decision is exact).  One pass at one point: the system for v eliminated step by step; a pass ends
// with the tower, or with the point moved by a Newton step (the caller starts again there), or undecided.
#include "dcad/reference/nonlinear/ide_formulas.hpp"

#include "dcad/reference/nonlinear/calculus.hpp"
#include "dcad/reference/nonlinear/jet.hpp"
#include "dcad/reference/nonlinear/pointwise/eliminate.hpp"
#include "rational_functions.hpp"

#include <flint/fmpz.h>
#include <flint/fmpz_poly.h>
#include <flint/fmpz_poly_factor.h>

#include <map>
#include <memory>
#include <optional>
#include <unordered_map>

namespace dcad::reference {

namespace {

using expr::Expr;

/// A decision the formulas cannot make exactly (the pass stops; the caller reports IdeUndecided).
struct Undecided {
  std::string why;
};
/// No exact Newton step lands from this point (IdeUndecided::no_point).
struct NoLanding {
  std::string why;
};

/// Formulas' values at the point, each node once (a cached node is kept alive: its address is never reused).
class Values {
 public:
  explicit Values(const std::vector<Rational>& point) : none_(std::make_shared<const JetSpace>(0, 0)) {
    for (const Rational& x : point) vars_.emplace_back(none_, x);
  }
  Rational operator()(const Expr& e) {
    if (expr::is_number(e)) return e->value;
    keep_.push_back(e);
    return expr::evaluate<J>(
               e, vars_, [&](const Rational& q) { return J(none_, q); }, memo_)
        .value();
  }

 private:
  using J = Jet<Rational>;
  std::shared_ptr<const JetSpace> none_;
  std::vector<J> vars_;
  std::unordered_map<const expr::ExprNode*, J> memo_;
  std::vector<Expr> keep_;
};

/// A row of the system for v: Σ_j a_j v_j = h, only the entries that are not the number 0.
struct Row {
  std::map<std::size_t, Expr> a;
  Expr h;
  std::string name;
};

/// r_j −= f·x, dropping an entry that folds to the number 0.
void subtract(std::map<std::size_t, Expr>& r, std::size_t j, const Expr& f, const Expr& x) {
  const auto it = r.find(j);
  const Expr v = expr::sub(it == r.end() ? expr::number(0) : it->second, expr::mul(f, x));
  if (expr::is_number(v, 0)) {
    if (it != r.end()) r.erase(it);
  } else if (it != r.end()) {
    it->second = v;
  } else {
    r.emplace(j, v);
  }
}

/// The rational root of Σ a_k δ^k (a polynomial in δ = z − z0) nearest to z0, as z; nothing if it has none.
std::optional<Rational> nearest_root(const std::vector<Rational>& a, const Rational& z0) {
  boost::multiprecision::mpz_int l = 1;  // the coefficients over Z: times the lcm of their denominators
  for (const Rational& x : a) l = boost::multiprecision::lcm(l, boost::multiprecision::denominator(x));
  fmpz_poly_t p;
  fmpz_poly_init(p);
  fmpz_t c;
  fmpz_init(c);
  for (std::size_t k = 0; k < a.size(); ++k) {
    const boost::multiprecision::mpz_int v =
        boost::multiprecision::numerator(a[k]) * (l / boost::multiprecision::denominator(a[k]));
    fmpz_set_mpz(c, v.backend().data());
    fmpz_poly_set_coeff_fmpz(p, static_cast<slong>(k), c);
  }
  std::optional<Rational> best;
  if (fmpz_poly_degree(p) >= 1) {
    fmpz_poly_factor_t f;
    fmpz_poly_factor_init(f);
    fmpz_poly_factor(f, p);
    for (slong i = 0; i < f->num; ++i) {
      if (fmpz_poly_degree(f->p + i) != 1) continue;
      boost::multiprecision::mpz_int b0, b1;  // b1 δ + b0 = 0
      fmpz_poly_get_coeff_fmpz(c, f->p + i, 0);
      fmpz_get_mpz(b0.backend().data(), c);
      fmpz_poly_get_coeff_fmpz(c, f->p + i, 1);
      fmpz_get_mpz(b1.backend().data(), c);
      const Rational delta = Rational(-b0) / Rational(b1);
      if (!best || abs(delta) < abs(*best - z0)) best = z0 + delta;
    }
    fmpz_poly_factor_clear(f);
  }
  fmpz_clear(c);
  fmpz_poly_clear(p);
  return best;
}

class Pass {
 public:
  Pass(const LagrangianSystem& s, const LagrangianDerivatives& d, expr::Differentiator& D,
       const std::vector<Rational>& point, const std::vector<bool>& fixed, std::size_t& nudges)
      : s_(s),
        d_(d),
        D_(D),
        fixed_(fixed),
        point_(point),
        value_(point),
        rf_(2 * s.n + 1),
        names_(s.variable_names()),
        solved_col_(s.n + 1, false),
        nudges_(nudges) {}

  /// The tower (true) or a Newton step that moved `point` (false); Undecided is thrown.
  bool run(IdeFormulas& out, std::vector<Rational>& point) {
    const std::size_t n = s_.n;
    PointwiseResult<Rational>& r = out.result;
    r.dims.push_back(static_cast<long>(n));
    level_.dim = static_cast<long>(n);
    level_.chart = chart();
    std::vector<Row> fresh;
    for (std::size_t e = 0; e < s_.m(); ++e) {  // a(t, x) v = −b(t, x)
      Row row;
      for (std::size_t i = 0; i < n; ++i)
        if (!expr::is_number(d_.a[e][i], 0)) row.a.emplace(i, d_.a[e][i]);
      row.h = expr::neg(d_.b[e]);
      row.name = "equation " + std::to_string(e + 1);
      fresh.push_back(std::move(row));
    }
    for (std::size_t k = 0;; ++k) {
      std::vector<Expr> cand;
      std::vector<std::string> from;
      for (Row& row : fresh)
        if (!insert(row)) {
          cand.push_back(row.h);
          from.push_back(row.name);
        }
      for (const Pivot& p : pivots_) level_.pivots.push_back({rows_[p.row].name, "d/dt " + names_[p.col], p.value});
      std::vector<Rational> val;
      bool on = true;
      for (const Expr& c : cand) {
        val.push_back(value_(c));
        on = on && val.back() == 0;
      }
      if (!on) return !move(k, cand, val, out, point);
      const std::vector<std::size_t> added = new_constraints(k, cand, out);
      if (!r.consistent) return true;  // a condition on the time alone
      if (added.empty()) {
        finish(out);
        return true;
      }
      fresh.clear();
      for (std::size_t c : added) {  // ∂c/∂x v = −∂c/∂t: v tangent to M_{k+1}(t)
        Row row;
        for (std::size_t i = 0; i < n; ++i) {
          const Expr g = D_(cons_[c].f, s_.q(i));
          if (!expr::is_number(g, 0)) row.a.emplace(i, g);
        }
        row.h = s_.has_time ? expr::neg(D_(cons_[c].f, s_.t())) : expr::number(0);
        row.name = "tangent to constraint " + std::to_string(c + 1) + " (M_" + std::to_string(k + 1) + ")";
        fresh.push_back(std::move(row));
      }
    }
  }

 private:
  struct Pivot {
    std::size_t row, col;
    Rational value;
  };
  struct Constraint {
    Expr f;              ///< f = 0 on M_{k+1} (the candidate as found)
    std::size_t solved;  ///< its coordinate (column), Gauss–Jordan at the point
  };

  /// M_k's chart (variable indices): the time first if any, then the coordinates not solved for.
  std::vector<std::size_t> chart() const {
    std::vector<std::size_t> c;
    if (s_.has_time) c.push_back(s_.t());
    for (std::size_t i = 0; i < s_.n; ++i)
      if (!solved_col_[i]) c.push_back(s_.q(i));
    return c;
  }

  /// Row `r` reduced by the pivots so far (forward elimination: r − (e/P)·pr, P nonzero near the point;
  /// fraction-free elimination would keep polynomials polynomial, but its values grow like 2^k in bits
  /// without Bareiss's exact divisions — a chain of 40 pendulums did not finish); true if it takes a pivot (its first
  /// entry nonzero at the point), false if it is free: then every entry must vanish identically (else the rank may drop
  /// at the point), and r.h is a candidate.
  bool insert(Row& r) {
    for (const Pivot& p : pivots_) {
      const auto it = r.a.find(p.col);
      if (it == r.a.end()) continue;
      const Row& pr = rows_[p.row];
      const Expr P = pr.a.at(p.col), e = it->second;
      r.a.erase(it);  // the pivot's column: e − (e/P)·P is 0, exactly
      const Expr f = expr::div(e, P);
      for (const auto& [j, x] : pr.a)
        if (j != p.col) subtract(r.a, j, f, x);
      r.h = expr::sub(r.h, expr::mul(f, pr.h));
    }
    // the pivot: a number if the row has one (its multiples keep the other rows' formulas polynomial, whose
    // zero tests are then exact), else the first entry nonzero at the point
    std::optional<std::size_t> col;
    for (const auto& [j, x] : r.a)
      if (expr::is_number(x) && x->value != 0) {
        col = j;
        break;
      }
    if (!col)
      for (const auto& [j, x] : r.a)
        if (value_(x) != 0) {
          col = j;
          break;
        }
    if (col) {
      const Expr& x = r.a.at(*col);
      pivots_.push_back({rows_.size(), *col, value_(x)});
      if (!expr::is_number(x))
        valid_.push_back({"pivot of the system for v: " + r.name + ", column d/dt " + names_[*col], x});
      rows_.push_back(r);
      return true;
    }
    for (const auto& [j, x] : r.a)
      if (!identically_zero(x))
        throw Undecided{"after elimination, " + r.name + " keeps " + expr::to_text(x, names_) +
                        " as the coefficient of d/dt " + names_[j] +
                        ": 0 at the point but not identically (a point where the rank drops, or a formula that "
                        "vanishes on M_k only)"};
    r.a.clear();
    return false;
  }

  /// e in lowest terms is 0: e vanishes identically (a proof; false proves nothing).
  bool identically_zero(const Expr& e) { return rf_.zero(e); }

  /// e in lowest terms, if it involves no coordinate (a function of the time alone); else nothing (also
  /// where e is too large to reduce).  `rational`: it has no sin, cos, exp or sqrt (then, not 0, it is a
  /// nonzero function of the time, t^64 as surely as t).
  std::optional<Expr> of_time_alone(const Expr& e, bool* rational = nullptr) {
    std::vector<bool> inv;
    bool atoms = true;
    const std::optional<Expr> r = rf_.reduced(e, &inv, &atoms);
    if (!r) return std::nullopt;
    for (std::size_t i = 0; i < s_.n; ++i)
      if (inv[s_.q(i)]) return std::nullopt;
    if (rational) *rational = !atoms;
    return r;
  }

  /// A formula of the time alone (e, canonical, depends on no coordinate): is it a nonzero function? A
  /// nonzero Taylor coefficient at the point proves it is; all zero to its degree (a polynomial in t)
  /// proves it is not; else nothing.
  std::optional<bool> nonzero_in_time(const Expr& e) {
    if (expr::is_number(e)) return e->value != 0;
    if (!s_.has_time) return std::nullopt;
    const long degree = expr::degree_in(e, [&](std::size_t i) { return i == s_.t(); });
    const std::size_t order = degree >= 0 && degree <= 40 ? static_cast<std::size_t>(degree) : 12;
    try {
      const auto space = std::make_shared<const JetSpace>(1, order);
      std::vector<Jet<Rational>> x;
      for (std::size_t i = 0; i < point_.size(); ++i)
        x.push_back(i == s_.t() ? Jet<Rational>::variable(space, 0, point_[i]) : Jet<Rational>(space, point_[i]));
      const Jet<Rational> j =
          expr::evaluate<Jet<Rational>>(e, x, [&](const Rational& q) { return Jet<Rational>(space, q); });
      if (!j.is_zero()) return true;
    } catch (const NotExactHere&) {
      return std::nullopt;
    } catch (const std::domain_error&) {
      return std::nullopt;
    }
    if (degree >= 0 && degree <= 40) return false;
    return std::nullopt;
  }

  /// ∇ψ at the point over (x, t) (column n is the time), and reduced by the constraints' Gauss–Jordan rows:
  /// the differential along M_k's chart; `coef[l]` the multiple of row l taken off.
  std::vector<Rational> reduced_gradient(const Expr& psi, std::vector<Rational>& coef) {
    const std::size_t n = s_.n;
    std::vector<Rational> g(n + 1, Rational(0));
    for (std::size_t i = 0; i < n; ++i)
      if (D_.depends(psi, s_.q(i))) g[i] = value_(D_(psi, s_.q(i)));
    if (s_.has_time && D_.depends(psi, s_.t())) g[n] = value_(D_(psi, s_.t()));
    coef.assign(gj_.size(), Rational(0));
    for (std::size_t l = 0; l < gj_.size(); ++l) {
      coef[l] = g[cons_[l].solved];
      if (coef[l] == 0) continue;
      for (std::size_t j = 0; j <= n; ++j) g[j] -= coef[l] * gj_[l][j];
    }
    return g;
  }

  /// ψ − Σ_l coef_l C̃_l: the candidate with the multiples of the constraints taken off (its gradient at the
  /// point is the reduced one).
  Expr reduced_formula(const Expr& psi, const std::vector<Rational>& coef) {
    Expr e = psi;
    for (std::size_t l = 0; l < coef.size(); ++l)
      if (coef[l] != 0) e = expr::sub(e, expr::mul(expr::number(coef[l]), combined_[l]));
    return e;
  }

  /// Chart columns in the order to solve for them: coordinates not given before given ones, later before earlier
  /// (the jet route's order, pointwise/run.hpp), the time never; `only_movable`: not the given ones.
  std::vector<std::vector<std::size_t>> column_groups(bool only_movable) const {
    std::vector<std::vector<std::size_t>> g(2);
    for (std::size_t i = s_.n; i-- > 0;)
      if (!solved_col_[i]) {
        if (!fixed_[s_.q(i)])
          g[0].push_back(i);
        else if (!only_movable)
          g[1].push_back(i);
      }
    return g;
  }

  /// Each candidate's gradient reduced on M_k's chart (coefficients in `coefs`), followed by the unit row
  /// that records which candidates an elimination combines (columns n+1…n+m).
  std::vector<std::vector<Rational>> augmented(const std::vector<Expr>& cand,
                                               std::vector<std::vector<Rational>>& coefs) {
    const std::size_t n = s_.n, m = cand.size();
    std::vector<std::vector<Rational>> aug(m);
    coefs.assign(m, {});
    for (std::size_t i = 0; i < m; ++i) {
      aug[i] = reduced_gradient(cand[i], coefs[i]);
      aug[i].resize(n + 1 + m, Rational(0));
      aug[i][n + 1 + i] = 1;
    }
    return aug;
  }

  /// Σ_j row[n+1+j] ψ̃_j: the reduced candidates combined as an eliminated row of augmented() records.
  Expr combined_candidates(const std::vector<Rational>& row, const std::vector<Expr>& cand,
                           const std::vector<std::vector<Rational>>& coefs) {
    const std::size_t n = s_.n;
    Expr comb = expr::number(0);
    for (std::size_t j = 0; j < cand.size(); ++j)
      if (row[n + 1 + j] != 0)
        comb = expr::add(comb, expr::mul(expr::number(row[n + 1 + j]), reduced_formula(cand[j], coefs[j])));
    return comb;
  }

  /// The chart coordinates an elimination of `aug` (a copy) in the charts' order solves for: 1 at each.
  std::vector<char> pivot_columns(std::vector<std::vector<Rational>> aug) {
    std::vector<char> solves(s_.n, 0);
    std::vector<Rational> z(aug.size(), Rational(0));
    ExactDecisions<Rational> first;
    for (const auto& pc : pointwise_detail::eliminate_constants(aug, z, column_groups(false), first))
      solves[pc.second] = 1;
    return solves;
  }

  /// A new constraint's tangent equation g·(dq, dt) = g·(q, t) at the point, over M_k's chart in its order
  /// (the time first), solved for coordinate c (g normalized: g[c] = 1).
  PointwiseConstraint<Rational> tangent_equation(const std::vector<Rational>& g, std::size_t c) const {
    const std::size_t n = s_.n;
    PointwiseConstraint<Rational> t;
    t.solved_for = s_.q(c);
    for (std::size_t jj = 0; jj <= n; ++jj) {
      const std::size_t j = jj == 0 ? n : jj - 1;
      if (g[j] == 0) continue;
      const std::size_t var = j < n ? s_.q(j) : s_.t();
      t.gradient.emplace_back(var, g[j]);
      t.rhs += g[j] * point_[var];
    }
    return t;
  }

  /// The new constraints' Gauss–Jordan rows (`rows`, with their formulas `combined`; constraints `added`)
  /// join the old ones, which first lose their entries at the new solved columns.
  void add_gauss_jordan_rows(const std::vector<std::vector<Rational>>& rows, const std::vector<Expr>& combined,
                             const std::vector<std::size_t>& added) {
    for (std::size_t l = 0; l < gj_.size(); ++l)
      for (std::size_t a = 0; a < rows.size(); ++a) {
        const Rational f = gj_[l][cons_[added[a]].solved];
        if (f == 0) continue;
        for (std::size_t j = 0; j <= s_.n; ++j) gj_[l][j] -= f * rows[a][j];
        combined_[l] = expr::sub(combined_[l], expr::mul(expr::number(f), combined[a]));
      }
    for (std::size_t a = 0; a < rows.size(); ++a) {
      gj_.push_back(rows[a]);
      combined_.push_back(combined[a]);
      solved_col_[cons_[added[a]].solved] = true;
    }
  }

  /// The candidates (all 0 at the point): the independent ones become M_{k+1}'s constraints (their indices
  /// in cons_), the dependent ones must vanish identically with them; a condition on the time alone that
  /// is not identically zero makes the system inconsistent (out says so).  Empty: M_c = M_k.
  std::vector<std::size_t> new_constraints(std::size_t k, const std::vector<Expr>& cand, IdeFormulas& out) {
    const std::size_t n = s_.n, m = cand.size();
    std::vector<std::vector<Rational>> coefs;
    std::vector<std::vector<Rational>> aug = augmented(cand, coefs);
    std::vector<Rational> rhs(m, Rational(0));
    ExactDecisions<Rational> exact;
    const auto piv = pointwise_detail::eliminate_constants(aug, rhs, column_groups(false), exact);
    std::vector<char> is_piv(m, 0);
    for (const auto& pc : piv) is_piv[pc.first] = 1;
    std::vector<Expr> reduced(m);
    for (std::size_t i = 0; i < m; ++i) reduced[i] = reduced_formula(cand[i], coefs[i]);
    const auto combination = [&](std::size_t i) {  // Σ_j aug[i][n+1+j] ψ̃_j
      Expr e = expr::number(0);
      for (std::size_t j = 0; j < m; ++j)
        if (aug[i][n + 1 + j] != 0) e = expr::add(e, expr::mul(expr::number(aug[i][n + 1 + j]), reduced[j]));
      return e;
    };
    for (std::size_t i = 0; i < m; ++i) {  // a dependent candidate: identically a combination, or a condition on t
      if (is_piv[i]) continue;
      const Expr comb = combination(i);
      if (identically_zero(comb)) continue;
      bool rational = false;
      if (const std::optional<Expr> c = of_time_alone(comb, &rational)) {
        // a rational function of t alone that is not 0 in lowest terms is a nonzero function; with sin, cos,
        // exp or sqrt a nonzero Taylor coefficient proves it
        const std::optional<bool> nz = rational ? std::optional<bool>(true) : nonzero_in_time(*c);
        if (nz && !*nz) continue;
        if (nz && *nz) {
          inconsistent(out, "step " + std::to_string(k) + " gives a condition on the time alone, " +
                                expr::to_text(*c, names_) + " = 0 (its candidates combined): M_" +
                                std::to_string(k + 1) + "(t) is empty at generic times");
          return {};
        }
      }
      throw Undecided{"a candidate of step " + std::to_string(k) +
                      " vanishes with its differential at the point (mod the constraints) but is not "
                      "identically a combination of them: " +
                      expr::to_text(comb, names_)};
    }
    if (piv.empty()) return {};
    // the new constraints, their tangent equations (Gauss–Jordan among them, each solved for its pivot)
    PointwiseLevel<Rational> next;
    std::vector<std::size_t> added;
    out.levels.emplace_back();
    out.solved.emplace_back();
    out.result.plan.emplace_back();
    std::vector<std::vector<Rational>> rows;
    std::vector<Expr> combined;
    for (const auto& [p, c] : piv) {
      std::vector<Rational> g(aug[p].begin(), aug[p].begin() + static_cast<std::ptrdiff_t>(n + 1));
      const Rational scale = g[c];
      for (Rational& x : g) x /= scale;
      next.added.push_back(tangent_equation(g, c));
      rows.push_back(g);
      combined.push_back(expr::mul(expr::number(1 / scale), combination(p)));
      cons_.push_back({cand[p], c});
      added.push_back(cons_.size() - 1);
      out.levels.back().push_back(cand[p]);
      out.solved.back().push_back(s_.q(c));
      out.result.plan.back().push_back(s_.q(c));
    }
    add_gauss_jordan_rows(rows, combined, added);
    out.result.levels.push_back(level_);
    next.chart = chart();
    next.dim = static_cast<long>(s_.n - cons_.size());
    level_ = next;
    out.result.dims.push_back(level_.dim);
    return added;
  }

  /// Some candidate is nonzero at the point: one exact Newton step on the movable chart coordinates (those
  /// every nonzero candidate is affine in first), each constraint moving its pivot coordinate — true; or a
  /// combination that no coordinate moves, a nonzero constant or a condition on the time alone: M_{k+1} is
  /// empty (out says so) — false.  Anything else is undecided.
  bool move(std::size_t k, const std::vector<Expr>& cand, const std::vector<Rational>& val, IdeFormulas& out,
            std::vector<Rational>& point) {
    const std::size_t n = s_.n, m = cand.size();
    std::vector<std::vector<Rational>> coefs;
    std::vector<std::vector<Rational>> aug = augmented(cand, coefs);
    std::vector<Rational> rhs(m);
    for (std::size_t i = 0; i < m; ++i) rhs[i] = -val[i];
    const std::vector<std::vector<std::size_t>> movable = column_groups(true);
    std::vector<Expr> lowest(m);  // the candidates in lowest terms: (2x + 1)/(4x + 2) is affine in x
    for (std::size_t i = 0; i < m; ++i)
      if (val[i] != 0) lowest[i] = rf_.reduced(cand[i]).value_or(cand[i]);
    // the coordinates M_{k+1}'s chart will solve for move first (where every nonzero candidate is affine in
    // them): a coordinate moved here that stays in the chart would be moved again by the next step, away
    // from this one's constraints, forever
    const std::vector<char> chart_solves = pivot_columns(aug);
    std::vector<std::vector<std::size_t>> groups(3);
    for (std::size_t j : movable[0]) {
      bool affine = true;
      for (std::size_t i = 0; i < m && affine; ++i) {
        if (val[i] == 0) continue;
        const long d = expr::degree_in(lowest[i], [&](std::size_t v) { return v == s_.q(j); });
        affine = d == 0 || d == 1;
      }
      groups[!affine ? 2 : chart_solves[j] ? 0 : 1].push_back(j);
    }
    ExactDecisions<Rational> exact;
    const auto piv = pointwise_detail::eliminate_constants(aug, rhs, groups, exact);
    std::vector<char> is_piv(m, 0);
    for (const auto& pc : piv) is_piv[pc.first] = 1;
    // a critical point of the coordinates that may move is no verdict: from a nearby point (lam^3 + 1 at lam = 0),
    // one coordinate at a time in the charts' order (the multiplier before the velocities a lower M_k ties together)
    const auto nudge = [&](const std::string& why) {
      if (nudges_ >= 3 || movable[0].empty()) throw Undecided{"a candidate of step " + std::to_string(k) + " " + why};
      point[s_.q(movable[0][nudges_ % movable[0].size()])] += Rational(1, 3);
      ++nudges_;
      return true;
    };
    for (std::size_t i = 0; i < m; ++i) {
      if (is_piv[i] || rhs[i] == 0) continue;
      for (std::size_t j = 0; j < n; ++j)
        if (aug[i][j] != 0)
          return nudge(
              "that no coordinate that may move brings to zero (given values it conflicts with, or a critical point)");
      const Expr comb = combined_candidates(aug[i], cand, coefs);
      const std::optional<Expr> c = of_time_alone(comb);
      if (!c) return nudge("whose differential vanishes at the point although its value does not");
      if (expr::is_number(*c))
        inconsistent(out, "step " + std::to_string(k) + " requires 0 = " + (*c)->value.str() +
                              " (its constraints combined): M_" + std::to_string(k + 1) + " is empty");
      else
        inconsistent(out, "step " + std::to_string(k) + " gives a condition on the time alone, " +
                              expr::to_text(*c, names_) + " = 0, violated at " + names_[s_.t()] + " = " +
                              point_[s_.t()].str() + ": M_" + std::to_string(k + 1) + "(t) is empty there");
      return false;
    }
    // a step along a coordinate some nonzero candidate is not affine in does not land (the digits double
    // instead): where its combination is a polynomial in one such coordinate with a rational root, that root
    // is where it lands (lam^3 + 1 = 0: lam = -1), this coordinate alone; where none has one, later passes may
    // still land by other steps at small sizes — beyond 30 coordinates each such pass is dear and the jets
    // cannot follow: no point is reached from here (the caller's rational place next)
    for (const auto& [p, c] : piv) {
      if (rhs[p] == 0 || std::find(groups[2].begin(), groups[2].end(), c) == groups[2].end()) continue;
      const Expr comb = combined_candidates(aug[p], cand, coefs);
      std::vector<std::size_t> along{c};
      for (std::size_t j : groups[2])
        if (j != c) along.push_back(j);
      for (std::size_t j : along)
        if (const std::optional<Rational> root = nearest_rational_root(comb, s_.q(j))) {
          point[s_.q(j)] = *root;
          return true;
        }
      if (s_.n > 30)
        throw NoLanding{"no point of M_c reached from the given values: M_" + std::to_string(k + 1) +
                        "'s candidates are affine in no coordinate that may move (" + names_[c] +
                        " enters at second order, without a rational root), so no exact Newton step lands"};
      break;
    }
    for (const auto& [p, c] : piv) point[s_.q(c)] += rhs[p] / aug[p][c];
    return true;
  }

  /// The rational root of e (a polynomial of degree 2…12 in variable `var`, the others at the point) nearest to
  /// the point's value, if it has one: the polynomial's Taylor coefficients there (exact to its degree), over
  /// Z, factored (FLINT), its linear factors.
  std::optional<Rational> nearest_rational_root(const Expr& e, std::size_t var) {
    const std::optional<Expr> low = rf_.reduced(e);
    if (!low) return std::nullopt;
    const long d = expr::degree_in(*low, [&](std::size_t v) { return v == var; });
    if (d < 2 || d > 12) return std::nullopt;
    std::vector<Rational> a(static_cast<std::size_t>(d) + 1);
    try {
      const auto space = std::make_shared<const JetSpace>(1, static_cast<std::size_t>(d));
      std::vector<Jet<Rational>> x;
      for (std::size_t i = 0; i < point_.size(); ++i)
        x.push_back(i == var ? Jet<Rational>::variable(space, 0, point_[i]) : Jet<Rational>(space, point_[i]));
      const Jet<Rational> j =
          expr::evaluate<Jet<Rational>>(*low, x, [&](const Rational& q) { return Jet<Rational>(space, q); });
      for (std::size_t k = 0; k < a.size(); ++k) a[k] = j.coefficient(k);
    } catch (const std::exception&) {  // an irrational value, a division by zero: no root found exactly
      return std::nullopt;
    }
    return nearest_root(a, point_[var]);
  }

  /// M_{k+1} is empty: the point as it is.
  void inconsistent(IdeFormulas& out, const std::string& why) {
    PointwiseResult<Rational>& r = out.result;
    r.levels.push_back(level_);
    r.consistent = false;
    r.dims.push_back(-1);
    r.steps = r.dims.size() - 1;
    r.why = why;
    r.point.assign(point_.begin(), point_.begin() + static_cast<std::ptrdiff_t>(s_.n));
    r.time = point_[s_.t()];
  }

  /// M_c = M_k: the solution rank, a velocity (free unknowns 0) and the gauge at the point, T_x M_c, and
  /// the velocities as formulas (back substitution on the eliminated rows).
  void finish(IdeFormulas& out) {
    const std::size_t n = s_.n;
    PointwiseResult<Rational>& r = out.result;
    r.levels.push_back(level_);
    r.steps = r.dims.size() - 1;
    r.checked_order = -1;
    r.point.assign(point_.begin(), point_.begin() + static_cast<std::ptrdiff_t>(n));
    r.time = point_[s_.t()];
    std::vector<char> is_piv(n, 0);
    for (const Pivot& p : pivots_) is_piv[p.col] = 1;
    const auto back = [&](std::vector<Rational> v, bool with_rhs) {  // reverse pivot order: later columns first
      for (std::size_t q = pivots_.size(); q-- > 0;) {
        const Pivot& p = pivots_[q];
        const Row& row = rows_[p.row];
        Rational h = with_rhs ? value_(row.h) : Rational(0);
        for (const auto& [j, x] : row.a)
          if (j != p.col && v[j] != 0) h -= value_(x) * v[j];
        v[p.col] = h / p.value;
      }
      return v;
    };
    r.velocity = back(std::vector<Rational>(n, Rational(0)), true);
    r.gauge.clear();
    for (std::size_t f = 0; f < n; ++f) {
      if (is_piv[f]) continue;
      std::vector<Rational> e(n, Rational(0));
      e[f] = 1;
      r.gauge.push_back(back(e, false));
      out.free.push_back(s_.q(f));
    }
    r.solution_rank = r.gauge.size();
    r.tangent.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (solved_col_[j]) continue;
      std::vector<Rational> t(n, Rational(0));
      t[j] = 1;
      for (std::size_t l = 0; l < gj_.size(); ++l) t[cons_[l].solved] = -gj_[l][j];
      r.tangent.push_back(t);
    }
    out.rates.assign(n, expr::number(0));
    for (std::size_t q = pivots_.size(); q-- > 0;) {
      const Pivot& p = pivots_[q];
      const Row& row = rows_[p.row];
      Expr h = row.h;
      for (const auto& [j, x] : row.a)
        if (j != p.col && !expr::is_number(out.rates[j], 0)) h = expr::sub(h, expr::mul(x, out.rates[j]));
      out.rates[p.col] = expr::div(h, row.a.at(p.col));
    }
    for (const auto& v : valid_) out.valid_where.push_back({v.what, v.formula});
  }

  const LagrangianSystem& s_;
  const LagrangianDerivatives& d_;
  expr::Differentiator& D_;
  const std::vector<bool>& fixed_;
  std::vector<Rational> point_;
  Values value_;
  RationalFunctions rf_;
  std::vector<std::string> names_;
  std::vector<Row> rows_;      ///< the pivot rows, reduced
  std::vector<Pivot> pivots_;  ///< in the order they were taken
  std::vector<Constraint> cons_;
  std::vector<std::vector<Rational>>
      gj_;  ///< the constraints' gradients at the point over (x, t), Gauss–Jordan on their solved columns
  std::vector<Expr> combined_;  ///< the combination of constraint formulas each gj_ row is the gradient of
  std::vector<bool> solved_col_;
  PointwiseLevel<Rational> level_;
  std::vector<IdeFormulas::Condition> valid_;
  std::size_t& nudges_;  ///< moves to a nearby point from a critical one, over the whole call (at most 3)
};

/// The largest size of a value of x in bits (numerator and denominator).
std::size_t bits(const std::vector<Rational>& x) {
  std::size_t b = 0;
  for (const Rational& q : x)
    if (q != 0)
      b = std::max<std::size_t>(b, msb(boost::multiprecision::abs(boost::multiprecision::numerator(q))) +
                                       msb(boost::multiprecision::denominator(q)) + 2);
  return b;
}

}  // namespace

std::variant<IdeFormulas, IdeUndecided> ide_on_formulas(const LagrangianSystem& s, std::vector<Rational> start,
                                                        const std::vector<bool>& fixed, std::size_t max_moves) {
  if (!s.implicit) throw std::invalid_argument("ide_on_formulas: the implicit form's systems only");
  const LagrangianDerivatives d = derivatives(s);
  expr::Differentiator D;
  const std::size_t start_bits = bits(start);
  std::size_t nudges = 0;
  for (std::size_t moves = 0;; ++moves) {
    IdeFormulas out;
    std::vector<Rational> point = start;
    try {
      Pass pass(s, d, D, start, fixed, nudges);
      if (pass.run(out, point)) {
        out.result.moves = moves;
        return out;
      }
    } catch (const Undecided& u) {
      return IdeUndecided{u.why};
    } catch (const NoLanding& u) {
      return IdeUndecided{u.why, true};
    }
    if (moves + 1 > max_moves)
      return IdeUndecided{
          "no point of M_c reached from the given values in " + std::to_string(max_moves) + " exact Newton steps",
          true};
    // steps that do not land double the digits: beyond 16 times the start's bits (and 1,024) none is near
    if (bits(point) > std::max<std::size_t>(1024, 16 * start_bits))
      return IdeUndecided{
          "no point of M_c reached from the given values: the exact Newton steps' numbers outgrew the start's 16-fold",
          true};
    start = point;
  }
}

}  // namespace dcad::reference
