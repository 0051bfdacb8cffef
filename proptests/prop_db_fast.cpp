// fast Dirac–Bergmann and constraint classes = reference on every discrete output unless fast says
// uncertain (tower dims, consistency, dim Λ^(c), 2s, number of first class constraints); the fast
// Dirac tensor satisfies Lemma 3.23 (e) and gives the canonical motion on M_c, up to rounding.
#include "support/case_json.hpp"
#include "support/convert.hpp"
#include "support/fast_options.hpp"
#include "support/tally.hpp"

#include "dcad/fast/adapted.hpp"
#include "dcad/fast/quotient.hpp"
#include "dcad/reference/adapted.hpp"
#include "dcad/reference/quotient.hpp"
#include "generators.hpp"

#include <Eigen/LU>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

namespace {

/// A random constrained system, its fast twin (rounded, assessed) and both Dirac–Bergmann towers.
struct Twins {
  ref::ConstrainedSystem<Q> s;
  fast::Options opt;
  fast::ConstrainedSystem fs;
  ref::DiracBergmannResult<Q> r;
  fast::DiracBergmannResult f;
};

Twins any_twins() {
  Twins t{*constrained_systems(), any_route_options(), {}, {}, {}};
  t.fs = {to_double(t.s.omega, &t.opt), to_double(t.s.hessian, &t.opt),
          to_double(QM::column(t.s.gradient), &t.opt).col(0), to_double(t.s.primary, &t.opt)};
  t.r = ref::dirac_bergmann(t.s);
  t.f = fast::dirac_bergmann(t.fs, t.opt);
  return t;
}

}  // namespace

RC_GTEST_PROP(FastVsReference, DiracBergmann, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  bool same = f.tower.size() == r.tower.size();
  for (Index k = 0; same && k < r.tower.size(); ++k)
    same = (f.tower[k].empty ? -1 : f.tower[k].direction.dim()) ==
           (r.tower[k].empty ? -1L : static_cast<long>(r.tower[k].direction.dim()));
  RC_ASSERT(!tally("DB dims of M_k", f.certain.yes(), same));
  RC_ASSERT(!tally("DB consistent", f.certain.yes(), f.consistent == r.consistent));
  if (!r.consistent || !f.consistent || f.certain.unknown() || !same) return;
  const ref::ConstraintClasses<Q> rc_ = ref::classify_constraints(s.omega, r.constraints);
  const fast::ConstraintClasses fc = fast::classify_constraints(fs.omega, f.constraints, opt);
  RC_ASSERT(!tally("second class 2s", fc.certain.yes(), static_cast<Index>(fc.s) == rc_.s));
  RC_ASSERT(!tally("first class count", fc.certain.yes(), static_cast<Index>(fc.first.rows()) == rc_.first.rows()));
  const std::vector<Q> x = some_point(r.tower.back());
  const ref::AffineSubspace<Q> rl = ref::multipliers(s, r, x);
  const fast::AffineSubspace fl = fast::multipliers(fs, f, to_double(x), opt);
  RC_ASSERT(!tally("dim Lambda^(c)", fl.certain.yes(),
                   !fl.empty && static_cast<Index>(fl.direction.dim()) == rl.direction.dim()));
  if (fc.certain.unknown() || fl.empty || fl.certain.unknown()) return;
  // Lemma 3.23 (e) and the motion: J* skew, G J* = 0, J*(dE + λ·a) = J(dE + λ·a) on M_c
  const int n = static_cast<int>(fs.omega.rows());
  Truth nondegenerate = yes;
  const Eigen::MatrixXd j = fast::poisson_tensor(fs.omega, {}, nondegenerate);
  const double scale = 1 + fast::norm2(j) * fast::norm2(j) * (1 + fast::norm2(fs.hessian) + fs.gradient.norm()) *
                               (1 + fl.point.norm() + to_double(x).norm());
  const double tol = 1e-8 * scale;
  RC_ASSERT((fc.dirac_tensor + fc.dirac_tensor.transpose()).norm() <= tol);
  RC_ASSERT((fc.second.leftCols(n) * fc.dirac_tensor).norm() <= tol);
  const Eigen::VectorXd de = fs.hessian * to_double(x) + fs.gradient + fs.primary.leftCols(n).transpose() * fl.point;
  RC_ASSERT((fc.dirac_tensor * de - j * de).norm() <= tol);
}

