#include "solve_forced.hpp"
#include "dcad/fast/exact.hpp"

#include "dcad/graph.hpp"
#include "dcad/fast/forced.hpp"
#include "dcad/reference/rlc.hpp"

#include <cmath>
#include <map>
#include <numeric>
#include <sstream>

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;
using QM = ref::Matrix<Q>;
using ref::RlcKind;

std::vector<std::string> jet_names(const std::vector<io::Waveform>& waveforms, long orders) {
  std::vector<std::string> out{"1"};
  for (long d = 0; d < orders; ++d)
    for (const io::Waveform& w : waveforms) {
      const std::string f = w.element;
      out.push_back(d == 0 ? f + "(t)" : d <= 3 ? f + std::string(d, '\'') + "(t)" : "d" + std::to_string(d) + f + "/dt" + std::to_string(d) + "(t)");
    }
  return out;
}

namespace {

std::string row_text(const QM& row, const std::vector<std::string>& names, std::size_t first) {
  std::string s;
  for (std::size_t j = 0; j < row.cols(); ++j) {
    if (row(0, j) == 0) continue;
    Q c = row(0, j);
    const bool neg = c < 0;
    if (neg) c = -c;
    s += s.empty() ? (neg ? "-" : "") : (neg ? " - " : " + ");
    const std::string& nm = names[first + j];
    s += nm == "1" ? c.str() : (c == 1 ? "" : c.str() + "*") + nm;
  }
  return (s.empty() ? "0" : s) + " = 0";
}

}  // namespace

ConditionVerdict decide_condition(const QM& row, const std::vector<io::Waveform>& waveforms) {
  const std::size_t m = waveforms.size();
  const long orders = m ? static_cast<long>((row.cols() - 1) / m) : 0;
  ConditionVerdict v;
  v.text = row_text(row, jet_names(waveforms, orders), 0);
  // identical waveforms (same kind and parameters) are one function: sum their coefficients
  std::map<std::pair<std::string, long>, Q> sums;
  Q constant = row(0, 0);
  bool all_constant = true;
  for (std::size_t j = 0; j < m; ++j)
    for (long d = 0; d < orders; ++d) {
      const Q& c = row(0, 1 + d * m + j);
      if (c == 0) continue;
      const io::Waveform& w = waveforms[j];
      if (w.kind == io::Waveform::Kind::dc) {
        if (d == 0) constant += c * w.p[0];
        continue;
      }
      all_constant = false;
      std::string key = std::to_string(static_cast<int>(w.kind));
      for (const Q& p : w.p) key += " " + p.str();
      sums[{key, d}] += c;
    }
  bool zero = constant == 0;
  for (const auto& [k, c] : sums) zero = zero && c == 0;
  if (zero) {
    v.evidence = all_constant ? "exact (DC values)" : "exact (equal waveforms cancel)";
    return v;
  }
  if (all_constant) {
    v.holds = ConditionVerdict::Holds::no;
    v.evidence = "exact: the DC values give " + constant.str() + " = 0";
    return v;
  }
  // different waveforms: sample the combination (breakpoints, their midpoints, a spread of times)
  double horizon = 0;
  for (const io::Waveform& w : waveforms) horizon = std::max(horizon, w.horizon());
  if (horizon == 0) horizon = 1;
  std::vector<double> ts{0};
  for (const io::Waveform& w : waveforms)
    for (double b : w.breakpoints(horizon)) ts.push_back(b);
  std::sort(ts.begin(), ts.end());
  const std::size_t k = ts.size();
  for (std::size_t i = 1; i < k; ++i) ts.push_back((ts[i - 1] + ts[i]) / 2);
  for (int i = 1; i <= 97; ++i) ts.push_back(horizon * std::fmod(i * 0.6180339887498949, 1.0));
  double worst = 0, at = 0, scale = std::abs(row(0, 0).convert_to<double>());
  for (double t : ts) {
    double s = row(0, 0).convert_to<double>();
    for (std::size_t j = 0; j < m; ++j)
      for (long d = 0; d < orders; ++d) {
        const double c = row(0, 1 + d * m + j).convert_to<double>();
        if (c == 0) continue;
        const double term = c * waveforms[j].value(t, static_cast<int>(d));
        s += term;
        scale = std::max(scale, std::abs(term));
      }
    if (std::abs(s) > worst) {
      worst = std::abs(s);
      at = t;
    }
  }
  std::ostringstream o;
  o.precision(6);
  if (worst > 1e-9 * std::max(scale, 1e-300)) {
    v.holds = ConditionVerdict::Holds::no;
    o << "fails at t = " << at << " s: the left side is " << worst << " (sources evaluated in double)";
  } else {
    v.holds = ConditionVerdict::Holds::uncertain;
    o << "different waveforms agree to " << worst << " at " << ts.size() << " sample times: cannot decide exactly";
  }
  v.evidence = o.str();
  return v;
}

