// The CAD as formulas on a chart (chart.hpp: the route and its decisions).
#include "dcad/fast/chart.hpp"

#include "dcad/fast/tracked.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <Eigen/Dense>
#include <unordered_map>

namespace dcad::fast {

namespace ex = symbolic::expr;
using ex::Expr;
using ex::ExprOp;

namespace {

double apply(ExprOp op, double a, double b, long k, double c) {
  switch (op) {
    case ExprOp::Number: return c;
    case ExprOp::Add: return a + b;
    case ExprOp::Sub: return a - b;
    case ExprOp::Neg: return -a;
    case ExprOp::Mul: return a * b;
    case ExprOp::Div: return a / b;
    case ExprOp::Pow: {
      double r = 1, x = k < 0 ? 1 / a : a;
      for (long e = k < 0 ? -k : k; e; e >>= 1, x *= x)
        if (e & 1) r *= x;
      return r;
    }
    case ExprOp::Sin: return std::sin(a);
    case ExprOp::Cos: return std::cos(a);
    case ExprOp::Exp: return std::exp(a);
    case ExprOp::Sqrt: return std::sqrt(a);
    case ExprOp::Variable: break;
  }
  throw std::logic_error("chart: unknown operation");
}

/// Values of expressions at one point with their rounding-error bounds (tracked.hpp), each shared node
/// evaluated once (the nodes kept alive while cached).  A value within 64 × its bound is zero: the
/// rounding of an exact zero (pointwise.hpp's decisions, with its factor for "certainly nonzero").
class Values {
 public:
  explicit Values(std::vector<double> at) : at_(std::move(at)) {}
  Tracked operator()(const Expr& e) {
    if (const auto it = memo_.find(e.get()); it != memo_.end()) return it->second.second;
    using F = symbolic::JetFunctions<Tracked>;
    const auto x = [&](const Expr& y) { return (*this)(y); };
    Tracked r;
    switch (e->op) {
      case ExprOp::Number: r = Tracked::input(e->value.convert_to<double>()); break;
      case ExprOp::Variable: r = Tracked::input(at_.at(e->var)); break;
      case ExprOp::Add: r = x(e->a) + x(e->b); break;
      case ExprOp::Sub: r = x(e->a) - x(e->b); break;
      case ExprOp::Neg: r = -x(e->a); break;
      case ExprOp::Mul: r = x(e->a) * x(e->b); break;
      case ExprOp::Div: r = x(e->a) / x(e->b); break;
      case ExprOp::Pow: {
        const Tracked a = x(e->a);
        r = Tracked(1);
        for (long k = 0; k < std::abs(e->exponent); ++k) r = r * a;
        if (e->exponent < 0) r = Tracked(1) / r;
        break;
      }
      case ExprOp::Sin: r = F::sin(x(e->a)); break;
      case ExprOp::Cos: r = F::cos(x(e->a)); break;
      case ExprOp::Exp: r = F::exp(x(e->a)); break;
      case ExprOp::Sqrt: r = F::sqrt(x(e->a)); break;
    }
    memo_.emplace(e.get(), std::make_pair(e, r));
    return r;
  }
  double value(const Expr& e) { return (*this)(e).v; }
  bool zero(const Expr& e) {
    const Tracked t = (*this)(e);
    return std::abs(t.v) <= 64 * t.e;
  }
  /// Zero to `rel` of the size of its terms, at least of 1 (t.e / u bounds Σ|terms|), as the drift
  /// check measures: at a point that is on M_c only to a drift tolerance (simulate's integrated states,
  /// where x v_x + y v_y was 3e-10 with terms of 7e-3), an entry that vanishes on M_c is that small.
  bool zero_to(const Expr& e, double rel) {
    const Tracked t = (*this)(e);
    return std::abs(t.v) <= 64 * t.e + rel * std::max(1.0, t.e / Tracked::u);
  }

