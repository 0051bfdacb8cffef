// Golden: the 4-port LC circuit of CEF §6–§7 (and YM §6), exactly, at several rational values of
// L, C1, C2, C3 (one of them with negative values: CEF §6 says the CAD stops at M_3 regardless of
// signs).  Every printed result is asserted against the reference's computation:
//   M_1, M_2 and M_3 = (6.36) as sets, c = 3 (§6 before (6.36));  W_3 = (6.37) + d/dt (6.36), rank 2,
//   symplectic leaves;  the ODE after (6.36);  the leaf (6.38)–(6.42), H(q_L, p_L) and (6.43)–(6.44);
//   the whole 14×14 Σ (ERRATA: row 8 corrected);  [{E, ε_j}], λ⁹, λ¹¹ and X (ERRATA: the column);
//   the 16×16 Dirac bracket of §7 with its block A, and J*·∇E = X (ERRATA: the §7 gradient);
//   §7 on T*TQ: dims and the classes of the 14 constraints;  YM §6 reduced equations (ERRATA: YM's
//   misprinted vector).
// Each misprint is guarded twice: the corrected value is asserted, and the printed one is shown to fail.
#include "dcad/reference/adapted.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/reference/symplectic.hpp"

#include <gtest/gtest.h>

using namespace dcad::reference;
using Q = Rational;
using QM = Matrix<Q>;

namespace {

// y = (q_L, q_C1, q_C2, q_C3, v_L, …, v_C3, p_L, …, p_C3, ν_L, …, ν_C3) ∈ Q^16.
enum : Index { qL = 0, qC1, qC2, qC3, vL, vC1, vC2, vC3, pL, pC1, pC2, pC3, nL, nC1, nC2, nC3 };

struct Circuit {
  Q l, c1, c2, c3;
};

/// Ω = dq ∧ dp + dv ∧ dν (ERRATA, Appendix A).
QM omega() {
  QM w(16, 16);
  for (Index i = 0; i < 4; ++i) {
    w(qL + i, pL + i) = Q(1);
    w(pL + i, qL + i) = Q(-1);
    w(vL + i, nL + i) = Q(1);
    w(nL + i, vL + i) = Q(-1);
  }
  return w;
}

/// ε_1 … ε_14 of CEF (leaf through x0 with q_L0 = q_C20, q_C10 − q_C20 + q_C30 = 0), rows [a | 0].
QM epsilons(const Circuit& c) {
  QM e(14, 17);
  const auto set = [&](Index row, std::initializer_list<std::pair<Index, Q>> terms) {
    for (const auto& [var, coeff] : terms) e(row, var) = coeff;
  };
  set(0, {{pL, 1}, {vL, -c.l}});
  set(1, {{pC1, 1}});
  set(2, {{pC2, 1}});
  set(3, {{pC3, 1}});
  set(4, {{vL, 1}, {vC2, -1}});
  set(5, {{vC1, 1}, {vC2, -1}, {vC3, 1}});
  set(6, {{qC1, 1 / c.c1}, {qC3, -1 / c.c3}});
  set(7, {{vC1, 1 / c.c1}, {vC3, -1 / c.c3}});
  set(8, {{qL, 1}, {qC2, -1}});
  set(9, {{qC1, 1}, {qC2, -1}, {qC3, 1}});
  set(10, {{nL, 1}});
  set(11, {{nC1, 1}});
  set(12, {{nC2, 1}});
  set(13, {{nC3, 1}});
  return e;
}

/// CEF §6: Δ by (6.29)–(6.30), L(q, v) = ½ L v_L² − ½ Σ q_Ci²/C_i; x = (q, v, p) ∈ Q^12.
PontryaginInput<Q> cef_input(const Circuit& c) {
  PontryaginInput<Q> in;
  in.n = 4;
  in.k = QM::from_rows({{-1, 0, 1, 0}, {0, -1, 1, -1}}, 4);
  in.vv = QM(4, 4);
  in.vv(0, 0) = c.l;
  in.qq = QM(4, 4);
  in.qq(1, 1) = -1 / c.c1;
  in.qq(2, 2) = -1 / c.c2;
  in.qq(3, 3) = -1 / c.c3;
  in.qv = QM(4, 4);
  in.q.assign(4, Q(0));
  in.v.assign(4, Q(0));
  return in;
}

/// Rows a (a·x = 0) from sparse terms over the given number of coordinates.
QM equations(Index cols, std::initializer_list<std::initializer_list<std::pair<Index, Q>>> rows) {
  QM m(rows.size(), cols);
  Index r = 0;
  for (const auto& row : rows) {
    for (const auto& [var, coeff] : row) m(r, var) = coeff;
    ++r;
  }
  return m;
}

/// The point (6.38)–(6.42) of the leaf through x0 = 0 with coordinates (q_L, p_L) = (a, b), in
/// (q, v, p, ν) ∈ Q^16 (the first 12 entries are the point of the Pontryagin bundle).
std::vector<Q> leaf_point(const Circuit& c, const Q& a, const Q& b) {
  const Q s13 = c.c1 + c.c3;
  return {a,       c.c1 * a / s13,
          a,       c.c3 * a / s13,
          b / c.l, c.c1 * b / (c.l * s13),
          b / c.l, c.c3 * b / (c.l * s13),
          b,       0,
          0,       0,
          0,       0,
          0,       0};
}

std::vector<Q> first(const std::vector<Q>& y, Index n) { return std::vector<Q>(y.begin(), y.begin() + n); }

/// (x, ẋ) for each vector x of the canonical basis of M_c (a linear subspace here), ẋ the velocity the
/// reference solves from D; a point without a unique velocity is a test failure.
std::vector<std::pair<std::vector<Q>, std::vector<Q>>> motion_on_basis(const LinearSystem<Q>& s,
                                                                       const CadResult<Q>& r) {
  std::vector<std::pair<std::vector<Q>, std::vector<Q>>> out;
  const QM& basis = r.final_step().m.direction.basis();
  for (Index b = 0; b < basis.rows(); ++b) {
    std::vector<Q> x(basis.cols());
    for (Index i = 0; i < x.size(); ++i) x[i] = basis(b, i);
    const AffineSubspace<Q> vel = velocities(s, r, x);
    if (vel.empty || vel.direction.dim() != 0)
      ADD_FAILURE() << "no unique velocity at basis vector " << b;
    else
      out.emplace_back(x, vel.point);
  }
  return out;
}

class FourPort : public testing::TestWithParam<Circuit> {};

}  // namespace