namespace {

ref::RlcCircuit<Q> circuit_of(const io::Netlist& n) { return n.rlc; }

/// Loops of the subgraph `keep` that pass through a branch of kind `through`, by a spanning forest
/// that takes the `prefer` branches first (so each reported loop has one `through` chord).
std::vector<graph::Edge> edges_of(const io::Netlist& n) {
  std::vector<graph::Edge> e;
  for (const auto& b : n.rlc.branches) e.push_back({b.from, b.to});
  return e;
}

std::vector<bool> which(const io::Netlist& n, const std::function<bool(RlcKind)>& kind) {
  std::vector<bool> out;
  for (const auto& b : n.rlc.branches) out.push_back(kind(b.kind));
  return out;
}

std::vector<std::string> signed_names(const io::Netlist& n, const graph::Loop& l) {
  std::vector<std::string> names;
  for (const graph::LoopBranch& lb : l) names.push_back((lb.sign > 0 ? "+" : "-") + n.rlc.branches[lb.branch].name);
  return names;
}

std::vector<std::vector<std::string>> loops(const io::Netlist& n, const std::function<bool(RlcKind)>& keep,
                                            const std::function<bool(RlcKind)>& prefer, const std::function<bool(const graph::Loop&)>& report) {
  std::vector<std::vector<std::string>> out;
  for (const graph::Loop& l : graph::fundamental_loops(n.rlc.nodes, edges_of(n), which(n, keep), which(n, prefer)))
    if (report(l)) out.push_back(signed_names(n, l));
  return out;
}

/// CONTRACT `empty_loops`: the dimension of the cycle space of the subgraph of empty branches (the
/// wires, zero-volt sources; CEF Thm 6.8) — one fundamental loop per independent cycle.
long empty_loop_count(const io::Netlist& n) {
  const auto wire = [](RlcKind k) { return k == RlcKind::wire; };
  return static_cast<long>(loops(n, wire, wire, [](const graph::Loop&) { return true; }).size());
}

/// Cutsets made only of branches with `in(kind)`: contract every other branch; the cut around each
/// resulting super-node (one per connected piece left out) — independent cutsets, signed (+ = leaving).
std::vector<std::vector<std::string>> cutsets(const io::Netlist& n, const std::function<bool(RlcKind)>& in,
                                              const std::function<bool(RlcKind)>& must) {
  std::vector<std::vector<std::string>> out;
  for (const graph::Cutset& c : graph::cutsets(n.rlc.nodes, edges_of(n), which(n, in), which(n, must))) out.push_back(signed_names(n, c));
  return out;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& x : names) s += (s.empty() ? "" : " ") + x;
  return s;
}

Equation jet_equation(const QM& rows, std::size_t i, std::size_t nvars) {
  Equation e;
  for (std::size_t j = 0; j < rows.cols(); ++j) {
    if (j == nvars || rows(i, j) == 0) continue;
    e.terms.emplace_back(j < nvars ? j : j - 1, rows(i, j).str());
  }
  e.rhs = Q(-rows(i, nvars)).str();
  return e;
}

}  // namespace

namespace {

Eigen::MatrixXd to_d(const QM& m) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) d(i, j) = m(i, j).convert_to<double>();
  return d;
}

Q pow10(long e) {
  Q r(1);
  for (long k = 0; k < std::labs(e); ++k) r *= 10;
  return e >= 0 ? r : Q(1) / r;
}