 private:
  std::vector<double> at_;
  std::unordered_map<const ex::ExprNode*, std::pair<Expr, Tracked>> memo_;
};

/// Gaussian elimination on the expression DAG, its decisions made at the point: pivots the largest entry
/// left (full pivoting), an entry ≤ tol × its row's largest original entry is zero on M_k.
struct Elimination {
  std::vector<std::vector<Expr>> r;
  std::vector<Expr> h;
  std::vector<std::pair<std::size_t, std::size_t>> pivots;  ///< (row, column), in order
  std::vector<std::size_t> left;                            ///< rows without a pivot: 0 = h there
};

constexpr double kTol = 1e-8;
constexpr std::size_t kMaxDerivatives = 200000;

/// The number of distinct nodes of e (its size as a DAG).
std::size_t nodes(const Expr& e) {
  std::vector<const ex::ExprNode*> stack{e.get()};
  std::unordered_map<const ex::ExprNode*, char> seen;
  while (!stack.empty()) {
    const ex::ExprNode* x = stack.back();
    stack.pop_back();
    if (!seen.emplace(x, 1).second) continue;
    if (x->a) stack.push_back(x->a.get());
    if (x->b) stack.push_back(x->b.get());
  }
  return seen.size();
}

Elimination eliminate(std::vector<std::vector<Expr>> r, std::vector<Expr> h, Values& val,
                      std::vector<Expr>& vanishing) {
  Elimination e;
  const std::size_t rows = r.size(), cols = rows ? r[0].size() : 0;
  std::vector<double> scale(rows, 0);
  for (std::size_t i = 0; i < rows; ++i)
    for (const Expr& x : r[i]) scale[i] = std::max(scale[i], std::abs(val.value(x)));
  std::vector<char> used(rows, 0), done(cols, 0);
  for (;;) {
    double best = 0;
    for (std::size_t i = 0; i < rows; ++i) {
      if (used[i]) continue;
      for (std::size_t j = 0; j < cols; ++j) {
        if (done[j]) continue;
        const double v = std::abs(val.value(r[i][j]));
        if (!val.zero(r[i][j])) {
          if (!std::isfinite(v)) throw ChartFailure("a coefficient of the system is not finite at the point");
          best = std::max(best, v / scale[i]);
        } else {
          if (!ex::is_number(r[i][j])) vanishing.push_back(r[i][j]);
          r[i][j] = ex::number(0);  // vanishes on M_k
        }
      }
    }
    if (best == 0) break;
    // among the entries within 1/100 of the largest (relative to their rows: far from zero at the point),
    // the smallest formula: a number divides nothing into the next rows, and the formulas stay short
    std::size_t p = rows, c = cols, size = SIZE_MAX;
    for (std::size_t i = 0; i < rows; ++i) {
      if (used[i]) continue;
      for (std::size_t j = 0; j < cols; ++j) {
        if (done[j] || ex::is_number(r[i][j], 0) || std::abs(val.value(r[i][j])) / scale[i] < 1e-2 * best) continue;
        const std::size_t z = nodes(r[i][j]);
        if (z < size) size = z, p = i, c = j;
      }
    }
    used[p] = 1;
    done[c] = 1;
    e.pivots.emplace_back(p, c);
    for (std::size_t i = 0; i < rows; ++i) {
      if (used[i] || ex::is_number(r[i][c], 0)) continue;
      const Expr f = ex::div(r[i][c], r[p][c]);
      for (std::size_t j = 0; j < cols; ++j)
        if (!done[j] && !ex::is_number(r[p][j], 0)) r[i][j] = ex::sub(r[i][j], ex::mul(f, r[p][j]));
      r[i][c] = ex::number(0);
      h[i] = ex::sub(h[i], ex::mul(f, h[p]));
    }
  }
  for (std::size_t i = 0; i < rows; ++i)
    if (!used[i]) e.left.push_back(i);
  e.r = std::move(r);
  e.h = std::move(h);
  return e;
}

/// The independent rows among gradients (numerical echelon form with full pivoting, relative tolerance).
class Independent {
 public:
  explicit Independent(std::size_t w) : w_(w) {}
  /// Adds g if it is independent of the rows so far (relative to its own size); true if added.
  bool add(std::vector<double> g) {
    double size = 0;
    for (double x : g) size = std::max(size, std::abs(x));
    for (std::size_t k = 0; k < rows_.size(); ++k) {
      const double f = g[cols_[k]] / rows_[k][cols_[k]];
      for (std::size_t j = 0; j < w_; ++j) g[j] -= f * rows_[k][j];
    }
    std::size_t c = w_;
    double best = kTol * size;
    for (std::size_t j = 0; j < w_; ++j)
      if (std::abs(g[j]) > best) best = std::abs(g[j]), c = j;
    if (c == w_ || size == 0) return false;
    rows_.push_back(std::move(g));
    cols_.push_back(c);
    return true;
  }
  std::size_t rank() const { return rows_.size(); }

