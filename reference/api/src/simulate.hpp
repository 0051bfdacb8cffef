// `dcad simulate`'s routes (internal to dcad::api): the exact flow of a linear model (simulate.cpp),
// the forced route with its sources' exosystem (simulate_forced.cpp), RK4 on the pointwise CAD
// (simulate_lagrangian.cpp).
#pragma once

#include "dcad/api.hpp"
#include "dcad/certified/enclosure.hpp"
#include "dcad/reference/pipeline/forced.hpp"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <ostream>

namespace dcad::api {

using Summary = Simulated;

/// io::InputError unless 0 < step, 0 ≤ tstop < ∞ and tstop/step ≤ 1e9 (every simulate route).
void require_times(const SimulateOptions& opt);

/// Writes the CSV of the CONTRACT (header t, then every variable; full precision) to `out`, one
/// row at a time as it is computed (memory independent of the number of rows).
/// Throws io::InputError for an initial condition off M_c (naming the violated constraint).
/// `deck`: the netlist `c` stands for (then the structured circuit route builds the model; `c` need
/// only carry the variable names), or nullptr for a `pontryagin` case.
Summary simulate_linear(const io::CaseFile& c, const io::Netlist* deck,
                        const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                        RowSink& out, std::ostream& log);

/// As simulate_linear, for a deck with resistors, sources or couplings; `energy` (optional) receives the
/// energy-balance CSV t,E,P_forces,P_sources,P_constraints,W_… (YM §4: dE/dt = ⟨F x + Bσ, q̇⟩ + the work
/// of the reactions of affine constraints; for circuits −P_forces is what the resistors dissipate).
Summary simulate_forced(const io::Netlist& deck, const io::CaseFile& c,
                        const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                        RowSink& out, std::ostream& log, std::ostream* energy);
/// The sparse route for netlists at any size (simulate_sparse.cpp): its own initial state (opt.initial),
/// opt.columns honoured; every R, L, C > 0 and |k| < 1 (InputError otherwise).
Summary simulate_sparse(const io::Netlist& deck, const io::CaseFile& c, const SimulateOptions& opt, RowSink& out,
                        std::ostream& log, std::ostream* energy);
/// Whether the sparse route takes the deck (every R, L, C positive, Φ positive definite).
bool sparse_route_takes(const io::Netlist& deck);
/// The Krylov integrator's local error per output step, relative to the state's norm in energy units.
constexpr double kSparseStepTolerance = 1e-13;
/// Above this estimate (relative to the state) the sparse route warns that the circuit is stiff against the step.
constexpr double kSparseWarn = 1e-9;
/// Above this estimate the run stops with exit 1: its rows would not be the circuit's motion.
constexpr double kSparseRefuse = 1e-3;

/// As simulate_forced, for a `pontryagin` case with `forces` (no sources).
Summary simulate_forced_case(const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial,
                             const SimulateOptions& opt, RowSink& out, std::ostream& log, std::ostream* energy);

/// The expression form: RK4 on the pointwise CAD's vector field, projected onto M_c at every
/// evaluation, with Richardson step doubling per output step (simulate_lagrangian.cpp).
Summary simulate_lagrangian(const io::LagrangianCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log);
/// The linear DAE form: the exact velocities on M_c from the start completed onto M_c(t0), Dormand–Prince
/// (simulate_dae.cpp).
/// The implicit form: RK4 on the pointwise CEF (1.6) in double, projected onto M_c (simulate_implicit.cpp).
Summary simulate_implicit(const io::LagrangianCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log);
Summary simulate_dae(const io::DaeCase& c, const SimulateOptions& opt, RowSink& out, std::ostream& log);

/// The summary of a run: rows, and the worst of err[i]/scale[i] (the long-double shadow's difference
/// relative to the largest magnitude over the run among the variables of i's kind: q_, v_, p_ for
/// circuits, all variables otherwise) with the variable's name.  `natural` (circuits: the scales S of
/// the dimensionless twin, x = S x̃, dcad/units.hpp) floors each scale at the size of the whole state
/// in those units, so a kind that is zero in exact arithmetic (no current at an operating point) is
/// measured against the state, not against its own rounding.
Summary summarize(long rows, const std::vector<long double>& err, const std::vector<long double>& mag,
                  const std::vector<std::string>& names, const std::vector<long double>& natural = {});

/// simulate's rows as the CONTRACT's CSV on a stream: shortest round-trip doubles (std::to_chars: the same doubles
/// as %.17g, several times faster to write — at 10^4 rows formatting was most of the run time).
class CsvRows final : public RowSink {
 public:
  explicit CsvRows(std::ostream& out) : out_(out) {}
  void header(const std::vector<std::string>& names) override;
  void row(const std::vector<double>& values) override;
  void flush() override { out_.flush(); }