long mean_exponent(const ref::RlcCircuit<Q>& c, RlcKind kind) {
  double sum = 0;
  long count = 0;
  for (const auto& b : c.branches)
    if (b.kind == kind && b.value != 0) {
      sum += std::log10(std::abs(b.value.convert_to<double>()));
      ++count;
    }
  return count ? std::lround(sum / static_cast<double>(count)) : 0;
}

/// The dimensionless twin (as io::dimensionless for LC circuits): L/L0, C/C0, R/R0 and M/L0 with
/// L0 = 10^a, C0 = 10^b (a + b even), R0 = √(L0/C0) = 10^((a−b)/2).  With t = T t̃, v = ṽ/T,
/// p = (L0/T) p̃, V = Ṽ/C0, I = Ĩ/T the Lagrangian and the forces are C0⁻¹ times the twin's: the same
/// tower (dims, steps, solution rank, number of source conditions), only far better scaled in double.
ref::RlcCircuit<Q> forced_twin(const ref::RlcCircuit<Q>& c) {
  const long a = mean_exponent(c, RlcKind::inductor);
  long b = mean_exponent(c, RlcKind::capacitor);
  if ((a + b) % 2 != 0) ++b;
  ref::RlcCircuit<Q> out = c;
  const Q l0 = pow10(a), c0 = pow10(b), r0 = pow10((a - b) / 2);
  for (auto& br : out.branches) {
    if (br.kind == RlcKind::inductor) br.value /= l0;
    if (br.kind == RlcKind::capacitor) br.value /= c0;
    if (br.kind == RlcKind::resistor) br.value /= r0;
  }
  for (auto& mu : out.mutuals) mu.m /= l0;
  return out;
}

/// The input assessment of the fast forced twin: the element values of the (dimensionless) circuit, as
/// the LC route's (solve_circuit.cpp).  The exact system's matrices are derived from them exactly and
/// rounded once, which is less than computing them in double.
fast::Options circuit_options(const ref::RlcCircuit<Q>& c) {
  std::vector<Q> values;
  for (const auto& b : c.branches)
    if (b.kind == RlcKind::inductor || b.kind == RlcKind::capacitor || b.kind == RlcKind::resistor) values.push_back(b.value);
  for (const auto& mu : c.mutuals) values.push_back(mu.m);
  fast::Options opt;
  fast::to_double_values(values, opt);
  return opt;
}

/// The fast twin on the exact system rounded to double (YM §4 in double, fast/forced.hpp), with the
/// input's assessment `opt`: a value that rounding may have changed in a decisive digit makes every
/// rank deficiency uncertain (a C of -3.0000000000000000001 beside one of 3 read as their cancellation,
/// certain, and gave a tower two steps too long).
void fast_tower(const ref::ForcedSystem<Q>& f, const fast::Options& opt, SolveReport& s) {
  fast::ForcedSystem g;
  g.s.d.n = static_cast<int>(f.s.d.n);
  g.s.d.d = fast::Subspace::span(to_d(f.s.d.d.basis()));
  g.s.hessian = to_d(f.s.hessian);
  g.s.gradient = Eigen::VectorXd::Zero(f.s.d.n);
  g.force = to_d(f.force);
  g.sources = static_cast<int>(f.sources);
  g.source_force = to_d(f.source_force);
  g.shift = to_d(f.shift);
  g.given_conditions = to_d(f.given_conditions);
  const fast::ForcedResult r = fast::forced_tower(g, opt);
  s.dims.assign(r.dims.begin(), r.dims.end());
  for (long d : s.dims) {
    SolveReport::Step st;
    st.dim = d;
    s.tower.push_back(st);
  }
  s.steps = r.steps;
  s.consistent = r.consistent;
  s.solution_rank = r.solution_rank;
  s.certified = r.certain.yes() && r.conditions.rows() == 0;
  s.decisions_float = static_cast<long>(r.decisions.size());
  s.note = "forced route, fast twin (double, SVD rank decisions)";
  const std::string caveat = fast::input_caveat(opt);
  if (r.certain.unknown() && !caveat.empty()) s.note += "; " + caveat + ": use --backend certified";
  if (r.certain.unknown() && caveat.empty())
    for (std::size_t i = 0; i < r.decisions.size(); ++i)
      if (r.decisions[i].certain.unknown()) {
        s.note += "; rank decision " + std::to_string(i + 1) + " of " + std::to_string(r.decisions.size()) +
                  " was uncertain (" + r.decisions[i].describe() + "): use --backend certified";
        break;
      }
  if (r.conditions.rows())
    s.note += "; " + std::to_string(r.conditions.rows()) +
              " source condition(s) that the fast backend does not decide against the waveforms: use --backend certified";
}

