// The exact motion of an RLC circuit reduced from its state equations: see rlc_motion.hpp.
#include "dcad/reference/pipeline/rlc_motion.hpp"

#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/rlc_state.hpp"

#include <map>
#include <string>
#include <utility>

namespace dcad::reference::pipeline {

namespace {

using Q = Rational;
using QM = Matrix<Q>;

QM block(const StateEquations<Q>& s, const std::string& name) {
  for (const auto& [n, b] : s.blocks)
    if (n == name) {
      QM m(static_cast<Index>(b.rows), static_cast<Index>(b.cols));
      for (const auto& [i, j, v] : b.entries) m(static_cast<Index>(i), static_cast<Index>(j)) = v;
      return m;
    }
  throw std::logic_error("state_motion: no block " + name);
}

/// X with A X = B; A is one of C_ww, G_ρρ, Φ, S (positive definite where the graph route holds).
QM solve(const QM& a, const QM& b) {
  if (a.rows() == 0) return QM(0, b.cols());
  QM x;
  if (!solve_particular(a, b, x) || rank(a) != a.rows())
    throw std::logic_error("state_motion: a block expected positive definite is singular");
  return x;
}

/// Rows over the core coordinates (w, i_L, 1, σ, σ̇) of the header comment, and their layout.
struct Core {
  std::size_t nw = 0, nl = 0, m = 0;
  std::size_t ns() const { return nw + nl; }
  std::size_t nu() const { return 1 + 2 * m; }
  std::size_t nx() const { return ns() + nu(); }
  std::size_t one() const { return ns(); }
  std::size_t sigma(std::size_t j) const { return ns() + 1 + j; }
  std::size_t dsigma(std::size_t j) const { return ns() + 1 + m + j; }
  std::size_t ddsigma(std::size_t j) const { return ns() + 1 + 2 * m + j; }  ///< in the extended rows only
  /// `h` (rows × m) placed in the columns of σ (offset 0) or σ̇ (offset 1).
  QM place(const QM& h, std::size_t order) const {
    QM out(h.rows(), nx());
    for (Index i = 0; i < h.rows(); ++i)
      for (Index j = 0; j < h.cols(); ++j) out(i, order == 0 ? sigma(j) : dsigma(j)) = h(i, j);
    return out;
  }
  QM select(std::size_t from, std::size_t count) const {
    QM out(count, nx());
    for (std::size_t k = 0; k < count; ++k) out(k, from + k) = Q(1);
    return out;
  }
};

void add_row(QM& to, Index i, const QM& from, Index k, const Q& c) {
  if (c == 0) return;
  for (Index j = 0; j < from.cols(); ++j)
    if (from(k, j) != 0) to(i, j) += c * from(k, j);
}

}  // namespace

namespace {

/// Per branch, its voltage and current as rows over the core coordinates (capacitors i = C u̇, resistors
/// u / R, inductors and current sources their coordinates; voltage sources and wires by KCL at the child of
/// each forest edge, leaves first), the inductors' numbers and the branches whose charge is a state (every
/// non-capacitor).
struct BranchRows {
  QM volt, cur;
  std::vector<long> inductor;
  std::vector<std::size_t> charges;
};

BranchRows branch_rows(const RlcCircuit<Q>& c, const rlc::StateStructure& st, const Core& k, const QM& rho, const QM& e,
                       const QM& wdot) {
  const std::size_t nb = c.branches.size();
  BranchRows out{QM(nb, k.nx()), QM(nb, k.nx()), std::vector<long>(nb, -1), {}};
  QM &volt = out.volt, &cur = out.cur;
  std::vector<long>& inductor = out.inductor;
  long nl = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const RlcBranch<Q>& br = c.branches[b];
    const BranchPotential d = branch_potential(st, br.from, br.to);
    for (const auto& [i, sg] : d.w) volt(b, static_cast<Index>(i)) += Q(sg);
    for (const auto& [i, sg] : d.r) add_row(volt, b, rho, static_cast<Index>(i), Q(sg));
    for (const auto& [i, sg] : d.e) add_row(volt, b, e, static_cast<Index>(i), Q(sg));
    for (const auto& [j, sg] : d.o) volt(b, k.sigma(static_cast<std::size_t>(j))) += Q(sg);
    switch (br.kind) {
      case RlcKind::capacitor: {                     // i = C u̇ (both ends on one C-component: no ρ or e part)
        std::map<std::pair<char, long>, int> level;  // ρ and e parts: both ends' cancel (one C-component)
        for (const auto& [i, sg] : d.r) level[{'r', i}] += sg;
        for (const auto& [i, sg] : d.e) level[{'e', i}] += sg;
        for (const auto& [at, sum] : level)
          if (sum != 0) throw std::logic_error("state_motion: a capacitor whose ends lie on different levels");
        for (std::size_t i = 0; i < k.nw; ++i) add_row(cur, b, wdot, i, br.value * volt(b, i));
        for (std::size_t j = 0; j < k.m; ++j) cur(b, k.dsigma(j)) += br.value * volt(b, k.sigma(j));
        break;
      }
      case RlcKind::resistor: add_row(cur, b, volt, b, Q(1) / br.value); break;
      case RlcKind::inductor: cur(b, k.nw + static_cast<std::size_t>(nl)) = Q(1), inductor[b] = nl++; break;
      case RlcKind::current: cur(b, k.sigma(static_cast<std::size_t>(br.source))) = Q(1); break;
      default: break;  // voltage sources and wires: below
    }
    if (br.kind != RlcKind::capacitor) out.charges.push_back(b);
  }
  // voltage sources and wires: KCL at the child of each forest edge, leaves first
  QM net(c.nodes + 1, k.nx());
  for (std::size_t b = 0; b < nb; ++b) {
    const RlcKind kind = c.branches[b].kind;
    if (kind == RlcKind::voltage || kind == RlcKind::wire) continue;
    add_row(net, static_cast<Index>(c.branches[b].from + 1), cur, b, Q(1));
    add_row(net, static_cast<Index>(c.branches[b].to + 1), cur, b, Q(-1));
  }
  for (auto it = st.vtree.rbegin(); it != st.vtree.rend(); ++it) {
    const RlcBranch<Q>& br = c.branches[it->branch];
    const Index ch = static_cast<Index>(it->node + 1), pa = static_cast<Index>(it->parent + 1);
    add_row(cur, it->branch, net, ch, br.from == it->node ? Q(-1) : Q(1));
    add_row(net, pa, cur, it->branch, br.from == it->parent ? Q(1) : Q(-1));
  }
  return out;
}

/// e (the islands' levels, from their KCL through the inductors: L_e Φ⁻¹ (flux + L_eᵀ e) + I_e σ̇ = 0) and
/// i̇ = Φ⁻¹ (flux + L_eᵀ e), as rows over the core coordinates.
std::pair<QM, QM> island_levels_and_rates(const Core& k, QM flux, const QM& le, const QM& phi, const QM& ie_sigma) {
  QM e(0, k.nx());
  if (le.rows() > 0) {
    const QM s_mat = le * solve(phi, le.transpose());
    e = solve(s_mat, -(le * solve(phi, flux) + ie_sigma));
    flux = flux + le.transpose() * e;
  }
  return {e, solve(phi, flux)};
}

/// The state-equation model's preconditions: every R, L, C > 0, |k| < 1 and no rounded coupling, the source
/// conditions proved, M_c nonempty and the solution unique; std::invalid_argument saying which fails.
void require_state_model(const io::Netlist& deck) {
  const RlcCircuit<Q>& c = deck.rlc;
  if (!graph_route_holds(c))
    throw std::invalid_argument("the state-equation model (the enclosures' model beyond the dense one's " +
                                std::to_string(kForcedBranches) +
                                " branches) needs every R, L, C > 0 and couplings |k| < 1");
  if (rounded_coupling(c)) throw std::invalid_argument(kRoundedCoupling);
  const GraphForced g = graph_forced(deck);
  for (const SourceCondition& v : g.conditions)
    if (!v.holds.yes())
      throw std::invalid_argument("the source condition " + v.text + " is not proved to hold (" + v.evidence + ")");
  if (!g.consistent) throw std::invalid_argument("M_c is empty");
  if (g.solution_rank > 0)
    throw std::invalid_argument("the circuit's solutions are not unique (" + std::to_string(g.solution_rank) +
                                " free multipliers, a loop of voltage sources and wires)");
}

}  // namespace

