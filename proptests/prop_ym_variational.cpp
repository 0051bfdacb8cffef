// YM §3's variational framework on random linear data (L and H quadratic, Δ = ker K, small integers).
// On TQ ⊕ T*Q (dcad/reference/hamilton_pontryagin.hpp):
//  - Prop 3.2: the intrinsic integrand ((Tpr)*χ − τ*dE)·w is the coordinate one of (3.11) for every x, ẋ, w;
//  - Prop 3.3: the intrinsic implicit Euler–Lagrange equations (3.10) are (3.1), i.e. YM (4.3) with Δ = TQ;
//  - Prop 3.5: (3.13) implies (3.17), and the converse holds where A is nondegenerate on Δ; where it is
//    degenerate a planted q̇ = v + u (u ∈ Δ, A u ∈ Δ°, ṗ moved to stay in 𝒞) satisfies (3.17) and not (3.13).
// On T*Q, the implicit Hamiltonian systems (dcad/reference/implicit_hamiltonian.hpp):
//  - Thm 3.19 with Props 3.14, 3.15 and 3.18: (X, dH) ∈ D_Δ (3.47), the coordinate form (3.41), the
//    Hamilton–d'Alembert principle (3.43) and the intrinsic system (3.46) hold for the same X, on fields
//    of the system, fields moved along Δ° (still fields) and fields moved off it (no longer);
//  - the fields exist iff ∂H/∂p ∈ Δ and then form an affine space of dimension dim Δ° (ṗ's free part);
//  - without constraints they are Hamilton's equations, i_X Ω = dH read off as (∂H/∂p, −∂H/∂q) (Prop 3.11),
//    the only rates at which the Poincaré–Cartan integrand vanishes (Prop 3.9);
//  - the Legendre transform of a hyperregular L turns the implicit Lagrangian system into the implicit
//    Hamiltonian one: the same (q̇, ṗ) pointwise, and the CAD's towers on TQ ⊕ T*Q and on T*Q end in
//    manifolds of one dimension whose velocities agree;
//  - the CAD on (D_Δ, H) fixes the constraint force ṗ + ∂H/∂q ∈ Δ° when A is positive definite;
//  - fast = reference: the fields, the forces and the tower of (D_Δ, H).
#include "support/convert.hpp"
#include "support/gen.hpp"
#include "support/tally.hpp"

#include "dcad/fast/implicit_hamiltonian.hpp"
#include "dcad/fast/implicit_lagrangian.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/hamilton_pontryagin.hpp"
#include "dcad/reference/implicit_hamiltonian.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

namespace {

using Ham = ref::HamiltonianInput<Q>;

/// A random H with Δ = ker K; `definite`: A positive definite (H regular on every Δ).
Ham random_hamiltonian(bool definite) {
  const Index n = pick_size(1, 4);
  Ham h;
  h.n = n;
  h.k = integer_matrix(*rc::gen::inRange<Index>(0, n + 1), n, 2);
  if (definite) {
    const QM m = integer_matrix(n, n);
    h.pp = m.transpose() * m + QM::identity(n);
  } else {
    h.pp = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  }
  h.qp = *rc::gen::arbitrary<bool>() ? integer_matrix(n, n, 2) : QM(n, n);
  h.qq = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  h.q = integer_vector(n, 2);
  h.p = *rc::gen::arbitrary<bool>() ? integer_vector(n, 2) : std::vector<Q>(n, Q(0));
  return h;
}

/// A point z = (q, p), on M_1 = {K ∂H/∂p = 0} when it has one and `on_m1`.
std::vector<Q> random_point(const Ham& h, bool on_m1) {
  const Index n = h.n;
  if (on_m1 && h.k.rows()) {
    const QM eq = h.k * hstack(h.qp.transpose(), h.pp);  // K (Bᵀ q + A p) = −K b
    std::vector<Q> rhs = (h.k * QM::column(h.p)).col(0);
    for (Q& c : rhs) c = -c;
    const ref::AffineSubspace<Q> m1 = ref::solve(eq, rhs);
    if (!m1.empty) return some_point(m1);
  }
  return integer_vector(2 * n, 3);
}

bool in_affine(const ref::AffineSubspace<Q>& a, const std::vector<Q>& x) {
  if (a.empty) return false;
  std::vector<Q> d(x.size());
  for (Index i = 0; i < x.size(); ++i) d[i] = x[i] - a.point[i];
  return ref::contains(a.direction, d);
}

Index rank_of(const QM& k) { return k.rows() ? ref::rank(k) : 0; }

}  // namespace

