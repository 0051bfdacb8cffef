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
  long a = -1, b = -1;     ///< nodes (potential)
  std::size_t branch = 0;  ///< (the others)
  std::string meaning;
};

struct Names {
  std::map<std::string, long> nodes;            ///< lower-case name → index (ground −1)
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
    f.meaning = std::string(s[0] == 'q'   ? "charge"
                            : s[0] == 'v' ? "current"
                                          : "flux linkage") +
                " of " + deck.rlc.branches[f.branch].name;
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
  if (s.size() > 3 && s.rfind("i(", 0) == 0 && s.back() == ')')
    el = s.substr(2, s.size() - 3);
  else if (s.size() > 7 && s.compare(s.size() - 7, 7, "#branch") == 0)
    el = s.substr(0, s.size() - 7);
  if (el.size() > 4 && el[0] == '@' && el.compare(el.size() - 3, 3, "[i]") == 0)
    el = el.substr(1, el.size() - 4);  // .options savecurrents
  else if (s.size() > 4 && s[0] == '@' && s.compare(s.size() - 3, 3, "[i]") == 0)
    el = s.substr(1, s.size() - 4);
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
  throw io::InputError(file + ": vector '" + name +
                       "': expected v(node), v(node,node), i(element), element#branch or q_/v_/p_ names of " +
                       deck.file + " (nodes: " + listed(n.node_list) + "; elements: " + listed(n.branch_list) +
                       "), found none that names them");
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
  const double lo = std::nextafter(std::min(a.mid - a.rad, b.mid - b.rad), -HUGE_VAL),
               hi = std::nextafter(std::max(a.mid + a.rad, b.mid + b.rad), HUGE_VAL);
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
    case reference::RlcKind::capacitor: return {T{Of::x, b, io::Rational(1) / br.value}};  // q / C
    case reference::RlcKind::resistor: return {T{Of::x, nb + b, br.value}};                // R i
    case reference::RlcKind::inductor: return {T{Of::xdot, 2 * nb + b, io::Rational(1)}};  // dp/dt
    case reference::RlcKind::voltage:
      return {T{Of::u, 1 + static_cast<std::size_t>(br.source), io::Rational(1)}};  // V(t)
    default: return {};                                                             // a wire
  }
}

/// The certified tier's enclosures of the vectors at one precision, point by point in time order (the
/// exact motion advanced along the file's times): a time within 1e-13 of the run of a source corner is
/// read as that corner and given both one-sided values.
class Encloser {
 public:
  Encloser(const io::Problem& p, const std::vector<Functional>& fs, const WaveformOptions& opt, double step,
           long precision, double first, double last);
  bool ok() const { return why_.empty(); }
  const std::string& why() const { return why_; }
  /// The enclosures of every vector at t (`r`), and the other side's at a corner (`l`, else `r`); false
  /// with why() when the motion cannot be enclosed there.
  bool at(double t, std::vector<certified::Enclosure>& r, std::vector<certified::Enclosure>& l);
  long restarts() const { return cm_.flow ? cm_.flow->restarts() : 0; }

 private:
  CertifiedMotion cm_;
  std::vector<certified::Functional> cf_;
  std::map<double, io::Rational> corners_;
  double near_ = 0;
  std::string why_;
};

