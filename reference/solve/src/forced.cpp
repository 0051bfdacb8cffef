#include "dcad/reference/pipeline/forced.hpp"

#include "dcad/io/input_error.hpp"
#include "dcad/reference/rlc.hpp"
#include "dcad/rlc_graph.hpp"
#include "source_balls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace dcad::reference::pipeline {

using Q = Rational;
using QM = Matrix<Q>;

std::vector<std::string> jet_names(const std::vector<io::Waveform>& waveforms, long orders) {
  std::vector<std::string> out{"1"};
  for (long d = 0; d < orders; ++d)
    for (const io::Waveform& w : waveforms) {
      const std::string f = w.element;
      out.push_back(d == 0   ? f + "(t)"
                    : d <= 3 ? f + std::string(d, '\'') + "(t)"
                             : "d" + std::to_string(d) + f + "/dt" + std::to_string(d) + "(t)");
    }
  return out;
}

namespace {

std::string row_text(const QM& row, const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t j = 0; j < row.cols(); ++j) {
    if (row(0, j) == 0) continue;
    Q c = row(0, j);
    const bool neg = c < 0;
    if (neg) c = -c;
    s += s.empty() ? (neg ? "-" : "") : (neg ? " - " : " + ");
    const std::string& nm = names[j];
    s += nm == "1" ? c.str() : (c == 1 ? "" : c.str() + "*") + nm;
  }
  return (s.empty() ? "0" : s) + " = 0";
}

/// How fast σ_w's argument turns (per second: SIN's |ω| + |θ|, SFFM's 2π(FC + MDI·FS), EXP's 1/TAU1 + 1/TAU2),
/// and the radians it holds from the start (SIN's PHASE): where the double samples stay near the waveform's
/// values (a phase below 1e4 rad), so their largest values point at times where a ball proves a failure.
double phase_rate(const io::Waveform& w) {
  if (w.kind == io::Waveform::Kind::sin) return std::abs(w.omega()) + std::abs(w.decay());
  if (w.kind == io::Waveform::Kind::sffm)
    return 2 * M_PI * (std::abs(w.p[2].convert_to<double>()) + std::abs((w.p[3] * w.p[4]).convert_to<double>()));
  if (w.kind == io::Waveform::Kind::exp) return std::abs(w.rate1()) + std::abs(w.rate2());
  return 0;
}
double phase_held(const io::Waveform& w) {  // SIN's PHASE, and ω·|TD| for a negative TD (the argument is ω (t − TD))
  if (w.kind != io::Waveform::Kind::sin) return 0.0;
  return std::abs(w.p[5].convert_to<double>()) * M_PI / 180 +
         phase_rate(w) * std::max(0.0, -w.p[3].convert_to<double>());
}

