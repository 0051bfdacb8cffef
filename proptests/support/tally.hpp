// Counts of fast-vs-reference comparisons, printed at the end of a property run.
#pragma once

#include <map>
#include <ostream>
#include <string>

namespace dcad::test {

constexpr long kDefaultCases = 200;  ///< per property; × DCAD_PROP_SCALE

struct Tally {
  long certain_agree = 0, uncertain = 0, disagree = 0;
};

std::map<std::string, Tally>& tallies();

/// Records one discrete comparison; returns true if it must fail the test (certain and different).
inline bool tally(const std::string& what, bool certain, bool agree) {
  Tally& t = tallies()[what];
  if (!certain) {
    ++t.uncertain;
    return false;
  }
  if (agree) {
    ++t.certain_agree;
    return false;
  }
  ++t.disagree;
  return true;
}

void print_tally(std::ostream& o);

}  // namespace dcad::test