// Thm 3.28 by both backends on the reference's constraint rows (so the choice of χ can agree):
// s', 2s and the abridged count equal unless fast is uncertain; the fast X_(χ),E_AT is tangent to
// M_c and solves (3.18) up to rounding.
RC_GTEST_PROP(FastVsReference, AdaptedConstraints, ()) {
  const ref::ConstrainedSystem<Q> s = *constrained_systems();
  const ref::DiracBergmannResult<Q> r = ref::dirac_bergmann(s);
  if (!r.consistent) return;
  std::vector<bool> primary(r.constraints.rows(), false);
  for (Index i = 0; i < s.primary.rows(); ++i) primary[i] = true;
  const ref::AdaptedConstraints<Q> ra = ref::adapted_constraints(s.omega, r.constraints, primary);
  fast::Options opt = any_route_options();
  const Eigen::MatrixXd w = to_double(s.omega, &opt), cons = to_double(r.constraints, &opt);
  const fast::AdaptedConstraints fa = fast::adapted_constraints(w, cons, primary, opt);
  RC_ASSERT(!tally("adapted s'", fa.certain.yes(), static_cast<Index>(fa.s_prime) == ra.s_prime));
  RC_ASSERT(!tally("adapted 2s", fa.certain.yes(), static_cast<Index>(fa.s) == ra.s));
  RC_ASSERT(!tally("adapted chi", fa.certain.yes(), std::vector<Index>(fa.chi.begin(), fa.chi.end()) == ra.chi));
  if (fa.certain.unknown()) return;
  const int n = static_cast<int>(w.rows());
  const Eigen::VectorXd x = to_double(some_point(r.tower.back()));
  const Eigen::VectorXd lambda = to_double(integer_vector(fa.abridged.size()));
  const Eigen::MatrixXd h = to_double(s.hessian);
  const Eigen::VectorXd g = to_double(QM::column(s.gradient)).col(0);
  const Eigen::VectorXd xdot = fast::abridged_field(fa, cons, h, g, x, lambda);
  const double tol = 1e-8 * (1 + fast::norm2(fa.dirac_tensor)) *
                     (1 + fast::norm2(h) * x.norm() + g.norm() + lambda.norm() * fast::norm2(cons));
  RC_ASSERT((cons.leftCols(n) * xdot).norm() <= tol);                                        // tangent to M_c
  const Eigen::MatrixXd tsp = fast::kernel(to_double(ref::gradients(s.primary))).columns();  // T S'
  RC_ASSERT((tsp.transpose() * (w.transpose() * xdot - (h * x + g))).norm() <= tol);         // (3.18)
}