/// The combination sampled in double at times that show every feature of the waveforms (breakpoints, their
/// midpoints, 97 times spread over the horizon, 17 within a fast SIN's, SFFM's or EXP's first 1e4 rad): its
/// largest |value| and where (`worst`, `at`), its scale, and the times of its largest values first (`candidates`,
/// where condition_ball tries to prove it nonzero).
constexpr std::size_t kCandidates = 8;
struct Sampled {
  double worst = 0, at = 0, scale = 0;
  std::size_t samples = 0;
  std::vector<double> candidates;
};
Sampled sample(const QM& row, const std::vector<io::Waveform>& waveforms, long orders) {
  const std::size_t m = waveforms.size();
  std::vector<bool> in_row(m, false);  // only the row's own sources set the sample times
  for (std::size_t j = 0; j < m; ++j)
    for (long d = 0; d < orders; ++d) in_row[j] = in_row[j] || row(0, 1 + d * m + j) != 0;
  double horizon = 0;
  for (std::size_t j = 0; j < m; ++j)
    if (in_row[j]) horizon = std::max(horizon, waveforms[j].horizon());
  if (horizon == 0) horizon = 1;
  std::vector<double> ts{0};
  for (std::size_t j = 0; j < m; ++j)
    if (in_row[j]) {  // each waveform's corners up to its own horizon (a 4 ns PULSE beside a 1 Hz SIN: two periods)
      const double own = waveforms[j].horizon();
      const std::vector<double> corners = waveforms[j].breakpoints(own > 0 ? std::min(own, horizon) : horizon);
      ts.insert(ts.end(), corners.begin(), corners.end());
    }
  std::sort(ts.begin(), ts.end());
  const std::size_t k = ts.size();
  for (std::size_t i = 1; i < k; ++i) ts.push_back((ts[i - 1] + ts[i]) / 2);
  for (int i = 1; i <= 97; ++i) ts.push_back(horizon * std::fmod(i * 0.6180339887498949, 1.0));
  for (std::size_t j = 0; j < m; ++j) {  // and 17 within a fast SIN's, SFFM's or EXP's first 1e4 rad
    const double rate = in_row[j] ? phase_rate(waveforms[j]) : 0.0, reach = (1e4 - phase_held(waveforms[j])) / rate;
    const double from =
        waveforms[j].kind == io::Waveform::Kind::sin ? std::max(0.0, waveforms[j].p[3].convert_to<double>()) : 0.0;
    if (rate > 0 && from < reach && reach < horizon)
      for (int i = 1; i <= 17; ++i) ts.push_back(from + (reach - from) * std::fmod(i * 0.6180339887498949, 1.0));
  }
  Sampled out;
  out.scale = std::abs(row(0, 0).convert_to<double>());
  std::vector<std::pair<double, double>> by_size;  // (|value|, t)
  for (double t : ts) {
    double s = row(0, 0).convert_to<double>();
    for (std::size_t j = 0; j < m; ++j)
      for (long d = 0; d < orders && in_row[j]; ++d) {
        const double c = row(0, 1 + d * m + j).convert_to<double>();
        if (c == 0) continue;
        const double term = c * waveforms[j].value(t, static_cast<int>(d));
        s += term;
        out.scale = std::max(out.scale, std::abs(term));
      }
    if (std::abs(s) > out.worst) out.worst = std::abs(s), out.at = t;
    if (std::isfinite(t) && t >= 0) by_size.emplace_back(std::isfinite(s) ? std::abs(s) : HUGE_VAL, t);
  }
  std::stable_sort(by_size.begin(), by_size.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  for (std::size_t i = 0; i < by_size.size() && out.candidates.size() < kCandidates; ++i)
    out.candidates.push_back(by_size[i].second);
  out.samples = ts.size();
  return out;
}

}  // namespace

SourceCondition decide_condition(const QM& row, const std::vector<io::Waveform>& waveforms) {
  const std::size_t m = waveforms.size();
  const long orders = m ? static_cast<long>((row.cols() - 1) / m) : 0;
  SourceCondition v;
  v.text = row_text(row, jet_names(waveforms, orders));
  // identical waveforms (same kind and parameters) are one function: sum their coefficients
  std::map<std::pair<std::string, long>, Q> sums;
  Q constant = row(0, 0);
  bool all_constant = true;
  for (std::size_t j = 0; j < m; ++j)
    for (long d = 0; d < orders; ++d) {
      const Q& c = row(0, 1 + d * m + j);
      if (c == 0) continue;
      const io::Waveform& w = waveforms[j];
      if (w.kind == io::Waveform::Kind::dc) {
        if (d == 0) constant += c * w.p[0];
        continue;
      }
      all_constant = false;
      std::string key = std::to_string(static_cast<int>(w.kind));  // every parameter of the function: R=, NP too
      for (const Q& p : w.p) key += " " + p.str();
      key += " R " + (w.repeat ? w.repeat->str() : std::string("-")) + " NP " + std::to_string(w.pulses) + " P " +
             w.period.str();
      sums[{key, d}] += c;
    }
  bool zero = constant == 0;
  for (const auto& [k, c] : sums) zero = zero && c == 0;
  if (zero) {
    v.holds = yes;
    v.evidence = all_constant ? "exact (DC values)" : "exact (equal waveforms cancel)";
    return v;
  }
  if (all_constant) {
    v.holds = no;
    v.evidence = "exact: the DC values give " + constant.str() + " = 0";
    return v;
  }
  const Sampled sm = sample(row, waveforms, orders);
  const double cut = kConditionFails * std::max(sm.scale, 1e-300);
  std::ostringstream o;
  o.precision(6);
  for (long bits : {128L, 1024L})  // the largest values first; more bits only for the two largest
    for (std::size_t i = 0; i < sm.candidates.size() && (bits == 128 || i < 2); ++i) {
      const std::optional<ConditionBall> ball = condition_ball(row, waveforms, orders, Q(sm.candidates[i]), bits);
      if (!ball || !ball->excludes_zero) continue;
      v.holds = no;
      o.precision(17);
      o << "fails at t = " << sm.candidates[i] << " s (exactly this double): the left side is in " << ball->text
        << " (Arb balls at " << bits << " bits, the PULSE and PWL values exact), which excludes 0";
      v.evidence = o.str();
      return v;
    }
  v.holds = unknown;
  if (sm.worst > cut)
    o << "the left side is " << sm.worst << " at t = " << sm.at << " s in double, but no ball at the " << sm.samples
      << " sample times' largest values excludes 0 (not proved nonzero): cannot decide exactly";
  else
    o << "different waveforms agree to " << sm.worst << " at " << sm.samples
      << " sample times and no ball there excludes 0 (not proved nonzero): cannot decide exactly";
  v.evidence = o.str();
  return v;
}