Encloser::Encloser(const io::Problem& p, const std::vector<Functional>& fs, const WaveformOptions& opt, double step,
                   long precision, double first, double last) {
  const io::Netlist& deck = p.netlist();
  const std::size_t nb = deck.rlc.branches.size(), nodes = deck.node_names.size();
  try {
    cm_ = certified_motion(deck, p.linear(), opt.initial, step, precision);
  } catch (const std::exception& e) {
    why_ = e.what();
    return;
  }
  if (!cm_.flow) {
    why_ = cm_.why.empty() ? "no exact motion" : cm_.why;
    return;
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
  cf_.resize(fs.size());
  for (std::size_t k = 0; k < fs.size(); ++k) {
    const Functional& f = fs[k];
    using Of = certified::Functional::Of;
    if (f.kind == Functional::potential) {
      for (long node : {f.a, f.b}) {
        const auto& path = pot[static_cast<std::size_t>(node + 1)];
        if (!path) {
          why_ = "node " + deck.node_names[static_cast<std::size_t>(node)] +
                 " reaches ground only through current sources: its potential is not enclosed";
          return;
        }
        for (auto term : *path) {
          if (node == f.b) term.coef = -term.coef;
          cf_[k].terms.push_back(term);
        }
      }
    } else {
      const std::size_t base = f.kind == Functional::charge ? 0 : f.kind == Functional::current ? nb : 2 * nb;
      cf_[k].terms.push_back({Of::x, base + f.branch, io::Rational(1)});
    }
  }
  // the exact corners: a file time within 1e-13 of the run of one (a simulator's breakpoint, TD + k·PER
  // summed in double) is read as that corner and compared with its two one-sided values
  near_ = 1e-13 * std::max(std::abs(last), std::abs(first));
  try {
    const std::vector<io::Rational> all =
        cm_.flow->corners(certified::rational_of(last + 2 * near_), kEnclosedCorners + 1);
    if (all.size() > kEnclosedCorners) {
      why_ = "the sources have more than " + std::to_string(kEnclosedCorners) +
             " corners in the run (each is crossed exactly)";
      return;
    }
    for (const io::Rational& c : all) corners_.emplace(c.convert_to<double>(), c);
  } catch (const std::exception& e) {
    why_ = e.what();
  }
}

bool Encloser::at(double t, std::vector<certified::Enclosure>& r, std::vector<certified::Enclosure>& l) {
  if (!ok()) return false;
  try {
    const io::Rational at = certified::rational_of(t);
    auto it = corners_.lower_bound(t - near_);
    const io::Rational* c = it != corners_.end() && it->first <= t + near_ ? &it->second : nullptr;
    if (at < cm_.flow->time() || (c && *c < cm_.flow->time())) {
      why_ = "two of the file's times lie within 1e-13 of the run of one source corner";
      return false;
    }
    std::vector<certified::Enclosure> before;  // at the file's own time, when it is just before the corner
    if (c && at < *c) {
      cm_.flow->advance_to(at);
      before = cm_.flow->evaluate(cf_);
    }
    cm_.flow->advance_to(c ? *c : at);
    r = cm_.flow->evaluate(cf_);
    l = cm_.flow->at_corner() ? cm_.flow->evaluate(cf_, true) : r;
    // a time near a corner: the side it lies on holds the exact value at the file's own time (the hull
    // of that side's value at the corner and the value at the time), the other side the corner's
    // other one-sided value (the CONTRACT's allowance at a jump)
    if (c && at > *c) {
      cm_.flow->advance_to(at);
      const std::vector<certified::Enclosure> after = cm_.flow->evaluate(cf_);
      for (std::size_t k = 0; k < r.size(); ++k) r[k] = hull(r[k], after[k]);
    }
    for (std::size_t k = 0; k < before.size(); ++k) l[k] = hull(l[k], before[k]);
  } catch (const std::exception& e) {
    why_ = e.what();
    return false;
  }
  return true;
}

/// 2^-50: above the midpoint's own rounding to double (2^-53 of it, part of every radius), which more bits
/// cannot narrow (at 2^-60 every run was redone at 512, 1024 and 2048 bits).
constexpr int kNarrowEnough = -50;

/// Whether enclosures at `precision` bits should be redone at twice the bits: some radius above
/// 2^kNarrowEnough of its vector's largest value (wrapping through many corners: each doubling of the
/// bits buys about twice the corners), finite radii, the last run under 10 s, the previous precision's
/// widest narrowed 2^32-fold (a time a hair from a source corner is the hull of both sides: more bits
/// would only cost), and at most 2048 bits.  `widest` is over the vectors: largest radius / largest
/// |midpoint| (a vector whose radii are all below 2^-1000: 0; whose midpoints are all 0: infinite).
bool more_bits(long precision, bool finite, double seconds, double widest, double& before) {
  if (!finite || seconds > 10 || precision >= 2048) return false;
  if (widest <= std::ldexp(1.0, kNarrowEnough) || widest > std::ldexp(before, -32)) return false;
  before = widest;
  return true;
}

/// Enclosures at 256 bits, then at twice the precision while more_bits says so.
Enclosed enclose(const io::Traces& tr, const io::Problem& p, const std::vector<Functional>& fs,
                 const WaveformOptions& opt, double step) {
  Enclosed e;
  double before = HUGE_VAL;
  for (long precision = 256;; precision *= 2) {
    const auto start = std::chrono::steady_clock::now();
    e = Enclosed{};
    Encloser enc(p, fs, opt, step, precision, tr.time.front(), tr.time.back());
    if (!enc.ok()) {
      e.why = enc.why();
      return e;
    }
    e.right.assign(fs.size(), std::vector<certified::Enclosure>(tr.time.size()));
    e.left = e.right;
    std::vector<certified::Enclosure> r, l;
    bool finite = true;
    std::vector<double> scale(fs.size(), 0.0), rad(fs.size(), 0.0);
    for (std::size_t i = 0; i < tr.time.size(); ++i) {
      if (!enc.at(tr.time[i], r, l)) {
        e = Enclosed{};
        e.why = enc.why();
        return e;
      }
      for (std::size_t k = 0; k < fs.size(); ++k) {
        e.right[k][i] = r[k], e.left[k][i] = l[k];
        finite = finite && std::isfinite(r[k].rad);
        scale[k] = std::max({scale[k], std::abs(r[k].mid), std::abs(l[k].mid)}),
        rad[k] = std::max({rad[k], r[k].rad, l[k].rad});
      }
    }
    e.ok = true;
    e.restarts = enc.restarts();
    double widest = 0;
    for (std::size_t k = 0; k < fs.size(); ++k)
      widest = std::max(widest, rad[k] <= std::ldexp(1.0, -1000) ? 0.0 : scale[k] > 0 ? rad[k] / scale[k] : HUGE_VAL);
    if (!more_bits(precision, finite, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                   widest, before))
      return e;
  }
}

}  // namespace

