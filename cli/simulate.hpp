// `dcad simulate`: integrate the equations of motion on M_c from the file's initial condition.
#pragma once

#include "netlist.hpp"

#include <ostream>

namespace dcad::cli {

struct SimulateOptions {
  double tstop = 0, step = 0;
  std::string backend = "certified";
};

/// Writes the CSV of the CONTRACT (header t, then every variable; full precision) to `out`.
/// Throws io::InputError for an initial condition off M_c (naming the violated constraint).
void simulate(const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
              std::ostream& out, std::ostream& log);

/// The initial condition a netlist prescribes, as per-variable exact values (nullopt = free):
/// IC= of an inductor fixes v (its current), of a capacitor fixes q = C · voltage.
std::vector<std::optional<io::Rational>> netlist_initial(const io::Netlist& n);

}  // namespace dcad::cli