TEST_P(FourPort, SigmaCorrectedEntriesAndDeterminant) {
  const Circuit c = GetParam();
  const ConstraintClasses<Q> cl = classify_constraints(omega(), epsilons(c));
  const QM sigma = gradients(epsilons(c)) * poisson_tensor(omega()) * gradients(epsilons(c)).transpose();
  EXPECT_EQ(cl.s, 7u) << "all 14 constraints are second class (x0 + W̃_3 is symplectic)";
  EXPECT_EQ(cl.first.rows(), 0u);
  // printed entries that are right, with the ERRATA sign convention (1-based in the paper)
  EXPECT_EQ(sigma(0, 8), Q(-1));  // Σ₁,₉ = {p_L − L v_L, q_L − q_C2}
  EXPECT_EQ(sigma(0, 10), -c.l);  // Σ₁,₁₁
  EXPECT_EQ(sigma(1, 6), -1 / c.c1);
  EXPECT_EQ(sigma(3, 6), 1 / c.c3);
  // row 8, corrected: Σ₈,₁₂ = 1/C1, Σ₈,₁₄ = −1/C3 and zero where the paper prints them
  EXPECT_EQ(sigma(7, 11), 1 / c.c1);
  EXPECT_EQ(sigma(7, 13), -1 / c.c3);
  EXPECT_EQ(sigma(7, 10), Q(0));
  EXPECT_EQ(sigma(7, 12), Q(0));
  EXPECT_TRUE(is_skew(sigma));
  // det Σ = L² (C1 + C3)⁴ / (C1⁴ C3⁴)
  const Q s13 = c.c1 + c.c3;
  EXPECT_EQ(determinant(sigma),
            c.l * c.l * s13 * s13 * s13 * s13 / (c.c1 * c.c1 * c.c1 * c.c1 * c.c3 * c.c3 * c.c3 * c.c3));
  // the Dirac bracket of the leaf coordinates: {q_L, p_L}* = +1 (block A of §7, A₁,₅)
  EXPECT_EQ(cl.dirac_tensor(qL, pL), Q(1));
  // the whole Σ as printed after (6.42), 1-based as in the paper, row 8 corrected (ERRATA)
  QM printed(14, 14);
  const auto at = [&](Index i, Index j, const Q& v) { printed(i - 1, j - 1) = v; };
  at(1, 9, -1), at(1, 11, -c.l);
  at(2, 7, -1 / c.c1), at(2, 10, -1);
  at(3, 9, 1), at(3, 10, 1);
  at(4, 7, 1 / c.c3), at(4, 10, -1);
  at(5, 11, 1), at(5, 13, -1);
  at(6, 12, 1), at(6, 13, -1), at(6, 14, 1);
  at(7, 2, 1 / c.c1), at(7, 4, -1 / c.c3);
  at(8, 12, 1 / c.c1), at(8, 14, -1 / c.c3);  // printed at (8, 11) and (8, 13)
  at(9, 1, 1), at(9, 3, -1);
  at(10, 2, 1), at(10, 3, -1), at(10, 4, 1);
  at(11, 1, c.l), at(11, 5, -1);
  at(12, 6, -1), at(12, 8, -1 / c.c1);
  at(13, 5, 1), at(13, 6, 1);
  at(14, 6, -1), at(14, 8, 1 / c.c3);
  EXPECT_EQ(sigma, printed);
  EXPECT_EQ(cl.sigma.rows(), 14u);
  // the misprinted row 8 makes Σ neither skew nor invertible (ERRATA)
  QM misprinted = printed;
  misprinted(7, 11) = misprinted(7, 13) = Q(0);
  misprinted(7, 10) = 1 / c.c1, misprinted(7, 12) = -1 / c.c3;
  EXPECT_FALSE(is_skew(misprinted));
  EXPECT_EQ(determinant(misprinted), Q(0));
}

