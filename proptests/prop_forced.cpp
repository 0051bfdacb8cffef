// Forced systems with sources (YM §4) and the YM concepts, on random RLC circuits with every kind
// of element (L, C, R, V, I, wires, couplings) and small signed values:
//  - without forces and sources the forced CAD is the CAD (two routes to one tower);
//  - fast = reference (dims, steps, consistency, solution rank, number of source conditions);
//  - the CAD's velocities solve the Lagrange–d'Alembert–Pontryagin equations (YM Prop. 4.1, (4.3))
//    and are partial vector fields of the implicit Lagrangian system (YM (4.7), Thm 4.5);
//  - the graph route (dcad/rlc_graph.hpp: cycle ranks of subgraphs) is the dense route's tower, with
//    its conditions on the sources, for positive values and no coupling;
//  - the restriction of a Dirac structure to a subspace is a Dirac structure (YM Prop. 5.2), and
//    restricting to the whole space changes nothing.
#include "support/convert.hpp"
#include "support/gen.hpp"
#include "support/tally.hpp"

#include "dcad/fast/forced.hpp"
#include "dcad/reference/implicit_lagrangian.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/rlc.hpp"
#include "dcad/rlc_graph.hpp"

#include <Eigen/QR>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <functional>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;
using ref::RlcKind;

namespace {

struct Kinds {
  bool sources = true, resistors = true, couplings = true;
};

ref::RlcCircuit<Q> random_rlc(Kinds k) {
  ref::RlcCircuit<Q> c;
  c.nodes = pick_size(1, 4);
  const Index b = pick_size(2, 7);
  std::vector<RlcKind> kinds{RlcKind::inductor, RlcKind::capacitor, RlcKind::wire};
  if (k.resistors) kinds.push_back(RlcKind::resistor);
  if (k.sources) kinds.insert(kinds.end(), {RlcKind::voltage, RlcKind::current});
  const std::vector<Q> values{Q(1), Q(2), Q(3), Q(1, 2), Q(1, 1000), Q(5, 7)};
  for (Index i = 0; i < b; ++i) {
    ref::RlcBranch<Q> br;
    br.name = "b" + std::to_string(i);
    br.kind = *rc::gen::elementOf(kinds);
    br.from = *rc::gen::inRange<long>(-1, static_cast<long>(c.nodes));
    br.to = *rc::gen::inRange<long>(-1, static_cast<long>(c.nodes));
    br.value = *rc::gen::elementOf(values);
    if (br.kind == RlcKind::voltage || br.kind == RlcKind::current) br.source = c.sources++;
    c.branches.push_back(br);
  }
  if (k.couplings) {
    std::vector<Index> l;
    for (Index i = 0; i < b; ++i)
      if (c.branches[i].kind == RlcKind::inductor) l.push_back(i);
    if (l.size() >= 2 && *rc::gen::arbitrary<bool>()) c.mutuals.push_back({l[0], l[1], Q(1, 3)});
  }
  return c;
}

/// The circuit as a netlist, for counterexamples.
std::string deck(const ref::RlcCircuit<Q>& c) {
  std::string out;
  const char* letter = "LCRVIW";
  for (const auto& b : c.branches)
    out += std::string(1, letter[static_cast<int>(b.kind)]) + b.name + " " + std::to_string(b.from + 1) + " " +
           std::to_string(b.to + 1) + " " +
           (b.kind == RlcKind::voltage || b.kind == RlcKind::current ? "s" + std::to_string(b.source) : b.value.str()) +
           "\n";
  for (const auto& mu : c.mutuals)
    out += "K " + c.branches[mu.a].name + " " + c.branches[mu.b].name + " M=" + mu.m.str() + "\n";
  return out;
}

/// A point x of M_c(t) for source jets u (RC_PRE: u meets the source conditions) and u itself.
std::vector<Q> point_of_mc(const ref::ForcedResult<Q>& r, Index n, const std::vector<Q>& u) {
  for (Index i = 0; i < r.conditions.rows(); ++i) {  // random jets meet the conditions rarely: keep those that do
    Q s(0);
    for (Index j = 0; j < r.conditions.cols(); ++j) s += r.conditions(i, j) * u[j];
    RC_PRE(s == 0);
  }
  const QM ex = r.equations.block(0, r.equations.rows(), 0, n);
  std::vector<Q> rhs =
      ref::evaluate_rows(r.equations.block(0, r.equations.rows(), n, r.equations.cols()), std::vector<Q>(), u);
  for (Q& x : rhs) x = -x;
  return some_point(ref::solve(ex, rhs));
}

fast::ForcedSystem to_fast(const ref::ForcedSystem<Q>& f) {
  fast::ForcedSystem g;
  g.s.d.n = static_cast<int>(f.s.d.n);
  g.s.d.d = fast::Subspace::span(to_double(f.s.d.d.basis()));
  g.s.hessian = to_double(f.s.hessian);
  g.s.gradient = to_double(f.s.gradient);
  g.force = to_double(f.force);
  g.sources = static_cast<int>(f.sources);
  g.source_force = to_double(f.source_force);
  g.shift = to_double(f.shift);
  g.given_conditions = to_double(f.given_conditions);
  return g;
}

}  // namespace