namespace {

Equation<Q> jet_equation(const QM& rows, std::size_t i, std::size_t nvars) {
  Equation<Q> e;
  for (std::size_t j = 0; j < rows.cols(); ++j) {
    if (j == nvars || rows(i, j) == 0) continue;
    e.terms.emplace_back(j < nvars ? j : j - 1, rows(i, j));
  }
  e.rhs = -rows(i, nvars);
  return e;
}

Rows<Q> dense(const QM& m) {
  Rows<Q> out(m.rows());
  for (Index i = 0; i < m.rows(); ++i) out[i] = m.row(i);
  return out;
}

/// The exact forced CAD: the tower with its jet equations, the source conditions decided against the
/// waveforms (the first M_k whose condition fails is empty), the equations of motion with the sources'
/// jets.
dcad::Solution<Q> exact_forced(const ForcedSystem<Q>& f, const std::vector<io::Waveform>& waveforms,
                               const std::vector<std::string>& variables) {
  const ForcedResult<Q> r = forced_tower(f);
  dcad::Solution<Q> s;
  s.variables = variables;
  s.certified = yes;
  s.decisions.exact_recomputation = 1;
  s.note = "forced route (YM §4 forces and affine constraints, moving M_k(t) as in V §3), exact";
  const std::size_t nv = f.s.d.n;
  long empty_at = r.consistent ? -1 : static_cast<long>(r.dims.size()) - 1;
  long undecided_at = -1;  // the first level with a condition left undecided: it matters below the first empty M_k
  for (std::size_t k = 0; k < r.conditions_at.size() && (empty_at < 0 || static_cast<long>(k) < empty_at); ++k) {
    const QM& ck = r.conditions_at[k];
    for (std::size_t i = 0; i < ck.rows(); ++i) {
      const SourceCondition v = decide_condition(ck.block(i, i + 1, 0, ck.cols()), waveforms);
      const bool seen = std::any_of(s.source_conditions.begin(), s.source_conditions.end(),
                                    [&](const SourceCondition& o) { return o.text == v.text; });
      if (!seen) s.source_conditions.push_back(v);
      if (v.holds.no() && empty_at < 0) empty_at = static_cast<long>(k);
      if (v.holds.unknown() && undecided_at < 0) undecided_at = static_cast<long>(k);
    }
  }
  if (undecided_at >= 0 && (empty_at < 0 || undecided_at < empty_at)) s.certified = unknown;  // else M_k is ∅ anyway
  for (std::size_t k = 0; k < r.dims.size(); ++k) {
    Level<Q> st;
    st.dim = empty_at >= 0 && static_cast<long>(k) >= empty_at ? -1 : r.dims[k];
    for (std::size_t i = 0; i < r.added[k].rows(); ++i) st.constraints.push_back(jet_equation(r.added[k], i, nv));
    s.tower.push_back(st);
    if (st.dim < 0) break;
  }
  if (empty_at == static_cast<long>(r.dims.size())) s.tower.push_back(Level<Q>{-1, {}});  // M_{c+1}: conditions only
  s.steps = static_cast<long>(s.tower.size()) - 1;
  const std::vector<std::string> jets = jet_names(waveforms, static_cast<long>(r.orders) + 1);
  s.jets.assign(jets.begin() + 1, jets.end());
  for (const io::Waveform& w : waveforms) s.source_names.push_back(w.element);
  s.consistent = s.tower.back().dim >= 0;
  if (s.consistent) s.solution_rank = static_cast<long>(r.solution_rank);
  if (s.certified.unknown()) s.note += "; a source condition could not be decided exactly (see sources.conditions)";
  if (!s.consistent) return s;
  // equations of motion: ż = F z + f + S u_src(t) + G λ  [CEF (5.12) with the sources' jets]
  const ForcedReducedEquations<Q> red = forced_reduced_equations(forced_motion(f, r), f.sources);
  Motion<Q> mo;
  mo.coordinates.assign(red.coords.begin(), red.coords.end());
  mo.f_matrix = dense(red.f_matrix);
  mo.g = dense(red.g);
  mo.f = red.f;
  // only the jet orders that occur (the tower widens the jets by one order per step)
  std::size_t used = 0;
  for (std::size_t j = 0; j < red.s.cols(); ++j)
    for (std::size_t i = 0; i < red.s.rows(); ++i)
      if (red.s(i, j) != 0) used = j + 1;
  if (f.sources) used = (used + f.sources - 1) / f.sources * f.sources;
  mo.s = dense(red.s.block(0, red.s.rows(), 0, used));
  mo.source_columns.assign(jets.begin() + 1, jets.begin() + 1 + static_cast<long>(used));
  s.motion = mo;
  return s;
}

}  // namespace