RC_GTEST_PROP(ImplicitHamiltonian, Thm3_19_FourFormsAgree, ()) {
  const Ham h = random_hamiltonian(false);
  const std::vector<Q> z = random_point(h, *rc::gen::inRange(0, 4) != 0);
  const Index n = h.n;
  const std::vector<Q> dh = ref::hamiltonian_differential(h, z);
  const QSub delta = ref::hamiltonian_distribution(h);
  const ref::AffineSubspace<Q> fields = ref::implicit_hamiltonian_fields(h, z);
  // (3.41) is solvable iff ∂H/∂p ∈ Δ, and then ṗ is free in −∂H/∂q + Δ°, dim Δ° = rank K
  RC_ASSERT(fields.empty == !ref::contains(delta, std::vector<Q>(dh.begin() + n, dh.end())));
  if (!fields.empty) RC_ASSERT(fields.direction.dim() == rank_of(h.k));
  std::vector<std::vector<Q>> candidates{integer_vector(2 * n, 3)};
  if (!fields.empty) {
    const std::vector<Q> x = some_point(fields);
    candidates.push_back(x);
    const QSub ann = ref::annihilator(delta);  // moved along Δ°: still a field; off it: not
    std::vector<Q> along = x, off = x;
    const std::vector<Q> c = integer_vector(ann.dim() + 1, 3);
    for (Index i = 0; i < ann.dim(); ++i)
      for (Index j = 0; j < n; ++j) along[n + j] += c[i] * ann.basis()(i, j);
    off[*rc::gen::inRange<Index>(0, 2 * n)] += Q(1 + *rc::gen::inRange(0, 3));
    candidates.push_back(along);
    candidates.push_back(off);
    RC_ASSERT(ref::satisfies_implicit_hamiltonian(h, z, along));
  }
  for (const std::vector<Q>& x : candidates) {
    const bool dirac = ref::in_induced_dirac(h, z, x);  // (3.47)
    RC_ASSERT(dirac == in_affine(fields, x));
    RC_ASSERT(ref::satisfies_implicit_hamiltonian(h, z, x) == dirac);            // Prop 3.14, (3.41)
    RC_ASSERT(ref::satisfies_hamilton_dalembert(h, z, x) == dirac);              // Prop 3.15, (3.43)
    RC_ASSERT(ref::satisfies_intrinsic_implicit_hamiltonian(h, z, x) == dirac);  // Props 3.17–3.18, (3.46)
    if (dirac) RC_ASSERT(ref::contains(ref::annihilator(delta), ref::hamiltonian_constraint_force(h, z, x)));
  }
}

