// `dcad check WAVEFORM DECK` (CONTRACT "Checking a simulator's waveform"): each vector of another
// simulator's output, named as ngspice or gnucap name it (or as dcad names variables), against the
// exact flow of DECK from the state the simulator started from, evaluated at the file's own times.
#include "dcad/api.hpp"
#include "guarded.hpp"
#include "simulate.hpp"
#include "sparse_flow.hpp"

#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/initial_state.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

namespace dcad::api {

namespace {

std::size_t nb_of(const io::Netlist& d) { return d.rlc.branches.size(); }

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::string without_spaces(const std::string& s) {
  std::string t;
  for (char ch : s)
    if (!std::isspace(static_cast<unsigned char>(ch))) t += ch;
  return t;
}

/// A vector as a function of the circuit's values: e_a − e_b (nodes, −1 ground), or a branch's q, i or p.
struct Functional {
  enum Kind { potential, charge, current, flux } kind = potential;
  long a = -1, b = -1;    ///< nodes (potential)
  std::size_t branch = 0;  ///< (the others)
  std::string meaning;
};

struct Names {
  std::map<std::string, long> nodes;           ///< lower-case name → index (ground −1)
  std::map<std::string, std::size_t> branches;  ///< lower-case name → branch
  std::vector<std::string> node_list, branch_list;
};

Names names_of(const io::Netlist& deck) {
  Names n;
  n.nodes["0"] = -1;
  n.nodes["gnd"] = -1;
  for (std::size_t k = 0; k < deck.node_names.size(); ++k) {
    n.nodes[lower(deck.node_names[k])] = static_cast<long>(k);
    n.node_list.push_back(deck.node_names[k]);
  }
  for (std::size_t b = 0; b < deck.rlc.branches.size(); ++b) {
    n.branches[lower(deck.rlc.branches[b].name)] = b;
    n.branch_list.push_back(deck.rlc.branches[b].name);
  }
  return n;
}

std::string listed(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t k = 0; k < v.size() && k < 12; ++k) s += (k ? ", " : "") + v[k];
  if (v.size() > 12) s += ", … (" + std::to_string(v.size()) + ")";
  return s;
}

/// The vector `name` of the file as a Functional of the deck; InputError naming what it could be.
Functional functional(const std::string& name, const Names& n, const io::Netlist& deck, const std::string& file) {
  const std::string s = lower(without_spaces(name));
  const auto node = [&](const std::string& x, long& out) {
    const auto it = n.nodes.find(x);
    if (it == n.nodes.end()) return false;
    out = it->second;
    return true;
  };
  const auto branch = [&](const std::string& x, std::size_t& out) {
    const auto it = n.branches.find(x);
    if (it == n.branches.end()) return false;
    out = it->second;
    return true;
  };
  Functional f;
  // dcad's own variable names: q_X, v_X (the current), p_X
  if (s.size() > 2 && s[1] == '_' && (s[0] == 'q' || s[0] == 'v' || s[0] == 'p') && branch(s.substr(2), f.branch)) {
    f.kind = s[0] == 'q' ? Functional::charge : s[0] == 'v' ? Functional::current : Functional::flux;
    f.meaning = std::string(s[0] == 'q' ? "charge" : s[0] == 'v' ? "current" : "flux linkage") + " of " + deck.rlc.branches[f.branch].name;
    return f;
  }
  // v(a) and v(a,b): node voltages; a bare node name as older raw files write it
  if (s.size() > 3 && s.rfind("v(", 0) == 0 && s.back() == ')') {
    const std::string in = s.substr(2, s.size() - 3);
    const std::size_t comma = in.find(',');
    const std::string a = in.substr(0, comma), b = comma == std::string::npos ? "0" : in.substr(comma + 1);
    if (node(a, f.a) && node(b, f.b)) {
      f.kind = Functional::potential;
      f.meaning = comma == std::string::npos ? "potential of node " + a : "potential of node " + a + " minus node " + b;
      return f;
    }
  } else if (node(s, f.a)) {
    f.kind = Functional::potential;
    f.meaning = "potential of node " + s;
    return f;
  }
  // i(x), x#branch: the current through element x from its n+ to its n− (ngspice's and dcad's sign)
  std::string el;
  if (s.size() > 3 && s.rfind("i(", 0) == 0 && s.back() == ')') el = s.substr(2, s.size() - 3);
  else if (s.size() > 7 && s.compare(s.size() - 7, 7, "#branch") == 0) el = s.substr(0, s.size() - 7);
  if (el.size() > 4 && el[0] == '@' && el.compare(el.size() - 3, 3, "[i]") == 0) el = el.substr(1, el.size() - 4);  // .options savecurrents
  else if (s.size() > 4 && s[0] == '@' && s.compare(s.size() - 3, 3, "[i]") == 0) el = s.substr(1, s.size() - 4);
  // gnucap's hierarchical element x1.l1 is ngspice's (and dcad's) l.x1.l1
  if (!el.empty() && el.find('.') != std::string::npos && !branch(el, f.branch)) {
    const std::string leaf = el.substr(el.rfind('.') + 1);
    if (!leaf.empty() && branch(std::string(1, leaf[0]) + "." + el, f.branch)) el = std::string(1, leaf[0]) + "." + el;
  }
  if (!el.empty() && branch(el, f.branch)) {
    f.kind = Functional::current;
    f.meaning = "current of " + deck.rlc.branches[f.branch].name + " (n+ to n- through it)";
    return f;
  }
  throw io::InputError(file + ": vector '" + name + "': expected v(node), v(node,node), i(element), element#branch or q_/v_/p_ names of " +
                       deck.file + " (nodes: " + listed(n.node_list) + "; elements: " + listed(n.branch_list) + "), found none that names them");
}

double value(const Functional& f, const sr::BranchValues& bv, const Vec& e) {
  const auto pot = [&](long node) { return node < 0 ? 0.0 : e(node); };
  const auto b = static_cast<Eigen::Index>(f.branch);
  switch (f.kind) {
    case Functional::potential: return pot(f.a) - pot(f.b);
    case Functional::charge: return bv.q(b);
    case Functional::current: return bv.i(b);
    case Functional::flux: return bv.p(b);
  }
  return 0;
}

/// The smallest enclosure (rounded outward) of two.
certified::Enclosure hull(const certified::Enclosure& a, const certified::Enclosure& b) {
  const double lo = std::nextafter(std::min(a.mid - a.rad, b.mid - b.rad), -HUGE_VAL), hi = std::nextafter(std::max(a.mid + a.rad, b.mid + b.rad), HUGE_VAL);
  certified::Enclosure h;
  h.mid = lo / 2 + hi / 2;
  h.rad = std::nextafter(std::max(h.mid - lo, hi - h.mid), HUGE_VAL);
  return h;
}

/// Enclosures of every vector at the file's times (the certified tier), or why there are none.
struct Enclosed {
  bool ok = false;
  std::string why;
  std::vector<std::vector<certified::Enclosure>> right, left;  ///< [vector][point]
  long restarts = 0;
};

/// The voltage e_from − e_to of branch b as a functional of the motion (x = (q, v, p), ẋ, u_ext).
std::vector<certified::Functional::Term> branch_voltage(const io::Netlist& deck, std::size_t b) {
  using T = certified::Functional::Term;
  using Of = certified::Functional::Of;
  const auto& br = deck.rlc.branches[b];
  const std::size_t nb = deck.rlc.branches.size();
  switch (br.kind) {
    case reference::RlcKind::capacitor: return {T{Of::x, b, io::Rational(1) / br.value}};           // q / C
    case reference::RlcKind::resistor: return {T{Of::x, nb + b, br.value}};                         // R i
    case reference::RlcKind::inductor: return {T{Of::xdot, 2 * nb + b, io::Rational(1)}};           // dp/dt
    case reference::RlcKind::voltage: return {T{Of::u, 1 + static_cast<std::size_t>(br.source), io::Rational(1)}};  // V(t)
    default: return {};                                                                             // a wire
  }
}

Enclosed enclose_at(const io::Traces& tr, const io::Problem& p, const std::vector<Functional>& fs, const WaveformOptions& opt, double step, long precision);

/// Enclosures at 256 bits, then at twice the precision while some radius exceeds 2^-60 of its vector's
/// largest value (wrapping through many corners: each doubling of the bits buys about twice the corners),
/// up to 2048 bits.
Enclosed enclose(const io::Traces& tr, const io::Problem& p, const std::vector<Functional>& fs, const WaveformOptions& opt, double step) {
  Enclosed e;
  double before = HUGE_VAL;  // the widest relative radius of the previous precision
  for (long precision = 256; precision <= 2048; precision *= 2) {
    const auto start = std::chrono::steady_clock::now();
    e = enclose_at(tr, p, fs, opt, step, precision);
    if (!e.ok) return e;
    bool finite = true;
    for (const auto& v : e.right)
      for (const certified::Enclosure& x : v) finite = finite && std::isfinite(x.rad);
    // an infinite radius (a stiff circuit's exponential) does not narrow with more bits; nor is a run
    // that took 10 s repeated at twice the cost
    if (!finite || std::chrono::steady_clock::now() - start > std::chrono::seconds(10)) return e;
    double widest = 0;  // over the vectors: radius / scale (a vector whose exact values are all 0: radius alone)
    for (std::size_t k = 0; k < e.right.size(); ++k) {
      double scale = 0, rad = 0;
      for (std::size_t i = 0; i < e.right[k].size(); ++i)
        scale = std::max({scale, std::abs(e.right[k][i].mid), std::abs(e.left[k][i].mid)}), rad = std::max({rad, e.right[k][i].rad, e.left[k][i].rad});
      widest = std::max(widest, rad <= std::ldexp(1.0, -1000) ? 0.0 : scale > 0 ? rad / scale : HUGE_VAL);
    }
    // 2^-50: above the midpoint's own rounding to double (2^-53 of it, part of every radius), which more
    // bits cannot narrow (at 2^-60 every run was redone at 512, 1024 and 2048 bits); and a width that twice
    // the bits did not narrow 2^32-fold is not the precision's (a time a hair from a source corner is the
    // hull of both sides): more bits would only cost (a 6,900-point check ran to 2048 bits, 1.5 s)
    if (widest <= std::ldexp(1.0, -50) || widest > std::ldexp(before, -32)) return e;
    before = widest;
  }
  return e;
}

Enclosed enclose_at(const io::Traces& tr, const io::Problem& p, const std::vector<Functional>& fs, const WaveformOptions& opt, double step, long precision) {
  Enclosed out;
  const io::Netlist& deck = p.netlist;
  const std::size_t nb = deck.rlc.branches.size(), nodes = deck.node_names.size();
  CertifiedMotion cm;
  try {
    cm = certified_motion(deck, p.linear, opt.initial, step, precision);
  } catch (const std::exception& e) {
    out.why = e.what();
    return out;
  }
  if (!cm.flow) {
    out.why = cm.why;
    return out;
  }
  // node potentials along a spanning tree of the branches whose voltage is known (all but current sources)
  std::vector<std::optional<std::vector<certified::Functional::Term>>> pot(nodes + 1);  // index node + 1; 0 = ground
  pot[0] = std::vector<certified::Functional::Term>{};
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t b = 0; b < nb; ++b) {
      const auto& br = deck.rlc.branches[b];
      if (br.kind == reference::RlcKind::current) continue;
      const std::size_t f = static_cast<std::size_t>(br.from + 1), t = static_cast<std::size_t>(br.to + 1);
      if (pot[f].has_value() == pot[t].has_value()) continue;
      const bool forward = pot[f].has_value();  // e_to = e_from − v_b, or e_from = e_to + v_b
      std::vector<certified::Functional::Term> terms = forward ? *pot[f] : *pot[t];
      for (auto term : branch_voltage(deck, b)) {
        if (forward) term.coef = -term.coef;
        terms.push_back(term);
      }
      pot[forward ? t : f] = std::move(terms);
      grew = true;
    }
  }
  std::vector<certified::Functional> cf(fs.size());
  for (std::size_t k = 0; k < fs.size(); ++k) {
    const Functional& f = fs[k];
    using Of = certified::Functional::Of;
    if (f.kind == Functional::potential) {
      for (long node : {f.a, f.b}) {
        const auto& path = pot[static_cast<std::size_t>(node + 1)];
        if (!path) {
          out.why = "node " + deck.node_names[static_cast<std::size_t>(node)] + " reaches ground only through current sources: its potential is not enclosed";
          return out;
        }
        for (auto term : *path) {
          if (node == f.b) term.coef = -term.coef;
          cf[k].terms.push_back(term);
        }
      }
    } else {
      const std::size_t base = f.kind == Functional::charge ? 0 : f.kind == Functional::current ? nb : 2 * nb;
      cf[k].terms.push_back({Of::x, base + f.branch, io::Rational(1)});
    }
  }
  const std::size_t np = tr.time.size();
  // the exact corners: a file time within 1e-13 of the run of one (a simulator's breakpoint, TD + k·PER
  // summed in double) is read as that corner and compared with its two one-sided values
  const double near = 1e-13 * std::max(std::abs(tr.time.back()), std::abs(tr.time.front()));
  std::map<double, io::Rational> corners;
  const std::vector<io::Rational> all = cm.flow->corners(certified::rational_of(tr.time.back() + 2 * near), kEnclosedCorners + 1);
  if (all.size() > kEnclosedCorners) {
    out.why = "the sources have more than " + std::to_string(kEnclosedCorners) + " corners in the run (each is crossed exactly)";
    return out;
  }
  for (const io::Rational& c : all) corners.emplace(c.convert_to<double>(), c);
  const auto corner_of = [&](double t) -> const io::Rational* {
    auto it = corners.lower_bound(t - near);
    return it != corners.end() && it->first <= t + near ? &it->second : nullptr;
  };
  out.right.assign(fs.size(), std::vector<certified::Enclosure>(np));
  out.left = out.right;
  try {
    for (std::size_t i = 0; i < np; ++i) {
      const io::Rational at = certified::rational_of(tr.time[i]);
      const io::Rational* c = corner_of(tr.time[i]);
      if (at < cm.flow->time() || (c && *c < cm.flow->time())) {
        out.why = "two of the file's times lie within 1e-13 of the run of one source corner";
        return out;
      }
      std::vector<certified::Enclosure> before;  // at the file's own time, when it is just before the corner
      if (c && at < *c) {
        cm.flow->advance_to(at);
        before = cm.flow->evaluate(cf);
      }
      cm.flow->advance_to(c ? *c : at);
      std::vector<certified::Enclosure> r = cm.flow->evaluate(cf), l = cm.flow->at_corner() ? cm.flow->evaluate(cf, true) : r;
      // a time near a corner: the side it lies on holds the exact value at the file's own time (the hull
      // of that side's value at the corner and the value at the time), the other side the corner's
      // other one-sided value (the CONTRACT's allowance at a jump)
      if (c && at > *c) {
        cm.flow->advance_to(at);
        const std::vector<certified::Enclosure> after = cm.flow->evaluate(cf);
        for (std::size_t k = 0; k < fs.size(); ++k) r[k] = hull(r[k], after[k]);
      }
      for (std::size_t k = 0; k < before.size(); ++k) l[k] = hull(l[k], before[k]);
      for (std::size_t k = 0; k < fs.size(); ++k) out.right[k][i] = r[k], out.left[k][i] = l[k];
    }
  } catch (const std::exception& e) {
    out.why = e.what();
    return out;
  }
  out.restarts = cm.flow->restarts();
  out.ok = true;
  return out;
}

}  // namespace

