// `dcad simulate` on RLC netlists at any size (issue 27): the sparse equations of motion
// (dcad/fast/rlc_sparse.hpp) with the sources' exosystem as one linear system, advanced by the Krylov
// exponential action (dcad/fast/expv.hpp) — no dense matrix, memory proportional to the nonzeros,
// rows streamed.  The charges through resistors, inductors and sources are integrals of their currents,
// carried by the same Krylov basis.  Its own initial state (the dense route's is exact and ≤ 60
// branches): the DC operating point by contraction (inductors shorted, capacitors open), or the IC=
// values moved onto M_c(0+) by conservation of every supernode's charge and of the flux linkages
// outside the LI cutsets.
#include "exosystem.hpp"
#include "simulate.hpp"
#include "sparse_flow.hpp"

#include "dcad/fast/expv.hpp"
#include "dcad/fast/rlc_sparse.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/forced.hpp"

#include <charconv>
#include <cmath>
#include <map>

namespace dcad::api {

namespace {

rlc::Kind kind_of(reference::RlcKind k) {
  switch (k) {
    case reference::RlcKind::inductor: return rlc::Kind::inductor;
    case reference::RlcKind::capacitor: return rlc::Kind::capacitor;
    case reference::RlcKind::resistor: return rlc::Kind::resistor;
    case reference::RlcKind::voltage: return rlc::Kind::voltage;
    case reference::RlcKind::current: return rlc::Kind::current;
    default: return rlc::Kind::wire;
  }
}

/// Geometric mean of the values of a kind (0: none).
double typical(const sr::Network& c, rlc::Kind k) {
  double s = 0;
  int n = 0;
  for (const sr::Element& b : c.branches)
    if (b.kind == k) s += std::log(b.value), ++n;
  return n ? std::exp(s / n) : 0.0;
}

}  // namespace

sr::Network circuit_of(const io::Netlist& d) {
  sr::Network c;
  c.nodes = d.rlc.nodes;
  c.sources = static_cast<std::size_t>(d.rlc.sources);
  c.node_names = d.node_names;
  for (const auto& b : d.rlc.branches) {
    c.branches.push_back({kind_of(b.kind), b.from, b.to, b.value.convert_to<double>(), static_cast<long>(b.source)});
    c.branch_names.push_back(b.name);
  }
  for (const auto& mu : d.rlc.mutuals)
    c.mutuals.push_back({static_cast<std::size_t>(mu.a), static_cast<std::size_t>(mu.b), mu.m.convert_to<double>()});
  return c;
}

namespace {

/// Union–find over the nodes (ground −1 is node `nodes`).
struct Components {
  std::vector<std::size_t> up;
  explicit Components(std::size_t n) : up(n + 1) {
    for (std::size_t i = 0; i <= n; ++i) up[i] = i;
  }
  static std::size_t at(long node, std::size_t n) { return node < 0 ? n : static_cast<std::size_t>(node); }
  std::size_t root(std::size_t i) {
    while (up[i] != i) i = up[i] = up[up[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { up[root(a)] = root(b); }
};

/// The branches that are no bridge of the subgraph `in` (they lie on a loop of it): Tarjan's lowlink,
/// iterative, parallel branches told apart by their index.
std::vector<bool> on_loops(const sr::Network& c, const std::vector<bool>& in) {
  const std::size_t n = c.nodes + 1, nb = c.branches.size();
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> adj(n);  // (other node, branch)
  for (std::size_t b = 0; b < nb; ++b)
    if (in[b]) {
      const std::size_t u = Components::at(c.branches[b].from, c.nodes), v = Components::at(c.branches[b].to, c.nodes);
      adj[u].push_back({v, b});
      adj[v].push_back({u, b});
    }
  std::vector<long> disc(n, -1), low(n, 0);
  std::vector<bool> bridge(nb, false);
  long clock = 0;
  struct Frame {
    std::size_t node, via, next;
  };
  for (std::size_t s = 0; s < n; ++s) {
    if (disc[s] >= 0) continue;
    std::vector<Frame> stack{{s, nb, 0}};
    disc[s] = low[s] = clock++;
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next < adj[f.node].size()) {
        const auto [w, b] = adj[f.node][f.next++];
        if (b == f.via) continue;
        if (disc[w] < 0) {
          disc[w] = low[w] = clock++;
          stack.push_back({w, b, 0});
        } else {
          low[f.node] = std::min(low[f.node], disc[w]);
        }
        continue;
      }
      const Frame done = f;
      stack.pop_back();
      if (!stack.empty()) {
        Frame& parent = stack.back();
        low[parent.node] = std::min(low[parent.node], low[done.node]);
        if (low[done.node] > disc[parent.node]) bridge[done.via] = true;
      }
    }
  }
  std::vector<bool> out(nb, false);
  for (std::size_t b = 0; b < nb; ++b) out[b] = in[b] && !bridge[b];
  return out;
}

}  // namespace

std::vector<bool> jump_places(const sr::Network& c) {
  const std::size_t nb = c.branches.size();
  std::vector<bool> cv(nb), out(nb, false);
  for (std::size_t b = 0; b < nb; ++b) {
    const rlc::Kind k = c.branches[b].kind;
    cv[b] = k == rlc::Kind::capacitor || k == rlc::Kind::voltage || k == rlc::Kind::wire;
  }
  const std::vector<bool> loop = on_loops(c, cv);
  Components rest(c.nodes);  // the branches that are neither inductors nor current sources
  for (const sr::Element& e : c.branches)
    if (e.kind != rlc::Kind::inductor && e.kind != rlc::Kind::current)
      rest.join(Components::at(e.from, c.nodes), Components::at(e.to, c.nodes));
  for (std::size_t b = 0; b < nb; ++b) {
    const sr::Element& e = c.branches[b];
    if (e.kind == rlc::Kind::capacitor) out[b] = loop[b];
    if (e.kind == rlc::Kind::inductor)
      out[b] = rest.root(Components::at(e.from, c.nodes)) != rest.root(Components::at(e.to, c.nodes));
  }
  return out;
}

bool sparse_route_takes(const io::Netlist& deck) { return reference::pipeline::graph_route_holds(deck.rlc); }

SparseFlow::SparseFlow(const io::Netlist& deck, const std::string& file, Initial initial, double step, double horizon,
                       std::ostream& log)
    : deck_(deck), file_(file), step_(step) {
  namespace pl = reference::pipeline;
  if (const auto which = io::without_exact_flow(deck.waveforms))
    throw io::InputError(file + ": expected continuous sources with a finite exosystem for the exact flow, found " +
                         *which);
  if (!pl::graph_route_holds(deck.rlc))
    throw io::InputError(file +
                         ": simulate: expected every R, L and C positive, the couplings |k| < 1 and at most 200 "
                         "inductors per coupled group "
                         "for the sparse route, found another circuit"
                         " (the dense route takes it up to " +
                         std::to_string(pl::kForcedBranches) + " branches)");
  const pl::GraphForced g = pl::graph_forced(deck);
  for (const SourceCondition& v : g.conditions)
    if (v.holds.no())
      throw io::InputError(deck.file + ": simulate: expected a consistent circuit, found the source condition " +
                           v.text + " violated (" + v.evidence + ")");
  if (!g.consistent) throw io::InputError(deck.file + ": simulate: expected a consistent circuit, found M_c empty");
  if (g.solution_rank > 0)
    log << "note: solutions are not unique (" << g.solution_rank
        << " free currents around loops of voltage sources and wires); simulating the one with no current around "
           "them\n";
  circ_ = circuit_of(deck);
  try {
    model_ = std::make_unique<sr::Model>(circ_);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(file + ": simulate: expected values within double's range for the sparse route, found " +
                         e.what());
  }
  const std::size_t n = circ_.branches.size(), m = circ_.sources;
  nx_ = model_->state_size();
  const std::size_t nq = model_->charge_size(), ny = nx_ + 3 * m;
  log << "simulate: sparse route (" << nx_ << " states, " << model_->islands()
      << " LI cutsets; Krylov exponential action, Expokit's error control)\n";
  // sources at 0 (right limits)
  std::vector<double> s0(m), ds0(m);
  for (std::size_t j = 0; j < m; ++j) s0[j] = deck.waveforms[j].value(0, 0), ds0[j] = deck.waveforms[j].value(0, 1);
  // initial state
  const bool op = initial == Initial::op || (initial == Initial::deck && deck.tran == io::Netlist::Transient::op);
  Vec x;
  q_ = Vec::Zero(static_cast<Eigen::Index>(nq));
  if (op) {
    std::vector<std::pair<long, double>> held;
    for (const auto& [node, value] : deck.node_ic) held.emplace_back(node, value.convert_to<double>());
    log << "initial state: op: the DC operating point at t = 0 (capacitors open, inductors shorted), by contraction on "
           "the sparse route"
        << (held.empty() ? "" : ", the .ic node voltages held as ngspice holds them") << "\n";
    try {
      try {
        x = model_->operating_point(s0.data(), held);
      } catch (const std::domain_error& e) {
        if (held.empty() || std::string(e.what()).rfind(".ic", 0) != 0) throw;
        log << "note: " << e.what()
            << ": the operating point does not hold the .ic node voltages (as the dense route)\n";
        x = model_->operating_point(s0.data());
      }
    } catch (const std::domain_error& e) {
      throw io::InputError(file + ": initial state: expected a unique DC operating point, found " + e.what() +
                           "; use --initial uic");
    }
  } else {
    log << "initial state: uic: IC= values, everything else 0; moved onto M_c(0+) keeping every supernode's charge and "
           "the flux linkages "
           "outside cutsets of inductors and current sources\n";
    Vec qb = Vec::Zero(static_cast<Eigen::Index>(n)), ib = Vec::Zero(static_cast<Eigen::Index>(n));
    for (std::size_t b = 0; b < n; ++b) {
      if (!deck.initial[b]) continue;
      if (circ_.branches[b].kind == rlc::Kind::capacitor)
        qb(static_cast<Eigen::Index>(b)) = (deck.rlc.branches[b].value * *deck.initial[b]).convert_to<double>();
      if (circ_.branches[b].kind == rlc::Kind::inductor)
        ib(static_cast<Eigen::Index>(b)) = deck.initial[b]->convert_to<double>();
    }
    x = model_->from_charges(qb, ib, s0.data());
    // the jumps, each named with the kind of constraint that forced it
    const Vec zero = Vec::Zero(static_cast<Eigen::Index>(nq));
    const sr::BranchValues after = model_->values(x.data(), zero.data(), s0.data(), ds0.data());
    double qscale = 0, iscale = 0;
    for (std::size_t b = 0; b < n; ++b) {
      const auto bb = static_cast<Eigen::Index>(b);
      if (circ_.branches[b].kind == rlc::Kind::capacitor)
        qscale = std::max({qscale, std::abs(qb(bb)), std::abs(after.q(bb))});
      if (circ_.branches[b].kind == rlc::Kind::inductor)
        iscale = std::max({iscale, std::abs(ib(bb)), std::abs(after.i(bb))});
    }
    long told = 0;
    const std::vector<bool> movable =
        jump_places(circ_);  // a branch no loop or cutset can move keeps its value exactly
    for (std::size_t b = 0; b < n; ++b) {
      const auto bb = static_cast<Eigen::Index>(b);
      const bool cap = circ_.branches[b].kind == rlc::Kind::capacitor,
                 ind = circ_.branches[b].kind == rlc::Kind::inductor;
      if ((!cap && !ind) || !movable[b]) continue;
      const double from = cap ? qb(bb) : ib(bb), to = cap ? after.q(bb) : after.i(bb), scale = cap ? qscale : iscale;
      if (std::abs(to - from) <= 1e-12 * scale) continue;
      ++jumps_;
      jumped_.push_back((cap ? "q_" : "v_") + circ_.branch_names[b]);
      if (told++ < 20)
        log << "jump at t = 0: " << (cap ? "q_" : "v_") << circ_.branch_names[b] << " from " << io::float_text(from)
            << " to " << io::float_text(to) << ", forced by "
            << (cap ? "KVL around a loop of capacitors and voltage sources (the charge of each node is kept)"
                    : "KCL over a cutset of inductors and current sources (the flux linkages move only by impulses at "
                      "its level)")
            << "\n";
    }
    if (jumps_ > told) log << "jump at t = 0: … and " << (jumps_ - told) << " more values\n";
    q_ = model_->impulse_charges(qb, after.q);  // what the impulsive currents carried through the sources
  }
  // scales of the Krylov state: √energy for the circuit, the sources' values in the same units
  const double ctyp = typical(circ_, rlc::Kind::capacitor), ltyp = typical(circ_, rlc::Kind::inductor),
               rtyp = typical(circ_, rlc::Kind::resistor);
  // a circuit without inductors (or capacitors) takes the missing kind from its resistance, or without
  // resistors from the output step (R = step/C, L = step²/C): a fixed 1 Ω would put a current source
  // driving a 1 fF capacitor 10⁷ below the charge it moves in a step, and the error control (relative to
  // the state's norm) would let the Krylov basis drop what the source is about to carry
  const double cs = ctyp > 0 ? ctyp : ltyp > 0 ? ltyp / (rtyp > 0 ? rtyp * rtyp : ltyp * ltyp / (step * step)) : 1.0;
  const double ls = ltyp > 0 ? ltyp : cs * (rtyp > 0 ? rtyp * rtyp : ctyp > 0 ? step * step / (ctyp * ctyp) : 1.0);
  d_.resize(static_cast<Eigen::Index>(ny));
  d_.head(static_cast<Eigen::Index>(nx_)) = model_->energy_scale();
  std::vector<bool> current(m, false);
  for (const sr::Element& b : circ_.branches)
    if (b.kind == rlc::Kind::current) current[static_cast<std::size_t>(b.source)] = true;
  for (std::size_t j = 0; j < m; ++j) {
    const double sc = std::sqrt(current[j] ? ls : cs);
    d_(static_cast<Eigen::Index>(nx_ + 3 * j)) = sc;
    d_(static_cast<Eigen::Index>(nx_ + 3 * j + 1)) =
        deck.waveforms[j].is_sine() || deck.waveforms[j].is_exp() ? sc : sc * step;
    d_(static_cast<Eigen::Index>(nx_ + 3 * j + 2)) = sc;
  }
  for (Eigen::Index i = 0; i < d_.size(); ++i)
    if (!(d_(i) > 0) || !std::isfinite(d_(i))) d_(i) = 1;
  dinv_ = d_.cwiseInverse();
  // the operator on the scaled state [x; exosystem]: the circuit's rate and the sources' generator
  const auto op_fn = [this, m](const Vec& v, Vec& y, Vec* side) {
    Vec u = v.cwiseProduct(dinv_);
    std::vector<double> sig(m), dsig(m);
    y.resize(v.size());
    for (std::size_t j = 0; j < m; ++j) {
      exo_output(deck_.waveforms[j], u.data() + nx_ + 3 * j, sig[j], dsig[j]);
      exo_rate(deck_.waveforms[j], u.data() + nx_ + 3 * j, y.data() + nx_ + 3 * j);
    }
    model_->rate(u.data(), sig.data(), dsig.data(), y.data(), side ? side->data() : nullptr);
    y = y.cwiseProduct(d_);
  };
  krylov_ = std::make_unique<fast::KrylovExp>(op_fn, nq);
  for (const io::Waveform& w : deck.waveforms) try {
      for (double b : w.breakpoints(horizon)) breaks_.push_back(b);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(file + ": simulate: expected at most " + std::to_string(io::Waveform::kMaxPeriods) +
                           " source periods, found " + e.what());
    }
  std::sort(breaks_.begin(), breaks_.end());
  breaks_.erase(std::unique(breaks_.begin(), breaks_.end()), breaks_.end());
  y_ = Vec::Zero(static_cast<Eigen::Index>(ny));
  y_.head(static_cast<Eigen::Index>(nx_)) = x.cwiseProduct(d_.head(static_cast<Eigen::Index>(nx_)));
}

SparseFlow::~SparseFlow() = default;

void SparseFlow::sources(double t, bool left, std::vector<double>& sig, std::vector<double>& dsig) const {
  const std::size_t m = circ_.sources;
  sig.resize(m);
  dsig.resize(m);
  // a left derivative: the slope just before t on the piece that ends there (sources are smooth between breakpoints)
  double before = t;
  if (left && t > 0) {
    const auto it = std::lower_bound(breaks_.begin(), breaks_.end(), t * (1 - 1e-12));
    const double prev = it == breaks_.begin() ? 0.0 : *(it - 1);
    before = t - std::min(1e-9 * (t - prev), 1e-9 * t);
  }
  for (std::size_t j = 0; j < m; ++j) {
    const io::Waveform& w = deck_.waveforms[j];
    dsig[j] = w.value(left ? before : t, 1);
    // the left value: the piece that ends at t carried to t (a PULSE cut by its PER steps there: ngspice
    // holds V2 at t = PER itself, value(t) is the next period's start)
    sig[j] = left && before < t ? w.value(before, 0) + dsig[j] * (t - before) : w.value(t, 0);
  }
  if (left && t <= 0)
    std::fill(dsig.begin(), dsig.end(), 0.0);  // before t = 0 the circuit rests at the sources' values at 0
}

sr::BranchValues SparseFlow::values(bool left) const {
  std::vector<double> sig, dsig;
  sources(t_, left, sig, dsig);
  const Vec xs = state();
  return model_->values(xs.data(), q_.data(), sig.data(), dsig.data());
}

Vec SparseFlow::node_potentials(bool left) const {
  std::vector<double> sig, dsig;
  sources(t_, left, sig, dsig);
  const Vec xs = state();
  return model_->node_potentials(xs.data(), sig.data(), dsig.data());
}

Vec SparseFlow::state() const {
  return y_.head(static_cast<Eigen::Index>(nx_)).cwiseProduct(dinv_.head(static_cast<Eigen::Index>(nx_)));
}

bool SparseFlow::corner(double t) const {
  const auto it = std::lower_bound(breaks_.begin(), breaks_.end(), t - 1e-12 * std::max(step_, std::abs(t)));
  return it != breaks_.end() && std::abs(*it - t) <= 1e-12 * std::max(step_, std::abs(t));
}

void SparseFlow::advance_to(double to) {
  const std::size_t m = circ_.sources;
  double at = t_;
  while (at < to) {
    while (next_break_ < breaks_.size() && breaks_[next_break_] <= at + 1e-12 * step_) ++next_break_;
    const double stop =
        next_break_ < breaks_.size() && breaks_[next_break_] < to - 1e-12 * step_ ? breaks_[next_break_] : to;
    for (std::size_t j = 0; j < m; ++j) {
      long double w[3];
      exo_state_for(deck_.waveforms[j], at, stop, w);
      for (int q = 0; q < 3; ++q)
        y_(static_cast<Eigen::Index>(nx_ + 3 * j + q)) =
            static_cast<double>(w[q]) * d_(static_cast<Eigen::Index>(nx_ + 3 * j + q));
    }
    const double norm = y_.norm();
    max_norm_ = std::max(max_norm_, norm);
    krylov_->set_tolerance(kSparseStepTolerance * std::max(norm, 1e-300) / step_);
    try {
      krylov_->advance(stop - at, y_, q_);
    } catch (const std::runtime_error& e) {
      throw io::InputError(
          file_ + ": simulate: expected a circuit the sparse route integrates in double, found none at t = " +
          io::float_text(at) + " s: " + e.what() +
          " (time scales far below --step, or values beyond double's range; the dense route takes up to " +
          std::to_string(reference::pipeline::kForcedBranches) + " branches)");
    }
    if (krylov_->error_estimate() > kSparseRefuse * max_norm_)
      throw io::InputError(
          file_ + ": simulate: expected an error estimate below " + io::float_text(kSparseRefuse) +
          " of the state, found " + io::float_text(krylov_->error_estimate() / max_norm_) +
          " at t = " + io::float_text(at) +
          " s: the circuit is stiff against --step (eps*|A|*step per step); the dense route takes up to " +
          std::to_string(reference::pipeline::kForcedBranches) + " branches");
    if (!y_.allFinite() || !q_.allFinite())
      throw io::InputError(file_ + ": simulate: expected a finite state, found an overflow at t = " +
                           io::float_text(at) + " s (a growing source or values beyond double's range)");
    at = stop;
  }
  t_ = std::max(t_, to);
}

double SparseFlow::error_estimate() const { return max_norm_ > 0 ? krylov_->error_estimate() / max_norm_ : 0.0; }
long SparseFlow::products() const { return krylov_->products(); }
long SparseFlow::substeps() const { return krylov_->substeps(); }

namespace {
/// The indices of `names` among c's variables (all `count` of them when none is named); UsageError for a name the
/// case does not have.
std::vector<std::size_t> columns_of(const io::CaseFile& c, const std::vector<std::string>& names, std::size_t count) {
  std::vector<std::size_t> cols;
  if (names.empty())
    for (std::size_t i = 0; i < count; ++i) cols.push_back(i);
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < c.variables.size(); ++i) index[c.variables[i]] = i;
  for (const std::string& name : names) {
    const auto it = index.find(name);
    if (it == index.end())
      throw UsageError("--vars: expected variables of " + c.file + " (q_*, v_*, p_*), found " + name);
    cols.push_back(it->second);
  }
  return cols;
}
}  // namespace

Summary simulate_sparse(const io::Netlist& deck, const io::CaseFile& c, const SimulateOptions& opt, RowSink& out,
                        std::ostream& log, std::ostream* energy) {
  require_times(opt);
  SparseFlow flow(deck, c.file, opt.initial, opt.step, opt.tstop, log);
  const sr::Network& circ = flow.network();
  const std::size_t n = circ.branches.size();
  const std::vector<std::size_t> cols = columns_of(c, opt.columns, 3 * n);
  std::vector<std::string> names = {"t"};
  for (std::size_t i : cols) names.push_back(c.variables[i]);
  out.header(names);
  EnergyCsv energy_csv(energy);
  std::vector<double> row;
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  double wr = 0, wv = 0, wi = 0, lr = 0, lv = 0, li = 0, worst_balance = 0, power_scale = 0, e0 = 0;
  for (long k = 0; k <= steps; ++k) {
    const double t = static_cast<double>(k) * opt.step;
    flow.advance_to(t);
    const sr::BranchValues bv = flow.values();
    row.assign(1, t);
    for (std::size_t i : cols) {
      const auto b = static_cast<Eigen::Index>(i % n);
      row.push_back(i < n ? bv.q(b) : i < 2 * n ? bv.i(b) : bv.p(b));
    }
    out.row(row);
    // energy: E = ½ Σ q_C²/C + ½ i_Lᵀ Φ i_L; the forces', sources' and constraints' powers
    double en = 0, pr = 0, pv = 0, pi = 0, tell = 0, mag = 0;
    for (std::size_t b = 0; b < n; ++b) {
      const auto bb = static_cast<Eigen::Index>(b);
      const double ui = bv.u(bb) * bv.i(bb);
      tell += ui;
      mag = std::max(mag, std::abs(ui));
      switch (circ.branches[b].kind) {
        case rlc::Kind::capacitor: en += 0.5 * bv.q(bb) * bv.u(bb); break;
        case rlc::Kind::inductor: en += 0.5 * bv.p(bb) * bv.i(bb); break;
        case rlc::Kind::resistor: pr -= ui; break;
        case rlc::Kind::voltage: pv -= ui; break;
        case rlc::Kind::current: pi -= ui; break;
        default: break;
      }
    }
    power_scale = std::max(power_scale, mag);
    worst_balance = std::max(worst_balance, std::abs(tell));
    if (k == 0) e0 = en;
    if (k > 0) wr += opt.step * (pr + lr) / 2, wv += opt.step * (pv + lv) / 2, wi += opt.step * (pi + li) / 2;
    lr = pr, lv = pv, li = pi;
    energy_csv.row(t, en, pr, pv, pi, wr, wv, wi);
    if (k == steps)
      log << "simulate: energy: E(0) = " << io::float_text(e0) << ", E(" << io::float_text(t)
          << ") = " << io::float_text(en) << "; work of the forces " << io::float_text(wr) << " (dissipated "
          << io::float_text(-wr) << "), of the sources " << io::float_text(wv) << ", of the current sources "
          << io::float_text(wi) << " (trapezoid on the output rows); Tellegen's sum of u·i over the branches is "
          << io::float_text(power_scale > 0 ? worst_balance / power_scale : 0.0)
          << " of the largest branch power at the rows\n";
  }
  if (flow.error_estimate() > kSparseWarn)
    log << "warning: the sparse route's error estimate is " << io::float_text(flow.error_estimate())
        << " of the state: the circuit is stiff against --step (the Krylov matrix's rounding, eps*|A|*step, "
           "dominates); "
           "small variables may be far off — compare with --route dense (up to "
        << reference::pipeline::kForcedBranches << " branches)\n";
  Summary s;
  s.rows = steps + 1;
  s.error_estimate = flow.error_estimate();
  s.worst_variable = "the state";
  s.estimate_kind =
      "the Krylov integrator's local error estimates summed over the run (Expokit), relative to the largest norm of "
      "the state in "
      "energy units; " +
      std::to_string(flow.products()) + " operator products in " + std::to_string(flow.substeps()) + " substeps";
  return s;
}

}  // namespace dcad::api