// CEF §6, before (6.36): M_1 = {p_L = L v_L, p_C = 0, v ∈ Δ}, M_2 adds q_C1/C1 = q_C3/C3 (the KVL of the
// capacitor loop, Thm 6.4), M_3 = (6.36) adds v_C1/C1 = v_C3/C3, and the CAD stops there (c = 3): the
// printed equations define the same sets as the tower the reference computes from (6.10)–(6.13).
TEST_P(FourPort, Section6_TowerIsM1M2M3AsPrinted) {
  const Circuit c = GetParam();
  const CadResult<Q> r = constraint_tower(pontryagin_system(cef_input(c)));
  ASSERT_TRUE(r.consistent);
  ASSERT_EQ(r.steps, 3u);
  const QM m1 = equations(12, {{{pL, 1}, {vL, -c.l}},
                               {{pC1, 1}},
                               {{pC2, 1}},
                               {{pC3, 1}},
                               {{vL, 1}, {vC2, -1}},
                               {{vC1, 1}, {vC2, -1}, {vC3, 1}}});
  const QM m2 = vstack(m1, equations(12, {{{qC1, 1 / c.c1}, {qC3, -1 / c.c3}}}));
  const QM m3 = vstack(m2, equations(12, {{{vC1, 1 / c.c1}, {vC3, -1 / c.c3}}}));
  EXPECT_EQ(r.tower[1].m, solve(m1, std::vector<Q>(m1.rows(), Q(0))));
  EXPECT_EQ(r.tower[2].m, solve(m2, std::vector<Q>(m2.rows(), Q(0))));
  EXPECT_EQ(r.tower[3].m, solve(m3, std::vector<Q>(m3.rows(), Q(0))));
  EXPECT_EQ(r.tower[3].dim(), 4);  // "M_3, which has dimension 4"
  EXPECT_EQ(r.tower[0].dim(), 12);
  // W_3 = T M_3 ∩ E_D is (6.37) with d/dt (6.36): rank 2, and ω = dq ∧ dp is nondegenerate on it
  const QM w637 = equations(12, {{{qL, 1}, {qC2, -1}}, {{qC1, 1}, {qC2, -1}, {qC3, 1}}});
  EXPECT_EQ(r.tower[3].w, Subspace<Q>::solutions(vstack(m3, w637)));
  EXPECT_EQ(r.tower[3].w.dim(), 2u);
  QM omega12(12, 12);
  for (Index i = 0; i < 4; ++i) omega12(qL + i, 8 + i) = Q(1), omega12(8 + i, qL + i) = Q(-1);
  EXPECT_EQ(form_rank(restrict_form(omega12, r.tower[3].w)), 2u);
}