// Λ^(c) at a point far along M_c (x = x0 + 10^k d, d in its direction, k = 6…12: the charges of a
// picofarad circuit are such numbers next to 1/C = 10^12): the multiplier equations C λ = −A J (H x + g)
// are consistent exactly (CEF (3.12)), and fast must say so or be uncertain. The right-hand side is
// exactly 0 off im C, but computed from H x of norm 10^k its rounding is ε‖J‖‖H‖‖x‖: decided against ‖J‖
// alone, that residue was called a certain inconsistency.
RC_GTEST_PROP(FastVsReference, MultipliersFarAlongMc, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  if (!r.consistent || !f.consistent || f.certain.unknown() || r.tower.back().direction.dim() == 0) return;
  std::vector<Q> x = some_point(r.tower.back());
  Q far = 1;
  for (int k = *rc::gen::inRange(6, 13); k > 0; --k) far *= 10;
  const QM c = integer_matrix(1, r.tower.back().direction.dim());
  for (Index i = 0; i < r.tower.back().direction.dim(); ++i)
    for (Index k = 0; k < x.size(); ++k) x[k] += far * c(0, i) * r.tower.back().direction.basis()(i, k);
  const ref::AffineSubspace<Q> rl = ref::multipliers(s, r, x);
  const fast::AffineSubspace fl = fast::multipliers(fs, f, to_double(x), opt);
  RC_LOG() << case_json(s) << "x = " << json_vector(x) << "\nexact dim Lambda " << rl.direction.dim() << ", fast "
           << (fl.empty ? -1 : fl.direction.dim()) << (fl.certain.yes() ? " (certain)" : " (uncertain)") << "\n";
  RC_ASSERT(!rl.empty);
  RC_ASSERT(!tally("dim Lambda^(c) far along M_c", fl.certain.yes(),
                   !fl.empty && static_cast<Index>(fl.direction.dim()) == rl.direction.dim()));
}

// CEF §3.2 by both twins: fast's K_c, K̃_c and M̄_c (its own route: the SVD of Ω's Gram matrix on TM_c,
// (3.8) read off (3.4)) have the reference's dimensions unless fast says uncertain; the exact solution X
// of (3.4) at an exact x ∈ M_c projects by fast's C onto fast's X̄(C x) (Lemma 3.20 (d), (3.8)), and
// fast's ω̄_c pulls back to ω_c, up to rounding.
RC_GTEST_PROP(FastVsReference, GaugeQuotient, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  if (!r.consistent || !f.consistent || f.certain.unknown()) return;
  const ref::GaugeQuotient<Q> rq = ref::gauge_quotient(s, r);
  const fast::GaugeQuotient fq = fast::gauge_quotient(fs, f, opt);
  RC_ASSERT(!tally("quotient dim K_c", fq.certain.yes(), fq.gauge.dim() == static_cast<int>(rq.gauge.dim())));
  RC_ASSERT(!tally("quotient dim K~_c", fq.certain.yes(),
                   fq.physical_gauge.dim() == static_cast<int>(rq.physical_gauge.dim())));
  if (fq.certain.unknown() || fq.gauge.dim() != static_cast<int>(rq.gauge.dim())) return;
  const std::vector<Q> x = some_point(r.tower.back());
  const std::vector<Q> field = ref::total_energy_field(s, x, some_point(ref::multipliers(s, r, x)));
  const Eigen::VectorXd xd = to_double(x), xdot = to_double(field);
  const Eigen::VectorXd lhs = fq.coordinates * xdot, rhs = fast::quotient_field(fq, fq.coordinates * xd);
  const double w = fast::norm2(fs.omega), reach = 1 + fast::norm2(fq.section) * w;
  const double tol = 1e-8 * (1 + w) * reach * (1 + fast::norm2(fs.hessian)) *
                     (1 + xd.norm() + fq.point.norm() + fs.gradient.norm() + xdot.norm());
  RC_LOG() << case_json(s) << "x = " << json_vector(x) << "\n|C X - Xbar(C x)| = " << (lhs - rhs).norm() << ", tol "
           << tol << "\n";
  RC_ASSERT((lhs - rhs).norm() <= tol);
  // M̃_c (Thm 3.19, (3.6)): fast's C̃ gives two exact solutions one X̃, and P C̃ X = C X
  const std::vector<Q> other = ref::total_energy_field(s, x, some_point(ref::multipliers(s, r, x)));
  RC_ASSERT((fq.tilde_coordinates * (xdot - to_double(other))).norm() <= tol);
  RC_ASSERT((fq.fibration * fq.tilde_coordinates * xdot - lhs).norm() <= tol * (1 + fast::norm2(fq.fibration)));
  RC_ASSERT(fq.tilde_coordinates.rows() == static_cast<Eigen::Index>(rq.tilde_coordinates.rows()));
  const Eigen::MatrixXd y = fq.tangent.columns() * to_double(integer_matrix(fq.tangent.dim(), 2));
  const Eigen::MatrixXd cy = fq.coordinates * y;
  RC_ASSERT(std::abs((y.col(0).transpose() * fs.omega * y.col(1))(0, 0) -
                     (cy.col(0).transpose() * fq.form * cy.col(1))(0, 0)) <= tol * (1 + y.norm() * y.norm()));
}