 private:
  std::size_t w_;
  std::vector<std::vector<double>> rows_;
  std::vector<std::size_t> cols_;
};

}  // namespace

// ---- Tape -----------------------------------------------------------------------------------

Tape::Tape(const std::vector<Expr>& outputs) {
  std::unordered_map<const ex::ExprNode*, std::size_t> index;
  // iterative post-order: deep DAGs (derivatives of derivatives) must not overflow the stack
  for (const Expr& root : outputs) {
    std::vector<std::pair<const ex::ExprNode*, bool>> stack{{root.get(), false}};
    while (!stack.empty()) {
      auto [n, expanded] = stack.back();
      stack.pop_back();
      if (index.count(n)) continue;
      if (!expanded) {
        stack.emplace_back(n, true);
        if (n->b) stack.emplace_back(n->b.get(), false);
        if (n->a) stack.emplace_back(n->a.get(), false);
        continue;
      }
      Op o;
      o.op = n->op;
      if (n->op == ExprOp::Number) o.c = n->value.convert_to<double>();
      if (n->op == ExprOp::Variable) o.k = static_cast<long>(n->var);
      if (n->a) o.a = index.at(n->a.get());
      if (n->b) o.b = index.at(n->b.get());
      o.k = n->op == ExprOp::Pow ? n->exponent : o.k;
      index.emplace(n, ops_.size());
      ops_.push_back(o);
    }
    out_.push_back(index.at(root.get()));
  }
  val_.resize(ops_.size());
}

void Tape::evaluate(const double* vars, double* out) const {
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    const Op& o = ops_[i];
    val_[i] = o.op == ExprOp::Variable ? vars[o.k] : apply(o.op, val_[o.a], val_[o.b], o.k, o.c);
  }
  for (std::size_t k = 0; k < out_.size(); ++k) out[k] = val_[out_[k]];
}

void Tape::jacobian(const double* vars, std::size_t width, double* out, double* jac) const {
  evaluate(vars, out);
  std::vector<double> d(ops_.size() * width, 0.0);
  for (std::size_t i = 0; i < ops_.size(); ++i) {
    const Op& o = ops_[i];
    double* di = d.data() + i * width;
    const double *da = d.data() + o.a * width, *db = d.data() + o.b * width, a = val_[o.a], b = val_[o.b];
    const auto chain = [&](double f) {  // d(g(a)) = g'(a) da (0 where a does not move: √(t⁴) at t = 0 is no NaN in x)
      for (std::size_t j = 0; j < width; ++j) di[j] = da[j] == 0 ? 0.0 : f * da[j];
    };
    switch (o.op) {
      case ExprOp::Number: break;
      case ExprOp::Variable:
        if (static_cast<std::size_t>(o.k) < width) di[o.k] = 1;
        break;
      case ExprOp::Add:
        for (std::size_t j = 0; j < width; ++j) di[j] = da[j] + db[j];
        break;
      case ExprOp::Sub:
        for (std::size_t j = 0; j < width; ++j) di[j] = da[j] - db[j];
        break;
      case ExprOp::Mul:
        for (std::size_t j = 0; j < width; ++j) di[j] = b * da[j] + a * db[j];
        break;
      case ExprOp::Div:
        for (std::size_t j = 0; j < width; ++j) di[j] = (da[j] - val_[i] * db[j]) / b;
        break;
      case ExprOp::Neg: chain(-1); break;
      case ExprOp::Pow:
        chain(o.k == 0 ? 0.0 : static_cast<double>(o.k) * std::pow(a, static_cast<double>(o.k - 1)));
        break;
      case ExprOp::Sin: chain(std::cos(a)); break;
      case ExprOp::Cos: chain(-std::sin(a)); break;
      case ExprOp::Exp: chain(val_[i]); break;
      case ExprOp::Sqrt: chain(0.5 / val_[i]); break;
    }
  }
  for (std::size_t k = 0; k < out_.size(); ++k) std::copy_n(d.data() + out_[k] * width, width, jac + k * width);
}