// CEF §6 after (6.36): with (q_L, q_C1, q_C2, p_L) as independent variables the equations of motion on
// M_3 are q̇_L = p_L/L, q̇_C1 = C1 p_L/(L(C1+C3)), q̇_C2 = p_L/L, ṗ_L = −q_C1/C1 − q_C2/C2; every solution
// of the CAD also satisfies (6.31)–(6.35).  Checked on a basis of M_3, against the velocities the
// reference solves from D (unique: c = 3 and ker ω_D ∩ T M_3 = 0).
TEST_P(FourPort, Section6_EquationsOfMotionOnM3) {
  const Circuit c = GetParam();
  const LinearSystem<Q> s = pontryagin_system(cef_input(c));
  const CadResult<Q> r = constraint_tower(s);
  ASSERT_TRUE(r.unique());
  const Q s13 = c.c1 + c.c3;
  for (const auto& [x, dx] : motion_on_basis(s, r)) {
    EXPECT_EQ(dx[qL], x[pL] / c.l);
    EXPECT_EQ(dx[qC1], c.c1 / (c.l * s13) * x[pL]);
    EXPECT_EQ(dx[qC2], x[pL] / c.l);
    EXPECT_EQ(dx[pL], -x[qC1] / c.c1 - x[qC2] / c.c2);
    for (Index i = 0; i < 4; ++i) EXPECT_EQ(dx[qL + i], x[vL + i]);               // (6.31)
    EXPECT_EQ(dx[pL] + x[qC1] / c.c1 + dx[pC1] + x[qC2] / c.c2 + dx[pC2], Q(0));  // (6.32)
    EXPECT_EQ(dx[pL] + x[qC2] / c.c2 + dx[pC2] + x[qC3] / c.c3 + dx[pC3], Q(0));  // (6.33)
    EXPECT_EQ(x[pL], c.l * x[vL]);                                                // (6.34)
    EXPECT_EQ(x[vL], x[vC2]);                                                     // (6.35)
    EXPECT_EQ(x[vC1], x[vC2] - x[vC3]);
  }
}