WaveformEnclosures enclose_waveforms(const io::Problem& p, const std::vector<std::string>& names, const std::vector<double>& times, Initial initial,
                                     double step) {
  io::Traces tr;
  tr.file = p.netlist.file;
  tr.names = names;
  tr.time = times;
  const Names nm = names_of(p.netlist);
  std::vector<Functional> fs;
  for (const std::string& name : names) fs.push_back(functional(name, nm, p.netlist, p.netlist.file));
  WaveformOptions opt;
  opt.initial = initial;
  Enclosed e = enclose(tr, p, fs, opt, step);
  return WaveformEnclosures{e.ok, e.why, std::move(e.right), std::move(e.left)};
}

WaveformChecked check_waveform(const io::Traces& tr, const io::Problem& p, const WaveformOptions& opt, std::ostream& log) {
  io::validate(tr);
  io::validate(p);
  for (std::size_t k = 0; k < tr.skipped.size() && k < 5; ++k) log << "note: skipped a simulator's message inside the table at " << tr.skipped[k] << "\n";
  if (tr.skipped.size() > 5) log << "note: … and " << tr.skipped.size() - 5 << " more messages skipped\n";
  if (p.form != io::Form::netlist)
    throw io::InputError(p.netlist.file.empty() ? tr.file + ": check: expected a netlist as DECK for a waveform, found a case file"
                                                : p.netlist.file + ": check: expected a netlist for a waveform");
  const io::Netlist& deck = p.netlist;
  if (!deck.indefinite_inductance.empty())
    throw io::InputError(deck.indefinite_inductance + "; check: expected a positive semidefinite inductance matrix, found another (lower the couplings)");
  if (!(opt.rtol >= 0) || !(opt.atol >= 0)) throw UsageError("--rtol and --atol: expected numbers >= 0");
  if (tr.names.empty())
    throw io::InputError(tr.file + ": expected at least one vector besides time (" + tr.format + "), found none: nothing to check" +
                         (tr.format == "gnucap" ? " (gnucap runs .tran as it reads it: put .print before .tran)" : ""));
  const Names names = names_of(deck);
  std::vector<Functional> fs;
  for (const std::string& name : tr.names) fs.push_back(functional(name, names, deck, tr.file));
  WaveformChecked out;
  out.format = tr.format;
  out.points = static_cast<long>(tr.time.size());
  const double horizon = tr.time.back();
  const double step = tr.time.size() > 1 && horizon > 0 ? horizon / static_cast<double>(tr.time.size() - 1) : 1.0;
  const std::size_t nv = fs.size(), np = tr.time.size();
  // the certified tier first: enclosures of the exact values (rigorous), where dcad builds them
  const Enclosed enc = opt.enclose ? enclose(tr, p, fs, opt, step) : Enclosed{false, "not asked for (WaveformOptions::enclose false)", {}, {}, 0};
  const bool graph = reference::pipeline::graph_route_holds(deck.rlc);
  if (!graph && !enc.ok)
    throw io::InputError(deck.file + ": check: expected a circuit whose exact flow dcad evaluates at any time (every R, L, C > 0, couplings |k| < 1, "
                         "or up to " + std::to_string(reference::pipeline::kForcedBranches) + " branches for the enclosures on the dense model), found another: " + enc.why);
  // exact values at every time point: right values, and left ones where they may differ (corners, t = 0),
  // each with how far the exact value may be from it (an enclosure's radius, or the double flow's estimate)
  std::vector<std::vector<double>> right(nv, std::vector<double>(np)), left(nv, std::vector<double>(np)), rad_r(nv, std::vector<double>(np)),
      rad_l(nv, std::vector<double>(np));
  std::vector<bool> two_sided(np, false);
  long jumps = 0;
  std::vector<std::string> jumped;  // the variables that jump at t = 0 (q_C, v_L, p_L)
  std::vector<double> uncertainty(nv, 0.0);
  double circuit_kind_scale[4] = {0, 0, 0, 0};  // the graph route's: over every node and branch of the circuit
  if (graph) {
    SparseFlow flow(deck, deck.file, opt.initial, step, std::max(horizon, step), log);
    double* kind_scale = circuit_kind_scale;  // the largest potential, charge, current, flux linkage over the run
    for (std::size_t i = 0; i < np; ++i) {
      const double t = tr.time[i];
      flow.advance_to(t);
      const sr::BranchValues bv = flow.values();
      const Vec e = flow.node_potentials();
      kind_scale[Functional::potential] = std::max(kind_scale[Functional::potential], e.size() ? e.cwiseAbs().maxCoeff() : 0.0);
      kind_scale[Functional::charge] = std::max(kind_scale[Functional::charge], bv.q.size() ? bv.q.cwiseAbs().maxCoeff() : 0.0);
      kind_scale[Functional::current] = std::max(kind_scale[Functional::current], bv.i.size() ? bv.i.cwiseAbs().maxCoeff() : 0.0);
      kind_scale[Functional::flux] = std::max(kind_scale[Functional::flux], bv.p.size() ? bv.p.cwiseAbs().maxCoeff() : 0.0);
      for (std::size_t k = 0; k < nv; ++k) right[k][i] = left[k][i] = value(fs[k], bv, e);
      if (t == 0 || flow.corner(t)) {
        two_sided[i] = true;
        const sr::BranchValues bl = flow.values(true);
        const Vec el = flow.node_potentials(true);
        for (std::size_t k = 0; k < nv; ++k) left[k][i] = value(fs[k], bl, el);
      }
    }
    out.error_estimate = flow.error_estimate();
    jumps = flow.jumps();
    jumped = flow.jumped();
    if (nb_of(deck) <= reference::pipeline::kForcedBranches) {  // small enough for the exact jump: decided in rationals
      namespace pl = reference::pipeline;
      try {
        const pl::InitialState st = pl::initial_state(
            deck, opt.initial == Initial::op ? pl::InitialRule::op : opt.initial == Initial::uic ? pl::InitialRule::uic : pl::InitialRule::deck,
            p.linear.variables);
        if (st.computed) {
          jumped.clear();
          for (const pl::Jump& j : st.jumps) jumped.push_back(j.variable);
          jumps = static_cast<long>(jumped.size());
        }
      } catch (const std::exception&) {  // the flow's own decision stands (its start was computed the same way)
      }
    }
    // dcad's own uncertainty: the Krylov estimate (at least 64 ε for the rounding of the outputs) of
    // the largest value of the vector's kind; a potential difference v(a,b) counts both ends
    for (std::size_t k = 0; k < nv; ++k)
      uncertainty[k] = std::max(out.error_estimate, 64 * std::numeric_limits<double>::epsilon()) * kind_scale[fs[k].kind] *
                       (fs[k].kind == Functional::potential && fs[k].b >= 0 ? 2.0 : 1.0);
  } else {
    netlist_start(deck, p.linear.variables, opt.initial, log, &jumps, &jumped);
  }
  // an enclosure wider than the double flow's own uncertainty (a stiff circuit, wrapping) does not
  // decide its vector: the double flow does, and the run is not certified
  std::vector<bool> enclosed(nv, enc.ok);
  std::string wide;
  for (std::size_t k = 0; k < nv && enc.ok && graph; ++k) {
    double worst = 0;
    for (std::size_t i = 0; i < np; ++i) worst = std::max({worst, enc.right[k][i].rad, enc.left[k][i].rad});
    // (a vector that is 0 over the whole run has uncertainty 0: radii of 1e-308 are not wider than it)
    if (!(worst <= std::max(uncertainty[k], 1e-300))) {
      enclosed[k] = false;
      wide += std::string(wide.empty() ? "" : ", ") + tr.names[k] + " (radius " + io::float_text(worst) + ")";
    }
  }
  for (std::size_t k = 0; k < nv; ++k)
    for (std::size_t i = 0; i < np; ++i) {
      if (enclosed[k]) {
        right[k][i] = enc.right[k][i].mid, rad_r[k][i] = enc.right[k][i].rad;
        left[k][i] = enc.left[k][i].mid, rad_l[k][i] = enc.left[k][i].rad;
        two_sided[i] = two_sided[i] || left[k][i] != right[k][i] || rad_l[k][i] != rad_r[k][i];
      } else {
        rad_r[k][i] = rad_l[k][i] = uncertainty[k];
      }
    }
  // the vectors a jump at t = 0 moves: a jumped charge, current or flux linkage by its branch; potentials and
  // the currents of other branches (functions of the whole state) whenever anything jumps
  std::vector<bool> touched(nv, false);
  for (std::size_t k = 0; k < nv && !jumped.empty(); ++k) {
    if (fs[k].kind == Functional::potential) {
      touched[k] = true;
      continue;
    }
    const auto& br = deck.rlc.branches[fs[k].branch];
    if (fs[k].kind == Functional::current && br.kind != reference::RlcKind::inductor) touched[k] = true;
    for (const char* pre : {"q_", "v_", "p_"})
      touched[k] = touched[k] || std::find(jumped.begin(), jumped.end(), pre + br.name) != jumped.end();
  }
  out.jumped = jumped;
  for (double t : tr.time)
    if (t > 0) {
      out.first_after_zero = t;
      break;
    }
  out.certified = enc.ok && wide.empty();
  out.certified_reason =
      out.certified ? std::string()
      : enc.ok      ? "the enclosures of " + wide + " are wider than the double flow's own uncertainty: those vectors are decided by the double flow (estimated error " +
                     io::float_text(out.error_estimate) + " of the state), not proved"
                    : "the exact flow is evaluated in double (Krylov exponential action on the state equations, estimated error " + io::float_text(out.error_estimate) +
                          " of the state): values, not enclosures; no enclosure because " + enc.why;
  constexpr double u = std::numeric_limits<double>::epsilon();
  // the CONTRACT's scale of each vector (its largest |exact|) lies in [lo, hi]; a vector whose largest |exact|
  // is below 1e-12 of the largest of its kind (0 by symmetry, or without a source) is held to its kind's
  std::vector<double> own(nv, 0.0), own_lo(nv, 0.0), own_hi(nv, 0.0);
  double kind_lo[4] = {0, 0, 0, 0}, kind_hi[4] = {0, 0, 0, 0};
  for (int q = 0; q < 4; ++q) kind_lo[q] = kind_hi[q] = circuit_kind_scale[q];  // the whole circuit's, where the flow gives it
  for (std::size_t k = 0; k < nv; ++k) {
    for (std::size_t i = 0; i < np; ++i) {
      own[k] = std::max({own[k], std::abs(right[k][i]), std::abs(left[k][i])});
      own_hi[k] = std::max({own_hi[k], std::abs(right[k][i]) + rad_r[k][i], std::abs(left[k][i]) + rad_l[k][i]});
      own_lo[k] = std::max({own_lo[k], std::abs(right[k][i]) - rad_r[k][i], std::abs(left[k][i]) - rad_l[k][i]});
    }
    kind_lo[fs[k].kind] = std::max(kind_lo[fs[k].kind], own_lo[k]);
    kind_hi[fs[k].kind] = std::max(kind_hi[fs[k].kind], own_hi[k]);
  }
  for (std::size_t k = 0; k < nv; ++k) {
    WaveformVector v;
    v.name = tr.names[k];
    v.meaning = fs[k].meaning;
    double scale_lo = own_lo[k], scale_hi = own_hi[k];
    v.scale = own[k];
    const double klo = kind_lo[fs[k].kind], khi = kind_hi[fs[k].kind];
    if (own_hi[k] < 1e-12 * klo) {  // certainly a vector near 0: its kind's scale
      scale_lo = klo, scale_hi = khi, v.scale = std::max(own[k], klo);
      v.kind_scale = true;
    } else if (!(own_lo[k] >= 1e-12 * khi)) {  // either may hold: both
      scale_lo = std::min(own_lo[k], klo), scale_hi = std::max(own_hi[k], khi);
    }
    for (std::size_t i = 0; i < np; ++i) v.exact_uncertainty = std::max({v.exact_uncertainty, rad_r[k][i], two_sided[i] ? rad_l[k][i] : 0.0});
    const double tol_lo = (opt.atol + opt.rtol * scale_lo) * (1 - 4 * u), tol_hi = (opt.atol + opt.rtol * scale_hi) * (1 + 4 * u);
    bool first = true, within = true, beyond = false;
    for (std::size_t i = 0; i < np; ++i) {
      const double found = tr.values[k][i];
      if (!std::isfinite(found)) {
        within = false, beyond = true;
        v.max_error = HUGE_VAL, v.at = tr.time[i], v.exact = right[k][i], v.found = found;
        break;
      }
      // after a jump onto M_c at t = 0 (decided on the exact model) the simulator shows the state before it at
      // t = 0: there, and only there, the vectors the jump moves are not compared
      if (tr.time[i] <= 0 && touched[k]) {
        ++v.skipped_at_jump;
        continue;
      }
      const double er = std::abs(found - right[k][i]), el = std::abs(found - left[k][i]);
      const double err = two_sided[i] ? std::min(er, el) : er;
      // bounds on the true error |found − exact| at this point: either side may be taken at a corner
      const double hi_r = er * (1 + 2 * u) + rad_r[k][i], lo_r = er * (1 - 2 * u) - rad_r[k][i];
      const double hi_l = el * (1 + 2 * u) + rad_l[k][i], lo_l = el * (1 - 2 * u) - rad_l[k][i];
      const double hi = two_sided[i] ? std::min(hi_r, hi_l) : hi_r, lo = two_sided[i] ? std::min(lo_r, lo_l) : lo_r;
      within = within && hi <= tol_lo;
      beyond = beyond || lo > tol_hi;
      if (first || err > v.max_error) {
        first = false;
        v.max_error = err;
        v.at = tr.time[i];
        v.exact = two_sided[i] && el < er ? left[k][i] : right[k][i];
        v.found = found;
        v.at_corner = two_sided[i];
      }
    }
    if (opt.keep_exact) {
      out.exact.emplace_back(np);
      for (std::size_t i = 0; i < np; ++i)  // the side the simulator is nearer at a corner
        out.exact.back()[i] = std::abs(tr.values[k][i] - left[k][i]) < std::abs(tr.values[k][i] - right[k][i]) ? left[k][i] : right[k][i];
    }
    // agreement needs every point within the tolerance with dcad's own uncertainty, a disagreement one
    // point beyond it with the uncertainty; between the two dcad cannot tell
    v.agree = within && !beyond;
    v.decided = v.agree || beyond;
    out.agree = out.agree && v.agree;
    out.vectors.push_back(v);
  }
  const auto rel = [&](std::size_t k) { return out.vectors[k].scale > 0 ? out.vectors[k].max_error / out.vectors[k].scale : out.vectors[k].max_error; };
  for (std::size_t k = 1; k < out.vectors.size(); ++k)
    if (rel(k) > rel(out.worst)) out.worst = k;
  return out;
}