// Lemma 3.23 (d)–(e) by both twins on the same random V (a complement of ker ω in (T M_c)^Ω): fast's Dirac
// tensor — the Poisson tensor of Ω on V^Ω — is the reference's, Dirac's formula with χ′, up to rounding,
// and V^Ω has the reference's dimension, unless fast says uncertain; Thm 3.24 for that V in both: S^V ⊇ S is
// symplectic of dimension dim S + dim ker ω and the image of J*, a leaf of the Dirac bracket.
RC_GTEST_PROP(FastVsReference, SecondClassChoice, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  if (!r.consistent) return;
  const ref::Subspace<Q> tmc = r.tower.back().direction;
  const ref::Subspace<Q> kerw = ref::form_kernel(ref::restrict_form(s.omega, tmc));
  const QM e = ref::extending_rows(kerw.basis(), ref::symplectic_complement(s.omega, tmc).basis());
  const ref::Subspace<Q> v = ref::Subspace<Q>::span(e + integer_matrix(e.rows(), kerw.dim()) * kerw.basis());
  const ref::SecondClassChoice<Q> rch = ref::second_class_choice(s.omega, r.tower.back(), v);
  // Thm 3.24 for this V: S^V ⊇ S is symplectic, of dimension dim S + dim ker ω, and a symplectic leaf of the Dirac
  // bracket — the image of its tensor J* is T S^V = V^Ω
  RC_ASSERT(ref::contains(rch.tangent, tmc));
  RC_ASSERT(rch.tangent.dim() == tmc.dim() + kerw.dim());
  RC_ASSERT(ref::form_kernel(ref::restrict_form(s.omega, rch.tangent)).dim() == 0u);
  RC_ASSERT(ref::image(rch.dirac_tensor) == rch.tangent);
  fast::AffineSubspace mc;
  mc.empty = false;
  mc.point = to_double(r.tower.back().point);
  mc.direction =
      tmc.dim() > 0 ? fast::Subspace::span(to_double(tmc.basis()), -1, opt) : fast::Subspace::zero(fs.omega.rows());
  const fast::Subspace fv =
      v.dim() > 0 ? fast::Subspace::span(to_double(v.basis()), -1, opt) : fast::Subspace::zero(fs.omega.rows());
  const fast::SecondClassChoice fch = fast::second_class_choice(fs.omega, mc, fv, opt);
  const Truth first = fast::is_first_class_submanifold(fs.omega, mc.direction, opt);
  RC_ASSERT(!tally("first class submanifold (Def 3.22)", first != unknown,
                   first.yes() == ref::is_first_class_submanifold(s.omega, tmc)));
  RC_ASSERT(!tally("second class choice dim V^Omega", fch.certain.yes(),
                   fch.tangent.dim() == static_cast<int>(rch.tangent.dim())));
  if (fch.certain.unknown()) return;
  const fast::RankDecision leaf = fast::form_rank(fast::restrict_form(fs.omega, fch.tangent), opt);
  RC_ASSERT(!tally("Thm 3.24: S^V symplectic", leaf.certain.yes(), static_cast<int>(leaf.rank) == fch.tangent.dim()));
  const Eigen::MatrixXd jr = to_double(rch.dirac_tensor);
  const double tol = 1e-8 * (1 + fast::norm2(fs.omega)) * (1 + fast::norm2(jr)) * (1 + fast::norm2(jr));
  RC_LOG() << case_json(s) << "|J*_fast - J*_ref| = " << (fch.dirac_tensor - jr).norm() << ", tol " << tol << "\n";
  RC_ASSERT((fch.dirac_tensor - jr).norm() <= tol);
}