// CEF §6, (6.38)–(6.44): the leaf x0 + W̃_3 through x0 = 0 is the graph (6.38)–(6.41) over (q_L, p_L),
// ω pulls back to dq_L ∧ dp_L, E restricted to it is H = p_L²/(2L) + q_L²/2 (1/(C1+C3) + 1/C2), and the
// motion there is Hamilton's (6.43)–(6.44).  E is the system's energy ½ xᵀ H x + g·x, not the formula.
TEST_P(FourPort, Section6_LeafHamiltonianAndMotion) {
  const Circuit c = GetParam();
  const LinearSystem<Q> s = pontryagin_system(cef_input(c));
  const CadResult<Q> r = constraint_tower(s);
  ASSERT_TRUE(r.unique());
  const Q k = 1 / (c.c1 + c.c3) + 1 / c.c2;
  const std::vector<Q> e_q = first(leaf_point(c, 1, 0), 12), e_p = first(leaf_point(c, 0, 1), 12);
  EXPECT_EQ(r.tower[3].w, Subspace<Q>::span(QM::from_rows({e_q, e_p}, 12)));
  QM omega12(12, 12);
  for (Index i = 0; i < 4; ++i) omega12(qL + i, 8 + i) = Q(1), omega12(8 + i, qL + i) = Q(-1);
  EXPECT_EQ(form_value(omega12, e_q, e_p), Q(1));  // ω_c = dq_L ∧ dp_L
  for (const auto& [a, b] : std::vector<std::pair<Q, Q>>{{3, 5}, {-2, 7}, {Q(1) / 3, 0}, {0, Q(-5) / 2}}) {
    const std::vector<Q> x = first(leaf_point(c, a, b), 12);
    ASSERT_TRUE(r.final_step().m.contains_point(x));
    const Q energy = (QM::from_rows({x}, 12) * s.hessian * QM::column(x))(0, 0) / 2;
    EXPECT_EQ(energy, b * b / (2 * c.l) + a * a / 2 * k);  // H(q_L, p_L); g = 0 here
    const AffineSubspace<Q> vel = velocities(s, r, x);
    ASSERT_FALSE(vel.empty);
    EXPECT_EQ(vel.point[qL], b / c.l);               // (6.43) ∂H/∂p_L
    EXPECT_EQ(vel.point[pL], -a * k);                // (6.44) −∂H/∂q_L
    EXPECT_TRUE(contains(r.tower[3].w, vel.point));  // the flow preserves the leaf
  }
}

// §7 on T*TQ: the CAD on S' = {ν = 0} with leaves {κ·q = C} gives dims 12, 6, 5, 4; all 14
// constraints of S_0 are second class (s' = 4 from ν, a' − s' = 0: E_AT = E); X = J* dE at points
// of every leaf reproduces the motion: on the leaf through (6.38)–(6.41), q̇_L = p_L/L,
// ṗ_L = −ω² L q_L with ω² = (C1+C2+C3)/(L C2 (C1+C3)), and ν̇ = 0 (ERRATA: labels of X).
TEST_P(FourPort, Section7_DiracBracketMotion) {
  const Circuit c = GetParam();
  const FoliatedEmbedding<Q> f = tangent_cotangent_embedding(cef_input(c));
  const CadResult<Q> r = foliated_tower(f);
  ASSERT_TRUE(r.consistent);
  std::vector<long> dims;
  for (const auto& st : r.tower) dims.push_back(st.dim());
  EXPECT_EQ(dims, (std::vector<long>{12, 6, 5, 4}));
  const AdaptedToPrimary<Q> to = adapted_to_primary(f.omega, f.primary, secondary_constraints(r), f.leaf);
  const QM& all = to.constraints;
  const AdaptedConstraints<Q>& ad = to.adapted;
  EXPECT_EQ(all.rows(), 14u);
  EXPECT_EQ(2 * ad.s, 14u);
  EXPECT_TRUE(ad.abridged.empty());  // a' − s' = 0 = d^(c): E_AT = E
  // the point of (6.38)–(6.41) with q_L = 3, p_L = 5 (leaf C = 0)
  const Q a = 3, b = 5, s13 = c.c1 + c.c3;
  std::vector<Q> y = leaf_point(c, a, b);
  ASSERT_TRUE(r.final_step().m.contains_point(y));
  const std::vector<Q> x = abridged_field(ad, all, f.hessian, f.gradient, y, {});
  const Q omega2 = (c.c1 + c.c2 + c.c3) / (c.l * c.c2 * s13);
  EXPECT_EQ(x[qL], b / c.l);
  EXPECT_EQ(x[qC1], c.c1 * b / (c.l * s13));
  EXPECT_EQ(x[qC2], b / c.l);
  EXPECT_EQ(x[pL], -omega2 * c.l * a);
  for (Index i = pC1; i <= pC3; ++i) EXPECT_EQ(x[i], Q(0));
  for (Index i = nL; i <= nC3; ++i) EXPECT_EQ(x[i], Q(0));
  // at a point of S on another leaf (y plus every direction of M_c, which moves κ·q off 0), X is
  // tangent to that leaf S_C
  const AffineSubspace<Q>& sfin = r.final_step().m;
  std::vector<Q> z = y;
  for (Index i = 0; i < sfin.direction.dim(); ++i)
    for (Index k = 0; k < z.size(); ++k) z[k] += sfin.direction.basis()(i, k);
  ASSERT_TRUE(sfin.contains_point(z));
  EXPECT_NE((gradients(f.leaf) * QM::column(z)).col(0), std::vector<Q>(2, Q(0)));
  const std::vector<Q> xz = abridged_field(ad, all, f.hessian, f.gradient, z, {});
  EXPECT_TRUE(contains(intersection(sfin.direction, kernel(gradients(f.leaf))), xz));
}