/// The exact forced CAD as a report: the tower with its jet equations, the source conditions
/// decided against the waveforms (the first M_k whose condition fails is empty).
void exact_report(const ref::ForcedSystem<Q>& f, const std::vector<io::Waveform>& waveforms, const std::vector<std::string>& variables,
                  const std::string& backend, ForcedReport& out) {
  const ref::ForcedResult<Q> r = ref::forced_tower(f);
  SolveReport& s = out.report;
  s.backend = backend == "reference" ? "reference" : backend;
  s.certified = true;
  s.decisions_exact = 1;
  s.note = "forced route (YM §4 forces and affine constraints, moving M_k(t) as in V §3), exact";
  const std::size_t nv = f.s.d.n;
  long empty_at = r.consistent ? -1 : static_cast<long>(r.dims.size()) - 1;
  for (std::size_t k = 0; k < r.conditions_at.size() && (empty_at < 0 || static_cast<long>(k) < empty_at); ++k) {
    const QM& ck = r.conditions_at[k];
    for (std::size_t i = 0; i < ck.rows(); ++i) {
      const ConditionVerdict v = decide_condition(ck.block(i, i + 1, 0, ck.cols()), waveforms);
      bool dup = false;
      for (const ConditionVerdict& o : out.conditions) dup = dup || o.text == v.text;
      if (!dup) out.conditions.push_back(v);
      if (v.holds == ConditionVerdict::Holds::no && empty_at < 0) empty_at = static_cast<long>(k);
      if (v.holds == ConditionVerdict::Holds::uncertain) s.certified = false;
    }
  }
  for (std::size_t k = 0; k < r.dims.size(); ++k) {
    SolveReport::Step st;
    st.dim = r.dims[k];
    if (empty_at >= 0 && static_cast<long>(k) >= empty_at) st.dim = -1;
    for (std::size_t i = 0; i < r.added[k].rows(); ++i) st.equations.push_back(jet_equation(r.added[k], i, nv));
    s.tower.push_back(st);
    s.dims.push_back(st.dim);
    if (st.dim < 0) break;
  }
  s.steps = static_cast<long>(s.dims.size()) - 1;
  out.names = variables;
  const std::vector<std::string> jets = jet_names(waveforms, static_cast<long>(r.orders) + 1);
  out.names.insert(out.names.end(), jets.begin() + 1, jets.end());
  for (const io::Waveform& w : waveforms) out.source_names.push_back(w.element);
  s.consistent = s.dims.back() >= 0;
  s.solution_rank = s.consistent ? static_cast<long>(r.solution_rank) : 0;
  if (!s.certified) s.note += "; a source condition could not be decided exactly (see sources.conditions)";
  if (!s.consistent) return;
  // equations of motion: ż = F z + f + S u_src(t) + G λ  [CEF (5.12) with the sources' jets]
  const ref::ForcedReducedEquations<Q> red = ref::forced_reduced_equations(ref::forced_motion(f, r), f.sources);
  s.has_reduced = true;
  s.coords.assign(red.coords.begin(), red.coords.end());
  const auto text = [](const QM& m) {
    std::vector<std::vector<std::string>> t(m.rows(), std::vector<std::string>(m.cols()));
    for (std::size_t i = 0; i < m.rows(); ++i)
      for (std::size_t j = 0; j < m.cols(); ++j) t[i][j] = m(i, j).str();
    return t;
  };
  s.f_matrix = text(red.f_matrix);
  s.g = text(red.g);
  for (const Q& x : red.f) s.f.push_back(x.str());
  // only the jet orders that occur (the tower widens the jets by one order per step)
  std::size_t used = 0;
  for (std::size_t j = 0; j < red.s.cols(); ++j)
    for (std::size_t i = 0; i < red.s.rows(); ++i)
      if (red.s(i, j) != 0) used = j + 1;
  if (f.sources) used = (used + f.sources - 1) / f.sources * f.sources;
  out.source_terms = text(red.s.block(0, red.s.rows(), 0, used));
  out.source_columns.assign(jets.begin() + 1, jets.begin() + 1 + static_cast<long>(used));
  s.extra_names = out.source_columns;
  s.extra_terms = out.source_terms;
}