// CEF Lemma 3.17 by both twins: fast's first class covectors have the reference's dimension unless fast is
// uncertain, and the brackets of two exact first class functions, {f, h} = αᵀ J β on N, equal those of
// their push-forwards by fast's own quotient (ᾱ = Sᵀ α, the bracket of ω̄_c), up to rounding.
RC_GTEST_PROP(FastVsReference, FirstClassFunctions, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  if (!r.consistent || !f.consistent || f.certain.unknown()) return;
  const ref::GaugeQuotient<Q> rq = ref::gauge_quotient(s, r);
  const fast::GaugeQuotient fq = fast::gauge_quotient(fs, f, opt);
  const ref::Subspace<Q> rr = ref::first_class_covectors(s.omega, rq.tangent);
  const fast::Subspace fr = fast::first_class_covectors(fs.omega, fq.tangent, opt);
  const bool certain = fq.certain.yes() && fr.certain().yes();
  RC_ASSERT(!tally("first class covectors dim", certain, fr.dim() == static_cast<int>(rr.dim())));
  if (!certain || fq.form.rows() == 0) return;
  const QM alpha = integer_matrix(1, rr.dim()) * rr.basis(), beta = integer_matrix(1, rr.dim()) * rr.basis();
  const double exact = to_double(alpha * ref::poisson_tensor(s.omega) * beta.transpose())(0, 0);
  const Eigen::VectorXd a = to_double(alpha).row(0).transpose(), b = to_double(beta).row(0).transpose();
  const Eigen::MatrixXd jbar = fq.form.transpose().fullPivLu().inverse();
  const double bracket = fast::push_forward(fq, a).dot(jbar * fast::push_forward(fq, b));
  const double tol = 1e-8 * (1 + fast::norm2(jbar)) * (1 + fast::norm2(fq.section) * fast::norm2(fq.section)) *
                     (1 + a.norm() * b.norm());
  RC_LOG() << case_json(s) << "{f, h} = " << exact << " exactly, " << bracket << " on fast's quotient\n";
  RC_ASSERT(std::abs(bracket - exact) <= tol);
}

// CEF §7 by both twins on random foliated systems: fast's Λ_x (Remark 7.3's route: a velocity of its own CAD
// solved for λ) has the reference's dimension unless fast is uncertain, and fast's field (7.8) with its λ is
// tangent to the exact leaf S_C and solves (7.7) there, up to rounding.
RC_GTEST_PROP(FastVsReference, FoliatedMultipliers, ()) {
  const ref::ConstrainedSystem<Q> s = *constrained_systems();
  const QM leaf = any_leaf_functions(s);
  if (leaf.rows() == 0 && leaf.cols() == 0) return;
  const ref::FoliatedEmbedding<Q> f{s.omega, s.hessian, s.gradient, s.primary, leaf};
  const ref::CadResult<Q> r = ref::foliated_tower(f);
  if (!r.consistent) return;
  const std::vector<Q> x = some_point(r.final_step().m);
  const ref::AffineSubspace<Q> rl = ref::foliated_multipliers(f, ref::secondary_constraints(r), x);
  fast::Options opt = any_route_options();
  const fast::FoliatedEmbedding ff{to_double(s.omega, &opt), to_double(s.hessian, &opt), to_double(s.primary, &opt),
                                   to_double(leaf, &opt), to_double(QM::column(s.gradient), &opt).col(0)};
  const fast::CadResult fr = fast::foliated_tower(ff, opt);
  if (!fr.consistent || fr.certain.unknown()) return;
  const Eigen::VectorXd xd = to_double(x);
  const fast::AffineSubspace fl = fast::foliated_multipliers(ff, fr, fast::secondary_constraints(fr), xd, opt);
  RC_LOG() << "fast: empty " << fl.empty << " dim " << (fl.empty ? -1 : fl.direction.dim()) << ", exact dim "
           << rl.direction.dim() << "\n";
  RC_ASSERT(!tally("foliated dim Lambda", fl.certain.yes(),
                   !fl.empty && fl.direction.dim() == static_cast<int>(rl.direction.dim())));
  if (fl.empty || fl.certain.unknown()) return;
  const Eigen::VectorXd field = fast::foliated_field(ff, xd, fl.point);
  const QM both = ref::vstack(s.primary, leaf);
  const Eigen::MatrixXd off = to_double(
      ref::annihilator(ref::intersection(r.final_step().m.direction, ref::kernel(ref::gradients(leaf)))).basis());
  const Eigen::MatrixXd tsp = to_double(ref::kernel(ref::gradients(both)).basis());  // T S'_C, rows
  const Eigen::VectorXd de = ff.hessian * xd + ff.gradient;
  const double tol = 1e-8 * (1 + fast::norm2(ff.omega)) * (1 + field.norm() + de.norm()) * (1 + fl.point.norm());
  RC_LOG() << case_json(s) << "x = " << json_vector(x) << "\n";
  RC_ASSERT((off * field).norm() <= tol * (1 + fast::norm2(off)));                                // tangent to S_C
  RC_ASSERT((tsp * (ff.omega.transpose() * field - de)).norm() <= tol * (1 + fast::norm2(tsp)));  // (7.7)
}