// CEF §7, "The concrete example of an LC circuit of section 6 revisited": all 14 constraints are second
// class, and the Dirac bracket of y = (q, v, p, ν) is [[0, A, 0], [−Aᵀ, 0, 0], [0, 0, 0]] (blocks 4, 5, 7)
// with the printed 4×5 block A.  The product with ∇E at points of M_3 is X of §6: ∇E is the embedding's
// dE(y) = H y + g, equal to the corrected gradient (ERRATA: §7 gradient); the printed gradient gives
// another field.
TEST_P(FourPort, Section7_DiracBracketMatrixAsPrinted) {
  const Circuit c = GetParam();
  const ConstraintClasses<Q> cl = classify_constraints(omega(), epsilons(c));
  const Q s13 = c.c1 + c.c3, l = c.l, c1 = c.c1, c3 = c.c3;
  const std::vector<std::vector<Q>> a = {
      {1 / l, c1 / (s13 * l), 1 / l, c3 / (s13 * l), 1},
      {c1 / (s13 * l), c1 * c1 / (s13 * s13 * l), c1 / (s13 * l), c1 * c3 / (s13 * s13 * l), c1 / s13},
      {1 / l, c1 / (s13 * l), 1 / l, c3 / (s13 * l), 1},
      {c3 / (s13 * l), c1 * c3 / (s13 * s13 * l), c3 / (s13 * l), c3 * c3 / (s13 * s13 * l), c3 / s13}};
  QM printed(16, 16);
  for (Index i = 0; i < 4; ++i)
    for (Index j = 0; j < 5; ++j) printed(i, 4 + j) = a[i][j], printed(4 + j, i) = -a[i][j];
  EXPECT_EQ(cl.dirac_tensor, printed);
  const FoliatedEmbedding<Q> f = tangent_cotangent_embedding(cef_input(c));
  for (const auto& [qa, pb] : std::vector<std::pair<Q, Q>>{{3, 5}, {-7, Q(1) / 2}}) {
    const std::vector<Q> y = leaf_point(c, qa, pb);
    std::vector<Q> grad = (f.hessian * QM::column(y)).col(0);
    for (Index i = 0; i < 16; ++i) grad[i] += f.gradient[i];
    const std::vector<Q> corrected = {0,
                                      y[qC1] / c1,
                                      y[qC2] / c.c2,
                                      y[qC3] / c3,
                                      y[pL] - l * y[vL],
                                      y[pC1],
                                      y[pC2],
                                      y[pC3],
                                      y[vL],
                                      y[vC1],
                                      y[vC2],
                                      y[vC3],
                                      0,
                                      0,
                                      0,
                                      0};
    EXPECT_EQ(grad, corrected);
    const Q g = y[qC1] / c1 + y[qC2] / c.c2;
    const std::vector<Q> x = {
        y[vL], y[vC1], y[vC2], y[vC3], -g / l, -c1 / s13 * g / l, -g / l, -c3 / s13 * g / l, -g, 0, 0, 0, 0, 0, 0, 0};
    EXPECT_EQ((cl.dirac_tensor * QM::column(grad)).col(0), x);
    std::vector<Q> misprinted = corrected;
    for (Index i = qC1; i <= qC3; ++i) misprinted[i] = -corrected[i];
    misprinted[vL] = y[pL] - y[vL];
    EXPECT_NE((cl.dirac_tensor * QM::column(misprinted)).col(0), x);
  }
}

