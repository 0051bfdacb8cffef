// The reference pipeline in certified ball arithmetic (the one translation unit that instantiates
// solve_exact on certified::Ball).  Numbers printed are exact where the ball is a point, else ball
// midpoints as floats (%.17g, never an integer string); a coefficient whose
// ball contains 0 is not printed as a term.
#include "dcad/certified/ball.hpp"
#include "solve_circuit_exact.hpp"

#include <algorithm>
#include <cmath>

namespace dcad::cli {

namespace {
thread_local double widest = 0;  // the largest radius printed
}

template <>
struct Scalar<certified::Ball> {
  static certified::Ball lift(const io::Rational& q) { return certified::Ball::enclosing(q); }
  static std::string text(const certified::Ball& b) {
    widest = std::max(widest, b.rad());
    // a point ball is the exact value (ball.hpp): print it exactly; otherwise its midpoint, as a float
    return b.rad() == 0 && std::isfinite(b.mid()) ? io::Rational(b.mid()).str() : float_text(b.mid());
  }
  static bool printable(const certified::Ball& b) { return std::abs(b.mid()) > b.rad(); }
  static void keep_final(SolveReport&, const reference::Matrix<certified::Ball>&, const std::vector<certified::Ball>&) {}
};

SolveReport solve_ball(const io::CaseFile& c, double& max_radius, const Parts& parts) {
  widest = 0;
  SolveReport out = solve_exact<certified::Ball>(c, parts);
  max_radius = widest;
  return out;
}

SolveReport solve_circuit_ball(const io::Netlist& n, const io::CaseFile& c, double& max_radius, const Parts& parts) {
  widest = 0;
  SolveReport out = solve_circuit_exact<certified::Ball>(n, c, parts);
  max_radius = widest;
  return out;
}

}  // namespace dcad::cli