WaveformEnclosures enclose_waveforms(const io::Problem& p, const std::vector<std::string>& names,
                                     const std::vector<double>& times, Initial initial, double step) {
  if (p.form() != io::Form::netlist)
    throw io::InputError(p.file + ": enclose_waveforms: expected a netlist, found another form");
  io::Traces tr;
  tr.file = p.netlist().file;
  tr.names = names;
  tr.time = times;
  const Names nm = names_of(p.netlist());
  std::vector<Functional> fs;
  for (const std::string& name : names) fs.push_back(functional(name, nm, p.netlist(), p.netlist().file));
  WaveformOptions opt;
  opt.initial = initial;
  Enclosed e = enclose(tr, p, fs, opt, step);
  return WaveformEnclosures{e.ok, e.why, std::move(e.right), std::move(e.left)};
}

namespace {

/// One vector against one source of exact values (the enclosures, or the double flow with its radius
/// added at the end), reduced over the points as they stream by: what the verdict needs of them.
struct Reduced {
  double own = 0, own_lo = 0, own_hi = 0;         ///< the largest |exact|, and its bounds with the radii
  double max_hi = -HUGE_VAL, max_lo = -HUGE_VAL;  ///< the largest upper and lower bounds on |found − exact|
  bool hi_nan = false;
  double unc = 0;                         ///< the largest radius that counts (the other side's at a corner)
  double widest_rad = 0, widest_mid = 0;  ///< over both sides (the wide test, the precision loop)
  bool finite = true;                     ///< every right radius finite
  bool first = true, nonfinite = false, at_corner = false;
  double max_error = 0, at = 0, exact = 0, found = 0;
  long skipped = 0;
  std::vector<double> kept;  ///< with keep_exact: the exact value at each point (the side nearer the file's)
};

void reduce(Reduced& a, double t, double found, double right, double left, double rad_r, double rad_l, bool two_sided,
            bool touched, bool keep) {
  constexpr double u = std::numeric_limits<double>::epsilon();
  a.own = std::max({a.own, std::abs(right), std::abs(left)});
  a.own_hi = std::max({a.own_hi, std::abs(right) + rad_r, std::abs(left) + rad_l});
  a.own_lo = std::max({a.own_lo, std::abs(right) - rad_r, std::abs(left) - rad_l});
  a.unc = std::max({a.unc, rad_r, two_sided ? rad_l : 0.0});
  a.widest_rad = std::max({a.widest_rad, rad_r, rad_l}),
  a.widest_mid = std::max({a.widest_mid, std::abs(right), std::abs(left)});
  a.finite = a.finite && std::isfinite(rad_r);
  if (keep)
    a.kept.push_back(std::abs(found - left) < std::abs(found - right)
                         ? left
                         : right);  // the side the simulator is nearer at a corner
  if (a.nonfinite) return;
  if (!std::isfinite(found)) {
    a.nonfinite = true;
    a.max_error = HUGE_VAL, a.at = t, a.exact = right, a.found = found;
    return;
  }
  // after a jump onto M_c at t = 0 (decided on the exact model) the simulator shows the state before it at
  // t = 0: there, and only there, the vectors the jump moves are not compared
  if (t <= 0 && touched) {
    ++a.skipped;
    return;
  }
  const double er = std::abs(found - right), el = std::abs(found - left);
  const double err = two_sided ? std::min(er, el) : er;
  // bounds on the true error |found − exact| at this point: either side may be taken at a corner
  const double hi_r = er * (1 + 2 * u) + rad_r, lo_r = er * (1 - 2 * u) - rad_r;
  const double hi_l = el * (1 + 2 * u) + rad_l, lo_l = el * (1 - 2 * u) - rad_l;
  const double hi = two_sided ? std::min(hi_r, hi_l) : hi_r, lo = two_sided ? std::min(lo_r, lo_l) : lo_r;
  if (std::isnan(hi))
    a.hi_nan = true;
  else
    a.max_hi = std::max(a.max_hi, hi);
  if (lo > a.max_lo) a.max_lo = lo;
  if (a.first || err > a.max_error) {
    a.first = false;
    a.max_error = err;
    a.at = t;
    a.exact = two_sided && el < er ? left : right;
    a.found = found;
    a.at_corner = two_sided;
  }
}

/// The double flow's reductions with its radius `rad` at every point: the bounds a constant radius gives
/// (reduce ran with radius 0).
Reduced with_radius(Reduced a, double rad) {
  a.own_hi = a.own + rad, a.own_lo = std::max(0.0, a.own - rad), a.unc = rad;
  if (a.max_hi > -HUGE_VAL) a.max_hi += rad;
  if (a.max_lo > -HUGE_VAL) a.max_lo -= rad;
  return a;
}

/// One vector's verdict from its reductions and its kind's scale bounds [klo, khi] over the run.
WaveformVector verdict(const Reduced& a, const std::string& name, const std::string& meaning, double klo, double khi,
                       const WaveformOptions& opt) {
  constexpr double u = std::numeric_limits<double>::epsilon();
  WaveformVector v;
  v.name = name;
  v.meaning = meaning;
  double scale_lo = a.own_lo, scale_hi = a.own_hi;
  v.scale = a.own;
  if (a.own_hi < 1e-12 * klo) {  // certainly a vector near 0: its kind's scale
    scale_lo = klo, scale_hi = khi, v.scale = std::max(a.own, klo);
    v.kind_scale = true;
  } else if (!(a.own_lo >= 1e-12 * khi)) {  // either may hold: both
    scale_lo = std::min(a.own_lo, klo), scale_hi = std::max(a.own_hi, khi);
  }
  v.exact_uncertainty = a.unc;
  const double tol_lo = (opt.atol + opt.rtol * scale_lo) * (1 - 4 * u),
               tol_hi = (opt.atol + opt.rtol * scale_hi) * (1 + 4 * u);
  v.skipped_at_jump = a.skipped;
  if (!a.first || a.nonfinite)
    v.max_error = a.max_error, v.at = a.at, v.exact = a.exact, v.found = a.found, v.at_corner = a.at_corner;
  // agreement needs every point within the tolerance with dcad's own uncertainty, a disagreement one
  // point beyond it with the uncertainty; between the two dcad cannot tell
  const bool within = !a.nonfinite && !a.hi_nan && a.max_hi <= tol_lo, beyond = a.nonfinite || a.max_lo > tol_hi;
  v.agree = within && !beyond;
  v.decided = v.agree || beyond;
  return v;
}

/// The variables that jump onto M_c at t = 0: decided exactly (in rationals) where the circuit is small
/// enough, else the sparse flow's own decision `flow_jumped` (its start was computed the same way).
std::vector<std::string> exact_jumps(const io::Problem& p, Initial initial, std::vector<std::string> flow_jumped) {
  const io::Netlist& deck = p.netlist();
  if (nb_of(deck) > reference::pipeline::kForcedBranches) return flow_jumped;
  namespace pl = reference::pipeline;
  try {
    const pl::InitialState st = pl::initial_state(deck, initial, p.linear().variables);
    if (!st.computed) return flow_jumped;
    std::vector<std::string> jumped;
    for (const pl::Jump& j : st.jumps) jumped.push_back(j.variable);
    return jumped;
  } catch (const std::exception&) {
    return flow_jumped;
  }
}

/// The vectors a jump at t = 0 moves: a jumped charge, current or flux linkage by its branch; potentials and
/// the currents of other branches (functions of the whole state) whenever anything jumps.
std::vector<bool> touched_by(const std::vector<Functional>& fs, const io::Netlist& deck,
                             const std::vector<std::string>& jumped) {
  std::vector<bool> touched(fs.size(), false);
  for (std::size_t k = 0; k < fs.size() && !jumped.empty(); ++k) {
    if (fs[k].kind == Functional::potential) {
      touched[k] = true;
      continue;
    }
    const auto& br = deck.rlc.branches[fs[k].branch];
    if (fs[k].kind == Functional::current && br.kind != reference::RlcKind::inductor) touched[k] = true;
    for (const char* pre : {"q_", "v_", "p_"})
      touched[k] = touched[k] || std::find(jumped.begin(), jumped.end(), pre + br.name) != jumped.end();
  }
  return touched;
}

/// The double flow's values of the vectors at t (right, and left where the flow has a corner or t = 0),
/// and the largest potential, charge, current and flux linkage so far in `kind_scale`.
void flow_values(SparseFlow& flow, const std::vector<Functional>& fs, double t, bool sided, std::vector<double>& right,
                 std::vector<double>& left, double* kind_scale) {
  flow.advance_to(t);
  const sr::BranchValues bv = flow.values();
  const Vec e = flow.node_potentials();
  kind_scale[Functional::potential] =
      std::max(kind_scale[Functional::potential], e.size() ? e.cwiseAbs().maxCoeff() : 0.0);
  kind_scale[Functional::charge] =
      std::max(kind_scale[Functional::charge], bv.q.size() ? bv.q.cwiseAbs().maxCoeff() : 0.0);
  kind_scale[Functional::current] =
      std::max(kind_scale[Functional::current], bv.i.size() ? bv.i.cwiseAbs().maxCoeff() : 0.0);
  kind_scale[Functional::flux] = std::max(kind_scale[Functional::flux], bv.p.size() ? bv.p.cwiseAbs().maxCoeff() : 0.0);
  for (std::size_t k = 0; k < fs.size(); ++k) right[k] = left[k] = value(fs[k], bv, e);
  if (!sided) return;
  const sr::BranchValues bl = flow.values(true);
  const Vec el = flow.node_potentials(true);
  for (std::size_t k = 0; k < fs.size(); ++k) left[k] = value(fs[k], bl, el);
}

/// Points read and compared at a time: memory is this many points of every vector, whatever the file's size.
constexpr std::size_t kChunk = 4096;

/// One pass over the stream: every point of every vector reduced against the double flow (`run_flow`: the
/// graph route's first pass; `flow` also gives the corners in every pass) and against the enclosures of
/// `enc` (if any).  False when the enclosures failed on the way (enc->why()); the flow's reductions go on.
bool stream_pass(io::TraceStream& tr, const std::vector<Functional>& fs, const std::vector<bool>& touched, bool keep,
                 SparseFlow* flow, bool run_flow, std::vector<Reduced>& flow_acc, double* kind_scale, Encloser* enc,
                 std::vector<Reduced>& enc_acc, double& enc_seconds, double& first_after_zero) {
  const std::size_t nv = fs.size();
  run_flow = run_flow && flow;
  std::vector<double> t, right(nv), left(nv);
  std::vector<std::vector<double>> vals;
  std::vector<certified::Enclosure> r, l;
  bool enclosing = enc != nullptr;
  double previous = -HUGE_VAL;
  tr.rewind();
  while (tr.next(kChunk, t, vals)) {
    // a stream is held to what the readers guarantee (one value per vector and point, finite times in
    // order), whoever implements it
    bool sized = vals.size() == nv;
    for (std::size_t k = 0; k < vals.size() && sized; ++k) sized = vals[k].size() == t.size();
    if (!sized)
      throw io::InputError(tr.file() + ": expected " + std::to_string(nv) +
                           " values per time point from the stream, found another count");
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double ti = t[i];
      if (!(ti >= previous) || !std::isfinite(ti))
        throw io::InputError(tr.file() + ": expected finite, nondecreasing times from the stream, found " +
                             io::float_text(ti) + " after " + io::float_text(previous));
      previous = ti;
      if (ti > 0 && first_after_zero == 0) first_after_zero = ti;
      const bool flow_sided = flow && (ti == 0 || flow->corner(ti));
      if (run_flow) flow_values(*flow, fs, ti, flow_sided, right, left, kind_scale);
      bool enc_sided = false;
      if (enclosing) {
        const auto t0 = std::chrono::steady_clock::now();
        enclosing = enc->at(ti, r, l);
        for (std::size_t k = 0; k < nv && enclosing; ++k)
          enc_sided = enc_sided || l[k].mid != r[k].mid || l[k].rad != r[k].rad;
        enc_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      }
      const bool sided = flow_sided || enc_sided;
      for (std::size_t k = 0; k < nv; ++k) {
        if (run_flow) reduce(flow_acc[k], ti, vals[k][i], right[k], left[k], 0.0, 0.0, sided, touched[k], keep);
        if (enclosing)
          reduce(enc_acc[k], ti, vals[k][i], r[k].mid, l[k].mid, r[k].rad, l[k].rad, sided, touched[k], keep);
      }
    }
  }
  return enclosing || !enc;
}

}  // namespace