// §6 after (6.44): λ_(3) = Σ⁻¹ [{E, ε_j}] with the corrected column (ERRATA: 14 entries,
// (0, +q_C1/C1, +q_C2/C2, +q_C3/C3, 0, …)), λ⁹ = q_C1/C1 + q_C2/C2, λ¹¹ = −(q_C1/C1 + q_C2/C2)/L, and
// X = dE^♯ + λ^j X_{ε_j} as printed (last four components ν̇ = 0, ERRATA: labels of X).
TEST_P(FourPort, MultipliersAndVectorField) {
  const Circuit c = GetParam();
  const QM w = omega(), j = poisson_tensor(w), a = gradients(epsilons(c));
  const QM sigma = a * j * a.transpose();
  const Q s13 = c.c1 + c.c3;
  const std::vector<Q> y = leaf_point(c, 3, 5);  // the point of (6.38)–(6.41), leaf x0 = 0
  // dE(y) = (Ψ q, p − Φ v, v, 0) (ERRATA: dE = (Ψq, p − Φv, v))
  std::vector<Q> de(16, Q(0));
  const Q psi[4] = {0, 1 / c.c1, 1 / c.c2, 1 / c.c3};
  for (Index i = 0; i < 4; ++i) {
    de[qL + i] = psi[i] * y[qL + i];
    de[vL + i] = y[pL + i] - (i == 0 ? c.l : Q(0)) * y[vL + i];
    de[pL + i] = y[vL + i];
  }
  const std::vector<Q> braces = (a * j.transpose() * QM::column(de)).col(0);  // {E, ε_j} = dEᵀ J a_j
  std::vector<Q> want(14, Q(0));
  want[1] = y[qC1] / c.c1;
  want[2] = y[qC2] / c.c2;
  want[3] = y[qC3] / c.c3;
  EXPECT_EQ(braces, want);
  const std::vector<Q> lambda = (inverse(sigma) * QM::column(braces)).col(0);
  const Q f = y[qC1] / c.c1 + y[qC2] / c.c2;
  EXPECT_EQ(lambda[8], f);
  EXPECT_EQ(lambda[10], -f / c.l);
  std::vector<Q> x = (j * QM::column(de)).col(0);  // dE^♯ + λ^j X_{ε_j}, X_g = J dg
  const std::vector<Q> xe = (j * a.transpose() * QM::column(lambda)).col(0);
  for (Index i = 0; i < 16; ++i) x[i] += xe[i];
  const std::vector<Q> printed = {
      y[vL], y[vC1], y[vC2], y[vC3], -f / c.l, -c.c1 / s13 * f / c.l, -f / c.l, -c.c3 / s13 * f / c.l, -f, 0, 0,
      0,     0,      0,      0,      0};
  EXPECT_EQ(x, printed);
}