// ---- The chart ------------------------------------------------------------------------------

Chart chart_at(const symbolic::LagrangianSystem& s, const std::vector<double>& generic) {
  const std::size_t n = s.n, m = s.m(), w = n + m;
  const symbolic::LagrangianDerivatives der = symbolic::derivatives(s);
  Differentiator d;
  Values val(generic);
  const std::vector<std::string> names = s.variable_names();
  Chart ch;
  ch.point = generic;
  ch.dims.push_back(static_cast<long>(3 * n));
  // the dynamic rows: ∂²L/∂v∂v v̇ − aᵀλ = ∂L/∂q + F − ∂²L/∂v∂q v − ∂²L/∂v∂t
  std::vector<std::vector<Expr>> dyn_r(n, std::vector<Expr>(w, ex::number(0)));
  std::vector<Expr> dyn_h(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) dyn_r[i][j] = d(der.dl_dv[i], s.v(j));
    for (std::size_t a = 0; a < m; ++a) dyn_r[i][n + a] = ex::neg(der.a[a][i]);
    Expr h = der.dl_dq[i];
    if (!s.forces.empty()) h = ex::add(h, s.forces[i]);
    for (std::size_t j = 0; j < n; ++j) h = ex::sub(h, ex::mul(d(der.dl_dv[i], s.q(j)), ex::variable(s.v(j))));
    if (s.has_time) h = ex::sub(h, d(der.dl_dv[i], s.t()));
    dyn_h[i] = h;
  }
  // the tangency row of a constraint φ over (v̇, λ)
  std::vector<std::vector<Expr>> tan_r;
  std::vector<Expr> tan_h, phi;
  Independent indep(2 * n);
  const auto gradient = [&](const Expr& f) {
    std::vector<double> g(2 * n);
    for (std::size_t j = 0; j < 2 * n; ++j) g[j] = val.zero(d(f, j)) ? 0 : val.value(d(f, j));
    return g;
  };
  const auto take = [&](const Expr& f) {
    std::vector<Expr> row(w, ex::number(0));
    Expr h = ex::number(0);
    for (std::size_t j = 0; j < n; ++j) {
      row[j] = d(f, s.v(j));
      h = ex::sub(h, ex::mul(d(f, s.q(j)), ex::variable(s.v(j))));
    }
    if (s.has_time) h = ex::sub(h, d(f, s.t()));
    tan_r.push_back(row);
    tan_h.push_back(h);
    phi.push_back(f);
  };
  double vscale = 1;
  for (double x : generic) vscale = std::max(vscale, std::abs(x));
  // a candidate that does not vanish at the point: the point is not on the next level (NotOnLevel)
  const auto off = [&](const Expr& c) {
    double hs = 0;
    for (std::size_t j = 0; j < 2 * n; ++j) hs = std::max(hs, std::abs(val.value(d(c, j))));
    return !std::isfinite(val.value(c)) || std::abs(val.value(c)) > 1e-9 * std::max(hs * vscale, 1.0);
  };
  const auto not_on = [&](std::vector<Expr> more, const std::string& why) {
    NotOnLevel e(why);
    e.constraints = phi;
    e.constraints.insert(e.constraints.end(), more.begin(), more.end());
    for (const Expr& f : e.constraints) {
      e.gradients.emplace_back();
      for (std::size_t j = 0; j < 2 * n; ++j) e.gradients.back().push_back(d(f, j));
    }
    return e;
  };
  ch.levels.emplace_back();
  {
    std::vector<Expr> offs;
    for (std::size_t a = 0; a < m; ++a)
      if (off(s.constraints[a])) offs.push_back(s.constraints[a]);
    if (!offs.empty()) throw not_on(offs, "the point is not on M_1");
  }
  for (std::size_t a = 0; a < m; ++a) {
    if (indep.add(gradient(s.constraints[a]))) {
      take(s.constraints[a]);
      ch.levels.back().push_back(s.constraints[a]);
    }
  }
  ch.dims.push_back(static_cast<long>(2 * n - indep.rank()));
  for (std::size_t level = 1;; ++level) {
    if (level > 2 * n + 2) throw ChartFailure("the tower did not end within 2n + 2 steps");
    // a bound on the work (the formulas of a deep tower can grow fast): no formulas rather than no answer
    if (d.size() > kMaxDerivatives)
      throw ChartFailure("the formulas grow beyond " + std::to_string(kMaxDerivatives) + " derivative nodes by M_" +
                         std::to_string(level));
    std::vector<std::vector<Expr>> r = dyn_r;
    std::vector<Expr> h = dyn_h;
    std::vector<std::string> rows;
    for (std::size_t i = 0; i < n; ++i) rows.push_back("d/dt p_" + s.names[i]);
    for (std::size_t k = 0; k < tan_r.size(); ++k) {
      r.push_back(tan_r[k]);
      h.push_back(tan_h[k]);
      rows.push_back("d/dt of constraint " + std::to_string(k + 1));
    }
    const Elimination e = eliminate(r, h, val, ch.vanishing);
    std::vector<Expr> found, offs;
    for (std::size_t i : e.left)
      if (off(e.h[i])) offs.push_back(e.h[i]);
    if (!offs.empty()) throw not_on(offs, "the point is not on M_" + std::to_string(level + 1));
    for (std::size_t i : e.left)
      if (indep.add(gradient(e.h[i])))
        found.push_back(e.h[i]);
      else if (!ex::is_number(e.h[i]))
        ch.vanishing.push_back(e.h[i]);  // implied by the constraints so far
    if (found.empty()) {                 // M_c = M_k: back substitution, free unknowns 0
      std::vector<Expr> u(w, ex::number(0));
      std::vector<char> pivoted(w, 0);
      for (const auto& pc : e.pivots) pivoted[pc.second] = 1;
      for (auto it = e.pivots.rbegin(); it != e.pivots.rend(); ++it) {
        const auto [p, c] = *it;
        Expr x = e.h[p];
        for (std::size_t j = 0; j < w; ++j)
          if (j != c && pivoted[j] && !ex::is_number(e.r[p][j], 0)) x = ex::sub(x, ex::mul(e.r[p][j], u[j]));
        u[c] = ex::div(x, e.r[p][c]);
      }
      for (std::size_t i = 0; i < n; ++i) ch.rates.push_back(ex::variable(s.v(i)));
      for (std::size_t i = 0; i < n; ++i) {
        ch.rates.push_back(u[i]);
        if (!pivoted[i]) ch.free.push_back(s.v(i));
      }
      for (const auto& [p, c] : e.pivots)
        ch.valid_where.push_back({"pivot of the system on M_c: row " + rows[p] + ", column " +
                                      (c < n ? "d/dt v_" + s.names[c] : "lambda_" + std::to_string(c - n + 1)),
                                  e.r[p][c]});
      break;
    }
    for (const auto& [p, c] : e.pivots)  // the new constraints divide by these
      ch.valid_where.push_back({"pivot of the system on M_" + std::to_string(level) + ": row " + rows[p] + ", column " +
                                    (c < n ? "d/dt v_" + s.names[c] : "lambda_" + std::to_string(c - n + 1)),
                                e.r[p][c]});
    ch.levels.emplace_back();
    for (const Expr& c : found) {
      take(c);
      ch.levels.back().push_back(c);
    }
    ch.dims.push_back(static_cast<long>(2 * n - indep.rank()));
  }
  // M_c's chart: the constraints' Jacobian over (q, v), eliminated on the DAG; its pivot columns are solved for
  {
    std::vector<std::vector<Expr>> jac;
    for (const Expr& f : phi) {
      std::vector<Expr> row;
      for (std::size_t j = 0; j < 2 * n; ++j) row.push_back(d(f, j));
      jac.push_back(row);
    }
    const Elimination e = eliminate(jac, std::vector<Expr>(jac.size(), ex::number(0)), val, ch.vanishing);
    std::vector<char> solved(2 * n, 0);
    for (const auto& [p, c] : e.pivots) {
      solved[c] = 1;
      ch.valid_where.push_back({"chart: constraint " + std::to_string(p + 1) + " solved for " + names[c], e.r[p][c]});
    }
    for (std::size_t j = 0; j < 2 * n; ++j) (solved[j] ? ch.solved : ch.kept).push_back(j);
    ch.constraints = phi;
    ch.gradients = jac;
  }
  ch.momenta = der.dl_dv;
  // a pivot that is a nonzero number holds everywhere: not a condition
  ch.valid_where.erase(std::remove_if(ch.valid_where.begin(), ch.valid_where.end(),
                                      [](const Chart::Condition& c) { return ex::is_number(c.formula); }),
                       ch.valid_where.end());
  return ch;
}

