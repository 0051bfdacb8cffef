// dcad::Decision — one decision behind an answer, with its evidence (issue 47: "a decision trace with its
// evidence").  Solution::trace holds them in the order they were made: the fast twin's rank decisions with their
// singular values (or |r_ii| of a pivoted QR), thresholds and gap; the exact tiers' levels of the tower, each an
// exact zero test (or a theorem on the circuit's graph, CEF Thms 6.4, 6.6, 6.8, where no rank is decided).
#pragma once

#include "dcad/truth.hpp"

#include <string>
#include <vector>

namespace dcad {

/// How a decision was made.
enum class DecidedBy {
  exact,            ///< zero tests on exact rationals: no threshold, nothing to doubt
  graph,            ///< a theorem on the circuit's graph (CEF Thms 6.4, 6.6, 6.8): no rank decided
  singular_values,  ///< fast: the singular values against the zero and nonzero thresholds
  pivoted_qr,       ///< fast: |r_ii| of a column-pivoted QR (bounds of the singular values)
  norm,             ///< fast: rank 0 because ‖A‖_F is below the zero threshold
  two_routes,       ///< fast: two routes' verdicts combined (decide_rank_either)
};

inline const char* decided_by_name(DecidedBy b) {
  switch (b) {
    case DecidedBy::exact: return "exact";
    case DecidedBy::graph: return "graph";
    case DecidedBy::singular_values: return "singular values";
    case DecidedBy::pivoted_qr: return "pivoted QR";
    case DecidedBy::norm: return "norm";
    case DecidedBy::two_routes: return "two routes";
  }
  return "?";
}

/// One decision: what was decided, the rank (or dimension) it gave, how, whether it is certain, and why.
struct Decision {
  std::string what;  ///< "CAD (CEF §5)", "dim M_2", "Wong V_1: A⁻¹(E V_0)" …
  long rows = 0, cols = 0;
  long rank = 0;  ///< the rank decided (exact tiers: the level's dimension)
  DecidedBy by = DecidedBy::exact;
  Truth certain = unknown;
  std::vector<double> singular_values;  ///< fast: descending (pivoted QR: |r_ii|); empty on the exact tiers
  double zero_threshold = 0, nonzero_threshold = 0;  ///< fast: τ0 and τ1
  double gap = 0;                                    ///< fast: σ_rank / σ_{rank+1} (or a lower bound)
  std::string evidence;                              ///< the same in one line
};

/// The exact tiers' trace: one decision per level M_1 … M_c of a tower of dimensions `dims`, each decided by
/// `by` (exact zero tests, or the graph's theorems), certain.
inline std::vector<Decision> exact_trace(const std::vector<long>& dims, DecidedBy by, const std::string& evidence) {
  std::vector<Decision> t;
  for (std::size_t k = 1; k < dims.size(); ++k) {
    Decision d;
    d.what = "dim M_" + std::to_string(k);
    d.rows = d.cols = dims[0];
    d.rank = dims[k];
    d.by = by;
    d.certain = yes;
    d.evidence = evidence;
    t.push_back(d);
  }
  return t;
}

}  // namespace dcad