std::vector<std::string> netlist_variables(const io::Netlist& n) {
  std::vector<std::string> v;
  for (const char* p : {"q_", "v_", "p_"})
    for (const auto& b : n.rlc.branches) v.push_back(p + b.name);
  return v;
}

}  // namespace

ref::ForcedSystem<Q> case_forced_system(const io::CaseFile& c) {
  const io::PontryaginInput& in = c.pontryagin;
  const std::size_t n = in.n;
  ref::ForcedSystem<Q> f{ref::pontryagin_system(ref::PontryaginInput<Q>{in.n, in.k, in.vv, in.qv, in.qq, in.q, in.v}),
                         QM(3 * n, 3 * n), 0, QM(3 * n, 0), QM(3 * n, 0), QM(0, 1)};
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      f.force(i, j) = in.fq(i, j);      // F(q, v)·δq: a horizontal one-form  [YM §4]
      f.force(i, n + j) = in.fv(i, j);
    }
  return f;
}

ForcedReport solve_forced_case(const io::CaseFile& c, const std::string& backend) {
  ForcedReport out;
  const ref::ForcedSystem<Q> f = case_forced_system(c);
  if (backend == "fast") {
    out.report.backend = "fast";
    fast::Options opt;  // the case's own numbers, assessed (the matrices are discarded)
    fast::to_fast(c.pontryagin, opt);
    fast::to_double(c.pontryagin.fq, opt);
    fast::to_double(c.pontryagin.fv, opt);
    fast_tower(f, opt, out.report);
    out.names = c.variables;
    return out;
  }
  exact_report(f, {}, c.variables, backend, out);
  return out;
}