// YM §6 (L-C example): with YM's KCL ω¹ = −dq_L + dq_C2, ω² = −dq_C1 + dq_C2 − dq_C3, A = [[−1, 0], [−1, 1]]
// (f_L, f_C1) = −A (f_C2, f_C3), p̃_C2 = p_C2 + p_L + p_C1 and p̃_C3 = p_C3 − p_C1, every solution of the
// CAD system (CEF §6) satisfies YM's reduced equations
//   q̇_C1 = f_C2 − f_C3, q̇_C2 = f_C2, q̇_C3 = f_C3, d/dt p̃_C2 = −q_C1/C1 − q_C2/C2, p̃_C2 = L f_C2,
//   0 = −q_C3/C3 + q_C1/C1,
// and the matrix form with the corrected vector (ṗ_L, ṗ_C1 + q_C1/C1) — ERRATA: YM prints ṗ_C1 + q_C2/C3,
// which fails on M_c.
TEST_P(FourPort, YoshimuraMarsden6ReducedEquations) {
  const Circuit c = GetParam();
  PontryaginInput<Q> in;
  in.n = 4;
  in.k = QM(2, 4);
  in.k(0, 0) = Q(-1), in.k(0, 2) = Q(1);                      // ω¹ = −dq_L + dq_C2
  in.k(1, 1) = Q(-1), in.k(1, 2) = Q(1), in.k(1, 3) = Q(-1);  // ω² = −dq_C1 + dq_C2 − dq_C3
  in.vv = QM(4, 4);
  in.vv(0, 0) = c.l;
  in.qq = QM(4, 4);
  in.qq(1, 1) = -1 / c.c1, in.qq(2, 2) = -1 / c.c2, in.qq(3, 3) = -1 / c.c3;
  in.qv = QM(4, 4);
  in.q.assign(4, Q(0));
  in.v.assign(4, Q(0));
  const LinearSystem<Q> s = pontryagin_system(in);
  const CadResult<Q> r = constraint_tower(s);
  ASSERT_TRUE(r.unique());
  ASSERT_EQ(r.final_step().m.direction.dim(), 4);
  enum : Index { q = 0, v = 4, p = 8 };  // q_L … q_C3, v_L … v_C3 (= f), p_L … p_C3
  const Index L = 0, C1 = 1, C2 = 2, C3 = 3;
  bool printed_fails = false;
  for (const auto& [x, dx] : motion_on_basis(s, r)) {
    EXPECT_EQ(dx[q + C1], x[v + C2] - x[v + C3]);
    EXPECT_EQ(dx[q + C2], x[v + C2]);
    EXPECT_EQ(dx[q + C3], x[v + C3]);
    EXPECT_EQ(x[p + C2] + x[p + L] + x[p + C1], c.l * x[v + C2]);                          // p̃_C2 = L f_C2
    EXPECT_EQ(x[p + C3] - x[p + C1], Q(0));                                                // p̃_C3 = 0
    EXPECT_EQ(dx[p + C2] + dx[p + L] + dx[p + C1], -x[q + C1] / c.c1 - x[q + C2] / c.c2);  // d/dt p̃_C2
    EXPECT_EQ(-x[q + C3] / c.c3 + x[q + C1] / c.c1, Q(0));
    // matrix form: (ṗ_C2 + q_C2/C2, ṗ_C3 + q_C3/C3) = [[−1, −1], [0, 1]] (ṗ_L, ṗ_C1 + q_C1/C1)
    const Q u1 = dx[p + L], u2 = dx[p + C1] + x[q + C1] / c.c1;
    EXPECT_EQ(dx[p + C2] + x[q + C2] / c.c2, -u1 - u2);
    EXPECT_EQ(dx[p + C3] + x[q + C3] / c.c3, u2);
    const Q printed_u2 = dx[p + C1] + x[q + C2] / c.c3;
    printed_fails = printed_fails || dx[p + C3] + x[q + C3] / c.c3 != printed_u2;
  }
  EXPECT_TRUE(printed_fails);
}

// Stable ctest names for the four circuits (proptests/papers.tsv cites them; the default printed the bytes).
std::string circuit_name(const testing::TestParamInfo<Circuit>& i) {
  static const char* const names[] = {"integers", "ones", "component_scales", "signed"};
  return names[i.index];
}

INSTANTIATE_TEST_SUITE_P(CEF6, FourPort,
                         testing::Values(Circuit{Q(2), Q(3), Q(5), Q(7)}, Circuit{Q(1), Q(1), Q(1), Q(1)},
                                         Circuit{Q(1) / Q(1000), Q(22) / Q(1000000), Q(47) / Q(1000000000),
                                                 Q(1) / Q(3)},
                                         Circuit{Q(-2), Q(5), Q(-3), Q(4)}),
                         circuit_name);
