// The double twin alone (README "dcad from C++"): x = (q, p, z) with ω = dq ∧ dp on the first two
// coordinates (z is in the kernel of ω) and E = ½(q² + p²) + z.  Then dE(∂_z) = 1 must vanish on M_1:
// no motion exists, the tower ends empty (CEF §5: M_1 = {x : dE(x)(v) = 0 for v ∈ ker ω} = ∅), and the
// rank decisions are certain on these exact small integers.
#include <dcad/fast/cad.hpp>

#include <Eigen/Core>
#include <iostream>

int main() {
  namespace fast = dcad::fast;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(3, 3), h = Eigen::MatrixXd::Zero(3, 3);
  w(0, 1) = 1;
  w(1, 0) = -1;
  h(0, 0) = h(1, 1) = 1;
  const fast::LinearSystem s{fast::dirac_from_presymplectic(w), h, Eigen::Vector3d(0, 0, 1), 0.0};
  const fast::CadResult r = fast::constraint_tower(s);
  if (!r.certain.yes() || r.consistent) {
    std::cerr << "consumer_fast: expected a certain, inconsistent tower, found certain " << r.certain.yes()
              << ", consistent " << r.consistent << "\n";
    return 1;
  }
  std::cout << "consumer_fast: the tower is empty, certain (dcad::fast alone)\n";
  return 0;
}
