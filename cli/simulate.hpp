// `dcad simulate`: integrate the equations of motion on M_c from the file's initial condition.
#pragma once

#include "dcad/io/lagrangian_case.hpp"
#include "dcad/io/netlist.hpp"

#include <Eigen/Core>

#include <ostream>

namespace dcad::cli {

struct SimulateOptions {
  double tstop = 0, step = 0;
  std::string backend = "certified";
};

struct SimulateSummary {
  long rows = 0;
  /// max over variables of (largest |x_double − x_long_double| over the run) / (largest |x|): the
  /// a-posteriori estimate of the CSV's error relative to each variable's magnitude
  double error_estimate = 0;
  std::string worst_variable;
};

/// io::InputError unless 0 < step, 0 ≤ tstop < ∞ and tstop/step ≤ 1e9 (every simulate route).
void require_times(const SimulateOptions& opt);

/// Writes the CSV of the CONTRACT (header t, then every variable; full precision) to `out`, one
/// row at a time as it is computed (memory independent of the number of rows).
/// Throws io::InputError for an initial condition off M_c (naming the violated constraint).
/// `deck`: the netlist `c` stands for (then the structured circuit route builds the model; `c` need
/// only carry the variable names), or nullptr for a `pontryagin` case.
SimulateSummary simulate(const io::CaseFile& c, const io::Netlist* deck, const std::vector<std::optional<io::Rational>>& initial,
                         const SimulateOptions& opt, std::ostream& out, std::ostream& log);

/// The summary of a run: rows, and the worst of err[i]/mag[i] (the long-double shadow's difference
/// relative to each variable's largest magnitude) with the variable's name.
SimulateSummary summarize(long rows, const std::vector<long double>& err, const std::vector<long double>& mag,
                          const std::vector<std::string>& names);

/// The expression form: RK4 on the pointwise CAD's vector field, projected onto M_c at every
/// evaluation, with Richardson step doubling per output step (simulate_lagrangian.cpp).
SimulateSummary simulate_lagrangian(const io::LagrangianCase& c, const SimulateOptions& opt, std::ostream& out, std::ostream& log);

/// Circuits up to this size: the flow is a dense (m+1)×(m+1) matrix exponential, m = dim M_c.
constexpr std::size_t kSimulateBranches = 400;

/// Diagonal D of powers of two such that D⁻¹ A D has off-diagonal row and column sums equal within
/// a factor 4 (Parlett–Reinsch balancing); similarity by D is exact in floating point.
std::vector<double> balancing(const Eigen::MatrixXd& a);

/// The initial condition a netlist prescribes, as per-variable exact values (nullopt = free):
/// IC= of an inductor fixes v (its current), of a capacitor fixes q = C · voltage.
std::vector<std::optional<io::Rational>> netlist_initial(const io::Netlist& n);

}  // namespace dcad::cli
