// Another project's property, written with dcad's generators (dcad::testing): "my double-precision
// CAD agrees with the exact reference on random Dirac systems with planted structure".  Here "my
// CAD" is dcad::fast; a user puts their own implementation in its place.
#include "dcad/fast/cad.hpp"
#include "dcad/reference/cad.hpp"
#include "dcad/testing/convert.hpp"  // to_double: exact matrices as Eigen doubles
#include "dcad/testing/gen.hpp"      // any_system(): random exact linear Dirac systems (CEF §5)

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

namespace ref = dcad::reference;
namespace fast = dcad::fast;
using namespace dcad::test;

RC_GTEST_PROP(MyCad, AgreesWithTheReferenceWhereItIsCertain, ()) {
  const ref::LinearSystem<Q> s = any_system();
  const ref::CadResult<Q> exact = ref::constraint_tower(s);

  fast::Options opt;
  const fast::LinearSystem mine{fast::dirac_from_basis(to_double(s.d.d.basis(), &opt), opt), to_double(s.hessian, &opt),
                                to_double(QM::column(s.gradient), &opt).col(0), 0.0};
  const fast::CadResult r = fast::constraint_tower(mine, opt);
  RC_CLASSIFY(r.certain.unknown(), "uncertain");
  if (r.certain.unknown()) return;  // an honest "don't know" is allowed; a wrong certain answer is not
  RC_ASSERT(r.tower.size() == exact.tower.size());
  for (std::size_t k = 0; k < exact.tower.size(); ++k) RC_ASSERT(r.tower[k].dim() == exact.tower[k].dim());
  RC_ASSERT(r.consistent == exact.consistent);
}

// The pipeline as a library (dcad::api): solve a netlist, and check a result — here the fast backend's —
// against the exact reference, as `dcad solve` and `dcad check` would.
#include "dcad/api.hpp"

#include <fstream>

TEST(MyPipeline, FastResultAgreesWithTheReference) {
  const std::string deck = DCAD_CASES "/lc-4port.cir";
  const dcad::api::Solved mine = dcad::api::solve(deck, {"fast", "none"});
  ASSERT_TRUE(mine.result["certified"].get<bool>());
  EXPECT_EQ(mine.result["dims"], nlohmann::json::parse("[12, 6, 5, 4]"));
  std::ofstream("lc-4port.result.json") << mine.result.dump();
  EXPECT_TRUE(dcad::api::check("lc-4port.result.json", deck).agrees);
  EXPECT_THROW(dcad::api::solve("no-such-deck.cir"), dcad::api::InputError);
}