ForcedSystem<Q> forced_system(const io::CaseFile& c) {
  const io::PontryaginInput& in = c.pontryagin;
  const std::size_t n = in.n;
  ForcedSystem<Q> f{pontryagin_system(PontryaginInput<Q>{in.n, in.k, in.vv, in.qv, in.qq, in.q, in.v}),
                    QM(3 * n, 3 * n),
                    0,
                    QM(3 * n, 0),
                    QM(3 * n, 0),
                    QM(0, 1)};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      f.force(i, j) = in.fq(i, j);  // F(q, v)·δq: a horizontal one-form  [YM §4]
      f.force(i, n + j) = in.fv(i, j);
    }
  return f;
}

dcad::Solution<Q> solve_forced(const io::CaseFile& c) {
  dcad::Solution<Q> s = exact_forced(forced_system(c), {}, c.variables);
  s.file = c.file;
  s.name = c.name;
  return s;
}

namespace {

/// Φ positive definite, exactly: per group of inductors joined by couplings (a transformer's windings),
/// every pivot of Gaussian elimination on its symmetric block positive (Sylvester).  A group whose
/// couplings all come from K cards is decided on its coupling coefficients (1 on the diagonal, k off
/// it): Φ = D^½ K D^½ with D = diag(L) > 0 has the inertia of K, which is exact where M = k√(L_a L_b)
/// is irrational and was rounded (three couplings of −1/2 make Φ singular; rounded, it looked positive
/// definite).  Groups above kCoupledGroup inductors are not examined (false).
constexpr std::size_t kCoupledGroup = 200;
bool inductance_positive_definite(const RlcCircuit<Q>& c) {
  const std::size_t n = c.branches.size();
  graph::UnionFind uf(n);
  for (const Mutual<Q>& mu : c.mutuals) uf.join(mu.a, mu.b);
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t b = 0; b < n; ++b)
    if (c.branches[b].kind == RlcKind::inductor) groups[uf.find(b)].push_back(b);
  for (const auto& [root, members] : groups) {
    if (members.size() > kCoupledGroup) return false;
    std::map<std::size_t, std::size_t> at;
    for (std::size_t i = 0; i < members.size(); ++i) at[members[i]] = i;
    const std::size_t g = members.size();
    std::vector<std::vector<Q>> m(g, std::vector<Q>(g, Q(0)));
    bool by_k = true;
    for (const Mutual<Q>& mu : c.mutuals)
      if (uf.find(mu.a) == root) by_k = by_k && mu.k.has_value();
    for (std::size_t i = 0; i < g; ++i) {
      if (c.branches[members[i]].value <= 0) return false;
      m[i][i] = by_k ? Q(1) : c.branches[members[i]].value;
    }
    for (const Mutual<Q>& mu : c.mutuals)
      if (uf.find(mu.a) == root) {
        m[at[mu.a]][at[mu.b]] += by_k ? *mu.k : mu.m;
        m[at[mu.b]][at[mu.a]] += by_k ? *mu.k : mu.m;
      }
    for (std::size_t k = 0; k < g; ++k) {
      if (m[k][k] <= 0) return false;
      for (std::size_t i = k + 1; i < g; ++i) {
        if (m[i][k] == 0) continue;
        const Q f = m[i][k] / m[k][k];
        for (std::size_t j = k; j < g; ++j) m[i][j] -= f * m[k][j];
      }
    }
  }
  return true;
}

}  // namespace

bool rounded_coupling(const RlcCircuit<Q>& c) {
  return std::any_of(c.mutuals.begin(), c.mutuals.end(), [](const Mutual<Q>& mu) { return mu.rounded; });
}

bool graph_route_holds(const RlcCircuit<Q>& c) {
  for (const RlcBranch<Q>& b : c.branches)
    if ((b.kind == RlcKind::capacitor || b.kind == RlcKind::resistor) && b.value <= 0) return false;
  return inductance_positive_definite(c);  // (L > 0 without couplings)
}