namespace {

/// The enclosures at `precision` bits (null with `why` when there are none), the time it took in `seconds`.
std::unique_ptr<Encloser> enclosures(const io::Problem& p, const std::vector<Functional>& fs,
                                     const WaveformOptions& opt, double step, long precision, const io::TraceStream& tr,
                                     std::string& why, double& seconds) {
  const auto start = std::chrono::steady_clock::now();
  auto enc = std::make_unique<Encloser>(p, fs, opt, step, precision, tr.first_time(), tr.last_time());
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (enc->ok()) return enc;
  why = enc->why();
  return nullptr;
}

/// The problem and the file held to what a waveform check needs (a netlist, a positive definite
/// inductance matrix, tolerances >= 0, a vector and a point), the simulator's skipped messages noted, and
/// each vector as a functional of the circuit's motion.
std::vector<Functional> functionals_of(const io::TraceStream& tr, const io::Problem& p, const WaveformOptions& opt,
                                       std::ostream& log) {
  io::validate(p);
  const std::vector<std::string>& skipped = tr.skipped();
  for (std::size_t k = 0; k < skipped.size() && k < 5; ++k)
    log << "note: skipped a simulator's message inside the table at " << skipped[k] << "\n";
  if (skipped.size() > 5) log << "note: … and " << skipped.size() - 5 << " more messages skipped\n";
  for (const std::string& n : tr.notes()) log << "note: " << n << "\n";
  if (p.form() != io::Form::netlist)
    throw io::InputError(tr.file() + ": check: expected a netlist as DECK for a waveform, found a case file");
  const io::Netlist& deck = p.netlist();
  if (!deck.indefinite_inductance.empty())
    throw io::InputError(
        deck.indefinite_inductance +
        "; check: expected a positive semidefinite inductance matrix, found another (lower the couplings)");
  if (!(opt.rtol >= 0) || !(opt.atol >= 0)) throw UsageError("--rtol and --atol: expected numbers >= 0");
  if (tr.names().empty())
    throw io::InputError(
        tr.file() + ": expected at least one vector besides time (" + tr.format() + "), found none: nothing to check" +
        (tr.format() == "gnucap" ? " (gnucap runs .tran as it reads it: put .print before .tran)" : ""));
  if (tr.points() == 0) throw io::InputError(tr.file() + ": expected at least one time point, found none");
  const Names names = names_of(deck);
  std::vector<Functional> fs;
  for (const std::string& name : tr.names()) fs.push_back(functional(name, names, deck, tr.file()));
  return fs;
}

/// Over the vectors: the largest radius / the largest |midpoint| (a vector whose radii are all below
/// 2^-1000: 0; whose midpoints are all 0: infinite), and whether every radius is finite.
double widest_of(const std::vector<Reduced>& acc, bool& finite) {
  double widest = 0;
  finite = true;
  for (const Reduced& a : acc) {
    finite = finite && a.finite;
    widest = std::max(widest, a.widest_rad <= std::ldexp(1.0, -1000) ? 0.0
                              : a.widest_mid > 0                     ? a.widest_rad / a.widest_mid
                                                                     : HUGE_VAL);
  }
  return widest;
}

/// Which exact values decide each vector: the enclosures (if `enc_ok`), unless (`test_width`) an
/// enclosure is wider than the double flow's own uncertainty (a stiff circuit, wrapping) — then the double
/// flow with that uncertainty as its radius, and the vector is named in `wide`.
std::vector<Reduced> chosen(std::vector<Reduced>& enc_acc, std::vector<Reduced>& flow_acc,
                            const std::vector<double>& uncertainty, bool test_width, bool enc_ok,
                            const std::vector<std::string>& names, std::string& wide) {
  std::vector<Reduced> acc(flow_acc.size());
  for (std::size_t k = 0; k < acc.size(); ++k) {
    // (a vector that is 0 over the whole run has uncertainty 0: radii of 1e-308 are not wider than it)
    const bool too_wide = test_width && !(enc_acc[k].widest_rad <= std::max(uncertainty[k], 1e-300));
    if (too_wide)
      wide +=
          std::string(wide.empty() ? "" : ", ") + names[k] + " (radius " + io::float_text(enc_acc[k].widest_rad) + ")";
    acc[k] = enc_ok && !too_wide ? std::move(enc_acc[k]) : with_radius(std::move(flow_acc[k]), uncertainty[k]);
  }
  return acc;
}

/// dcad's own uncertainty on the graph route: the Krylov estimate (at least 64 ε for the rounding of the
/// outputs) of the largest value of the vector's kind; a potential difference v(a,b) counts both ends.
std::vector<double> flow_uncertainty(const std::vector<Functional>& fs, double error_estimate,
                                     const double* kind_scale) {
  std::vector<double> uncertainty(fs.size(), 0.0);
  for (std::size_t k = 0; k < fs.size(); ++k)
    uncertainty[k] = std::max(error_estimate, 64 * std::numeric_limits<double>::epsilon()) * kind_scale[fs[k].kind] *
                     (fs[k].kind == Functional::potential && fs[k].b >= 0 ? 2.0 : 1.0);
  return uncertainty;
}

/// Why a check is not certified: the vectors `wide` whose enclosures were too wide (`enc_ok`), or no
/// enclosure at all (`enc_why`).
std::string not_certified_because(bool enc_ok, const std::string& wide, double error_estimate,
                                  const std::string& enc_why) {
  if (enc_ok)
    return "the enclosures of " + wide +
           " are wider than the double flow's own uncertainty: those vectors are decided by the double flow "
           "(estimated error " +
           io::float_text(error_estimate) + " of the state), not proved";
  return "the exact flow is evaluated in double (Krylov exponential action on the state equations, estimated error " +
         io::float_text(error_estimate) + " of the state): values, not enclosures; no enclosure because " + enc_why;
}

/// Every vector's verdict into `out` (its agree, exact values with keep_exact, the worst vector).
void add_verdicts(WaveformChecked& out, std::vector<Reduced>& acc, const std::vector<Functional>& fs,
                  const std::vector<std::string>& names, const double* kind_scale, const WaveformOptions& opt) {
  const std::size_t nv = acc.size();
  // the CONTRACT's scale of each vector (its largest |exact|) lies in [lo, hi]; a vector whose largest |exact|
  // is below 1e-12 of the largest of its kind (0 by symmetry, or without a source) is held to its kind's
  double kind_lo[4] = {0, 0, 0, 0}, kind_hi[4] = {0, 0, 0, 0};
  for (int q = 0; q < 4; ++q) kind_lo[q] = kind_hi[q] = kind_scale[q];  // the whole circuit's, where the flow gives it
  for (std::size_t k = 0; k < nv; ++k) {
    kind_lo[fs[k].kind] = std::max(kind_lo[fs[k].kind], acc[k].own_lo);
    kind_hi[fs[k].kind] = std::max(kind_hi[fs[k].kind], acc[k].own_hi);
  }
  for (std::size_t k = 0; k < nv; ++k) {
    out.vectors.push_back(verdict(acc[k], names[k], fs[k].meaning, kind_lo[fs[k].kind], kind_hi[fs[k].kind], opt));
    out.agree = out.agree && out.vectors.back().agree;
    if (opt.keep_exact) out.exact.push_back(std::move(acc[k].kept));
  }
  const auto rel = [&](std::size_t k) {
    return out.vectors[k].scale > 0 ? out.vectors[k].max_error / out.vectors[k].scale : out.vectors[k].max_error;
  };
  for (std::size_t k = 1; k < out.vectors.size(); ++k)
    if (rel(k) > rel(out.worst)) out.worst = k;
}

/// Whether the enclosures of one pass already settle the check: none wider than the double flow's own
/// uncertainty (graph route: `flow`) and every vector decided.  More bits would then only narrow radii
/// that decide nothing (the 8-branch filter's tight run: 256 bits settle it, 512 bits doubled the time).
bool settled(std::vector<Reduced> enc_acc, std::vector<Reduced> flow_acc, const std::vector<Functional>& fs,
             const std::vector<std::string>& names, const SparseFlow* flow, const double* kind_scale,
             const WaveformOptions& opt) {
  const std::vector<double> uncertainty =
      flow ? flow_uncertainty(fs, flow->error_estimate(), kind_scale) : std::vector<double>(fs.size(), 0.0);
  std::string wide;
  std::vector<Reduced> acc = chosen(enc_acc, flow_acc, uncertainty, flow != nullptr, true, names, wide);
  if (!wide.empty()) return false;
  WaveformChecked c;
  WaveformOptions o = opt;
  o.keep_exact = false;
  add_verdicts(c, acc, fs, names, kind_scale, o);
  return std::all_of(c.vectors.begin(), c.vectors.end(), [](const WaveformVector& v) { return v.decided; });
}

}  // namespace