RC_GTEST_PROP(ImplicitHamiltonian, Prop3_11_WithoutConstraintsHamiltonsEquations, ()) {
  Ham h = random_hamiltonian(false);
  h.k = QM(0, h.n);
  const std::vector<Q> z = integer_vector(2 * h.n, 3);
  const std::vector<Q> dh = ref::hamiltonian_differential(h, z), x = ref::hamilton_field(h, z);
  for (Index i = 0; i < h.n; ++i) {  // (3.40): q̇ = ∂H/∂p, ṗ = −∂H/∂q
    RC_ASSERT(x[i] == dh[h.n + i]);
    RC_ASSERT(x[h.n + i] == -dh[i]);
  }
  const ref::AffineSubspace<Q> fields = ref::implicit_hamiltonian_fields(h, z);
  RC_ASSERT(!fields.empty);
  RC_ASSERT(fields.direction.dim() == 0);  // D_Δ with Δ = TQ is the graph of Ω: X is X_H
  RC_ASSERT(fields.point == x);
  // Prop 3.9: the Poincaré–Cartan integrand vanishes for all (δq, δp) exactly at (3.34), and not one coordinate off
  RC_ASSERT(ref::satisfies_hamilton_dalembert(h, z, x));
  std::vector<Q> off = x;
  off[*rc::gen::inRange<Index>(0, 2 * h.n)] += Q(1);
  RC_ASSERT(!ref::satisfies_hamilton_dalembert(h, z, off));
}

RC_GTEST_PROP(ImplicitHamiltonian, LegendreOfTheImplicitLagrangianSystem, ()) {
  const Index n = pick_size(1, 3);
  ref::PontryaginInput<Q> l;
  l.n = n;
  l.k = integer_matrix(*rc::gen::inRange<Index>(0, n + 1), n, 2);
  const QM m = integer_matrix(n, n);
  l.vv = *rc::gen::arbitrary<bool>() ? m.transpose() * m + QM::identity(n) : symmetric_matrix(n, n);
  RC_PRE(ref::determinant(l.vv) != Q(0));
  l.qv = integer_matrix(n, n, 2);
  l.qq = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  l.q = integer_vector(n, 2);
  l.v = integer_vector(n, 2);
  const Ham h = ref::legendre_hamiltonian(l);
  // pointwise: at (q, v), v ∈ Δ, p = FL(q, v), (q̇, ṗ) of (L, Δ) [YM (4.7)] are those of (H, Δ) [Def 3.12]
  const std::vector<Q> q = integer_vector(n, 3), v = some_point(ref::AffineSubspace<Q>{
                                                     false, std::vector<Q>(n), ref::hamiltonian_distribution(h)});
  std::vector<Q> z = q;
  const std::vector<Q> p = ref::legendre(l, q, v);
  z.insert(z.end(), p.begin(), p.end());
  const std::vector<Q> dh = ref::hamiltonian_differential(h, z);
  RC_ASSERT(std::vector<Q>(dh.begin() + n, dh.end()) == v);  // ∂H/∂p = v at p = FL(q, v)
  const ref::AffineSubspace<Q> lag = ref::implicit_lagrangian_fields(l, QM(n, n), QM(n, n), q, v);
  const ref::AffineSubspace<Q> ham = ref::implicit_hamiltonian_fields(h, z);
  RC_ASSERT(!lag.empty && !ham.empty);
  RC_ASSERT(lag.direction == ham.direction);
  RC_ASSERT(in_affine(ham, lag.point));
  // the CAD on TQ ⊕ T*Q (CEF §6) and on T*Q: M_c of one dimension, and the same (q̇, ṗ) at a point of it
  const ref::LinearSystem<Q> sl = ref::pontryagin_system(l), sh = ref::implicit_hamiltonian_system(h);
  const ref::CadResult<Q> rl = ref::constraint_tower(sl), rh = ref::constraint_tower(sh);
  RC_ASSERT(rl.consistent == rh.consistent);
  if (!rl.consistent) return;
  RC_ASSERT(rl.final_step().m.direction.dim() == rh.final_step().m.direction.dim());
  const std::vector<Q> x = some_point(rl.final_step().m);  // (q, v, p)
  std::vector<Q> zx(x.begin(), x.begin() + n);
  zx.insert(zx.end(), x.begin() + 2 * n, x.end());
  RC_ASSERT(in_affine(rh.final_step().m, zx));
  const std::vector<Q> xd = some_point(ref::velocities(sl, rl, x));
  std::vector<Q> proj(xd.begin(), xd.begin() + n);
  proj.insert(proj.end(), xd.begin() + 2 * n, xd.end());
  RC_ASSERT(in_affine(ref::velocities(sh, rh, zx), proj));
}