StateMotion state_motion(const io::Netlist& deck) {
  const RlcCircuit<Q>& c = deck.rlc;
  require_state_model(deck);
  const StateEquations<Q> s = deck_state_equations<Q>(deck);
  const rlc::StateStructure st = state_structure(c);
  const QM Cww = block(s, "C_ww"), Gww = block(s, "G_ww"), Gwr = block(s, "G_wr"), Grr = block(s, "G_rr"),
           Lw = block(s, "L_w"), Lr = block(s, "L_r"), Le = block(s, "L_e"), Phi = block(s, "Phi"),
           Hw = block(s, "H_w"), Hwd = block(s, "H_wd"), Hr = block(s, "H_r"), Ie = block(s, "I_e"),
           Ol = block(s, "O_L");
  Core k{st.nw, Phi.rows(), c.sources};
  const QM W = k.select(0, k.nw), I = k.select(k.nw, k.nl);
  // ρ, ẇ, e, i̇ as rows over the core coordinates (the header's four solves)
  const QM rho = solve(Grr, -(Gwr.transpose() * W + Lr * I + k.place(Hr, 0)));
  const QM wdot = solve(Cww, -(Gww * W + Gwr * rho + Lw * I + k.place(Hw, 0) + k.place(Hwd, 1)));
  const std::pair<QM, QM> levels =
      island_levels_and_rates(k, Lw.transpose() * W + Lr.transpose() * rho + k.place(Ol, 0), Le, Phi, k.place(Ie, 1));
  const QM &e = levels.first, &idot = levels.second;  // (named: the lambdas below capture idot)
  // per branch: voltage, current (rows over the core coordinates); voltage sources and wires by KCL
  const std::size_t nb = c.branches.size();
  StateMotion out;
  const auto [volt, cur, inductor, charges] = branch_rows(c, st, k, rho, e, wdot);
  out.charges = charges;
  // y = (w, i_L, q_x): split a core row into its y part (w, i_L) and its u part
  out.nw = k.nw, out.nl = k.nl, out.nq = out.charges.size();
  const std::size_t dm = k.ns() + out.nq, nu = k.nu(), nue = 1 + 3 * k.m;
  const auto split = [&](const QM& from, Index row, QM& y, QM& u, Index at) {
    for (std::size_t j = 0; j < k.ns(); ++j) y(at, j) = from(row, j);
    for (std::size_t j = k.ns(); j < k.nx(); ++j) u(at, j - k.ns()) = from(row, j);
  };
  // d/dt of a core row, as an extended row (… , σ̈): w and i through ẇ and i̇, σ → σ̇, σ̇ → σ̈
  const auto deriv = [&](const QM& from, Index row, QM& y, QM& u, Index at) {
    QM r(1, k.nx() + k.m);
    for (std::size_t j = 0; j < k.nw; ++j) add_row(r, 0, wdot, j, from(row, j));
    for (std::size_t j = 0; j < k.nl; ++j) add_row(r, 0, idot, j, from(row, k.nw + j));
    for (std::size_t j = 0; j < k.m; ++j) {
      r(0, k.dsigma(j)) += from(row, k.sigma(j));
      r(0, k.ddsigma(j)) += from(row, k.dsigma(j));
    }
    for (std::size_t j = 0; j < k.ns(); ++j) y(at, j) = r(0, j);
    for (std::size_t j = k.ns(); j < k.nx() + k.m; ++j) u(at, j - k.ns()) = r(0, j);
  };
  out.bt = QM(3 * nb, dm), out.x0 = QM(3 * nb, nu), out.vy = QM(3 * nb, dm), out.vu = QM(3 * nb, nue);
  out.ay = QM(dm, dm), out.au = QM(dm, nue);
  QM flux_rows(nb, k.nx());  // p_b = (Φ i)_b on inductors
  for (std::size_t b = 0; b < nb; ++b)
    if (inductor[b] >= 0)
      for (std::size_t j = 0; j < k.nl; ++j) flux_rows(b, k.nw + j) = Phi(static_cast<Index>(inductor[b]), j);
  std::vector<long> charge_of(nb, -1);
  for (std::size_t q = 0; q < out.nq; ++q) charge_of[out.charges[q]] = static_cast<long>(q);
  for (std::size_t b = 0; b < nb; ++b) {
    if (charge_of[b] < 0) {  // a capacitor: q = C u
      QM qrow(1, k.nx());
      add_row(qrow, 0, volt, b, c.branches[b].value);
      split(qrow, 0, out.bt, out.x0, b);
    } else {
      out.bt(b, k.ns() + static_cast<std::size_t>(charge_of[b])) = Q(1);
    }
    split(cur, b, out.bt, out.x0, nb + b);
    split(flux_rows, b, out.bt, out.x0, 2 * nb + b);
    split(cur, b, out.vy, out.vu, b);  // q̇ = i
    deriv(cur, b, out.vy, out.vu, nb + b);
    deriv(flux_rows, b, out.vy, out.vu, 2 * nb + b);
  }
  for (std::size_t i = 0; i < k.nw; ++i) split(wdot, i, out.ay, out.au, i);
  for (std::size_t i = 0; i < k.nl; ++i) split(idot, i, out.ay, out.au, k.nw + i);
  for (std::size_t q = 0; q < out.nq; ++q) split(cur, out.charges[q], out.ay, out.au, k.ns() + q);
  return out;
}