 private:
  std::ostream& out_;
  std::string line_;
};
/// t, then `names`: a header.
std::vector<std::string> with_time(const std::vector<std::string>& names);

/// The energy-balance CSV of the circuit routes (YM §4): its header on construction, then a row per call —
/// t, E, the powers P_forces, P_sources, P_constraints and their works W_… at full precision.  Null: nothing.
class EnergyCsv {
 public:
  explicit EnergyCsv(std::ostream* out);
  void row(double t, double e, double p_forces, double p_sources, double p_constraints, double w_forces,
           double w_sources, double w_constraints);

 private:
  std::ostream* out_;
  std::string line_;
};

/// Circuits up to this size: the flow is a dense (m+1)×(m+1) matrix exponential, m = dim M_c.
constexpr std::size_t kSimulateBranches = 400;

/// Diagonal D of powers of two such that D⁻¹ A D has off-diagonal row and column sums equal within
/// a factor 4 (Parlett–Reinsch balancing); similarity by D is exact in floating point.
std::vector<double> balancing(const Eigen::MatrixXd& a);

/// The initial condition a netlist prescribes, as per-variable exact values (nullopt = free):
/// IC= of an inductor fixes v (its current), of a capacitor fixes q = C · voltage.
std::vector<std::optional<io::Rational>> netlist_initial(const io::Netlist& n);

/// The certified tier: the circuit's exact motion from the start SPICE's `rule` gives, enclosed in
/// balls (certified/enclosure.hpp).  Two exact models: the dense forced tower (reference/forced.hpp) up
/// to kForcedBranches branches, its start from netlist_start; the state equations reduced exactly
/// (pipeline/rlc_motion.hpp) up to kCertifiedBranches where the graph route holds, its start from
/// state_start.  `flow` null and `why` set when it cannot be (too large, solutions not unique, a
/// start through π, a PULSE with a jump).
struct CertifiedMotion {
  std::unique_ptr<certified::MotionEnclosure> flow;
  std::string why;
  std::string model;  ///< "dense" or "state equations"
};
constexpr std::size_t kCertifiedBranches = 200;
/// check encloses runs through at most this many source corners (each is crossed exactly).
constexpr std::size_t kEnclosedCorners = 100000;
enum class EnclosureModel { automatic, dense, state };
CertifiedMotion certified_motion(const io::Netlist& deck, const io::CaseFile& c, Initial rule, double step,
                                 long precision = 256, EnclosureModel model = EnclosureModel::automatic,
                                 std::ostream* log = nullptr);
/// `simulate --certified`: the rows are the midpoints of the enclosures, with the largest radius of each
/// kind (rad_q, rad_v, rad_p) per row.
Summary simulate_enclosed(const io::Netlist& deck, const io::CaseFile& c, const SimulateOptions& opt, RowSink& out,
                          std::ostream& log);
/// Enclosures of the vectors `names` (ngspice's or dcad's names) of a netlist at `times` (ascending),
/// from the start `initial` (check's and the waveform export's certified tier); ok false and `why` when
/// dcad cannot build them.  InputError for a name the deck does not have.
struct WaveformEnclosures {
  bool ok = false;
  std::string why;
  std::vector<std::vector<certified::Enclosure>> right, left;  ///< [vector][time]
};
WaveformEnclosures enclose_waveforms(const io::Problem& p, const std::vector<std::string>& names,
                                     const std::vector<double>& times, Initial initial, double step);

/// The state a netlist starts from (SPICE's rule, the jump onto M_c), told on `log`, as per-variable values.
std::vector<std::optional<io::Rational>> netlist_start(const io::Netlist& deck,
                                                       const std::vector<std::string>& variables, Initial rule,
                                                       std::ostream& log, long* jumps = nullptr,
                                                       std::vector<std::string>* jumped = nullptr);

}  // namespace dcad::api