RC_GTEST_PROP(ImplicitHamiltonian, CadFixesTheConstraintForces, ()) {
  const Ham h = random_hamiltonian(true);
  const ref::LinearSystem<Q> s = ref::implicit_hamiltonian_system(h);
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  RC_PRE(r.consistent);
  const std::vector<Q> z = some_point(r.final_step().m);
  const ref::AffineSubspace<Q> vel = ref::velocities(s, r, z);
  RC_ASSERT(!vel.empty);                // CEF Thm 5.4
  RC_ASSERT(vel.direction.dim() == 0);  // A > 0: the motion, and with it μ_a ω^a, is unique
  const std::vector<Q> x = vel.point;
  RC_ASSERT(ref::in_induced_dirac(h, z, x));  // a solution of the implicit Hamiltonian system
  RC_ASSERT(ref::satisfies_implicit_hamiltonian(h, z, x));
  RC_ASSERT(
      ref::contains(ref::annihilator(ref::hamiltonian_distribution(h)), ref::hamiltonian_constraint_force(h, z, x)));
}

RC_GTEST_PROP(FastVsReference, ImplicitHamiltonian, ()) {
  const Ham h = random_hamiltonian(*rc::gen::arbitrary<bool>());
  const std::vector<Q> z = random_point(h, *rc::gen::inRange(0, 4) != 0);
  fast::HamiltonianInput fh;
  fh.n = h.n;
  fh.k = h.k.rows() ? to_double(h.k) : Eigen::MatrixXd(0, h.n);
  fh.pp = to_double(h.pp);
  fh.qp = to_double(h.qp);
  fh.qq = to_double(h.qq);
  fh.q = to_double(h.q);
  fh.p = to_double(h.p);
  const Eigen::VectorXd zd = to_double(z);
  const ref::AffineSubspace<Q> rf = ref::implicit_hamiltonian_fields(h, z);
  const fast::AffineSubspace ff = fast::implicit_hamiltonian_fields(fh, zd);
  RC_ASSERT(!tally("implicit Hamiltonian: fields exist", ff.certain.yes(), ff.empty == rf.empty));
  const double tol =
      1e-9 * (1 + zd.norm()) * (1 + fh.pp.norm() + fh.qp.norm() + fh.qq.norm() + fh.q.norm() + fh.p.norm());
  RC_ASSERT((fast::hamilton_field(fh, zd) - to_double(ref::hamilton_field(h, z))).norm() <= tol);
  if (!rf.empty && !ff.empty && ff.certain.yes()) {
    RC_ASSERT(ff.direction.dim() == static_cast<int>(rf.direction.dim()));
    const Eigen::VectorXd gap = to_double(rf.point) - ff.point;
    const Eigen::MatrixXd& dir = ff.direction.columns();
    RC_ASSERT((gap - dir * (dir.transpose() * gap)).norm() <= tol);
    const std::vector<Q> x = some_point(rf);
    RC_ASSERT((fast::hamiltonian_constraint_force(fh, zd, to_double(x)) -
               to_double(ref::hamiltonian_constraint_force(h, z, x)))
                  .norm() <= tol);
  }
  // the tower of (D_Δ, H): the same dimensions where fast is certain
  const ref::CadResult<Q> r = ref::constraint_tower(ref::implicit_hamiltonian_system(h));
  const fast::CadResult f = fast::constraint_tower(fast::implicit_hamiltonian_system(fh));
  RC_ASSERT(!tally("implicit Hamiltonian: consistent", f.certain.yes(), f.consistent == r.consistent));
  if (f.certain.yes() && f.consistent && r.consistent)
    RC_ASSERT(f.final_step().dim() == static_cast<long>(r.final_step().m.direction.dim()));
}

