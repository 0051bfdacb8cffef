#include "tally.hpp"

namespace dcad::test {

std::map<std::string, Tally>& tallies() {
  static std::map<std::string, Tally> t;
  return t;
}

void print_tally(std::ostream& o) {
  if (tallies().empty()) return;
  Tally all;
  o << "fast vs reference (discrete outputs):\n";
  for (const auto& [what, t] : tallies()) {
    o << "  " << what << ": certain agreements " << t.certain_agree << ", uncertain " << t.uncertain
      << ", disagreements " << t.disagree << "\n";
    all.certain_agree += t.certain_agree;
    all.uncertain += t.uncertain;
    all.disagree += t.disagree;
  }
  o << "  TOTAL: certain agreements " << all.certain_agree << ", uncertain " << all.uncertain << ", disagreements "
    << all.disagree << "\n";
}

}  // namespace dcad::test