std::string waveform_text(const WaveformChecked& c, const std::string& waveform_file, const std::string& deck_file, const WaveformOptions& o) {
  std::ostringstream s;
  s << "dcad check: " << waveform_file << " (" << c.format << ", " << c.points << " time points) against the exact flow of " << deck_file
    << (c.agree ? ": agrees" : std::any_of(c.vectors.begin(), c.vectors.end(), [](const WaveformVector& v) { return v.decided && !v.agree; }) ? ": DISAGREES" : ": UNDECIDED")
    << " (--rtol " << io::float_text(o.rtol) << " --atol " << io::float_text(o.atol)
    << " of each vector's largest |exact|)\n";
  std::size_t wide = 6;
  for (const WaveformVector& v : c.vectors) wide = std::max(wide, v.name.size());
  for (const WaveformVector& v : c.vectors) {
    s << "  " << (v.agree ? "agrees    " : v.decided ? "DISAGREES " : "UNDECIDED ") << v.name << std::string(wide - v.name.size() + 1, ' ') << "largest error "
      << io::float_text(v.max_error) << " (" << io::float_text(v.scale > 0 ? v.max_error / v.scale : 0.0) << " of " << io::float_text(v.scale) << (v.kind_scale ? ", its kind's largest: the vector is 0 or nearly" : "")
      << ") at t = " << io::float_text(v.at) << ": exact " << io::float_text(v.exact) << ", found " << io::float_text(v.found)
      << (v.at_corner ? " (a source corner or t = 0: either one-sided value allowed)" : "") << "\n";
    if (!v.decided)
      s << "    dcad's own value is uncertain by " << io::float_text(v.exact_uncertainty)
        << (c.certified ? " (the largest radius of its enclosures)" : " (its error estimate times the largest value of this kind)")
        << ": it cannot tell this difference from the tolerance; not a proof either way (--atol above the uncertainty decides it)\n";
    if (!v.agree && !c.jumped.empty() && v.at > 0 && v.at == c.first_after_zero)
      s << "    the state jumps at t = 0 (" << c.jumped.front() << (c.jumped.size() > 1 ? ", …" : "")
        << "): a simulator that smears the impulse over its first step shows it here; the exact waveform has no such step\n";
    if (v.skipped_at_jump)
      s << "    t = 0 not compared (" << v.skipped_at_jump << (v.skipped_at_jump == 1 ? " point" : " points")
        << "): the state jumps onto M_c at t = 0 (decided on the exact model) and a simulator shows the state before it there\n";
  }
  if (c.format == "gnucap" && o.rtol < 1e-4)
    s << "  note: gnucap prints 5 significant digits unless told otherwise (.options numdgt=12): below --rtol 1e-4 its rounding alone may disagree\n";
  s << "  certified: " << (c.certified ? "yes" : "no, " + c.certified_reason) << "\n";
  return s.str();
}

std::string waveform_json(const WaveformChecked& c, const WaveformOptions& o) {
  nlohmann::json vs = nlohmann::json::array();
  for (const WaveformVector& v : c.vectors)
    vs.push_back({{"name", v.name},   {"meaning", v.meaning}, {"max_error", v.max_error}, {"at", v.at},
                  {"exact", v.exact}, {"found", v.found},     {"scale", v.scale},         {"kind_scale", v.kind_scale}, {"agree", v.agree},
                  {"at_corner", v.at_corner}, {"not_compared_at_jump", v.skipped_at_jump}, {"exact_uncertainty", io::printed_radius(v.exact, v.exact_uncertainty)}, {"decided", v.decided}});
  nlohmann::json j = {{"agree", c.agree},   {"certified", c.certified}, {"certified_reason", c.certified_reason},
                      {"format", c.format}, {"points", c.points},       {"rtol", o.rtol},
                      {"atol", o.atol},     {"error_estimate", c.error_estimate}, {"jumped_at_zero", c.jumped}, {"vectors", vs}};
  return j.dump(2);
}

}  // namespace dcad::api