namespace {

ref::PontryaginInput<Q> random_lagrangian(Index n, bool constrained) {
  ref::PontryaginInput<Q> l;
  l.n = n;
  l.k = constrained ? integer_matrix(*rc::gen::inRange<Index>(0, n + 1), n, 2) : QM(0, n);
  l.vv = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  l.qv = *rc::gen::arbitrary<bool>() ? integer_matrix(n, n, 2) : QM(n, n);
  l.qq = symmetric_matrix(n, *rc::gen::inRange<Index>(0, n + 1));
  l.q = integer_vector(n, 2);
  l.v = integer_vector(n, 2);
  return l;
}

}  // namespace

RC_GTEST_PROP(YoshimuraMarsden, Prop3_2_IntrinsicIsTheCoordinateIntegrand, ()) {
  const Index n = pick_size(1, 4);
  const ref::PontryaginInput<Q> l = random_lagrangian(n, true);
  const std::vector<Q> x = integer_vector(3 * n, 3), xd = integer_vector(3 * n, 3), w = integer_vector(3 * n, 3);
  RC_ASSERT(ref::intrinsic_hamilton_pontryagin(l, x, xd, w) == ref::hamilton_pontryagin_integrand(l, x, xd, w));
}

RC_GTEST_PROP(YoshimuraMarsden, Prop3_3_IntrinsicImplicitEulerLagrange, ()) {
  const Index n = pick_size(1, 4);
  const ref::PontryaginInput<Q> l = random_lagrangian(n, false);
  const std::vector<Q> q = integer_vector(n, 3), v = integer_vector(n, 3);
  std::vector<Q> x = q, xd = v;  // a solution of (3.1): q̇ = v, p = ∂L/∂v, ṗ = ∂L/∂q, v̇ free
  x.insert(x.end(), v.begin(), v.end());
  const std::vector<Q> p = ref::legendre(l, q, v), lq = ref::dirac_differential(l, QM(n, n), QM(n, n), q, v);
  x.insert(x.end(), p.begin(), p.end());
  const std::vector<Q> vdot = integer_vector(n, 3);
  xd.insert(xd.end(), vdot.begin(), vdot.end());
  for (Index i = 0; i < n; ++i) xd.push_back(-lq[i]);
  std::vector<Q> moved = xd;
  moved[*rc::gen::inRange<Index>(0, 3 * n)] += Q(1);
  const QM none(n, n);
  RC_ASSERT(ref::satisfies_intrinsic_euler_lagrange(l, x, xd));
  RC_ASSERT(ref::satisfies_ldap(l, none, none, x, xd));
  const bool moved_v = *rc::gen::arbitrary<bool>();
  const std::vector<Q> at = moved_v ? integer_vector(3 * n, 3) : x, rate = moved_v ? xd : moved;
  RC_ASSERT(ref::satisfies_intrinsic_euler_lagrange(l, at, rate) == ref::satisfies_ldap(l, none, none, at, rate));
}