ForcedReport solve_forced(const io::Netlist& n, const std::string& backend) {
  if (n.rlc.branches.size() > kForcedBranches)
    throw io::InputError(n.file + ": expected at most " + std::to_string(kForcedBranches) +
                         " branches for a circuit with resistors, sources or couplings, found " + std::to_string(n.rlc.branches.size()) +
                         " (the forced route is dense and exact; larger ones are not supported yet)");
  ForcedReport out;
  if (backend == "fast") {
    out.report.backend = "fast";
    const ref::RlcCircuit<Q> twin = forced_twin(n.rlc);  // the dimensionless twin: same tower
    fast_tower(ref::rlc_system(twin), circuit_options(twin), out.report);
    out.names = netlist_variables(n);
    for (const io::Waveform& w : n.waveforms) out.source_names.push_back(w.element);
    out.circuit = {{"branches", n.rlc.branches.size()}, {"nodes", n.rlc.nodes + 1},
                   {"pc_loops", out.report.consistent && out.report.dims.size() > 2 ? out.report.dims[1] - out.report.dims[2] : 0},
                   {"empty_loops", empty_loop_count(n)}};
    return out;
  }
  exact_report(ref::rlc_system(circuit_of(n)), n.waveforms, netlist_variables(n), backend, out);
  SolveReport& s = out.report;
  // loops and cutsets by name
  const auto is = [](std::initializer_list<RlcKind> ks) {
    return [ks](RlcKind k) { return std::find(ks.begin(), ks.end(), k) != ks.end(); };
  };
  const auto has = [&](RlcKind kind) {
    return [&n, kind](const graph::Loop& l) {
      for (const graph::LoopBranch& b : l)
        if (n.rlc.branches[b.branch].kind == kind) return true;
      return false;
    };
  };
  const auto cv = loops(n, is({RlcKind::capacitor, RlcKind::voltage, RlcKind::wire}), is({RlcKind::voltage, RlcKind::wire}),
                        has(RlcKind::capacitor));
  const auto vloops = loops(n, is({RlcKind::voltage, RlcKind::wire}), is({RlcKind::wire}), has(RlcKind::voltage));
  const auto li = cutsets(n, is({RlcKind::inductor, RlcKind::current}), is({RlcKind::inductor}));
  const auto icut = cutsets(n, is({RlcKind::current}), is({RlcKind::current}));
  long counts[6] = {0, 0, 0, 0, 0, 0};
  for (const auto& b : n.rlc.branches) ++counts[static_cast<int>(b.kind)];
  out.circuit = {{"branches", n.rlc.branches.size()},
                 {"nodes", n.rlc.nodes + 1},
                 {"pc_loops", s.consistent && s.dims.size() > 2 ? s.dims[1] - s.dims[2] : 0},
                 {"empty_loops", empty_loop_count(n)},
                 {"inductors", counts[0]},
                 {"capacitors", counts[1]},
                 {"resistors", counts[2]},
                 {"voltage_sources", counts[3]},
                 {"current_sources", counts[4]},
                 {"wires", counts[5]},
                 {"couplings", n.rlc.mutuals.size()},
                 {"cv_loops", cv},
                 {"source_loops", vloops},
                 {"li_cutsets", li},
                 {"source_cutsets", icut}};
  std::ostringstream o;
  o << "  circuit \"" << n.title << "\": " << n.rlc.branches.size() << " branches, " << n.rlc.nodes + 1 << " nodes (ground included); "
    << counts[0] << " L, " << counts[1] << " C, " << counts[2] << " R, " << counts[3] << " V, " << counts[4] << " I, " << n.rlc.mutuals.size()
    << " K\n";
  for (const auto& l : cv)
    o << "    CV loop " << joined(l) << ": KVL fixes its capacitor charges by the sources (Σ ±q/C = Σ ±V on M_2, the currents on M_3)\n";
  for (const auto& l : vloops) o << "    loop of voltage sources " << joined(l) << ": KVL is a condition on the sources alone (Σ ±V(t) = 0)\n";
  for (const auto& c : li)
    o << "    LI cutset " << joined(c) << ": KCL fixes its inductor currents by the current sources (Σ ±v_L = Σ ±I on M_1)\n";
  for (const auto& c : icut) o << "    cutset of current sources " << joined(c) << ": KCL is a condition on the sources alone (Σ ±I(t) = 0)\n";
  for (const ConditionVerdict& v : out.conditions)
    o << "    source condition " << v.text << ": "
      << (v.holds == ConditionVerdict::Holds::yes ? "holds" : v.holds == ConditionVerdict::Holds::no ? "FAILS — the circuit is inconsistent" : "UNDECIDED")
      << " (" << v.evidence << ")\n";
  for (const std::string& w : n.warnings) o << "    warning: " << w << "\n";
  out.circuit_text = o.str();
  return out;
}

nlohmann::json to_json(const ForcedReport& r, const io::CaseFile& c) {
  io::CaseFile ext = c;
  ext.variables = r.names;
  nlohmann::json j = to_json(r.report, ext);
  j["variables"] = c.variables;
  if (!r.circuit.is_null()) j["circuit"] = r.circuit;
  nlohmann::json conds = nlohmann::json::array();
  for (const ConditionVerdict& v : r.conditions)
    conds.push_back({{"condition", v.text},
                     {"holds", v.holds == ConditionVerdict::Holds::yes ? nlohmann::json(true)
                               : v.holds == ConditionVerdict::Holds::no ? nlohmann::json(false)
                                                                        : nlohmann::json(nullptr)},
                     {"evidence", v.evidence}});
  if (!r.source_names.empty() || !conds.empty()) j["sources"] = {{"names", r.source_names}, {"conditions", conds}};
  if (j.contains("reduced") && !r.source_columns.empty()) j["reduced"]["sources"] = {{"columns", r.source_columns}, {"S", r.source_terms}};
  return j;
}

std::string to_text(const ForcedReport& r, const io::CaseFile& c) {
  io::CaseFile ext = c;
  ext.variables = r.names;
  return to_text(r.report, ext) + r.circuit_text;
}

}  // namespace dcad::cli