WaveformChecked check_waveform(const io::Traces& tr, const io::Problem& p, const WaveformOptions& opt,
                               std::ostream& log) {
  const std::unique_ptr<io::TraceStream> stream = io::stream_of(tr);  // validates tr
  return check_waveform(*stream, p, opt, log);
}

/// The deck a waveform is checked against: a netlist (a case file is no deck) whose sources have an exact flow.
static void require_checkable_deck(const io::TraceStream& tr, const io::Problem& p) {
  if (p.form() != io::Form::netlist)  // before any read of the deck
    throw io::InputError(tr.file() + ": check: expected a netlist as DECK for a waveform, found a case file");
  if (const auto which = io::without_exact_flow(p.netlist().waveforms))
    throw io::InputError(p.file + ": check: expected continuous sources with a finite exosystem, found " + *which +
                         ": dcad has no exact flow for it; write the waveform as a continuous PWL(t1 v1 t2 v2 …)");
}

WaveformChecked check_waveform(io::TraceStream& tr, const io::Problem& p, const WaveformOptions& opt,
                               std::ostream& log) {
  require_checkable_deck(tr, p);
  const std::vector<Functional> fs = functionals_of(tr, p, opt, log);
  const io::Netlist& deck = p.netlist();
  WaveformChecked out;
  out.format = tr.format();
  out.points = static_cast<long>(tr.points());
  const double horizon = tr.last_time();
  const double step = tr.points() > 1 && horizon > 0 ? horizon / static_cast<double>(tr.points() - 1) : 1.0;
  const std::size_t nv = fs.size();
  const bool graph = reference::pipeline::graph_route_holds(deck.rlc);
  // the certified tier's first precision: a circuit off the graph route has only the enclosures
  double enc_seconds = 0;
  std::string enc_why = "not asked for (WaveformOptions::enclose false)";
  long precision = 256;
  std::unique_ptr<Encloser> enc =
      opt.enclose ? enclosures(p, fs, opt, step, precision, tr, enc_why, enc_seconds) : nullptr;
  const auto refuse_without_enclosures = [&] {
    throw io::InputError(deck.file +
                         ": check: expected a circuit whose exact flow dcad evaluates at any time (every R, L, C > 0, "
                         "couplings |k| < 1, "
                         "or up to " +
                         std::to_string(reference::pipeline::kForcedBranches) +
                         " branches for the enclosures on the dense model), found another: " + enc_why);
  };
  if (!graph && !enc) refuse_without_enclosures();
  // the start and the jump at t = 0 (which vectors it moves), before any point is compared
  std::vector<std::string> jumped;  // the variables that jump at t = 0 (q_C, v_L, p_L)
  std::unique_ptr<SparseFlow> flow;
  if (graph) {
    flow = std::make_unique<SparseFlow>(deck, deck.file, opt.initial, step, std::max(horizon, step), log);
    jumped = exact_jumps(p, opt.initial, flow->jumped());
  } else {
    long jumps = 0;
    netlist_start(deck, p.linear().variables, opt.initial, log, &jumps, &jumped);
  }
  const std::vector<bool> touched = touched_by(fs, deck, jumped);
  // One pass over the file per precision of the enclosures; the first also runs the double flow (graph
  // route).  Exact values on both sides of a corner (and at t = 0) where they may differ, each with how
  // far the exact value may be from it (an enclosure's radius, or the double flow's estimate, known at
  // the end: added then).
  std::vector<Reduced> flow_acc(nv), enc_acc(nv);
  double kind_scale[4] = {0, 0, 0, 0};  // the graph route's: over every node and branch of the circuit
  double before = HUGE_VAL;
  for (bool first_pass = true;; first_pass = false) {
    enc_acc.assign(nv, Reduced{});
    if (!stream_pass(tr, fs, touched, opt.keep_exact, flow.get(), first_pass, flow_acc, kind_scale, enc.get(), enc_acc,
                     enc_seconds, out.first_after_zero)) {
      enc_why = enc->why();
      enc.reset();
      if (!graph) refuse_without_enclosures();
    }
    if (!enc) break;
    bool finite = true;
    const double widest = widest_of(enc_acc, finite);
    if (settled(enc_acc, flow_acc, fs, tr.names(), flow.get(), kind_scale, opt) ||
        !more_bits(precision, finite, enc_seconds, widest, before))
      break;
    enc = enclosures(p, fs, opt, step, precision *= 2, tr, enc_why, enc_seconds);
    if (!enc) {
      if (!graph) refuse_without_enclosures();
      break;
    }
  }
  const bool enc_ok = enc != nullptr;
  if (graph) out.error_estimate = flow->error_estimate();
  const std::vector<double> uncertainty =
      graph ? flow_uncertainty(fs, out.error_estimate, kind_scale) : std::vector<double>(nv, 0.0);
  std::string wide;
  std::vector<Reduced> acc = chosen(enc_acc, flow_acc, uncertainty, enc_ok && graph, enc_ok, tr.names(), wide);
  out.jumped = jumped;
  out.certified = enc_ok && wide.empty();
  out.certified_reason =
      out.certified ? std::string() : not_certified_because(enc_ok, wide, out.error_estimate, enc_why);
  add_verdicts(out, acc, fs, tr.names(), kind_scale, opt);
  return out;
}

