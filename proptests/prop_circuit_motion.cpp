// The structured circuit route (reference/circuit_motion.hpp) against the generic CAD (cad.hpp) on
// the circuit's `pontryagin` system, on random circuits with wires and signed values (every case of
// CEF §6): the same tower (every M_j as a subspace of Q^{3n}), the same solution rank, and the same
// equations of motion — F and f modulo span(G) and span(G) itself, in the default coordinates and in
// random valid ones.  Two routes to one object: a slip in either shows.
#include "support/case_json.hpp"
#include "support/circuit_gen.hpp"
#include "support/convert.hpp"
#include "support/tally.hpp"

#include "dcad/fast/circuit_motion.hpp"

#include "dcad/reference/circuit_motion.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <Eigen/QR>

using namespace dcad;
using namespace dcad::test;
namespace ref = dcad::reference;

namespace {

/// F₁ − F₂ has columns in span(G) and span(G₁) = span(G₂)  [the affine family of (5.12)].
bool same_modulo_gauge(const ref::ReducedEquations<Q>& a, const ref::ReducedEquations<Q>& b) {
  if (a.coords != b.coords || a.g.cols() != b.g.cols()) return false;
  const QSub ga = QSub::span(a.g.transpose()), gb = QSub::span(b.g.transpose());
  if (!(ga == gb)) return false;
  const QM n = ref::annihilator(ga).basis();  // rows y with yᵀ G = 0
  return n * a.f_matrix == n * b.f_matrix && n * QM::column(a.f) == n * QM::column(b.f);
}

}  // namespace

RC_GTEST_PROP(CircuitMotion, TowerEqualsGenericCad, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const ref::CadResult<Q> r = ref::constraint_tower(ref::pontryagin_system(ref::circuit_lagrangian(c)));
  const std::vector<ref::ProductStep<Q>> t = ref::circuit_tower(c);
  RC_TAG("c = " + std::to_string(r.steps));
  RC_ASSERT(t.size() == r.steps);  // M_1 … M_c
  for (Index j = 1; j <= r.steps; ++j) RC_ASSERT(QSub::span(ref::product_basis(c, t[j - 1])) == r.tower[j].m.direction);
}

RC_GTEST_PROP(CircuitMotion, EquationsOfMotionEqualGenericCad, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const ref::LinearSystem<Q> s = ref::pontryagin_system(ref::circuit_lagrangian(c));
  const ref::CadResult<Q> r = ref::constraint_tower(s);
  const ref::ProductStep<Q> mc = ref::circuit_tower(c).back();
  const ref::ReducedEquations<Q> generic = ref::reduced_equations(s, r), ours = ref::circuit_reduced_equations(c, mc);
  RC_CLASSIFY(generic.g.cols() > 0, "gauge freedom");
  RC_ASSERT(generic.g.cols() == static_cast<long>(r.solution_rank));
  RC_ASSERT(same_modulo_gauge(generic, ours));
  // random coordinates: the first independent variables of a random order of the 3n variables
  std::vector<Index> order(3 * c.branches.size());
  for (Index i = 0; i < order.size(); ++i) order[i] = i;
  for (Index i = order.size(); i > 1; --i) std::swap(order[i - 1], order[*rc::gen::inRange<Index>(0, i)]);
  const QM b = ref::product_basis(c, mc);
  std::vector<Index> coords;
  QM picked(0, b.rows());
  for (Index v : order) {
    QM row(1, b.rows());
    for (Index i = 0; i < b.rows(); ++i) row(0, i) = b(i, v);
    if (ref::rank(ref::vstack(picked, row)) > picked.rows()) {
      picked = ref::vstack(picked, row);
      coords.push_back(v);
    }
  }
  RC_ASSERT(same_modulo_gauge(ref::reduced_equations(s, r, coords), ref::circuit_reduced_equations(c, mc, coords)));
}

// fast::circuit_motion = the reference's equations of motion, in the coordinates fast chose:
// F − F_ref ∈ span(G) column by column and span(G) = span(G_ref), to 1e-9 relative (principal
// angles / projected residuals), unless fast says it is uncertain.
RC_GTEST_PROP(CircuitMotion, FastEqualsReference, ()) {
  const Circuit<Q> c = random_circuit(true, *rc::gen::arbitrary<bool>());
  RC_LOG() << case_json(ref::circuit_lagrangian(c));
  const fast::CircuitGraph g = fast_graph(c);
  const fast::CircuitTower t = fast::circuit_tower(g);
  const ref::ProductStep<Q> mc = ref::circuit_tower(c).back();
  RC_PRE(t.dims.back() == static_cast<long>(mc.dim()));  // the tower itself: prop_circuit_graph
  const fast::CircuitMotion f = fast::circuit_motion(g, t);
  const ref::ReducedEquations<Q> r =
      ref::circuit_reduced_equations(c, mc, std::vector<Index>(f.coords.begin(), f.coords.end()));
  const Eigen::MatrixXd fr = to_double(r.f_matrix), gr = to_double(r.g);
  const bool same_rank = f.g.cols() == gr.cols();
  RC_ASSERT(!tally("circuit motion: solution rank", f.certain.yes(), same_rank));
  if (!same_rank) return;
  // project off span(G_ref) (orthonormal basis from the exact G)
  Eigen::MatrixXd proj = Eigen::MatrixXd::Identity(fr.rows(), fr.rows());
  if (gr.cols()) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(gr);
    const Eigen::MatrixXd qg = qr.householderQ() * Eigen::MatrixXd::Identity(gr.rows(), gr.cols());
    proj -= qg * qg.transpose();
  }
  const double scale = 1 + fr.cwiseAbs().maxCoeff();
  const bool f_ok = (proj * (f.f_matrix - fr)).cwiseAbs().maxCoeff() <= 1e-9 * scale * fr.rows();
  const bool g_ok =
      gr.cols() == 0 || (proj * f.g).cwiseAbs().maxCoeff() <= 1e-9 * (1 + f.g.cwiseAbs().maxCoeff()) * fr.rows();
  RC_ASSERT(!tally("circuit motion: F modulo G", f.certain.yes(), f_ok));
  RC_ASSERT(!tally("circuit motion: span G", f.certain.yes(), g_ok));
}

// The coordinates a caller may give: as many as dim M_c (or none: the default ones), each a variable
// of Q^{3n}, parametrizing M_c; anything else is refused (an index of 3n would read past the basis).  Killed by: the
// index bound taken as ≤ 3n.
RC_GTEST_PROP(CircuitMotion, CoordinatesOutsideTheVariablesAreRefused, ()) {
  const Circuit<Q> c = random_circuit(true, false);
  const ref::ProductStep<Q> mc = ref::circuit_tower(c).back();
  const ref::ReducedEquations<Q> red = ref::circuit_reduced_equations(c, mc);
  RC_PRE(!red.coords.empty());
  const Index n3 = ref::product_basis(c, mc).cols();  // the variables (q, v, p) of every branch
  std::vector<Index> bad = red.coords;
  bad.back() = n3;
  RC_ASSERT_THROWS_AS(ref::circuit_reduced_equations(c, mc, bad), std::invalid_argument);
  bad.back() = red.coords.back();
  bad.push_back(red.coords.front());  // one more than dim M_c (an empty list means: the default ones)
  RC_ASSERT_THROWS_AS(ref::circuit_reduced_equations(c, mc, bad), std::invalid_argument);
  RC_ASSERT(ref::circuit_reduced_equations(c, mc, red.coords).coords == red.coords);
}
