// Unit tests of the exact reference: row reduction, exact numbers, bad input, and that the
// templates also compile over cpp_rational.
#include "dcad/reference/dirac.hpp"
#include "dcad/reference/implicit_lagrangian.hpp"
#include "dcad/reference/rlc.hpp"
#include "dcad/reference/rational.hpp"

#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

using namespace dcad::reference;
using Q = Rational;
using QM = Matrix<Q>;

static QM m(std::vector<std::vector<Q>> rows) { return QM::from_rows(rows, rows.empty() ? 0 : rows[0].size()); }

static_assert(is_exact_field<Q>::value, "mpq_rational is exact");
static_assert(!is_exact_field<double>::value, "double must be rejected by the reference");
static_assert(!is_exact_field<long>::value, "integers are not a field");

TEST(Rref, KnownMatrix) {
  const Rref<Q> e = rref(m({{2, 4, 6}, {1, 2, 4}, {3, 6, 10}}));
  EXPECT_EQ(e.pivots, (std::vector<Index>{0, 2}));
  EXPECT_EQ(e.r, m({{1, 2, 0}, {0, 0, 1}}));
  EXPECT_EQ(nullspace(m({{2, 4, 6}, {1, 2, 4}})), m({{-2, 1, 0}}));
}

TEST(Rref, InverseAndSingular) {
  EXPECT_EQ(inverse(m({{2, 1}, {1, 1}})), m({{1, -1}, {-1, 2}}));
  EXPECT_THROW(inverse(m({{1, 2}, {2, 4}})), std::invalid_argument);
}

TEST(Subspace, Operations) {
  const Subspace<Q> u = Subspace<Q>::span(m({{1, 0, 0}, {0, 1, 0}})), w = Subspace<Q>::span(m({{0, 1, 0}, {0, 0, 1}}));
  EXPECT_EQ(intersection(u, w), Subspace<Q>::span(m({{0, 1, 0}})));
  EXPECT_EQ(sum(u, w).dim(), 3u);
  EXPECT_EQ(annihilator(u), Subspace<Q>::span(m({{0, 0, 1}})));
  EXPECT_TRUE(contains(sum(u, w), u));
  EXPECT_FALSE(contains(u, w));
  EXPECT_EQ(preimage(m({{1, 1, 0}}), Subspace<Q>::zero(1)), Subspace<Q>::span(m({{1, -1, 0}, {0, 0, 1}})));
  EXPECT_EQ(image(m({{1, 2}, {2, 4}})), Subspace<Q>::span(m({{1, 2}})));
}

TEST(Rational, ParsesExactly) {
  EXPECT_EQ(parse_rational("3"), Q(3));
  EXPECT_EQ(parse_rational("-2/7"), Q(-2) / Q(7));
  EXPECT_EQ(parse_rational("0.125"), Q(1) / Q(8));
  EXPECT_EQ(parse_rational("0.1"), Q(1) / Q(10));  // not the double 0.1000000000000000055…
  EXPECT_EQ(parse_rational("1e-3"), Q(1) / Q(1000));
  // leading zeros are decimal, not octal (Boost's mpz_int("010") is 8: "0.010" was read as 1/125;
  // found by fuzz_netlist, proptests/fuzz/regressions/netlist/leading-zero-digits)
  EXPECT_EQ(parse_rational("0.010"), Q(1) / Q(100));
  EXPECT_EQ(parse_rational("010"), Q(10));
  EXPECT_EQ(parse_rational("08"), Q(8));
  EXPECT_EQ(parse_rational("3/010"), Q(3) / Q(10));
  EXPECT_EQ(parse_rational("000861293337707602830"), Q(boost::multiprecision::mpz_int("861293337707602830")));
  EXPECT_EQ(parse_rational("-0.00"), Q(0));
  EXPECT_EQ(parse_rational("-1.5E+2"), Q(-150));
  EXPECT_EQ(parse_rational("-1.00000000000000001"), Q(-100000000000000001) / Q(100000000000000000));
  for (const char* bad : {"", "1/0", "abc", "1/2/3", "1.5/2", "--1", "1e", "0x10", "nan", "inf", "1 "})
    EXPECT_THROW(parse_rational(bad), std::invalid_argument) << bad;
}