// The chart must hold at `near` itself: M_c's constraints vanish there (the generic point may have
// landed on another component: {x v_y = 0} is two) and none of its conditions does.  `why` says which failed.
static bool chart_holds_at(const symbolic::LagrangianSystem& s, const Chart& c, const std::vector<double>& near,
                           const std::vector<double>* velocity, std::string& why) {
  const ChartField f(c);
  const std::vector<double> y(near.begin(), near.end() - 1);
  if (f.drift(y, near.back()) > 1e-8) {
    why = "the generic points reached lie on another component of M_c";
    return false;
  }
  // every entry the elimination took as zero on M_k (decided at the generic point) vanishes at `near`
  // too: else `near` lies on a component where the chart's elimination is not valid
  Values val(near);
  for (const Expr& z : c.vanishing)  // to the drift check's 1e-8: `near` is on M_c to that
    if (!val.zero_to(z, 1e-8)) {
      why = "the generic points reached lie on another component of M_c (" + ex::to_text(z, s.variable_names()) +
            " vanishes there, not at the given point)";
      return false;
    }
  if (velocity) {
    std::vector<double> u(2 * s.n);
    f.rates(y.data(), near.back(), u.data());
    double scale = 1, worst = 0;
    for (std::size_t i = 0; i < 2 * s.n; ++i) scale = std::max(scale, std::abs((*velocity)[i]));
    for (std::size_t i = 0; i < 2 * s.n; ++i) worst = std::max(worst, std::abs(u[i] - (*velocity)[i]));
    if (!(worst <= 1e-7 * scale)) {
      why = "the chart's equations disagree with the pointwise CAD at the given point (by " +
            std::to_string(worst / scale) + " relative)";
      return false;
    }
  }
  std::size_t weakest = 0;
  if (f.margin(y, near.back(), &weakest) < 1e-6) {
    why = "the condition " + ex::to_text(c.valid_where[weakest].formula, s.variable_names()) + " != 0 (" +
          c.valid_where[weakest].what + ") fails at the given point";
    return false;
  }
  return true;
}

