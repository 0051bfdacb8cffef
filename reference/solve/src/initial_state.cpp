#include "dcad/reference/pipeline/initial_state.hpp"

#include "dcad/io/input_error.hpp"
#include "dcad/io/report.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/rlc.hpp"

namespace dcad::reference::pipeline {

using Q = Rational;
using QM = Matrix<Q>;

namespace {

/// σ^{(order)}(0+), exactly where rational, else rounded once (a SIN's jets involve π).
Q jet_at_zero(const io::Waveform& w, int order) {
  if (const std::optional<Q> e = w.exact_at_zero(order)) return *e;
  return Q(w.value(0.0, order));
}

/// The point of the affine subspace s nearest to `target` (exact least squares along its directions).
std::vector<Q> nearest(const AffineSubspace<Q>& s, const std::vector<Q>& target) {
  std::vector<Q> x = s.point;
  const QM& d = s.direction.basis();  // one direction per row
  if (d.rows() == 0) return x;
  std::vector<Q> diff(x.size());
  for (Index i = 0; i < x.size(); ++i) diff[i] = target[i] - x[i];
  const QM moved = d.transpose() * (inverse(d * d.transpose()) * (d * QM::column(diff)));
  for (Index i = 0; i < x.size(); ++i) x[i] += moved(i, 0);
  return x;
}

/// One row [a | b] of {a y = b}, y of width `w`.
struct Rows {
  QM m;
  std::vector<std::string> what;
  explicit Rows(Index w) : m(0, w + 1) {}
  void add(const QM& row, std::string why) {
    m = vstack(m, row);
    what.push_back(std::move(why));
  }
};

/// The first row of `rows` after which {a y = b} is empty (rows in order).
std::size_t first_inconsistent(const Rows& rows, const QM& fixed) {
  for (Index i = 0; i < rows.m.rows(); ++i)
    if (affine_from_augmented(vstack(fixed, rows.m.block(0, i + 1, 0, rows.m.cols()))).empty) return i;
  return rows.m.rows();
}

std::string node_name(const io::Netlist& d, long k) { return k < 0 ? "0" : d.node_names[k]; }

/// The DC equations in y = (e, i): KCL at every node (or, with `hold`, e_k = value at a node `.ic` holds)
/// and each branch's law with capacitors open, inductors shorted and the sources at t = 0.
Rows dc_equations(const io::Netlist& d, const std::vector<bool>& held_node, bool hold) {
  const RlcCircuit<Q>& c = d.rlc;
  const Index n = c.branches.size(), nodes = c.nodes, w = nodes + n;
  Rows rows(w);
  for (Index k = 0; k < nodes; ++k) {  // KCL
    QM r(1, w + 1);
    if (hold && held_node[k]) {
      r(0, k) = Q(1);
      for (const auto& [node, v] : d.node_ic)
        if (node == static_cast<long>(k)) r(0, w) = v;
      rows.add(r, ".ic v(" + d.node_names[k] + ")");
      continue;
    }
    for (Index b = 0; b < n; ++b) {
      if (c.branches[b].from == static_cast<long>(k)) r(0, nodes + b) += Q(1);
      if (c.branches[b].to == static_cast<long>(k)) r(0, nodes + b) -= Q(1);
    }
    rows.add(r, "KCL at node " + d.node_names[k]);
  }
  for (Index b = 0; b < n; ++b) {
    const RlcBranch<Q>& br = c.branches[b];
    QM r(1, w + 1);
    const auto potential_difference = [&] {  // u_b = e_from − e_to
      if (br.from >= 0) r(0, br.from) += Q(1);
      if (br.to >= 0) r(0, br.to) -= Q(1);
    };
    switch (br.kind) {
      case RlcKind::capacitor:
        r(0, nodes + b) = Q(1);
        rows.add(r, br.name + " open at DC: i = 0");
        break;
      case RlcKind::inductor:
        potential_difference();
        rows.add(r, br.name + " shorted at DC: u = 0");
        break;
      case RlcKind::wire:
        potential_difference();
        rows.add(r, br.name + ": u = 0");
        break;
      case RlcKind::resistor:
        potential_difference();
        r(0, nodes + b) = -br.value;
        rows.add(r, br.name + ": u = R i");
        break;
      case RlcKind::voltage:
        potential_difference();
        r(0, w) = jet_at_zero(d.waveforms[br.source], 0);
        rows.add(r, br.name + ": u = " + r(0, w).str() + " V at t = 0");
        break;
      case RlcKind::current:
        r(0, nodes + b) = Q(1);
        r(0, w) = jet_at_zero(d.waveforms[br.source], 0);
        rows.add(r, br.name + ": i = " + r(0, w).str() + " A at t = 0");
        break;
    }
  }
  return rows;
}

/// The DC operating point: charges, currents and flux linkages (q, v, p).  [CONTRACT]
std::vector<Q> operating_point(const io::Netlist& d, InitialState& s) {
  const RlcCircuit<Q>& c = d.rlc;
  const Index n = c.branches.size(), nodes = c.nodes, w = nodes + n;  // y = (e, i)
  // `.ic` holds its nodes as ngspice does, through a source: KCL at a held node is that source's
  // business, so its row is replaced by e_k = value (tried without the holding if they contradict)
  std::vector<bool> held_node(nodes, false);
  for (const auto& [k, v] : d.node_ic) held_node[k] = true;
  Rows rows = dc_equations(d, held_node, true);
  AffineSubspace<Q> sol = affine_from_augmented(rows.m);
  if (sol.empty && !d.node_ic.empty()) {
    s.notes.push_back(
        "the .ic node voltages contradict the circuit at DC (ideal sources or shorts between them): the operating "
        "point does not hold them");
    rows = dc_equations(d, held_node, false);
    sol = affine_from_augmented(rows.m);
  }
  if (sol.empty)
    throw io::InputError(
        d.file +
        ": initial state: expected a DC operating point at t = 0 (capacitors open, inductors shorted), found none: " +
        rows.what[first_inconsistent(rows, QM(0, w + 1))] + " contradicts the equations before it");
  if (sol.direction.dim() > 0)
    s.notes.push_back(
        "the DC operating point is not unique (" + std::to_string(sol.direction.dim()) +
        " free: floating nodes or loops of inductors, wires and voltage sources); its free parts are taken as small as "
        "possible (ngspice reports a singular matrix)");
  const std::vector<Q> y = nearest(sol, std::vector<Q>(w, Q(0)));
  std::vector<Q> x(3 * n, Q(0)), i(n);
  for (Index b = 0; b < n; ++b) {
    const RlcBranch<Q>& br = c.branches[b];
    i[b] = y[nodes + b];
    x[n + b] = i[b];
    if (br.kind == RlcKind::capacitor) {
      const Q u = (br.from >= 0 ? y[br.from] : Q(0)) - (br.to >= 0 ? y[br.to] : Q(0));
      x[b] = br.value * u;
    }
  }
  const QM p = rlc_inductance(c) * QM::column(i);
  for (Index b = 0; b < n; ++b) x[2 * n + b] = p(b, 0);
  return x;
}

/// uic: IC= values (capacitor voltages, inductor currents; `.ic` gave the capacitors between held
/// nodes theirs), everything else 0.
std::vector<Q> use_initial_conditions(const io::Netlist& d) {
  const RlcCircuit<Q>& c = d.rlc;
  const Index n = c.branches.size();
  std::vector<Q> x(3 * n, Q(0)), i(n, Q(0));
  for (Index b = 0; b < n; ++b) {
    if (!d.initial[b]) continue;
    if (c.branches[b].kind == RlcKind::capacitor) x[b] = c.branches[b].value * *d.initial[b];
    if (c.branches[b].kind == RlcKind::inductor) x[n + b] = i[b] = *d.initial[b];
  }
  const QM p = rlc_inductance(c) * QM::column(i);
  for (Index b = 0; b < n; ++b) x[2 * n + b] = p(b, 0);
  return x;
}

std::string row_text(const QM& eq, Index i, Index n, const std::vector<std::string>& names) {
  Equation<std::string> e;
  for (Index j = 0; j < eq.cols(); ++j)
    if (j != n && eq(i, j) != 0) e.terms.emplace_back(j < n ? j : j - 1, eq(i, j).str());
  e.rhs = Q(-eq(i, n)).str();
  return io::equation_text(e, names);
}

/// The jump onto M_c(0+) from x⁻ (see the header).
void jump(const io::Netlist& d, const std::vector<std::string>& variables, InitialState& s) {
  const RlcCircuit<Q>& c = d.rlc;
  const Index n = c.branches.size(), nx = 3 * n, m = c.sources;
  const ForcedSystem<Q> f = rlc_system(c);
  const ForcedResult<Q> r = forced_tower(f);
  if (!r.consistent)
    throw io::InputError(d.file + ": initial state: M_c is empty whatever the sources are: nothing to start from");
  std::vector<Q> u{Q(1)};  // (1, σ⁽⁰⁾(0+), σ⁽¹⁾(0+), …)
  for (Index k = 0; k < r.orders; ++k)
    for (Index j = 0; j < m; ++j) u.push_back(jet_at_zero(d.waveforms[j], static_cast<int>(k)));
  Rows mc(nx);  // M_c(0+): E x = −(jet part)
  std::vector<std::string> names = variables;
  const std::vector<std::string> jets = jet_names(d.waveforms, static_cast<long>(r.orders));
  names.insert(names.end(), jets.begin() + 1, jets.end());
  for (Index i = 0; i < r.equations.rows(); ++i) {
    QM row(1, nx + 1);
    for (Index j = 0; j < nx; ++j) row(0, j) = r.equations(i, j);
    for (Index j = 0; j < u.size() && nx + j < r.equations.cols(); ++j) row(0, nx) -= r.equations(i, nx + j) * u[j];
    mc.add(row, row_text(r.equations, i, nx, names));
  }
  // The impulses (integrals over the instant t = 0) circuit theory allows [CONTRACT]:
  //   currents: Δq ∈ Δ = ker K_I (KCL; a current source's current is bounded), and Δq_L = 0 (an
  //     inductor's current i = Φ⁻¹p stays bounded);
  //   voltages: w ∈ Δ° = row K_I (KVL; a current source takes any voltage) where w is each branch's
  //     voltage impulse — Δp on inductors, R Δq on resistors, 0 on capacitors, sources and wires
  //     (bounded voltages) — i.e. d · w = 0 for every d in a basis of Δ.
  QM ki, ri;
  affine_kcl(c, ki, ri);
  const QM delta = nullspace(ki);  // rows: a basis of Δ
  QM impulses(0, nx + 1);
  const auto fix = [&](const QM& coeffs_q, const QM& coeffs_p, Index i) {  // Σ a (q⁺ − q⁻) + Σ b (p⁺ − p⁻) = 0
    QM row(1, nx + 1);
    for (Index b = 0; b < n; ++b) {
      row(0, b) = coeffs_q(i, b);
      row(0, 2 * n + b) = coeffs_p(i, b);
      row(0, nx) += coeffs_q(i, b) * s.before[b] + coeffs_p(i, b) * s.before[2 * n + b];
    }
    impulses = vstack(impulses, row);
  };
  const QM none(std::max<Index>(ki.rows(), std::max<Index>(delta.rows(), n)), n);
  for (Index i = 0; i < ki.rows(); ++i) fix(ki, none, i);
  QM inductor(n, n), wq(delta.rows(), n), wp(delta.rows(), n);
  for (Index b = 0; b < n; ++b) {
    const RlcBranch<Q>& br = c.branches[b];
    if (br.kind == RlcKind::inductor) inductor(b, b) = Q(1);
    for (Index i = 0; i < delta.rows(); ++i) {
      if (br.kind == RlcKind::inductor) wp(i, b) = delta(i, b);
      if (br.kind == RlcKind::resistor) wq(i, b) = delta(i, b) * br.value;
    }
  }
  for (Index b = 0; b < n; ++b)
    if (c.branches[b].kind == RlcKind::inductor) fix(inductor, none, b);
  for (Index i = 0; i < delta.rows(); ++i) fix(wq, wp, i);
  const AffineSubspace<Q> reach = affine_from_augmented(vstack(impulses, mc.m));
  if (reach.empty)
    throw io::InputError(
        d.file +
        ": initial state: expected a jump onto M_c at t = 0 that impulsive currents (KCL) and voltages (KVL) can make, "
        "found none: no impulse satisfies " +
        mc.what[first_inconsistent(mc, impulses)] + " (ideal sources or constraints that disagree at t = 0)");
  s.after = nearest(reach, s.before);
  const auto violated = [&](Index var) {  // an equation of M_c(0+) that x⁻ violates, through var if one does
    std::string any;
    for (Index i = 0; i < mc.m.rows(); ++i) {
      Q lhs(0);
      for (Index j = 0; j < nx; ++j) lhs += mc.m(i, j) * s.before[j];
      if (lhs == mc.m(i, nx)) continue;
      if (mc.m(i, var) != 0) return mc.what[i];
      if (any.empty()) any = mc.what[i];
    }
    return any.empty() ? std::string("(none: moved with a coupled variable)") : any;
  };
  for (Index v = 0; v < nx; ++v) {
    const bool state =
        v < n || v >= 2 * n || c.branches[v - n].kind == RlcKind::inductor;  // q, p and inductor currents
    if (state && s.after[v] != s.before[v]) s.jumps.push_back({variables[v], s.before[v], s.after[v], violated(v)});
  }
}

}  // namespace

InitialState initial_state(const io::Netlist& d, InitialRule rule, const std::vector<std::string>& variables) {
  InitialState s;
  using T = io::Netlist::Transient;
  const bool op = rule == InitialRule::op || (rule == InitialRule::deck && d.tran == T::op);
  s.rule = rule == InitialRule::op    ? "the DC operating point (--initial op)"
           : rule == InitialRule::uic ? "uic: IC= and .ic values, everything else 0 (--initial uic)"
           : d.tran == T::op          ? "the DC operating point (.tran without uic at " + d.tran_where + ")"
           : d.tran == T::uic ? "uic: IC= and .ic values, everything else 0 (.tran … uic at " + d.tran_where + ")"
                              : "uic: IC= and .ic values, everything else 0 (no .tran card)";
  const std::size_t n = d.rlc.branches.size();
  const bool dense = n <= kForcedBranches;
  if (!dense) {  // larger decks: LC ones only reach simulate; their operating point without .ic is 0
    if (op && (!d.node_ic.empty() || d.rlc.sources > 0))
      throw io::InputError(d.file + ": initial state: expected at most " + std::to_string(kForcedBranches) +
                           " branches for a DC operating point with sources or .ic voltages, found " +
                           std::to_string(n) + " (use --initial uic, or .tran … uic)");
    s.before = op ? std::vector<Q>(3 * n, Q(0)) : use_initial_conditions(d);
    s.after = s.before;
    s.computed = false;
    s.notes.push_back("beyond " + std::to_string(kForcedBranches) +
                      " branches the state is not moved onto M_c: it must lie on it");
    return s;
  }
  s.before = op ? operating_point(d, s) : use_initial_conditions(d);
  jump(d, variables, s);
  return s;
}

}  // namespace dcad::reference::pipeline