std::string waveform_text(const WaveformChecked& c, const std::string& waveform_file, const std::string& deck_file,
                          const WaveformOptions& o) {
  std::ostringstream s;
  s << "dcad check: " << waveform_file << " (" << c.format << ", " << c.points
    << " time points) against the exact flow of " << deck_file
    << (c.agree ? ": agrees"
        : std::any_of(c.vectors.begin(), c.vectors.end(), [](const WaveformVector& v) { return v.decided && !v.agree; })
            ? ": DISAGREES"
            : ": UNDECIDED")
    << " (--rtol " << io::float_text(o.rtol) << " --atol " << io::float_text(o.atol)
    << " of each vector's largest |exact|)\n";
  std::size_t wide = 6;
  for (const WaveformVector& v : c.vectors) wide = std::max(wide, v.name.size());
  for (const WaveformVector& v : c.vectors) {
    s << "  "
      << (v.agree     ? "agrees    "
          : v.decided ? "DISAGREES "
                      : "UNDECIDED ")
      << v.name << std::string(wide - v.name.size() + 1, ' ') << "largest error " << io::float_text(v.max_error) << " ("
      << io::float_text(v.scale > 0 ? v.max_error / v.scale : 0.0) << " of " << io::float_text(v.scale)
      << (v.kind_scale ? ", its kind's largest: the vector is 0 or nearly" : "") << ") at t = " << io::float_text(v.at)
      << ": exact " << io::float_text(v.exact) << ", found " << io::float_text(v.found)
      << (v.at_corner ? " (a source corner or t = 0: either one-sided value allowed)" : "") << "\n";
    if (!v.decided)
      s << "    dcad's own value is uncertain by " << io::float_text(v.exact_uncertainty)
        << (c.certified ? " (the largest radius of its enclosures)"
                        : " (its error estimate times the largest value of this kind)")
        << ": it cannot tell this difference from the tolerance; not a proof either way (--atol above the uncertainty "
           "decides it)\n";
    if (!v.agree && !c.jumped.empty() && v.at > 0 && v.at == c.first_after_zero)
      s << "    the state jumps at t = 0 (" << c.jumped.front() << (c.jumped.size() > 1 ? ", …" : "")
        << "): a simulator that smears the impulse over its first step shows it here; the exact waveform has no such "
           "step\n";
    if (v.skipped_at_jump)
      s << "    t = 0 not compared (" << v.skipped_at_jump << (v.skipped_at_jump == 1 ? " point" : " points")
        << "): the state jumps onto M_c at t = 0 (decided on the exact model) and a simulator shows the state before "
           "it there\n";
  }
  if (c.format == "gnucap" && o.rtol < 1e-4)
    s << "  note: gnucap prints 5 significant digits unless told otherwise (.options numdgt=12): below --rtol 1e-4 its "
         "rounding alone may disagree\n";
  s << "  certified: " << (c.certified ? "yes" : "no, " + c.certified_reason) << "\n";
  return s.str();
}

std::string waveform_json(const WaveformChecked& c, const WaveformOptions& o) {
  nlohmann::json vs = nlohmann::json::array();
  for (const WaveformVector& v : c.vectors)
    vs.push_back({{"name", v.name},
                  {"meaning", v.meaning},
                  {"max_error", v.max_error},
                  {"at", v.at},
                  {"exact", v.exact},
                  {"found", v.found},
                  {"scale", v.scale},
                  {"kind_scale", v.kind_scale},
                  {"agree", v.agree},
                  {"at_corner", v.at_corner},
                  {"not_compared_at_jump", v.skipped_at_jump},
                  {"exact_uncertainty", io::printed_radius(v.exact, v.exact_uncertainty)},
                  {"decided", v.decided}});
  nlohmann::json j = {{"agree", c.agree},
                      {"certified", c.certified},
                      {"certified_reason", c.certified_reason},
                      {"format", c.format},
                      {"points", c.points},
                      {"rtol", o.rtol},
                      {"atol", o.atol},
                      {"error_estimate", c.error_estimate},
                      {"jumped_at_zero", c.jumped},
                      {"vectors", vs}};
  return j.dump(2);
}

}  // namespace dcad::api