// CEF Remark 2.2 by both sides: f ≈ 0 (f|_{M_c} = 0: the reference, literally) ⇔ f = ν^i φ_i^(c) with affine ν
// (fast: the coefficient matching decided solvable), on quadratic f planted in the ideal of M_c's constraints
// (half the cases) or moved off it by a random quadratic (which may or may not vanish on M_c).
RC_GTEST_PROP(FastVsReference, Remark2_2_WeakEquality, ()) {
  const auto& [s, opt, fs, r, f] = any_twins();
  if (!r.consistent) return;
  const Index n = s.omega.rows(), k = r.constraints.rows();
  const QM nu = integer_matrix(k, n), nu0 = integer_matrix(k, 1), a = ref::gradients(r.constraints);
  ref::QuadraticFunction<Q> q{QM(n, n), std::vector<Q>(n, Q(0)), Q(0)};
  for (Index i = 0; i < k; ++i) {  // Σ (N_i·x + ν0_i)(a_i·x − β_i)
    const Q beta = r.constraints(i, n);
    for (Index p = 0; p < n; ++p) {
      for (Index c = 0; c < n; ++c) q.a(p, c) += nu(i, p) * a(i, c) + a(i, p) * nu(i, c);
      q.b[p] += nu0(i, 0) * a(i, p) - beta * nu(i, p);
    }
    q.c -= nu0(i, 0) * beta;
  }
  const bool planted = *rc::gen::arbitrary<bool>();
  if (!planted) {
    const QM extra = symmetric_matrix(n, *rc::gen::inRange<Index>(0, 2));
    for (Index p = 0; p < n; ++p)
      for (Index c = 0; c < n; ++c) q.a(p, c) += extra(p, c);
    q.c += Q(*rc::gen::inRange(0, 2));
  }
  const bool weak = ref::weakly_zero(r.tower.back(), q);
  RC_CLASSIFY(weak, "f ~ 0");
  if (planted) RC_ASSERT(weak);
  fast::Options o = opt;
  const fast::QuadraticFunction fq{to_double(q.a, &o), to_double(QM::column(q.b), &o).col(0), q.c.convert_to<double>()};
  const Truth fw = fast::weakly_zero(to_double(r.constraints, &o), fq, o);
  RC_ASSERT(!tally("Remark 2.2 f ~ 0", fw != unknown, fw.yes() == weak));
}