RC_GTEST_PROP(YoshimuraMarsden, Prop3_5_IntrinsicLdapWhereLIsRegularOnDelta, ()) {
  const Index n = pick_size(1, 4);
  ref::PontryaginInput<Q> l = random_lagrangian(n, true);
  if (!ref::constraint_tower(ref::pontryagin_system(l)).consistent) {  // homogeneous: x = 0 moves, so consistent
    l.q = std::vector<Q>(n);
    l.v = std::vector<Q>(n);
  }
  const ref::LinearSystem<Q> s = ref::pontryagin_system(l);
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  RC_ASSERT(r.consistent);
  const std::vector<Q> x = some_point(r.final_step().m);
  const std::vector<Q> xd = some_point(ref::velocities(s, r, x));
  const QM none(n, n);
  RC_ASSERT(ref::satisfies_ldap(l, none, none, x, xd));  // the CAD solves (3.13)  [CEF Thm 5.4]
  RC_ASSERT(ref::satisfies_intrinsic_ldap(l, x, xd));    // (3.13) ⇒ (3.17)
  // A on Δ: its kernel U = {u ∈ Δ : A u ∈ Δ°} = N ker(Nᵀ A N)
  const QSub delta = l.k.rows() ? ref::kernel(l.k) : QSub::whole(n);
  const QM nb = delta.basis();
  const QM ker = delta.dim() ? ref::nullspace(nb * l.vv * nb.transpose()) : QM(0, 0);
  const bool regular_on_delta = ker.rows() == 0;
  // a planted rate: q̇ = v + u (u ∈ U), v̇ + N y, ṗ + Bᵀ u + A N y, with Nᵀ A N y = Nᵀ (B − Bᵀ) u so that
  // ∂L/∂q − ṗ + B u stays in Δ°: in 𝒞(x), and (3.17) holds; (3.13) holds iff u = 0
  if (!regular_on_delta) {
    const std::vector<Q> u = (integer_matrix(1, ker.rows(), 2) * ker * nb).row(0);
    const std::vector<Q> rhs = (nb * (l.qv - l.qv.transpose()) * QM::column(u)).col(0);
    const ref::AffineSubspace<Q> ys = ref::solve(nb * l.vv * nb.transpose(), rhs);
    if (!ys.empty) {
      const std::vector<Q> dv = (QM::from_rows({ys.point}, nb.rows()) * nb).row(0);
      const std::vector<Q> dp = (l.qv.transpose() * QM::column(u) + l.vv * QM::column(dv)).col(0);
      std::vector<Q> planted = xd;
      for (Index i = 0; i < n; ++i) {
        planted[i] += u[i];
        planted[n + i] += dv[i];
        planted[2 * n + i] += dp[i];
      }
      RC_ASSERT(ref::satisfies_intrinsic_ldap(l, x, planted));
      RC_ASSERT(ref::satisfies_ldap(l, none, none, x, planted) == (u == std::vector<Q>(n)));
      RC_TAG(u == std::vector<Q>(n) ? "planted u = 0" : "planted u != 0: (3.17) without (3.13)");
    }
  }
  const QSub c = ref::ldap_variations(l);  // a random rate in 𝒞(x): the two agree where L is regular on Δ
  const std::vector<Q> other = (integer_matrix(1, c.dim(), 3) * c.basis()).row(0);
  const bool intrinsic = ref::satisfies_intrinsic_ldap(l, x, other),
             coordinates = ref::satisfies_ldap(l, none, none, x, other);
  if (coordinates) RC_ASSERT(intrinsic);
  if (regular_on_delta) RC_ASSERT(intrinsic == coordinates);
}