namespace {
/// The DC operating point as the state (w, i_L): unknowns (w, ρ, e, i), KCL on w, ρ and island rows at ẇ = 0, and
/// Φ i̇ = 0 on the inductors, solved exactly; std::invalid_argument where none exists or it is not unique.
std::vector<Q> operating_point_state(const io::Netlist& deck, const StateMotion& m, const StateEquations<Q>& s,
                                     const std::vector<Rational>& sigma0) {
  const QM Gww = block(s, "G_ww"), Gwr = block(s, "G_wr"), Grr = block(s, "G_rr"), Lw = block(s, "L_w"),
           Lr = block(s, "L_r"), Le = block(s, "L_e"), Hw = block(s, "H_w"), Hr = block(s, "H_r"), Ie = block(s, "I_e"),
           Ol = block(s, "O_L");
  const std::size_t nw = m.nw, nr = Grr.rows(), ne = Le.rows(), nl = m.nl;
  const QM sig = QM::column(sigma0);
  std::vector<Q> y(nw + nl + m.nq, Q(0));
  if (!deck.node_ic.empty())
    throw std::invalid_argument(
        ".ic node voltages held at the DC operating point are not enclosed on the state-equation model "
        "(the dense model takes them, up to " +
        std::to_string(kForcedBranches) + " branches)");
  // unknowns (w, ρ, e, i): KCL on w, ρ and island rows at ẇ = 0, and Φ i̇ = 0 on the inductors
  const std::size_t n = nw + nr + ne + nl;
  QM a(n, n + 1);
  const auto put = [&](const QM& blk, std::size_t r0, std::size_t c0) {
    for (Index i = 0; i < blk.rows(); ++i)
      for (Index j = 0; j < blk.cols(); ++j) a(r0 + i, c0 + j) = blk(i, j);
  };
  const QM bw = -(Hw * sig), br = -(Hr * sig), be = -(Ie * sig), bl = -(Ol * sig);
  put(Gww, 0, 0), put(Gwr, 0, nw), put(Lw, 0, nw + nr + ne), put(bw, 0, n);
  put(Gwr.transpose(), nw, 0), put(Grr, nw, nw), put(Lr, nw, nw + nr + ne), put(br, nw, n);
  put(Le, nw + nr, nw + nr + ne), put(be, nw + nr, n);
  put(Lw.transpose(), nw + nr + ne, 0), put(Lr.transpose(), nw + nr + ne, nw),
      put(Le.transpose(), nw + nr + ne, nw + nr), put(bl, nw + nr + ne, n);
  const Rref<Q> r = rref(a);
  if (!r.pivots.empty() && r.pivots.back() == n)
    throw std::invalid_argument(
        "no DC operating point exists (a voltage source across an inductor loop, or current sources into a capacitor "
        "cutset)");
  if (r.pivots.size() != n)
    throw std::invalid_argument("the DC operating point is not unique (ngspice: singular matrix)");
  for (std::size_t i = 0; i < nw; ++i) y[i] = r.r(i, n);
  for (std::size_t i = 0; i < nl; ++i) y[nw + i] = r.r(nw + nr + ne + i, n);
  return y;
}
}  // namespace