namespace {

/// The condition Σ sign·σ_source(b)(t) = 0 over the sources of `path` (a loop or a cutset), decided on
/// those sources alone (a row [0 | σ⁽⁰⁾] over them, its first coefficient made positive): the cost is
/// the path's, not the deck's (N parallel sources took O(N³)).
SourceCondition decide_path(const std::vector<graph::LoopBranch>& path, const RlcCircuit<Q>& c,
                            const std::vector<io::Waveform>& all) {
  std::map<Index, int> coeff;  // source index → Σ signs
  for (const graph::LoopBranch& lb : path) {
    const RlcBranch<Q>& b = c.branches[lb.branch];
    if (b.kind == RlcKind::voltage || b.kind == RlcKind::current) coeff[b.source] += lb.sign;
  }
  std::vector<io::Waveform> own;
  QM row(1, 1 + coeff.size());
  for (const auto& [j, k] : coeff) {
    own.push_back(all[j]);
    row(0, own.size()) = Q(k);
  }
  for (Index j = 1; j < row.cols(); ++j)
    if (row(0, j) != 0) {
      if (row(0, j) < 0)
        for (Index k = 1; k < row.cols(); ++k) row(0, k) = -row(0, k);
      break;
    }
  return decide_condition(row, own);
}

}  // namespace

GraphForced graph_forced(const io::Netlist& deck) {
  const RlcCircuit<Q>& c = deck.rlc;
  std::vector<rlc::Branch> branches;
  branches.reserve(c.branches.size());
  for (const RlcBranch<Q>& b : c.branches) branches.push_back({b.kind, b.from, b.to});
  const rlc::Tower t = rlc::tower(c.nodes, branches);
  GraphForced g;
  g.certified = yes;  // the graph decides the tower; each condition below may make it unknown
  g.dims = t.dims;
  g.solution_rank = t.solution_rank;
  long empty_at = -1, undecided_at = -1;  // cutsets bound M_1, loops of voltage sources M_2
  std::set<std::string> seen;
  const auto decide = [&](const std::vector<graph::LoopBranch>& path, long level) {
    if (empty_at >= 0 && level > empty_at) return;  // beyond the first empty M_k nothing is asked
    const SourceCondition v = decide_path(path, c, deck.waveforms);
    if (seen.insert(v.text).second) g.conditions.push_back(v);
    if (v.holds.unknown() && (undecided_at < 0 || level < undecided_at)) undecided_at = level;
    if (v.holds.no() && (empty_at < 0 || level < empty_at)) empty_at = level;
  };
  for (const graph::Cutset& cut : t.current_cutsets) decide(cut, 1);
  for (const graph::Loop& loop : t.voltage_loops) decide(loop, 2);
  // a condition left undecided matters below the first empty M_k only (one that fails beside it empties M_k anyway)
  if (undecided_at >= 0 && (empty_at < 0 || undecided_at < empty_at)) g.certified = unknown;
  if (empty_at >= 0) {
    g.dims.resize(std::min<std::size_t>(g.dims.size(), static_cast<std::size_t>(empty_at)));
    g.dims.push_back(-1);
    g.consistent = false;
    g.solution_rank = 0;
  }
  g.steps = static_cast<long>(g.dims.size()) - 1;
  return g;
}

dcad::Solution<Q> solve_forced(const io::Netlist& deck, const std::vector<std::string>& variables) {
  if (deck.rlc.branches.size() > kForcedBranches) {
    if (!graph_route_holds(deck.rlc))
      throw io::InputError(deck.file + ": expected at most " + std::to_string(kForcedBranches) +
                           " branches for a circuit with a non-positive R or C or an inductance matrix that is not "
                           "positive definite (k = 1, negative L), found " +
                           std::to_string(deck.rlc.branches.size()) +
                           " (the exact route for those is dense; the others take the graph route at any size)");
    return graph_solution<Q>(deck, variables,
                             "forced graph route (dcad/rlc_graph.hpp: cycle ranks of subgraphs; CEF Thms 6.4, 6.6, 6.8 "
                             "with YM §4's sources), "
                             "exact: the tower, the conditions on the sources and the state equations "
                             "(dcad/reference/rlc_state.hpp); the tower's "
                             "equations and the motion in (q, v, p) come from the dense exact route, up to " +
                                 std::to_string(kForcedBranches) + " branches");
  }
  dcad::Solution<Q> s = exact_forced(rlc_system(deck.rlc), deck.waveforms, variables);
  if (s.consistent && graph_route_holds(deck.rlc)) s.state = deck_state_equations<Q>(deck);
  if (rounded_coupling(deck.rlc)) {
    s.certified = unknown;
    s.note += "; " + std::string(kRoundedCoupling);
  }
  s.file = deck.file;
  s.name = deck.title;
  return s;
}

}  // namespace dcad::reference::pipeline