RC_GTEST_PROP(ForcedTower, WithoutForcesIsTheCad, ()) {
  const ref::ForcedSystem<Q> f = ref::rlc_system(random_rlc({false, false, *rc::gen::arbitrary<bool>()}));
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  const ref::CadResult<Q> c = ref::constraint_tower(f.s);
  RC_TAG("c = " + std::to_string(c.steps));
  RC_ASSERT(r.consistent == c.consistent);
  RC_ASSERT(r.steps == c.steps);
  for (Index k = 0; k <= c.steps; ++k) RC_ASSERT(r.dims[k] == c.tower[k].dim());
  RC_ASSERT(r.conditions.rows() == 0);
  if (!c.consistent) return;
  RC_ASSERT(r.solution_rank == c.solution_rank);
  const Index n = f.s.d.n;
  RC_ASSERT(QSub::solutions(r.equations.block(0, r.equations.rows(), 0, n)) == c.final_step().m.direction);
}

RC_GTEST_PROP(ForcedTower, FastEqualsReference, ()) {
  const ref::ForcedSystem<Q> f = ref::rlc_system(random_rlc({}));
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  const fast::ForcedResult g = fast::forced_tower(to_fast(f));
  RC_TAG(std::string(g.certain.yes() ? "certain" : "uncertain") + ", c = " + std::to_string(r.steps) +
         (r.conditions.rows() ? ", source conditions" : "") + (r.consistent ? "" : ", inconsistent"));
  if (g.certain.unknown()) return;  // an uncertain fast result says so; nothing to compare
  RC_ASSERT(g.consistent == r.consistent);
  RC_ASSERT(std::vector<long>(g.dims) == r.dims);
  RC_ASSERT(g.steps == static_cast<int>(r.steps));
  RC_ASSERT(g.conditions.rows() == static_cast<long>(r.conditions.rows()));
  if (r.consistent) RC_ASSERT(g.solution_rank == static_cast<int>(r.solution_rank));
  // the same source conditions and the same M_c(t), not only the same counts: each fast jet row (x-part
  // and source columns [1 | σ⁽⁰⁾ | σ⁽¹⁾ …]) lies in the row space of the reference's, to rounding.  An
  // equation is only defined modulo the conditions and their time derivatives (the conditions hold at
  // every t), so the equations are compared with those stacked under them.  Shrunk counterexamples:
  // x5 = 0 beside σ1 = 0 came out of fast as x5 = σ1/2; a wire across a source and a capacitor
  // (σ0 = 0, q_C = 0) gave the reference v_C = 0 and fast v_C = 3σ0′, equal once σ0′ = 0.
  if (!r.consistent) return;
  RC_ASSERT(g.orders == static_cast<int>(r.orders));
  RC_ASSERT(g.equations.rows() == static_cast<Eigen::Index>(r.equations.rows()));
  const auto within = [](const Eigen::MatrixXd& fast_rows, const Eigen::MatrixXd& exact) {
    RC_ASSERT(fast_rows.cols() == exact.cols());
    if (exact.rows() == 0) {
      RC_ASSERT(fast_rows.rows() == 0);
      return;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(exact.transpose());  // exact: the reference's, in double
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(exact.cols(), qr.rank());
    const Eigen::MatrixXd off = fast_rows - (fast_rows * q) * q.transpose();
    RC_ASSERT(off.norm() <= 1e-7 * (1 + fast_rows.norm()));
  };
  const Eigen::Index m = static_cast<Eigen::Index>(f.sources);
  const auto with_conditions = [m](const Eigen::MatrixXd& eq, const Eigen::MatrixXd& cond) {
    std::vector<Eigen::VectorXd> rows;  // the conditions [1 | σ⁽⁰⁾ …] and their derivatives within the jet
    for (Eigen::Index i = 0; i < cond.rows(); ++i)
      for (Eigen::VectorXd c = cond.row(i).transpose(); c.tail(c.size() - 1).norm() > 0;) {
        rows.push_back(c);
        if (c.tail(m).norm() > 0) break;  // σ of the top order: its derivative is outside the jet
        Eigen::VectorXd d = Eigen::VectorXd::Zero(c.size());
        d.segment(1 + m, c.size() - 1 - m) = c.segment(1, c.size() - 1 - m);  // σ⁽ᵏ⁾ → σ⁽ᵏ⁺¹⁾, the constant drops
        c = d;
      }
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(eq.rows() + static_cast<Eigen::Index>(rows.size()), eq.cols());
    out.topRows(eq.rows()) = eq;
    for (std::size_t k = 0; k < rows.size(); ++k)
      out.row(eq.rows() + static_cast<Eigen::Index>(k)).tail(cond.cols()) = rows[k].transpose();
    return out;
  };
  within(g.conditions, to_double(r.conditions));
  within(with_conditions(g.equations, g.conditions), with_conditions(to_double(r.equations), to_double(r.conditions)));
}

RC_GTEST_PROP(ImplicitLagrangian, CadVelocitiesSolveLagrangeDAlembertPontryagin, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({false, true, true});
  const ref::ForcedSystem<Q> f = ref::rlc_system(c);
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  RC_PRE(r.consistent);
  const Index n = f.s.d.n, nb = c.branches.size();
  // a random point of M_c (no sources: the jet columns hold only the constant)
  const QM ex = r.equations.block(0, r.equations.rows(), 0, n);
  std::vector<Q> rhs(r.equations.rows());
  for (Index i = 0; i < rhs.size(); ++i) rhs[i] = -r.equations(i, n);
  const std::vector<Q> x = some_point(ref::solve(ex, rhs));
  const ref::AffineSubspace<Q> vel = ref::forced_velocities(f, r, x, {Q(1)});
  RC_ASSERT(!vel.empty);  // M_c carries solutions [CEF Thm 5.4]
  const std::vector<Q> xdot = some_point(vel);
  // L and F of the circuit: F(q, v) = −R v
  ref::Matrix<Q> ki, ri;
  ref::affine_kcl(c, ki, ri);
  ref::PontryaginInput<Q> in{
      static_cast<Index>(nb), ki, ref::rlc_inductance(c), QM(nb, nb), QM(nb, nb), std::vector<Q>(nb),
      std::vector<Q>(nb)};
  QM fv(nb, nb);
  for (Index b = 0; b < nb; ++b) {
    if (c.branches[b].kind == RlcKind::capacitor) in.qq(b, b) = -Q(1) / c.branches[b].value;
    if (c.branches[b].kind == RlcKind::resistor) fv(b, b) = -c.branches[b].value;
  }
  RC_ASSERT(ref::satisfies_ldap(in, QM(nb, nb), fv, x, xdot));  // YM (4.3)
  // (q̇, ṗ) is a partial vector field of the implicit Lagrangian system (L, F, Δ, X)  [YM (4.7)]
  const std::vector<Q> q(x.begin(), x.begin() + nb), v(x.begin() + nb, x.begin() + 2 * nb);
  std::vector<Q> qp(xdot.begin(), xdot.begin() + nb);
  qp.insert(qp.end(), xdot.begin() + 2 * nb, xdot.end());
  const ref::AffineSubspace<Q> fields = ref::implicit_lagrangian_fields(in, QM(nb, nb), fv, q, v);
  RC_ASSERT(!fields.empty);
  std::vector<Q> diff(qp.size());
  for (Index i = 0; i < qp.size(); ++i) diff[i] = qp[i] - fields.point[i];
  RC_ASSERT(ref::contains(fields.direction, diff));
}

RC_GTEST_PROP(Restriction, OfADiracStructureIsDirac, ()) {
  const ref::DiracStructure<Q> d = any_dirac(8);
  const QSub n = random_subspace_of(QSub::whole(d.n));
  const ref::DiracStructure<Q> dn = ref::restrict_dirac(d, n);
  RC_TAG("dim N = " + std::to_string(n.dim()) + " of " + std::to_string(d.n));
  RC_ASSERT(ref::dirac_defect(dn).empty());  // YM Prop. 5.2
  RC_ASSERT(ref::restrict_dirac(d, QSub::whole(d.n)).d == d.d);
}

namespace {

/// Cycle rank (edges − vertices + components, ground included) of the branches with keep(kind).
Index cycle_rank_of(const ref::RlcCircuit<Q>& c, const std::function<bool(RlcKind)>& keep) {
  std::vector<long> parent(c.nodes + 1);
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<long>(i);
  const std::function<long(long)> find = [&](long x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
  Index cycles = 0;
  for (const auto& b : c.branches) {
    if (!keep(b.kind)) continue;
    const long u = find(b.from + 1), v = find(b.to + 1);
    if (u == v)
      ++cycles;
    else
      parent[u] = v;
  }
  return cycles;
}

}  // namespace

// Sources move the constraint submanifolds, they never turn them (V §3: M_k(t) = a fixed subspace
// translated by the sources): a voltage source has the tower of a zero-volt one (a wire, CONTRACT).
// So a voltage source across a capacitor loop constrains the charges exactly as the wire would.
RC_GTEST_PROP(ForcedTower, VoltageSourcesMoveButNeverTurnTheTower, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({});
  ref::RlcCircuit<Q> off = c;  // every voltage source switched off: a wire
  for (auto& b : off.branches)
    if (b.kind == RlcKind::voltage) b.kind = RlcKind::wire;
  const ref::ForcedResult<Q> r = ref::forced_tower(ref::rlc_system(c)), w = ref::forced_tower(ref::rlc_system(off));
  RC_PRE(r.consistent && w.consistent);  // (0 = 1 cannot come from sources; kept for clarity)
  RC_ASSERT(r.dims == w.dims);
  RC_ASSERT(r.solution_rank == w.solution_rank);
}

// CEF Thm 6.4 with YM §4 forces: for L, C, R > 0 the equations M_2 adds to M_1 are one KVL per
// independent loop of the non-inductive branches through which no current source passes (C, R, V,
// wires), modulo the loops of voltage sources and wires (those say nothing about x: 0 = 0 or a
// condition on the sources).  A resistor in a capacitor loop keeps the loop's equation (it now
// ties q/C to R v); a current source in a loop removes it (its voltage is a free reaction, Δ°).
RC_GTEST_PROP(ForcedTower, SecondStepCountsTheNonInductiveLoops, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({});  // values are positive
  const ref::ForcedResult<Q> r = ref::forced_tower(ref::rlc_system(c));
  RC_PRE(r.consistent);
  const Index loops = cycle_rank_of(c, [](RlcKind k) { return k != RlcKind::inductor && k != RlcKind::current; }) -
                      cycle_rank_of(c, [](RlcKind k) { return k == RlcKind::voltage || k == RlcKind::wire; });
  const long codim = r.dims.size() > 2 ? r.dims[1] - r.dims[2] : 0;
  RC_TAG("loops = " + std::to_string(loops));
  RC_ASSERT(codim == static_cast<long>(loops));
}

// With DC sources (σ constant, its derivatives 0) the CAD's velocities at a point of M_c obey the
// circuit laws directly — YM (4.3) with the affine constraint of the current sources and the
// source forces: KCL on q̇ = v, v_b = I_j on a current source, p = Φ v, and the branch voltages
// ṗ + q/C + R v (+ V on a voltage source: F = −V, so φ(n+) − φ(n−) = V as in SPICE) are potential
// differences φ(from) − φ(to) up to the
// free voltages of the current sources: in Δ° = row [K; E_I].
RC_GTEST_PROP(ImplicitLagrangian, DcSourcesObeyTheCircuitLaws, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({});
  RC_LOG() << deck(c);
  const ref::ForcedSystem<Q> f = ref::rlc_system(c);
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  RC_PRE(r.consistent);
  const Index n = f.s.d.n, nb = c.branches.size(), m = c.sources;
  std::vector<Q> u{Q(1)};
  for (Index j = 0; j < m; ++j) u.push_back(Q(*rc::gen::inRange(-3, 4)));
  for (Index k = 1; k <= r.orders; ++k)
    for (Index j = 0; j < m; ++j) u.push_back(Q(0));
  const std::vector<Q> x = point_of_mc(r, n, u);
  const ref::AffineSubspace<Q> vel = ref::forced_velocities(f, r, x, u);
  RC_ASSERT(!vel.empty);
  const std::vector<Q> xd = some_point(vel);
  ref::Matrix<Q> ki, ri;
  ref::affine_kcl(c, ki, ri);
  const QM phi = ref::rlc_inductance(c), k = ref::rlc_kcl(c);
  std::vector<Q> q(x.begin(), x.begin() + nb), v(x.begin() + nb, x.begin() + 2 * nb), p(x.begin() + 2 * nb, x.end());
  std::vector<Q> qd(xd.begin(), xd.begin() + nb), pd(xd.begin() + 2 * nb, xd.end());
  RC_ASSERT(qd == v);
  RC_ASSERT((k * QM::column(v)).is_zero());      // KCL
  RC_ASSERT(p == (phi * QM::column(v)).col(0));  // p = Φ v
  std::vector<Q> drop(nb);
  for (Index b = 0; b < nb; ++b) {
    const auto& br = c.branches[b];
    drop[b] = pd[b];
    if (br.kind == RlcKind::capacitor) drop[b] += q[b] / br.value;
    if (br.kind == RlcKind::resistor) drop[b] += br.value * v[b];
    if (br.kind == RlcKind::voltage) drop[b] += u[1 + br.source];  // F = −V: φ(n+) − φ(n−) = V
    if (br.kind == RlcKind::current) RC_ASSERT(v[b] == u[1 + br.source]);
  }
  RC_ASSERT(ref::contains(QSub::span(ki), drop));  // KVL, current sources free
}

// YM Thm 5.6, (a) ⇔ (c), for linear data with L regular on Δ: along a solution of the CAD the
// momentum stays in the constraint momentum space P = FL(Δ), so (q̇, ṗ) is tangent to P (no part in
// V of (5.11)), and it is a constrained partial vector field of (L_c, Δ, X_P): (X_P, 𝔇L_c) ∈ D_P,
// D_P the restriction of D_Δ to P [YM (5.12), Prop. 5.2] — two routes, the CAD on TQ ⊕ T*Q and
// the constrained Dirac structure on P, to the same motion.
RC_GTEST_PROP(ImplicitLagrangian, ConstrainedSystemByRestrictionIsTheCad, ()) {
  const Index n = pick_size(1, 4);
  ref::PontryaginInput<Q> in;
  in.n = n;
  in.k = integer_matrix(*rc::gen::inRange<Index>(0, n + 1), n);
  const QM m = integer_matrix(n, n);
  in.vv = m.transpose() * m + QM::identity(n);  // positive definite: regular on every Δ
  in.qv = integer_matrix(n, n);
  in.qq = symmetric_matrix(n, n);
  in.q = integer_vector(n);
  in.v = integer_vector(n);
  const ref::LinearSystem<Q> s = ref::pontryagin_system(in);
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  RC_PRE(r.consistent);
  const std::vector<Q> x = some_point(r.final_step().m);
  const ref::AffineSubspace<Q> vel = ref::velocities(s, r, x);
  RC_ASSERT(!vel.empty);
  const std::vector<Q> xd = some_point(vel);
  const std::vector<Q> q(x.begin(), x.begin() + n), v(x.begin() + n, x.begin() + 2 * n);
  std::vector<Q> big_x(xd.begin(), xd.begin() + n);  // X = (q̇, ṗ)
  big_x.insert(big_x.end(), xd.begin() + 2 * n, xd.end());
  const QSub tp = ref::constraint_momentum_tangent(in);
  RC_ASSERT(ref::contains(tp, big_x));                               // tangent to P: X_V = 0
  RC_ASSERT(ref::dirac_defect(ref::constrained_dirac(in)).empty());  // D_P is Dirac (Prop. 5.2)
  const std::vector<Q> c = ref::constrained_part(in, big_x);
  // (5.11) T_P(T*Q) = T P ⊕ V: a planted part (0, η), η ∈ Δ°, is split off again and c is unchanged.
  // Killed by: constrained_part's loop over Δ°'s basis starting at 1 (seed-26 survivor [85]; X alone
  // has no V part, so any basis of V passed).
  const QSub ann = ref::annihilator(in.k.rows() ? ref::kernel(in.k) : QSub::whole(n));
  std::vector<Q> planted = big_x;
  for (Index i = 0; i < ann.dim(); ++i) {
    const Q w(*rc::gen::inRange(-3, 4));
    for (Index j = 0; j < n; ++j) planted[n + j] += w * ann.basis()(i, j);
  }
  RC_ASSERT(ref::constrained_part(in, planted) == c);
  const ref::AffineSubspace<Q> xp = ref::implicit_constrained_fields(in, q, v);
  RC_ASSERT(!xp.empty);
  std::vector<Q> d(c.size());
  for (Index i = 0; i < c.size(); ++i) d[i] = c[i] - xp.point[i];
  RC_ASSERT(ref::contains(xp.direction, d));  // (X_P, 𝔇L_c) ∈ D_P
  RC_ASSERT(xp.direction.dim() == 0);         // L regular on Δ: X_P is unique (5.16)
}

// The equations of motion ż = F z + f + S u_src + G λ of the forced route (forced_motion,
// forced_reduced_equations) against the velocities solved pointwise (forced_velocities) at a random
// point of M_c(t) with random source jets that meet the conditions: the same ż, modulo G.  Without
// forces and sources they are the CAD's reduced equations (CEF (5.12)).
RC_GTEST_PROP(ForcedTower, EquationsOfMotionAreThePointwiseVelocities, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({});
  RC_LOG() << deck(c);
  const ref::ForcedSystem<Q> f = ref::rlc_system(c);
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  RC_PRE(r.consistent);
  const Index n = f.s.d.n, m = c.sources;
  std::vector<Q> u{Q(1)};
  for (Index k = 0; k <= r.orders; ++k)
    for (Index j = 0; j < m; ++j) u.push_back(Q(*rc::gen::inRange(-3, 4)));
  const std::vector<Q> x = point_of_mc(r, n, u);
  const ref::AffineSubspace<Q> vel = ref::forced_velocities(f, r, x, u);
  const ref::ForcedReducedEquations<Q> red = ref::forced_reduced_equations(ref::forced_motion(f, r), m);
  RC_TAG(red.g.cols() ? "gauge freedom" : "unique");
  // ż from the reduced equations, against the pivot coordinates of the pointwise velocities
  std::vector<Q> zdot = red.f;
  for (Index i = 0; i < red.coords.size(); ++i) {
    for (Index k = 0; k < red.coords.size(); ++k) zdot[i] += red.f_matrix(i, k) * x[red.coords[k]];
    for (Index j = 0; j < red.s.cols(); ++j) zdot[i] += red.s(i, j) * u[1 + j];
  }
  std::vector<Q> d(red.coords.size());
  for (Index i = 0; i < red.coords.size(); ++i) d[i] = zdot[i] - vel.point[red.coords[i]];
  QM dirs = red.g.transpose();
  for (Index i = 0; i < vel.direction.dim(); ++i) {
    QM row(1, red.coords.size());
    for (Index k = 0; k < red.coords.size(); ++k) row(0, k) = vel.direction.basis()(i, red.coords[k]);
    dirs = ref::vstack(dirs, row);
  }
  RC_ASSERT(ref::contains(QSub::span(dirs), d));
  RC_ASSERT(static_cast<Index>(red.g.cols()) == r.solution_rank);
}

// Two routes to one tower (dcad/rlc_graph.hpp against the literal dense CAD of reference/forced.hpp):
// for C, R > 0 and a positive definite inductance matrix (graph_route_holds: couplings of 1/3 between
// inductors of 1/1000 … 3 make it indefinite in some draws, which are skipped), the dims, steps and
// solution rank counted from cycle ranks of subgraphs are the exact CAD's, and its conditions on the
// sources are as many as the cutsets of current sources and the loops of voltage sources (and wires)
// the graph route names — at the step it names them (cutsets bound M_1, loops M_2).
RC_GTEST_PROP(ForcedTower, GraphRouteIsTheDenseRoute, ()) {
  const ref::RlcCircuit<Q> c = random_rlc({});  // values are positive
  RC_PRE(ref::pipeline::graph_route_holds(c));
  RC_TAG(c.mutuals.empty() ? "no coupling" : "coupled");
  RC_LOG() << deck(c);
  std::vector<rlc::Branch> branches;
  for (const auto& b : c.branches) branches.push_back({b.kind, b.from, b.to});
  const rlc::Tower t = rlc::tower(c.nodes, branches);
  const ref::ForcedResult<Q> r = ref::forced_tower(ref::rlc_system(c));
  RC_ASSERT(r.consistent);  // symbolic sources: never 1 = 0
  RC_ASSERT(r.dims == t.dims);
  RC_ASSERT(static_cast<long>(r.steps) == t.steps);
  RC_ASSERT(static_cast<long>(r.solution_rank) == t.solution_rank);
  RC_ASSERT(static_cast<std::size_t>(ref::rank(r.conditions)) == t.current_cutsets.size() + t.voltage_loops.size());
  std::size_t at1 = r.conditions_at.size() > 1 ? static_cast<std::size_t>(ref::rank(r.conditions_at[1])) : 0;
  RC_ASSERT(at1 == t.current_cutsets.size());
  RC_TAG(t.voltage_loops.empty() ? (t.current_cutsets.empty() ? "no condition" : "cutsets") : "loops");
  RC_TAG("steps " + std::to_string(t.steps));
}

// The same with couplings on purpose: 1 to 3 mutual inductances M = f·min(L_a, L_b) between random
// pairs of inductors, f ∈ {−9/10, −1/2, 1/3, 9/10, 1}: positive definite Φ (graph_route_holds) gives the
// uncoupled graph count, which is the dense CAD's; f = 1 on equal inductors (k = 1) and some sums of
// couplings make Φ singular or indefinite, and graph_route_holds must refuse them (the perfectly
// coupled transformer's tower, cases/transformer-perfect-coupling.cir, is not the graph count).
RC_GTEST_PROP(ForcedTower, GraphRouteHoldsThroughPositiveDefiniteCouplings, ()) {
  Kinds kinds;
  kinds.couplings = false;
  ref::RlcCircuit<Q> c = random_rlc(kinds);
  std::vector<Index> l;
  for (Index i = 0; i < c.branches.size(); ++i)
    if (c.branches[i].kind == RlcKind::inductor) l.push_back(i);
  while (l.size() < 2) {  // two inductors at least: add them between random nodes
    ref::RlcBranch<Q> br;
    br.name = "b" + std::to_string(c.branches.size());
    br.kind = RlcKind::inductor;
    br.from = *rc::gen::inRange<long>(-1, static_cast<long>(c.nodes));
    br.to = *rc::gen::inRange<long>(-1, static_cast<long>(c.nodes));
    br.value = *rc::gen::elementOf(std::vector<Q>{Q(1), Q(2), Q(1, 2), Q(1, 1000)});
    l.push_back(c.branches.size());
    c.branches.push_back(br);
  }
  const int couplings = *rc::gen::inRange(1, 4);
  for (int k = 0; k < couplings; ++k) {
    const Index a = *rc::gen::elementOf(l), b = *rc::gen::elementOf(l);
    if (a == b) continue;
    const Q f = *rc::gen::elementOf(std::vector<Q>{Q(-9, 10), Q(-1, 2), Q(1, 3), Q(9, 10), Q(1)});
    c.mutuals.push_back({a, b, f * std::min(c.branches[a].value, c.branches[b].value)});
  }
  RC_LOG() << deck(c);
  const ref::ForcedResult<Q> r = ref::forced_tower(ref::rlc_system(c));
  // graph_route_holds decides Φ > 0 by pivots per coupled group; cross-checked here on the dense Φ of
  // all inductors by another route: nonsingular, and vᵀΦv > 0 on random rational vectors
  const bool holds = ref::pipeline::graph_route_holds(c);
  const QM phi = ref::rlc_inductance(c);
  std::vector<Index> ind = l;
  QM block(ind.size(), ind.size());
  for (Index i = 0; i < ind.size(); ++i)
    for (Index j = 0; j < ind.size(); ++j) block(i, j) = phi(ind[i], ind[j]);
  if (holds) {  // positive definite: nonsingular and vᵀΦv > 0 on random rational v
    RC_ASSERT(ref::rank(block) == static_cast<Index>(ind.size()));
    for (int t = 0; t < 8; ++t) {
      QM v(ind.size(), 1);
      for (Index i = 0; i < ind.size(); ++i) v(i, 0) = Q(*rc::gen::inRange(-5, 6));
      if (v.is_zero()) continue;
      RC_ASSERT((v.transpose() * block * v)(0, 0) > 0);
    }
    std::vector<rlc::Branch> branches;
    for (const auto& b : c.branches) branches.push_back({b.kind, b.from, b.to});
    const rlc::Tower t = rlc::tower(c.nodes, branches);
    RC_ASSERT(r.dims == t.dims);
    RC_ASSERT(static_cast<long>(r.solution_rank) == t.solution_rank);
  }
  RC_TAG(holds ? "positive definite" : "refused");
}