std::vector<Rational> state_start(const io::Netlist& deck, const StateMotion& m, bool op,
                                  const std::vector<Rational>& sigma0) {
  const RlcCircuit<Q>& c = deck.rlc;
  const StateEquations<Q> s = deck_state_equations<Q>(deck);
  if (op) return operating_point_state(deck, m, s, sigma0);
  const rlc::StateStructure st = state_structure(c);
  const QM Cww = block(s, "C_ww"), Le = block(s, "L_e"), Phi = block(s, "Phi"), Ie = block(s, "I_e");
  const std::size_t nw = m.nw, ne = Le.rows(), nl = m.nl, nb = c.branches.size();
  const QM sig = QM::column(sigma0);
  std::vector<Q> y(nw + nl + m.nq, Q(0));
  // uic: charges kept per C-component, inductor currents moved along island levels, impulse charges
  std::vector<Q> qb(nb, Q(0)), dq(nb, Q(0));
  QM il(nl, 1), rhs(nw, 1);
  long li = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const RlcBranch<Q>& br = c.branches[b];
    if (br.kind == RlcKind::inductor) {
      if (deck.initial[b]) il(static_cast<Index>(li), 0) = *deck.initial[b];
      ++li;
    }
    if (br.kind != RlcKind::capacitor) continue;
    if (deck.initial[b]) qb[b] = br.value * *deck.initial[b];
    const BranchPotential d = branch_potential(st, br.from, br.to);
    Q v = qb[b];
    for (const auto& [j, sg] : d.o) v -= br.value * Q(sg) * sigma0[static_cast<std::size_t>(j)];
    for (const auto& [i, sg] : d.w) rhs(static_cast<Index>(i), 0) += Q(sg) * v;
  }
  const QM w = solve(Cww, rhs);
  if (ne > 0) il = il - solve(Phi, Le.transpose()) * solve(Le * solve(Phi, Le.transpose()), Le * il + Ie * sig);
  for (std::size_t i = 0; i < nw; ++i) y[i] = w(i, 0);
  for (std::size_t i = 0; i < nl; ++i) y[nw + i] = il(i, 0);
  // the capacitors' jumps: q⁺ = C u(0+) from x = X0 u + Bᵀ y (σ̇ does not enter q)
  QM u(1 + 2 * c.sources, 1);
  u(0, 0) = Q(1);
  for (std::size_t j = 0; j < c.sources; ++j) u(1 + j, 0) = sigma0[j];
  const QM x = m.x0 * u + m.bt * QM::column(y);
  QM net(c.nodes + 1, 1);
  for (std::size_t b = 0; b < nb; ++b)
    if (c.branches[b].kind == RlcKind::capacitor) {
      dq[b] = x(b, 0) - qb[b];
      net(static_cast<Index>(c.branches[b].from + 1), 0) += dq[b];
      net(static_cast<Index>(c.branches[b].to + 1), 0) -= dq[b];
    }
  for (auto it = st.vtree.rbegin(); it != st.vtree.rend(); ++it) {
    const RlcBranch<Q>& br = c.branches[it->branch];
    const Index ch = static_cast<Index>(it->node + 1), pa = static_cast<Index>(it->parent + 1);
    dq[it->branch] = br.from == it->node ? Q(-net(ch, 0)) : net(ch, 0);
    net(pa, 0) += br.from == it->parent ? dq[it->branch] : Q(-dq[it->branch]);
  }
  for (std::size_t q = 0; q < m.nq; ++q) y[nw + nl + q] = dq[m.charges[q]];
  return y;
}

}  // namespace dcad::reference::pipeline
