// certified::solve — the certified tier on any problem (issue 26): one cascade (cascade.hpp) of the
// reference's own pipelines — exact machine words, then balls, then FLINT's fmpq — and the graph route where
// a theorem decides everything (physical LC circuits above kDenseBranches).  `certified: true` is
// never wrong: every discrete answer is the exact one, by the tier's proof.
#pragma once

#include "dcad/io/problem.hpp"
#include "dcad/reference/rational.hpp"
#include "dcad/solution.hpp"

#include <string>

namespace dcad::certified {

using reference::Rational;

/// A number of a certified result: exact (the machine-word and fmpq tiers, and a ball that is a point),
/// or the enclosure mid ± rad of the exact value (the ball tier); rad = +inf where there is no
/// enclosure (a double-precision answer where no exact tier can run: `certified` is then unknown).
struct Number {
  bool exact = true;
  Rational q;               ///< exact: the value
  double mid = 0, rad = 0;  ///< else: the ball
};
/// "p/q" if exact, else the midpoint as a float (%.17g).
std::string number_text(const Number& x);

using Solution = dcad::Solution<Number>;

/// Circuits up to this many branches go through the cascade (the structured route, dense); larger
/// physical ones by the graph route (dcad/lc_graph.hpp: no decision), without equations of motion.
constexpr std::size_t kDenseBranches = 120;

/// io::InputError for bad input.  The expression form at a point where a formula is irrational throws
/// reference::NotExactHere (no exact tier can run there; dcad::api then answers by double precision,
/// not certified).
Solution solve(const io::Problem& p, const Parts& parts = {});

}  // namespace dcad::certified