Chart chart_near(const symbolic::LagrangianSystem& s, const std::vector<double>& near, const std::vector<long>& dims,
                 const std::vector<double>* velocity, const Completion& complete) {
  const auto dims_text = [](const std::vector<long>& d) {
    std::string t;
    for (long x : d) t += (t.empty() ? "" : " ") + std::to_string(x);
    return "[" + t + "]";
  };
  std::string why;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double size : {0.1, 0.1, 0.01, 0.001}) {
    std::vector<double> y(near.begin(), near.end() - 1);
    for (double& x : y) x += size * u(rng) * std::max(1.0, std::abs(x));
    // the time too: the formulas are functions of t, and at the given t a coefficient (sin Ωt at t = 0) may vanish
    const double t = s.has_time ? near.back() + size * u(rng) * std::max(1.0, std::abs(near.back())) : near.back();
    // CEF (5.2)'s levels one after another: the chart's decisions at y, and where y is not on the next
    // level, y projected onto every constraint found so far (the pointwise CAD's move, on formulas)
    for (int moves = 0; moves < 4 * static_cast<int>(s.n) + 8; ++moves) {
      std::vector<double> at(y);
      at.push_back(t);
      try {
        Chart c = chart_at(s, at);
        if (c.dims == dims && chart_holds_at(s, c, near, velocity, why)) return c;
        if (c.dims == dims) break;
        why = "the formulas' tower has dims " + dims_text(c.dims) + ", the pointwise CAD's " + dims_text(dims);
        break;
      } catch (const NotOnLevel& e) {
        why = e.what();
        if (!project_onto(e.constraints, e.gradients, y, t, 1e-14)) break;
      } catch (const std::exception& e) {
        why = e.what();
        break;
      }
    }
  }
  // the caller's completion of a perturbed point (the pointwise CAD's Newton moves on jets: another route onto M_c)
  for (unsigned seed = 1; seed <= 2 && complete; ++seed) {
    std::vector<double> start(near);
    for (std::size_t i = 0; i < start.size(); ++i)
      if (i + 1 < start.size() || s.has_time) start[i] += 0.05 * u(rng) * std::max(1.0, std::abs(start[i]));
    try {
      const std::optional<std::vector<double>> at = complete(start);
      if (!at) continue;
      Chart c = chart_at(s, *at);
      if (c.dims == dims && chart_holds_at(s, c, near, velocity, why)) return c;
    } catch (const std::exception&) {
    }
  }
  throw ChartFailure("no generic point of M_c was reached near the given one: " + why);
}