// Thm 3.8 (with Props 3.6, 3.7): for a possibly degenerate L, at x = (q, v, p) — on v ∈ Δ, p = FL(q, v) mostly,
// anywhere else sometimes — and candidate values X = (q̇, ṗ) of a partial vector field (fields of the system,
// moved along Δ° in ṗ, moved off, random): the LDAP equations (3.13) at the vertical lift, the intrinsic
// system (3.22) and (X, 𝔇L) ∈ D_Δ (3.24) hold together; on P, dE|_{T T*Q} = 𝔇L (3.28), so (3.32) is (3.24).
RC_GTEST_PROP(ImplicitLagrangian, Thm3_8_ThreeFormsAgree, ()) {
  const Index n = pick_size(1, 4);
  const ref::PontryaginInput<Q> l = random_lagrangian(n, true);
  const QSub delta = l.k.rows() ? ref::kernel(l.k) : QSub::whole(n);
  const std::vector<Q> q = integer_vector(n, 3);
  const bool on = *rc::gen::inRange(0, 5) != 0;
  const std::vector<Q> v =
      on ? some_point(ref::AffineSubspace<Q>{false, std::vector<Q>(n), delta}) : integer_vector(n, 3);
  std::vector<Q> x = q;
  x.insert(x.end(), v.begin(), v.end());
  const std::vector<Q> p = on ? ref::legendre(l, q, v) : integer_vector(n, 3);
  x.insert(x.end(), p.begin(), p.end());
  const QM none(n, n);
  // (3.28): dE(x) restricted to T_{(q, p)}T*Q is 𝔇L(q, v), so (3.32) is (3.24)
  const std::vector<Q> de = ref::energy_differential(ref::pontryagin_system(l), x);
  std::vector<Q> de_tq(de.begin(), de.begin() + n);
  de_tq.insert(de_tq.end(), de.begin() + 2 * n, de.end());
  RC_ASSERT(de_tq == ref::dirac_differential(l, none, none, q, v));
  const ref::AffineSubspace<Q> fields = ref::implicit_lagrangian_fields(l, none, none, q, v);
  std::vector<std::vector<Q>> candidates{integer_vector(2 * n, 3)};
  if (!fields.empty) {
    const std::vector<Q> f = some_point(fields);
    std::vector<Q> along = f, off = f;
    const QSub ann = ref::annihilator(delta);
    const std::vector<Q> c = integer_vector(ann.dim() + 1, 3);
    for (Index i = 0; i < ann.dim(); ++i)
      for (Index j = 0; j < n; ++j) along[n + j] += c[i] * ann.basis()(i, j);
    off[*rc::gen::inRange<Index>(0, 2 * n)] += Q(1);
    candidates.insert(candidates.end(), {f, along, off});
  }
  for (const std::vector<Q>& field : candidates) {
    const bool c = ref::satisfies_implicit_lagrangian_condition(l, x, field);          // (3.24)
    RC_ASSERT(ref::satisfies_ldap(l, none, none, x, ref::vertical_lift(field)) == c);  // (3.13)
    RC_ASSERT(ref::satisfies_intrinsic_implicit_lagrangian(l, x, field) == c);         // (3.22)
    if (on)
      RC_ASSERT(c == (!fields.empty && ref::contains(fields.direction, [&] {
                  std::vector<Q> d(field.size());
                  for (Index i = 0; i < d.size(); ++i) d[i] = field[i] - fields.point[i];
                  return d;
                }())));
  }
}

RC_GTEST_PROP(FastVsReference, ImplicitLagrangianFields, ()) {
  const Index n = pick_size(1, 4);
  const ref::PontryaginInput<Q> l = random_lagrangian(n, true);
  const QSub delta = l.k.rows() ? ref::kernel(l.k) : QSub::whole(n);
  const std::vector<Q> q = integer_vector(n, 3);
  const std::vector<Q> v = *rc::gen::inRange(0, 4) != 0
                               ? some_point(ref::AffineSubspace<Q>{false, std::vector<Q>(n), delta})
                               : integer_vector(n, 3);
  fast::PontryaginInput fl;
  fl.n = n;
  fl.k = l.k.rows() ? to_double(l.k) : Eigen::MatrixXd(0, n);
  fl.vv = to_double(l.vv);
  fl.qv = to_double(l.qv);
  fl.qq = to_double(l.qq);
  fl.q = to_double(l.q);
  fl.v = to_double(l.v);
  const Eigen::VectorXd qd = to_double(q), vd = to_double(v);
  const QM none(n, n);
  const ref::AffineSubspace<Q> rf = ref::implicit_lagrangian_fields(l, none, none, q, v);
  const fast::AffineSubspace ff = fast::implicit_lagrangian_fields(fl, qd, vd);
  const double tol =
      1e-9 * (1 + qd.norm() + vd.norm()) * (1 + fl.vv.norm() + fl.qv.norm() + fl.qq.norm() + fl.q.norm() + fl.v.norm());
  RC_ASSERT((fast::legendre(fl, qd, vd) - to_double(ref::legendre(l, q, v))).norm() <= tol);
  RC_ASSERT((fast::dirac_differential(fl, qd, vd) - to_double(ref::dirac_differential(l, none, none, q, v))).norm() <=
            tol);
  RC_ASSERT(!tally("implicit Lagrangian: fields exist", ff.certain.yes(), ff.empty == rf.empty));
  if (rf.empty || ff.empty || !ff.certain.yes()) return;
  RC_ASSERT(ff.direction.dim() == static_cast<int>(rf.direction.dim()));
  const Eigen::VectorXd gap = to_double(rf.point) - ff.point;
  const Eigen::MatrixXd& dir = ff.direction.columns();
  RC_ASSERT((gap - dir * (dir.transpose() * gap)).norm() <= tol);
}