TEST(BadInput, MessagesNameFunctionExpectedFound) {
  const QM nonsquare(2, 3), nonskew = m({{0, 1}, {2, 0}}), degenerate = m({{0, 0}, {0, 0}});
  const auto message = [](auto f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_EQ(message([&] { symplectic_complement(nonsquare, Subspace<Q>::zero(2)); }),
            "symplectic_complement: expected a square matrix, found 2x3");
  EXPECT_EQ(message([&] { dirac_from_presymplectic(nonskew); }),
            "dirac_from_presymplectic: expected a skew matrix (W = -Wᵀ), found a matrix that is not skew");
  EXPECT_EQ(message([&] {
              sharp(degenerate, std::vector<Q>{1, 0});
            }),
            "sharp: expected a nondegenerate form (rank 2), found rank 0");
  EXPECT_EQ(message([&] { sum(Subspace<Q>::zero(2), Subspace<Q>::zero(3)); }),
            "sum: expected subspaces of the same space, found Q^2 and Q^3");
  EXPECT_EQ(message([&] {
              dirac_from_basis(m({{1, 0, 0, 1}, {0, 1, 1, 0}}));
            }),
            "dirac_from_basis: expected a Dirac structure (Lemma 4.1), found D is not isotropic: <<e1, e2>> != 0 for "
            "basis vectors e of D");
  EXPECT_EQ(
      message([&] {
        dirac_from_basis(m({{1, 0, 0, 0}}));
      }),
      "dirac_from_basis: expected a Dirac structure (Lemma 4.1), found dim D = 1 (a Dirac structure on Q^2 has dim 2)");
  EXPECT_EQ(message([&] {
              dirac_from_basis(m({{1, 0, 0}}));
            }),
            "dirac_from_basis: expected rows (v, α) of even length 2n, found 1x3");
  EXPECT_EQ(message([&] {
              restrict_form(m({{0, 1}, {-1, 0}}), Subspace<Q>::zero(3));
            }),
            "restrict_form: expected a form on Q^3, found a 2x2 matrix");
}

// The reference is generic over exact fields: cpp_rational must compile and agree with mpq_rational.
TEST(Generic, CppRational) {
  using C = boost::multiprecision::cpp_rational;
  static_assert(is_exact_field<C>::value, "cpp_rational is exact");
  const Matrix<C> w = Matrix<C>::from_rows({{0, 0, 1, 0}, {0, 0, 0, 1}, {-1, 0, 0, 0}, {0, -1, 0, 0}}, 4);
  const Subspace<C> v = Subspace<C>::span(Matrix<C>::from_rows({{1, 0, 0, 0}, {0, 1, 0, 0}}, 4));
  EXPECT_EQ(symplectic_complement(w, v), v);  // a Lagrangian subspace
  const DiracStructure<C> d = dirac_from_presymplectic(w);
  EXPECT_TRUE(dirac_defect(d).empty());
  EXPECT_EQ(form_rank(dirac_form(d)), 4u);
  EXPECT_EQ(normal_form_basis(w, v).s, 0u);
  EXPECT_EQ(dirac_flat(d, v), annihilator(dirac_orthogonal(d, v)));
}

// Canonical Ω = dq ∧ dp: the sign conventions of ERRATA.md ({q, p} = 1, X_H = (∂H/∂p, -∂H/∂q)).
TEST(Conventions, CanonicalSigns) {
  const QM w = m({{0, 1}, {-1, 0}});
  EXPECT_EQ(sharp(w, std::vector<Q>{0, 1}), (std::vector<Q>{1, 0}));   // H = p: q̇ = 1
  EXPECT_EQ(sharp(w, std::vector<Q>{1, 0}), (std::vector<Q>{0, -1}));  // H = q: ṗ = -1
  const auto xq = sharp(w, std::vector<Q>{1, 0}), xp = sharp(w, std::vector<Q>{0, 1});
  EXPECT_EQ(form_value(w, xq, xp), Q(1));  // {q, p} = Ω(X_q, X_p) = 1
}

// YM §6, the L–C circuit (the 4-port of CEF §6, L = 2, C1 = 3, C2 = 5, C3 = 7) in the implicit
// Lagrangian form: KCL ω¹ = −dq_L + dq_C2, ω² = −dq_C1 + dq_C2 − dq_C3; every partial vector field
// (q̇, ṗ) of (L, Δ, X) [YM (4.7) with F = 0] satisfies YM's Lagrange–d'Alembert equations
//   (ṗ_C2 + q_C2/C2, ṗ_C3 + q_C3/C3)ᵀ = [[−1, −1], [0, 1]] (ṗ_L, ṗ_C1 + q_C1/C1)ᵀ
// — with q_C1/C1 in the last entry: YM prints q_C2/C3 there (ERRATA, misprints in YM), and the
// printed form fails; and q̇ = v, p = (L v_L, 0, 0, 0).
TEST(YoshimuraMarsden, LcCircuitImplicitLagrangianEquations) {
  const Q l(2), c1(3), c2(5), c3(7);
  PontryaginInput<Q> in;
  in.n = 4;
  in.k = QM::from_rows({{Q(-1), Q(0), Q(1), Q(0)}, {Q(0), Q(-1), Q(1), Q(-1)}}, 4);
  in.vv = QM(4, 4);
  in.vv(0, 0) = l;
  in.qq = QM(4, 4);
  in.qq(1, 1) = -Q(1) / c1;
  in.qq(2, 2) = -Q(1) / c2;
  in.qq(3, 3) = -Q(1) / c3;
  in.qv = QM(4, 4);
  in.q.assign(4, Q(0));
  in.v.assign(4, Q(0));
  const std::vector<Q> q{Q(1), Q(2), Q(-3), Q(5, 2)};
  const std::vector<Q> v{Q(1), Q(-1), Q(1), Q(2)};  // in Δ: f_L = f_C2, f_C1 = f_C2 − f_C3
  const QM zero(4, 4);
  const AffineSubspace<Q> x = implicit_lagrangian_fields(in, zero, zero, q, v);
  ASSERT_FALSE(x.empty);
  EXPECT_EQ(x.direction.dim(), 2);  // the multipliers of ω¹, ω²
  const std::vector<Q> p = legendre(in, q, v);
  EXPECT_EQ(p, (std::vector<Q>{l * v[0], Q(0), Q(0), Q(0)}));
  // every field: the point and the point plus each direction
  std::vector<std::vector<Q>> fields{x.point};
  for (Index i = 0; i < x.direction.dim(); ++i) {
    std::vector<Q> f = x.point;
    for (Index j = 0; j < 8; ++j) f[j] += x.direction.basis()(i, j);
    fields.push_back(f);
  }
  for (const std::vector<Q>& f : fields) {
    for (Index i = 0; i < 4; ++i) EXPECT_EQ(f[i], v[i]);  // q̇ = v
    const Q pl = f[4], pc1 = f[5], pc2 = f[6], pc3 = f[7];
    const Q a = pl, b = pc1 + q[1] / c1;
    EXPECT_EQ(pc2 + q[2] / c2, -a - b);
    EXPECT_EQ(pc3 + q[3] / c3, b);
    EXPECT_NE(pc3 + q[3] / c3, pc1 + q[2] / c3) << "YM's printed entry q_C2/C3 would hold";
    std::vector<Q> xs(q), xd(f.begin(), f.begin() + 4);
    xs.insert(xs.end(), v.begin(), v.end());
    xs.insert(xs.end(), p.begin(), p.end());
    xd.insert(xd.end(), 4, Q(0));  // v̇ is not constrained by (4.3)
    xd.insert(xd.end(), f.begin() + 4, f.end());
    EXPECT_TRUE(satisfies_ldap(in, zero, zero, xs, xd));  // YM (4.3)
  }
}

// The circuit of YM §6 as an RLC deck without R or sources: the forced CAD gives CEF's tower
// 12, 6, 5, 4 (CEF (6.36), "stops at M_3").
TEST(YoshimuraMarsden, LcCircuitForcedTowerIsCefs) {
  RlcCircuit<Q> c;
  c.nodes = 2;
  c.branches = {{"L", RlcKind::inductor, 0, 1, Q(2)},
                {"C1", RlcKind::capacitor, 1, -1, Q(3)},
                {"C2", RlcKind::capacitor, -1, 0, Q(5)},
                {"C3", RlcKind::capacitor, 1, -1, Q(7)}};
  const ForcedResult<Q> r = forced_tower(rlc_system(c));
  EXPECT_EQ(r.dims, (std::vector<long>{12, 6, 5, 4}));
  EXPECT_EQ(r.solution_rank, 0);
}