bool project_onto(const std::vector<Expr>& constraints, const std::vector<std::vector<Expr>>& gradients,
                  std::vector<double>& y, double t, double tol, const std::vector<bool>* held) {
  std::vector<Expr> g;
  for (const auto& row : gradients) g.insert(g.end(), row.begin(), row.end());
  const Tape phi_tape(constraints), jac_tape(g);
  const std::size_t k = constraints.size(), w = y.size();
  std::vector<double> at(w + 1), phi(k), jac(k * w);
  double previous = HUGE_VAL;
  int stalled = 0;
  for (int it = 0; it < 30; ++it) {
    std::copy(y.begin(), y.end(), at.begin());
    at[w] = t;
    phi_tape.evaluate(at.data(), phi.data());
    jac_tape.evaluate(at.data(), jac.data());
    double d = 0;
    bool small = true;  // each constraint against its own terms: x − 1 beside y/2^60 − 1 at y = 2^60 is not on it at
                        // x = 0.86 (a tolerance relative to the largest coordinate took it: a false alarm of check)
    for (std::size_t i = 0; i < k; ++i) {
      double terms = 0;
      for (std::size_t j = 0; j < w; ++j) terms += std::abs(jac[i * w + j] * y[j]);
      d = std::max(d, std::abs(phi[i]));
      small = small && std::abs(phi[i]) <= tol * terms;
    }
    if (!std::isfinite(d)) return false;
    if (small) return true;
    stalled = d < previous / 2 ? 0 : stalled + 1;
    previous = std::min(previous, d);
    if (stalled >= 3) {  // Newton no longer gains: at rounding level if every residual is within its rounding bound
      Values val(at);
      for (const Expr& c : constraints)
        if (!val.zero(c)) return false;
      return true;
    }
    Eigen::MatrixXd J(k, w);
    for (std::size_t i = 0; i < k; ++i)
      for (std::size_t j = 0; j < w; ++j) J(i, j) = held && j < held->size() && (*held)[j] ? 0.0 : jac[i * w + j];
    const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(phi.data(), static_cast<long>(k));
    const Eigen::VectorXd dy =
        J.completeOrthogonalDecomposition().solve(r);  // least norm (held columns 0: they do not move)
    if (!dy.allFinite()) return false;
    for (std::size_t j = 0; j < w; ++j) y[j] -= dy[static_cast<long>(j)];
  }
  return false;
}

std::vector<double> complete_on_chart(const symbolic::LagrangianSystem& s, const std::vector<double>& start,
                                      const std::vector<bool>& held) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double size : {0.1, 0.01, 0.3}) {
    std::vector<double> y(start.begin(), start.end() - 1);
    for (double& x : y) x += size * u(rng) * std::max(1.0, std::abs(x));
    const double t = s.has_time ? start.back() + size * u(rng) * std::max(1.0, std::abs(start.back())) : start.back();
    for (int moves = 0; moves < 4 * static_cast<int>(s.n) + 8; ++moves) {
      std::vector<double> at(y);
      at.push_back(t);
      try {
        const Chart c = chart_at(s, at);
        std::vector<double> z(start.begin(), start.end() - 1);
        if (!project_onto(c.constraints, c.gradients, z, start.back(), 1e-15, &held)) break;
        const ChartField f(c);
        if (f.margin(z, start.back()) < 1e-6) break;  // the completed point is outside this chart
        z.push_back(start.back());
        return z;
      } catch (const NotOnLevel& e) {
        if (!project_onto(e.constraints, e.gradients, y, t, 1e-14)) break;
      } catch (const std::exception&) {
        break;
      }
    }
  }
  return {};
}

