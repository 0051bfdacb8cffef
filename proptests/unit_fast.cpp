// Unit tests of the fast backend's decisions and its bad-input handling.
#include "dcad/fast/dirac.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace dcad::fast;

TEST(DecideRank, CertainOnClearGap) {
  MatrixXd a(3, 3);
  a << 1, 2, 3, 2, 4, 6, 0, 1, 1;
  const RankDecision d = decide_rank(a);
  EXPECT_EQ(d.rank, 2);
  EXPECT_TRUE(d.certain);
  EXPECT_GT(d.gap, 1e12);
  EXPECT_EQ(d.singular_values.size(), 3u);
  EXPECT_NE(d.describe().find("rank 2 of 3x3 (certain)"), std::string::npos);
}

TEST(DecideRank, UncertainInsideTheBand) {
  MatrixXd a = MatrixXd::Identity(3, 3);
  a(2, 2) = std::ldexp(1.0, -40);  // 9e-13: neither rounding noise nor clearly nonzero
  const RankDecision d = decide_rank(a);
  EXPECT_FALSE(d.certain);
  EXPECT_NE(d.describe().find("UNCERTAIN"), std::string::npos);
  a(2, 2) = std::ldexp(1.0, -20);  // 1e-6 > √ε: certainly nonzero
  EXPECT_TRUE(decide_rank(a).certain);
  EXPECT_EQ(decide_rank(a).rank, 3);
}

TEST(DecideRank, InexactInputNeverCertifiesADeficiency) {
  MatrixXd a(2, 2);
  a << 1, 1, 1, 1;
  Options opt;
  opt.input_exact = false;
  EXPECT_EQ(decide_rank(a, -1, opt).rank, 1);
  EXPECT_FALSE(decide_rank(a, -1, opt).certain);
  EXPECT_TRUE(decide_rank(MatrixXd::Identity(2, 2), -1, opt).certain);  // full rank is still certain
}

// Regression (shrunk counterexample of FastVsReference.Graded): exact rank 4, entries 2^-20, 2^-15
// and 64 — within the dynamic range that assess_input accepts — with singular values 4.5e-13 that
// look like rounding noise.  It was decided "rank 2, certain"; the equilibration cross-check makes
// it uncertain.
TEST(DecideRank, GradedRegression) {
  MatrixXd w = MatrixXd::Zero(5, 5);
  w(0, 2) = std::ldexp(1.0, -20);
  w(1, 3) = std::ldexp(1.0, -15);
  w(2, 3) = -64;
  w -= MatrixXd(w.transpose());
  Options opt;
  assess_input(w, opt);
  EXPECT_TRUE(opt.input_well_scaled);
  const RankDecision d = decide_rank(w, -1, opt);
  EXPECT_TRUE(d.rank == 4 || !d.certain) << d.describe();
}

TEST(DecideRank, Empty) {
  EXPECT_EQ(decide_rank(MatrixXd(0, 3)).rank, 0);
  EXPECT_TRUE(decide_rank(MatrixXd(0, 3)).certain);
  EXPECT_EQ(decide_rank(MatrixXd::Zero(2, 2)).rank, 0);
}

TEST(Subspace, Operations) {
  MatrixXd u(3, 2), w(3, 2);
  u << 1, 0, 0, 1, 0, 0;
  w << 0, 0, 1, 0, 0, 1;
  const Subspace su = Subspace::span(u), sw = Subspace::span(w);
  EXPECT_EQ(intersection(su, sw).dim(), 1);
  EXPECT_EQ(sum(su, sw).dim(), 3);
  EXPECT_TRUE(contains(sum(su, sw), su).value);
  EXPECT_FALSE(contains(su, sw).value);
  EXPECT_NEAR(std::abs(intersection(su, sw).basis()(1, 0)), 1.0, 1e-15);
}

TEST(BadInput, NanInfAndShapes) {
  MatrixXd w(2, 2);
  w << 0, std::numeric_limits<double>::quiet_NaN(), 0, 0;
  EXPECT_THROW(dirac_from_presymplectic(w), std::invalid_argument);
  w << 0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), 0;
  try {
    dirac_from_poisson(w);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "dirac_from_poisson: expected finite entries, found inf at (0, 1)");
  }
  EXPECT_THROW(Subspace::span(w), std::invalid_argument);
  EXPECT_THROW(symplectic_complement(MatrixXd(2, 3), Subspace::zero(2)), std::invalid_argument);
  MatrixXd notskew(2, 2);
  notskew << 0, 1, 2, 0;
  EXPECT_THROW(restrict_form(notskew, Subspace::whole(2)), std::invalid_argument);
  EXPECT_THROW(sharp(MatrixXd::Zero(2, 2), VectorXd::Zero(2)), std::invalid_argument);
  MatrixXd g(1, 4);
  g << 1, 0, 0, 1;
  EXPECT_THROW(dirac_from_basis(g), std::invalid_argument);
  EXPECT_THROW(intersection(Subspace::zero(2), Subspace::zero(3)), std::invalid_argument);
}