// Prop 3.5's gap on the smallest example: n = 2, Δ = TQ, L = ½ v₀² (A = diag(1, 0)).  At q = 0, v = (1, 2),
// p = FL = (1, 0), the rate q̇ = (1, 3), v̇ = 0, ṗ = 0 lies in 𝒞 and satisfies (3.17), not (3.13) (q̇ ≠ v);
// q̇ = v satisfies both.
TEST(YoshimuraMarsden, Prop3_5_HalfV0SquaredLosesQdotEqualsV) {
  ref::PontryaginInput<Q> l{2, QM(0, 2), QM(2, 2), QM(2, 2), QM(2, 2), std::vector<Q>(2), std::vector<Q>(2)};
  l.vv(0, 0) = Q(1);
  const std::vector<Q> x{Q(0), Q(0), Q(1), Q(2), Q(1), Q(0)};
  const std::vector<Q> solution{Q(1), Q(2), Q(0), Q(0), Q(0), Q(0)}, planted{Q(1), Q(3), Q(0), Q(0), Q(0), Q(0)};
  const QM none(2, 2);
  EXPECT_TRUE(ref::satisfies_ldap(l, none, none, x, solution));
  EXPECT_TRUE(ref::satisfies_intrinsic_ldap(l, x, solution));
  EXPECT_TRUE(ref::satisfies_intrinsic_ldap(l, x, planted));
  EXPECT_FALSE(ref::satisfies_ldap(l, none, none, x, planted));
}

// fast never certain and wrong on an ill-conditioned K: K = [2²³, 2²³ + 1], ∂H/∂p = b = (1, −1) at z = 0, so
// K ∂H/∂p = −1 and there are no fields (and likewise for the Lagrangian fields at v = (1, −1)).
TEST(FastVsReference, ImplicitFieldsOnAnIllConditionedK) {
  fast::HamiltonianInput h;
  h.n = 2;
  h.k = Eigen::MatrixXd(1, 2);
  h.k << std::ldexp(1.0, 23), std::ldexp(1.0, 23) + 1;
  h.pp = h.qp = h.qq = Eigen::MatrixXd::Zero(2, 2);
  h.q = Eigen::VectorXd::Zero(2);
  h.p = Eigen::VectorXd(2);
  h.p << 1, -1;
  const fast::AffineSubspace f = fast::implicit_hamiltonian_fields(h, Eigen::VectorXd::Zero(4));
  EXPECT_TRUE(f.empty || !f.certain.yes());
  fast::PontryaginInput l;
  l.n = 2;
  l.k = h.k;
  l.vv = l.qv = l.qq = Eigen::MatrixXd::Zero(2, 2);
  l.q = l.v = Eigen::VectorXd::Zero(2);
  Eigen::VectorXd v(2);
  v << 1, -1;
  const fast::AffineSubspace g = fast::implicit_lagrangian_fields(l, Eigen::VectorXd::Zero(2), v);
  EXPECT_TRUE(g.empty || !g.certain.yes());
}