// ---- ChartField -------------------------------------------------------------------------------

namespace {
std::vector<Expr> flat(const std::vector<std::vector<Expr>>& g) {
  std::vector<Expr> out;
  for (const auto& row : g) out.insert(out.end(), row.begin(), row.end());
  return out;
}
std::vector<Expr> formulas(const std::vector<Chart::Condition>& v) {
  std::vector<Expr> out;
  for (const auto& c : v) out.push_back(c.formula);
  return out;
}
}  // namespace

ChartField::ChartField(const Chart& c)
    : n_(c.rates.size() / 2),
      rates_(c.rates),
      constraints_(c.constraints),
      jacobian_(flat(c.gradients)),
      momenta_(c.momenta),
      valid_(formulas(c.valid_where)),
      k_(c.constraints.size()) {
  buf_.resize(2 * n_ + 1);
  valid0_.resize(c.valid_where.size());
  if (!valid0_.empty()) valid_.evaluate(c.point.data(), valid0_.data());
}

void ChartField::rates(const double* y, double t, double* dy) const {
  std::copy(y, y + 2 * n_, buf_.begin());
  buf_[2 * n_] = t;
  rates_.evaluate(buf_.data(), dy);
}

double ChartField::drift(const std::vector<double>& y, double t) const {
  std::vector<double> at(y.begin(), y.begin() + static_cast<long>(2 * n_)), phi(k_);
  at.push_back(t);
  if (k_) constraints_.evaluate(at.data(), phi.data());
  double scale = 1, d = 0;
  for (std::size_t i = 0; i < 2 * n_; ++i) scale = std::max(scale, std::abs(y[i]));
  for (double x : phi) {
    if (!std::isfinite(x)) return HUGE_VAL;  // a constraint undefined there (a root of a negative …) is not on M_c
    d = std::max(d, std::abs(x));
  }
  return d / scale;
}

bool ChartField::project(std::vector<double>& y, double t, double tol) const {
  const std::size_t w = 2 * n_;
  std::vector<double> at(w + 1), phi(k_), jac(k_ * w);
  for (int it = 0; it < 20; ++it) {
    if (drift(y, t) <= tol) return true;
    std::copy(y.begin(), y.begin() + static_cast<long>(w), at.begin());
    at[w] = t;
    constraints_.evaluate(at.data(), phi.data());
    jacobian_.evaluate(at.data(), jac.data());
    Eigen::MatrixXd J(k_, w);
    for (std::size_t i = 0; i < k_; ++i)
      for (std::size_t j = 0; j < w; ++j) J(i, j) = jac[i * w + j];
    const Eigen::VectorXd r = Eigen::Map<const Eigen::VectorXd>(phi.data(), static_cast<long>(k_));
    const Eigen::VectorXd dy = J.completeOrthogonalDecomposition().solve(r);
    if (!dy.allFinite()) return false;
    for (std::size_t j = 0; j < w; ++j) y[j] -= dy[static_cast<long>(j)];
  }
  return drift(y, t) <= tol;
}

std::vector<double> ChartField::momenta(const std::vector<double>& y, double t) const {
  std::vector<double> at(y.begin(), y.begin() + static_cast<long>(2 * n_)), p(n_);
  at.push_back(t);
  momenta_.evaluate(at.data(), p.data());
  return p;
}

double ChartField::margin(const std::vector<double>& y, double t, std::size_t* which) const {
  if (valid0_.empty()) return 1;
  std::vector<double> at(y.begin(), y.begin() + static_cast<long>(2 * n_)), v(valid0_.size());
  at.push_back(t);
  valid_.evaluate(at.data(), v.data());
  double m = HUGE_VAL;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const double r = std::abs(v[i]) / std::max(std::abs(valid0_[i]), 1e-300);
    if (r < m) {
      m = r;
      if (which) *which = i;
    }
  }
  return m;
}

}  // namespace dcad::fast
