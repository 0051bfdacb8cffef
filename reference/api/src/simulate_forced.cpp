// `dcad simulate` on forced decks (R, sources, K): the exact forced CAD (reference/forced.hpp)
// gives M_c(t) = {x = X0 u(t) + Bᵀ y} with u = (1, σ, σ', …) and ẏ = A_y y + A_u u_ext(t).  The
// sources are, between breakpoints, outputs of a linear exosystem (waveform.hpp), so the whole is
// an autonomous linear system [y; 1; w] whose flow is one balanced matrix exponential per step
// length (issue-7 accuracy: no truncation error, only rounding).  At a corner of a PWL/PULSE
// source σ' jumps, and σ'' carries a Dirac delta: y jumps by A_u,(2) Δσ' (deltas of higher
// derivatives are refused).  The constrained part X0 u(t) follows the sources exactly.
//
// Energy balance (YM §4): along solutions dE/dt = ⟨F, q̇⟩ + (reaction work of the affine
// constraints): −Σ R v² + Σ (−V) v_V, plus what the current sources supply.
#include "exosystem.hpp"
#include "simulate.hpp"

#include "dcad/io/report.hpp"
#include "dcad/reference/pipeline/forced.hpp"
#include "dcad/reference/pipeline/rlc_motion.hpp"
#include "dcad/reference/rlc.hpp"

#include <boost/math/constants/constants.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>

#include <Eigen/Core>
#include <unsupported/Eigen/MatrixFunctions>

#include <charconv>
#include <complex>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <type_traits>

namespace dcad::api {

namespace ref = dcad::reference;
using Q = ref::Rational;
using QM = ref::Matrix<Q>;

namespace {

/// What the integration needs: the forced system, its sources' waveforms, the file for messages.
struct ForcedScene {
  std::string file;
  ref::ForcedSystem<Q> f;
  std::vector<io::Waveform> waveforms;
  std::vector<long double> natural;  ///< circuits: the dimensionless twin's scales (summarize)
};

template <class S>
using Mat = Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic>;
template <class S>
using Vec = Eigen::Matrix<S, Eigen::Dynamic, 1>;

Mat<double> to_d(const QM& m) {
  Mat<double> d(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) d(i, j) = m(i, j).convert_to<double>();
  return d;
}

/// The exact model: x = X0 u + Bᵀ y on M_c(t), ẏ = A_y y + A_u u_ext, ẋ = V_y y + V_u u_ext.
struct ForcedModel {
  std::size_t n = 0, m = 0, dm = 0;
  std::size_t free = 0;  ///< solution rank: free multipliers (the flow takes the particular solution)
  long orders = 1;       ///< u has σ⁽⁰⁾ … σ^{(orders−1)}; u_ext one more
  QM eq, basis, x0, ay, au, vy, vu;
  ref::ForcedSystem<Q> f;
};

ForcedModel forced_model(const ForcedScene& deck) {
  ForcedModel fm;
  fm.f = deck.f;
  const ref::ForcedResult<Q> r = ref::forced_tower(fm.f);
  for (ref::Index i = 0; i < r.conditions.rows(); ++i) {
    const SourceCondition v =
        reference::pipeline::decide_condition(r.conditions.block(i, i + 1, 0, r.conditions.cols()), deck.waveforms);
    if (v.holds.no() || !r.consistent)
      throw io::InputError(deck.file + ": simulate: expected a consistent circuit, found the source condition " +
                           v.text + " violated (" + v.evidence + ")");
  }
  if (!r.consistent)
    throw io::InputError(deck.file + ": simulate: expected a consistent circuit, found M_" + std::to_string(r.steps) +
                         " empty");
  fm.n = fm.f.s.d.n;
  fm.m = fm.f.sources;
  fm.orders = static_cast<long>(r.orders);
  fm.eq = r.equations;
  const ref::ForcedMotion<Q> mo = ref::forced_motion(fm.f, r);
  fm.basis = mo.basis;
  fm.dm = mo.basis.rows();
  fm.x0 = mo.x0;
  fm.vy = mo.vy;
  fm.vu = mo.vu;
  fm.ay = mo.ay;
  fm.au = mo.au;
  fm.free = ref::rank(mo.gauge.transpose());
  return fm;
}

/// 113-bit floats for the two products whose terms cancel (A_u W and X0 u: a stiff circuit's large
/// coefficients against a source's jets; in double a 10 mΩ · 100 nF branch made the common-mode choke's
/// i(L1) 3.3e-6 wrong, and the long-double shadow, fed the same rounded product, could not see it).
using Wide = boost::multiprecision::cpp_bin_float_quad;

Wide wide(const Q& q) {
  return Wide(boost::multiprecision::numerator(q).str()) / Wide(boost::multiprecision::denominator(q).str());
}

Mat<Wide> to_wide(const QM& m) {
  Mat<Wide> w(m.rows(), m.cols());
  for (ref::Index i = 0; i < m.rows(); ++i)
    for (ref::Index j = 0; j < m.cols(); ++j) w(i, j) = wide(m(i, j));
  return w;
}

/// σ^{(order)}(t) (right limit) in 113 bits: SIN and EXP from their closed forms, PULSE and PWL exactly;
/// `tq` the exact time (k·step at an output row), `t` the double that picks the piece — the side of a corner
/// the double flow is on (its breakpoints are doubles), so that X0 u and the flow's y jump together.
Wide jet_wide(const io::Waveform& w, double t, const Q& tq, int order) {
  switch (w.kind) {
    case io::Waveform::Kind::dc: return order == 0 ? wide(w.p[0]) : Wide(0);
    case io::Waveform::Kind::sin: {
      const Wide pi = boost::math::constants::pi<Wide>(), phi = wide(w.p[5]) * pi / 180, va = wide(w.p[1]);
      if (t < w.p[3].convert_to<double>())
        return order == 0 ? wide(w.p[0]) + va * sin(phi) : Wide(0);  // the piece as the flow's corners
      const Wide tau = wide(tq - w.p[3]), omega = 2 * pi * wide(w.p[2]), decay = -wide(w.p[4]);
      // Im(VA s^order e^{s τ + iφ}), s = decay + iω = r e^{iα}
      const Wide r = sqrt(decay * decay + omega * omega), alpha = atan2(omega, decay);
      const Wide value = va * pow(r, order) * exp(decay * tau) * sin(order * alpha + omega * tau + phi);
      return (order == 0 ? wide(w.p[0]) : Wide(0)) + value;
    }
    case io::Waveform::Kind::exp: {
      const Wide v1 = wide(w.p[0]), v2 = wide(w.p[1]);
      const Wide r1 = -1 / wide(w.p[3]), r2 = -1 / wide(w.p[5]);
      Wide c = v1, e1 = 0, e2 = 0;
      if (t >=
          w.p[2]
              .convert_to<double>()) {  // the pieces as the flow's corners (double times), the values at the exact time
        e1 = (v1 - v2) * exp(r1 * wide(tq - w.p[2]));
        if (t < w.p[4].convert_to<double>())
          c = v2;
        else
          e2 = (v2 - v1) * exp(r2 * wide(tq - w.p[4]));
      }
      return (order == 0 ? c : Wide(0)) + e1 * pow(r1, order) + e2 * pow(r2, order);
    }
    default:  // PULSE, PWL: the pieces as the double route reads them (the side of a corner at a double time), values
              // exact enough
      return Wide(w.value(t, order));
  }
}

/// (1, σ, σ', …, σ^{(orders−1)}) in 113 bits at the exact time tq (t: tq rounded): the u that X0 multiplies.
Vec<Wide> jets_wide(const ForcedScene& deck, double t, const Q& tq, long orders, std::size_t wu) {
  const std::size_t m = deck.waveforms.size();
  Vec<Wide> u(wu);
  u(0) = 1;
  for (long d = 0; d < orders; ++d)
    for (std::size_t j = 0; j < m; ++j) u(1 + d * m + j) = jet_wide(deck.waveforms[j], t, tq, static_cast<int>(d));
  return u;
}

/// u_ext(t) (right limits): (1, σ, σ', …, σ^{(orders)}).
Vec<double> jets(const ForcedScene& deck, double t, long orders) {
  const std::size_t m = deck.waveforms.size();
  Vec<double> u(1 + m * (orders + 1));
  u(0) = 1;
  for (long d = 0; d <= orders; ++d)
    for (std::size_t j = 0; j < m; ++j) u(1 + d * m + j) = deck.waveforms[j].value(t, static_cast<int>(d));
  return u;
}

/// exo_output in 113 bits (ω = 2π FREQ and its powers, EXP's rates): the factor of A_u W.
Mat<Wide> exo_output_wide(const ForcedScene& deck, long orders) {
  const std::size_t m = deck.waveforms.size();
  Mat<Wide> out = Mat<Wide>::Zero(1 + m * (orders + 1), 1 + 3 * m);
  out(0, 0) = 1;
  for (std::size_t j = 0; j < m; ++j) {
    const io::Waveform& w = deck.waveforms[j];
    const std::size_t c = 1 + 3 * j;
    if (w.is_exp()) {
      out(1 + j, c) = 1;
      const Wide r1 = -1 / wide(w.p[3]), r2 = -1 / wide(w.p[5]);
      for (long d = 0; d <= orders; ++d) out(1 + d * m + j, c + 1) = pow(r1, d), out(1 + d * m + j, c + 2) = pow(r2, d);
    } else if (w.is_sine()) {
      const Wide omega = 2 * boost::math::constants::pi<Wide>() * wide(w.p[2]), decay = -wide(w.p[4]);
      Eigen::Matrix<Wide, 2, 2> mm, pw = Eigen::Matrix<Wide, 2, 2>::Identity();
      mm << decay, -omega, omega, decay;
      for (long d = 0; d <= orders; ++d) {
        if (d == 0) out(1 + j, c) = 1;
        out(1 + d * m + j, c + 1) = pw(1, 0);
        out(1 + d * m + j, c + 2) = pw(1, 1);
        pw = (mm * pw).eval();
      }
    } else {
      out(1 + j, c) = 1;
      if (orders >= 1) out(1 + m + j, c + 1) = 1;
    }
  }
  return out;
}

/// The map w-state → u_ext (the generator of [y; 1; w] is exo_generator's), rounded once from 113 bits.
Mat<double> exo_output(const ForcedScene& deck, long orders) { return exo_output_wide(deck, orders).cast<double>(); }

template <class S = double>
Mat<S> exo_generator(const ForcedScene& deck) {
  const std::size_t m = deck.waveforms.size();
  Mat<S> s = Mat<S>::Zero(1 + 3 * m, 1 + 3 * m);
  for (std::size_t j = 0; j < m; ++j) {
    const io::Waveform& w = deck.waveforms[j];
    const std::size_t c = 1 + 3 * j;
    if (w.is_exp()) {  // the shadow's rates from the exact TAUs (as omega_ld for a sine)
      s(c + 1, c + 1) = std::is_same_v<S, double> ? S(w.rate1()) : S(-1 / w.p[3].convert_to<long double>());
      s(c + 2, c + 2) = std::is_same_v<S, double> ? S(w.rate2()) : S(-1 / w.p[5].convert_to<long double>());
    } else if (w.is_sine()) {
      const S omega = std::is_same_v<S, double> ? S(w.omega()) : S(omega_ld(w)),
              decay = std::is_same_v<S, double> ? S(w.decay()) : S(decay_ld(w));
      s(c + 1, c + 1) = s(c + 2, c + 2) = decay;
      s(c + 1, c + 2) = -omega;
      s(c + 2, c + 1) = omega;
    } else {
      s(c, c + 1) = 1;
    }
  }
  return s;
}

template <class S>
struct ForcedFlow {
  Mat<S> g;               ///< balanced generator D⁻¹ G D
  std::vector<double> d;  ///< balancing
  std::map<long double, Mat<S>> cache;
  Vec<S> s;  ///< balanced state [y; 1; w]
  std::size_t dm = 0;
  const Mat<S>& step(long double h) {
    auto it = cache.find(h);
    if (it == cache.end()) {
      if (cache.size() > 64) cache.clear();  // substeps cut by breakpoints rarely repeat: keep memory bounded
      it = cache.emplace(h, (g * static_cast<S>(h)).exp()).first;
    }
    return it->second;
  }
  /// The sources' exosystem state at t for the substep (t, stop): each waveform is read at the
  /// substep's midpoint and carried back to t along its piece, so that a time that rounds onto the
  /// wrong side of a breakpoint (k·PER computed as 0.99999…) cannot pick the neighbouring piece.
  void set_exo(const ForcedScene& deck, double t, double stop) {
    const std::size_t m = deck.waveforms.size();
    s(dm) = S(1) / static_cast<S>(d[dm]);
    for (std::size_t j = 0; j < m; ++j) {
      long double w[3];
      if (std::is_same_v<S, double>)
        exo_state_for(deck.waveforms[j], t, stop, w);
      else
        exo_state_for_ld(deck.waveforms[j], t, stop, w);
      for (int k = 0; k < 3; ++k) s(dm + 1 + 3 * j + k) = static_cast<S>(w[k]) / static_cast<S>(d[dm + 1 + 3 * j + k]);
    }
  }
  /// Carries the exosystem from set_exo's double time t to t + dt (dt: that time's rounding, ~ulp(t)), to
  /// first order: (ω·dt)² is far below either flow's rounding.
  void shift_exo(long double dt) {
    if (dt == 0) return;
    const Eigen::Index e = g.rows() - static_cast<Eigen::Index>(dm);
    const Vec<S> rate = g.bottomRows(e) * s;
    s.tail(e) += static_cast<S>(dt) * rate;
  }
  Vec<S> y() const {
    Vec<S> out(dm);
    for (std::size_t i = 0; i < dm; ++i) out(i) = s(i) * static_cast<S>(d[i]);
    return out;
  }
  void add_to_y(const Vec<double>& dy) {
    for (std::size_t i = 0; i < dm; ++i) s(i) += static_cast<S>(dy(i)) / static_cast<S>(d[i]);
  }
};

template <class S, class G>
ForcedFlow<S> make_flow(const Mat<G>& gen, const std::vector<double>& d, std::size_t dm) {
  ForcedFlow<S> f;
  f.d = d;
  f.dm = dm;
  f.g = gen.template cast<S>();
  for (Eigen::Index i = 0; i < gen.rows(); ++i)
    for (Eigen::Index j = 0; j < gen.cols(); ++j) f.g(i, j) *= static_cast<S>(d[j] / d[i]);
  f.s = Vec<S>::Zero(gen.rows());
  return f;
}

/// The start: the given values, M_c(0), then 0 where M_c(0) allows (exact).  `exact` is false when a
/// constraint at 0 went through a source's jet that involves π (then rounded to double).
struct ForcedStart {
  std::vector<Q> x0q;
  bool exact = true;
};

ForcedStart forced_start(const ForcedScene& deck, const ForcedModel& fm, const io::CaseFile& c,
                         const std::vector<std::optional<io::Rational>>& initial) {
  const std::size_t n = fm.n, m = fm.m, wu = 1 + m * fm.orders;
  // initial point: the file's values, M_c(0), then 0 where M_c(0) allows
  const Vec<double> u0 = jets(deck, 0.0, fm.orders);
  QM given(0, n + 1), cons(0, n + 1), defaults(0, n + 1);
  for (std::size_t i = 0; i < n; ++i) {
    QM row(1, n + 1);
    row(0, i) = Q(1);
    row(0, n) = initial[i] ? *initial[i] : Q(0);
    (initial[i] ? given : defaults) = ref::vstack(initial[i] ? given : defaults, row);
  }
  // the sources' jets at 0, exactly where rational: a capacitor charged to a DC source's 1 V is on
  // M_c(0) at C = 1u too (with the jet in double, q_C = 1e-6 missed 1/1000000 and was refused)
  std::vector<std::optional<Q>> u0q(wu);
  u0q[0] = Q(1);
  for (std::size_t k = 1; k < wu; ++k)
    u0q[k] = deck.waveforms[(k - 1) % m].exact_at_zero(static_cast<int>((k - 1) / m));
  std::vector<bool> inexact(static_cast<std::size_t>(fm.eq.rows()), false);  // rows through an irrational jet (π)
  for (ref::Index i = 0; i < fm.eq.rows(); ++i) {
    QM row(1, n + 1);
    Q exact(0);
    double rhs = 0;
    for (std::size_t j = 0; j < wu; ++j) {
      if (fm.eq(i, n + j) == 0) continue;
      rhs -= fm.eq(i, n + j).convert_to<double>() * u0(j);
      if (u0q[j])
        exact -= fm.eq(i, n + j) * *u0q[j];
      else
        inexact[static_cast<std::size_t>(i)] = true;
    }
    for (std::size_t j = 0; j < n; ++j) row(0, j) = fm.eq(i, j);
    row(0, n) = inexact[static_cast<std::size_t>(i)] ? Q(rhs) : exact;
    cons = ref::vstack(cons, row);
  }
  const std::vector<std::string> names = [&] {
    std::vector<std::string> v = c.variables;
    const std::vector<std::string> j = reference::pipeline::jet_names(deck.waveforms, fm.orders);
    v.insert(v.end(), j.begin() + 1, j.end());
    return v;
  }();
  ref::AffineSubspace<Q> start = ref::affine_from_augmented(ref::vstack(given, cons));
  if (start.empty) {
    for (ref::Index i = 0; i < fm.eq.rows(); ++i)
      if (ref::affine_from_augmented(ref::vstack(given, cons.block(0, i + 1, 0, n + 1))).empty) {
        Equation<std::string> e;
        for (std::size_t j = 0; j < fm.eq.cols(); ++j)
          if (j != n && fm.eq(i, j) != 0) e.terms.emplace_back(j < n ? j : j - 1, fm.eq(i, j).str());
        e.rhs = Q(-fm.eq(i, n)).str();
        throw io::InputError(c.file + ": initial condition: expected a point of M_c(0), found one that violates " +
                             io::equation_text(e, names) + " at t = 0" +
                             (inexact[static_cast<std::size_t>(i)]
                                  ? " (a source's jet at 0 involves pi: checked with it rounded to double)"
                                  : ""));
      }
  }
  const ref::AffineSubspace<Q> with_defaults =
      ref::affine_from_augmented(ref::vstack(ref::vstack(given, cons), defaults));
  ForcedStart out;
  out.x0q = with_defaults.empty ? start.point : with_defaults.point;
  out.exact = std::none_of(inexact.begin(), inexact.end(), [](bool b) { return b; });
  return out;
}

/// The sources' corners the flow stops at (`breaks`, sorted) and each source's own (`own`): to TSTOP and a
/// step beyond it.  Refuses (InputError) a step (PER < TR + PW + TF) inside the run or on its last row, whose
/// jets would take the step's right side, a state the flow never reached (q printed -0.001 for 0.999 on
/// ngspice's rc.cir), and more than kMaxPeriods periods.
void source_corners(const std::vector<io::Waveform>& waveforms, const SimulateOptions& opt, const std::string& file,
                    std::vector<double>& breaks, std::vector<std::vector<double>>& own) {
  const double last_row = std::max(opt.tstop, std::floor(opt.tstop / opt.step + 1e-9) * opt.step);
  for (std::size_t j = 0; j < waveforms.size(); ++j) try {
      own[j] = waveforms[j].breakpoints(last_row * (1 + 8 * std::numeric_limits<double>::epsilon()));
      try {  // and a corner an ulp after the last row (k·STEP may pass TSTOP by an ulp): applied with it
        own[j] = waveforms[j].breakpoints(opt.tstop + opt.step);
      } catch (const std::invalid_argument&) {  // a step after the last row: the run ends before it
      }
      for (double b : own[j]) breaks.push_back(b);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(file + ": simulate: expected sources continuous over the run, in at most " +
                           std::to_string(io::Waveform::kMaxPeriods) + " periods, found " + e.what());
    }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
}

}  // namespace

Summary simulate_scene(const ForcedScene& deck, const io::CaseFile& c,
                       const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                       RowSink& out, std::ostream& log, std::ostream* energy) {
  require_times(opt);
  const ForcedModel fm = forced_model(deck);
  if (fm.free > 0)
    log << "note: solutions are not unique (" << fm.free
        << " free multipliers, e.g. a loop of equal sources); simulating one particular solution\n";
  const std::size_t n = fm.n, m = fm.m, dm = fm.dm, wu = 1 + m * fm.orders;
  const std::vector<Q> x0q = forced_start(deck, fm, c, initial).x0q;
  const Vec<double> u0 = jets(deck, 0.0, fm.orders);
  Vec<double> x0(n);
  for (std::size_t i = 0; i < n; ++i) x0(i) = x0q[i].convert_to<double>();
  const Mat<double> X0 = to_d(fm.x0), B = to_d(fm.basis),
                    P = to_d(ref::inverse(fm.basis * fm.basis.transpose()) * fm.basis);
  const Mat<double> Ay = to_d(fm.ay), Au = to_d(fm.au), Vy = to_d(fm.vy), Vu = to_d(fm.vu);
  for (const Mat<double>* mtx : {&X0, &B, &Ay, &Au, &Vy, &Vu})
    if (!mtx->allFinite())
      throw io::InputError(c.file +
                           ": simulate: expected equations of motion within double's range, found larger coefficients");
  const Vec<double> y0 = P * (x0 - X0 * u0.head(wu));
  // impulses: a corner of a piecewise-linear source (σ' jumps) feeds A_u's σ'' column; deeper is refused
  for (std::size_t j = 0; j < m; ++j) {
    if (deck.waveforms[j].constant() ||
        deck.waveforms[j].breakpoints(std::min(opt.tstop, deck.waveforms[j].horizon())).empty())
      continue;
    for (long d = deck.waveforms[j].is_sine() ? 2 : 3; d <= fm.orders; ++d)
      if (Au.col(1 + d * m + j).cwiseAbs().maxCoeff() > 0)
        throw io::InputError(c.file + ": simulate: " + deck.waveforms[j].element +
                             " has breakpoints and the motion needs its derivative of order " + std::to_string(d) +
                             " (a derivative of a Dirac delta): smooth it (finite TR/TF) or use SIN");
  }
  const Mat<double> S = exo_generator(deck);
  const Mat<Wide> coupling = to_wide(fm.au) * exo_output_wide(deck, fm.orders);  // A_u W: its terms cancel
  Mat<double> gen = Mat<double>::Zero(dm + 1 + 3 * m, dm + 1 + 3 * m);
  gen.topLeftCorner(dm, dm) = Ay;
  gen.topRightCorner(dm, 1 + 3 * m) = coupling.cast<double>();
  gen.bottomRightCorner(1 + 3 * m, 1 + 3 * m) = S;
  const std::vector<double> bal = balancing(gen * opt.step);
  ForcedFlow<double> flow = make_flow<double>(gen, bal, dm);
  Mat<long double> gen_l = gen.cast<long double>();  // the shadow: the model rounded once more finely
  gen_l.topLeftCorner(dm, dm) = to_wide(fm.ay).cast<long double>();
  gen_l.topRightCorner(dm, 1 + 3 * m) = coupling.cast<long double>();
  gen_l.bottomRightCorner(1 + 3 * m, 1 + 3 * m) = exo_generator<long double>(deck);
  ForcedFlow<long double> shadow = make_flow<long double>(gen_l, bal, dm);
  const Mat<Wide> x0_wide = to_wide(fm.x0);
  const Mat<long double> basis_l = to_wide(fm.basis).cast<long double>();
  // the shadow's start from the exact data in 113 bits (the double start's rounding is part of what it measures)
  Vec<Wide> x0w(n);
  for (std::size_t i = 0; i < n; ++i) x0w(i) = wide(x0q[i]);
  const Vec<Wide> y0w = to_wide(ref::inverse(fm.basis * fm.basis.transpose()) * fm.basis) *
                        (x0w - x0_wide * jets_wide(deck, 0.0, Q(0), fm.orders, wu));
  for (std::size_t i = 0; i < dm; ++i)
    flow.s(i) = y0(i) / bal[i], shadow.s(i) = static_cast<long double>(y0w(i)) / bal[i];

  std::vector<double> breaks;
  std::vector<std::vector<double>> own(m);  // each source's own corners: only they jump there
  source_corners(deck.waveforms, opt, c.file, breaks, own);
  // energy: E(x) = ½ xᵀHx (+ gᵀx), and the power of the forces ⟨F x, q̇⟩, of the sources ⟨Bσ, q̇⟩ (the
  // q-rows: the force one-form is horizontal, YM §4) and, from the balance, of the reactions of the
  // affine constraints (current sources): dE/dt = ⟨F x + Bσ, q̇⟩ + P_constraints.
  const Mat<double> H = to_d(fm.f.s.hessian), F = to_d(fm.f.force.rows() ? fm.f.force : QM(n, n)),
                    Bs = to_d(fm.f.source_force);
  const Vec<double> grad = to_d(QM::column(fm.f.s.gradient));
  const std::size_t nq = n / 3;
  bool has_i = false;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < m; ++j) has_i = has_i || fm.f.shift(i, j) != 0;
  double wr = 0, wv = 0, wi = 0, last_pr = 0, last_pv = 0, last_pi = 0, worst_balance = 0, power_scale = 0;
  out.header(with_time(c.variables));
  EnergyCsv energy_csv(energy);
  std::vector<double> row;
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  std::vector<long double> err(n, 0), mag(n, 0);
  std::size_t next_break = 0;
  double e0 = 0;
  // Row k is the motion at the exact time k·step (as the enclosures' rows): every step the flows take is
  // exactly --step, or pieces of it between breakpoints summing to it in long double, and the sources'
  // state is carried from the printed double time to the exact one.  Steps of (k+1)·step − k·step in
  // double drift by ulp(t): 1e-14 of the state on a 3e10 rad/s tank after ten steps, unseen by the shadow.
  const Q hq = certified::rational_of(opt.step);
  for (long k = 0; k <= steps; ++k) {
    const double t = static_cast<double>(k) * opt.step;
    const long double t_exact = static_cast<long double>(k) * static_cast<long double>(opt.step);
    // the side of each corner the flow is on: it has applied every breakpoint <= t + 1e-12·step (an EXP's TD1
    // an ulp after the row, or equal to it in double and 2e-26 after it exactly): the jets take the same pieces
    const double t_pick = next_break > 0 ? std::max(t, breaks[next_break - 1]) : t;
    const Vec<double> u = jets(deck, t_pick, fm.orders);
    const Vec<double> y = flow.y();
    const Vec<Wide> x0u = x0_wide * jets_wide(deck, t_pick, hq * Q(k), fm.orders, wu);  // X0 u: its terms cancel too
    const Vec<double> x = x0u.cast<double>() + B.transpose() * y;
    if (!x.allFinite())
      throw io::InputError(c.file + ": simulate: expected a finite state, found an overflow at t = " +
                           io::float_text(t) + " s (a growing source or values beyond double's range)");
    const Vec<long double> xl = x0u.cast<long double>() + basis_l.transpose() * shadow.y();
    for (std::size_t i = 0; i < n; ++i) {
      err[i] = std::max(err[i], std::abs(xl(i) - static_cast<long double>(x(i))));
      mag[i] = std::max(mag[i], std::abs(xl(i)));
    }
    row.assign(1, t);
    for (Eigen::Index i = 0; i < x.size(); ++i)
      row.push_back(static_cast<double>(xl(i)));  // the long-double flow: the double one is its error estimate
    out.row(row);
    // energy balance at this row
    const Vec<double> xdot = Vy * y + Vu * u;
    const double en = 0.5 * x.dot(H * x) + grad.dot(x);
    const double de = (H * x + grad).dot(xdot);
    const Vec<double> fx = F * x, bs = Bs * u.segment(1, m);
    const double pr = fx.head(nq).dot(xdot.head(nq)), pv = bs.head(nq).dot(xdot.head(nq));
    const double pi = de - pr - pv;  // what the reactions of the affine constraints supply
    power_scale = std::max({power_scale, std::abs(de), std::abs(pr), std::abs(pv)});
    if (!has_i) worst_balance = std::max(worst_balance, std::abs(pi));
    if (k == 0) e0 = en;
    if (k > 0) {
      wr += opt.step * (pr + last_pr) / 2;
      wv += opt.step * (pv + last_pv) / 2;
      wi += opt.step * (pi + last_pi) / 2;
    }
    last_pr = pr, last_pv = pv, last_pi = pi;
    energy_csv.row(t, en, pr, pv, pi, wr, wv, wi);
    if (k == steps) {
      log << "simulate: energy: E(0) = " << io::float_text(e0) << ", E(" << io::float_text(t)
          << ") = " << io::float_text(en) << "; work of the forces " << io::float_text(wr) << " (dissipated "
          << io::float_text(-wr) << "), of the sources " << io::float_text(wv)
          << (has_i ? ", of the affine constraints (current sources) " + io::float_text(wi) : "")
          << " (trapezoid on the output rows)";
      if (!has_i)
        log << "; balance dE/dt = <F, qdot> holds to "
            << io::float_text(power_scale > 0 ? worst_balance / power_scale : 0.0) << " relative at the rows";
      log << "\n";
      break;
    }
    // advance one output step, stopping at the breakpoints inside it
    double at = t;
    long double at_exact = t_exact;
    const double to = static_cast<double>(k + 1) * opt.step;
    const long double to_exact = static_cast<long double>(k + 1) * static_cast<long double>(opt.step);
    while (true) {
      const double stop =
          next_break < breaks.size() && breaks[next_break] < to - 1e-12 * opt.step ? breaks[next_break] : to;
      const long double stop_exact = stop == to ? to_exact : static_cast<long double>(stop);
      const bool whole = at == t && stop == to;
      const long double h = whole ? static_cast<long double>(opt.step) : stop_exact - at_exact;
      flow.set_exo(deck, at, stop);
      shadow.set_exo(deck, at, stop);
      flow.shift_exo(at_exact - static_cast<long double>(at));
      shadow.shift_exo(at_exact - static_cast<long double>(at));
      if (h > 0) {
        flow.s =
            flow.step(whole ? static_cast<long double>(opt.step) : static_cast<long double>(static_cast<double>(h))) *
            flow.s;
        shadow.s = shadow.step(h) * shadow.s;
      }
      at = stop;
      at_exact = stop_exact;
      // a breakpoint at `at`: σ' jumps, σ'' has a delta of that weight
      while (next_break < breaks.size() && breaks[next_break] <= at + 1e-12 * opt.step) {
        const double tb = breaks[next_break++];
        const double delta = std::max(1e-9 * opt.step, std::abs(tb) * 1e-12), before = tb - delta, after = tb + delta;
        Vec<double> dy = Vec<double>::Zero(dm);
        for (std::size_t j = 0; j < m; ++j)
          for (long d = 1; d <= fm.orders && std::binary_search(own[j].begin(), own[j].end(), tb); ++d) {
            const io::Waveform& wf = deck.waveforms[j];
            // σ^{(d−1)} across the corner; σ itself is continuous for PULSE/PWL, its slope is read off the pieces
            const std::optional<double> closed =
                wf.corner_jump(tb, static_cast<int>(d - 1));  // EXP, SIN: exact, not read off tb ± delta
            const double jump =
                closed  ? *closed
                : d > 1 ? wf.value(after, static_cast<int>(d - 1)) - wf.value(before, static_cast<int>(d - 1))
                        : 0.0;
            if (jump != 0) dy += Au.col(1 + d * m + j) * jump;
          }
        flow.add_to_y(dy);
        shadow.add_to_y(dy);
      }
      if (stop >= to) break;
    }
  }
  Summary sum = summarize(steps + 1, err, mag, c.variables, deck.natural);
  // the rows are the long-double flow rounded to double at t = k·step rounded to double: never less than
  // those roundings (a few ε of the scale)
  sum.error_estimate = std::max(sum.error_estimate, 4 * std::numeric_limits<double>::epsilon());
  return sum;
}

Summary simulate_forced(const io::Netlist& deck, const io::CaseFile& c,
                        const std::vector<std::optional<io::Rational>>& initial, const SimulateOptions& opt,
                        RowSink& out, std::ostream& log, std::ostream* energy) {
  if (const auto which = io::without_exact_flow(deck.waveforms))
    throw io::InputError(c.file +
                         ": simulate: expected continuous sources with a finite exosystem (DC, SIN, PULSE, PWL, EXP), "
                         "found " +
                         *which);
  if (deck.rlc.branches.size() > reference::pipeline::kForcedBranches)
    throw io::InputError(c.file + ": simulate: expected at most " +
                         std::to_string(reference::pipeline::kForcedBranches) +
                         " branches for a circuit with resistors, sources or couplings, found " +
                         std::to_string(deck.rlc.branches.size()));
  return simulate_scene(ForcedScene{deck.file, ref::rlc_system(deck.rlc), deck.waveforms,
                                    io::units_of(deck).variable_scales(deck.rlc.branches.size(), false)},
                        c, initial, opt, out, log, energy);
}

Summary simulate_forced_case(const io::CaseFile& c, const std::vector<std::optional<io::Rational>>& initial,
                             const SimulateOptions& opt, RowSink& out, std::ostream& log, std::ostream* energy) {
  return simulate_scene(ForcedScene{c.file, reference::pipeline::forced_system(c), {}}, c, initial, opt, out, log,
                        energy);
}

}  // namespace dcad::api

// ---- the certified tier: rigorous enclosures of the same exact motion (certified/enclosure.hpp) ----

namespace dcad::api {

namespace {

/// The engine's data and start on the model both routes end in: balanced by the double generator.
CertifiedMotion enclose(certified::ForcedMotionData data, const std::vector<Q>& y, const ForcedScene& scene,
                        double step, long precision) {
  CertifiedMotion out;
  const std::size_t m = data.waveforms.size(), dm = static_cast<std::size_t>(data.ay.rows());
  const long orders = data.orders;
  const Mat<double> W = exo_output(scene, orders), S = exo_generator(scene);
  Mat<double> gen =
      Mat<double>::Zero(static_cast<Eigen::Index>(dm + 1 + 3 * m), static_cast<Eigen::Index>(dm + 1 + 3 * m));
  gen.topLeftCorner(dm, dm) = to_d(data.ay);
  gen.topRightCorner(dm, 1 + 3 * m) = to_d(data.au) * W;
  gen.bottomRightCorner(1 + 3 * m, 1 + 3 * m) = S;
  if (gen.allFinite()) data.balance = balancing(gen * step);
  try {
    out.flow = std::make_unique<certified::MotionEnclosure>(data, y, precision);
  } catch (const std::invalid_argument& e) {
    out.why = e.what();
  }
  return out;
}

/// The dense route: the forced tower's model, from netlist_start's exact start.
CertifiedMotion dense_motion(const io::Netlist& deck, const io::CaseFile& c, Initial rule, double step, long precision,
                             std::ostream& log) {
  CertifiedMotion out;
  if (reference::pipeline::rounded_coupling(
          deck.rlc)) {  // the model is the rounded circuit's: its balls need not hold the deck's motion
    out.why = reference::pipeline::kRoundedCoupling;
    return out;
  }
  const ForcedScene scene{deck.file, ref::rlc_system(deck.rlc), deck.waveforms, {}};
  const ForcedModel fm = forced_model(scene);
  if (fm.free > 0) {
    out.why = "the circuit's solutions are not unique (" + std::to_string(fm.free) +
              " free multipliers): the flow takes one particular solution";
    return out;
  }
  const std::vector<std::optional<io::Rational>> initial = netlist_start(deck, c.variables, rule, log);
  const ForcedStart st = forced_start(scene, fm, c, initial);
  const std::size_t m = fm.m, wu = 1 + m * static_cast<std::size_t>(fm.orders);
  std::vector<Q> u0(wu, Q(0));
  u0[0] = Q(1);
  for (std::size_t k = 1; k < wu; ++k) {
    bool used = false;
    for (ref::Index i = 0; i < fm.x0.rows(); ++i) used = used || fm.x0(i, static_cast<ref::Index>(k)) != 0;
    if (!used) continue;
    const std::optional<Q> v = deck.waveforms[(k - 1) % m].exact_at_zero(static_cast<int>((k - 1) / m));
    if (!v) {
      out.why = "the state at t = 0 depends on " + deck.waveforms[(k - 1) % m].element + "'s derivative of order " +
                std::to_string((k - 1) / m) + " at 0, which involves pi (the start is not an exact rational)";
      return out;
    }
    u0[k] = *v;
  }
  if (!st.exact) {
    out.why = "the state at t = 0 is constrained through a source's jet that involves pi (rounded to double)";
    return out;
  }
  const QM p = ref::inverse(fm.basis * fm.basis.transpose()) * fm.basis;
  QM dx = QM::column(st.x0q) - fm.x0 * QM::column(u0);
  const QM y0 = p * dx;
  certified::ForcedMotionData data;
  data.x0 = fm.x0, data.basis = fm.basis, data.ay = fm.ay, data.au = fm.au, data.vy = fm.vy, data.vu = fm.vu;
  data.orders = fm.orders;
  data.waveforms = deck.waveforms;
  std::vector<Q> y(fm.dm);
  for (std::size_t i = 0; i < fm.dm; ++i) y[i] = y0(static_cast<ref::Index>(i), 0);
  return enclose(std::move(data), y, scene, step, precision);
}

/// The state-equation route (pipeline/rlc_motion.hpp): its model and its exact start.
CertifiedMotion state_motion(const io::Netlist& deck, Initial rule, double step, long precision, std::ostream& log) {
  CertifiedMotion out;
  std::vector<Q> sigma0;
  for (const io::Waveform& w : deck.waveforms) sigma0.push_back(*w.exact_at_zero(0));  // checked by the caller
  const bool op = rule == Initial::op || (rule == Initial::deck && deck.tran == io::Netlist::Transient::op);
  reference::pipeline::StateMotion sm;
  std::vector<Q> y;
  try {
    sm = reference::pipeline::state_motion(deck);
    y = reference::pipeline::state_start(deck, sm, op, sigma0);
  } catch (const std::invalid_argument& e) {
    out.why = e.what();
    return out;
  }
  log << "initial state: "
      << (op ? "the DC operating point at t = 0, exact on the state equations"
             : "uic: IC= values, everything else 0, moved onto M_c(0+) keeping every C-component's charge (exact, on "
               "the state equations)")
      << "\n";
  certified::ForcedMotionData data;
  data.x0 = sm.x0, data.basis = sm.bt.transpose(), data.ay = sm.ay, data.au = sm.au, data.vy = sm.vy, data.vu = sm.vu;
  data.orders = 2;
  data.waveforms = deck.waveforms;
  const ForcedScene scene{deck.file, {}, deck.waveforms, {}};
  out = enclose(std::move(data), y, scene, step, precision);
  return out;
}

}  // namespace

CertifiedMotion certified_motion(const io::Netlist& deck, const io::CaseFile& c, Initial rule, double step,
                                 long precision, EnclosureModel model, std::ostream* log) {
  CertifiedMotion out;
  if (const auto which = io::without_exact_flow(deck.waveforms)) {
    out.why = "a source the exact flows do not take, " + *which;
    return out;
  }
  const std::size_t nb = deck.rlc.branches.size();
  const bool automatic = model == EnclosureModel::automatic;
  if (automatic) model = nb <= reference::pipeline::kForcedBranches ? EnclosureModel::dense : EnclosureModel::state;
  out.model = model == EnclosureModel::dense ? "dense" : "state equations";
  const std::size_t limit = model == EnclosureModel::dense ? reference::pipeline::kForcedBranches : kCertifiedBranches;
  if (nb > limit) {  // before the exact start (gigabytes at 10^4 branches)
    out.why = model == EnclosureModel::dense
                  ? "the dense model is built up to " + std::to_string(reference::pipeline::kForcedBranches) +
                        " branches; this circuit has " + std::to_string(nb)
                  : "enclosures are built up to " + std::to_string(kCertifiedBranches) +
                        " branches (the dense model up to " + std::to_string(reference::pipeline::kForcedBranches) +
                        ", the state equations beyond); this circuit has " + std::to_string(nb);
    return out;
  }
  // the start (the operating point, the jump at 0) is computed from the sources' values at 0 in double
  // where they involve π: exact only when every one is rational
  for (const io::Waveform& w : deck.waveforms)
    if (!w.exact_at_zero(0)) {
      out.why = "the state at t = 0 depends on " + w.element +
                "'s value at 0, which involves pi (the start is not an exact rational)";
      return out;
    }
  std::ostringstream quiet;
  std::ostream& to = log ? *log : quiet;
  CertifiedMotion r = model == EnclosureModel::dense ? dense_motion(deck, c, rule, step, precision, to)
                                                     : state_motion(deck, rule, step, precision, to);
  r.model = out.model;
  // automatic: where the dense model refuses (a start through a source's derivative that involves π) the
  // state equations, which need only σ(0), may not
  if (!r.flow && automatic && model == EnclosureModel::dense && reference::pipeline::graph_route_holds(deck.rlc)) {
    std::ostringstream second;
    CertifiedMotion s = state_motion(deck, rule, step, precision, second);
    if (s.flow) {
      to << second.str();
      s.model = "state equations";
      return s;
    }
  }
  return r;
}

Summary simulate_enclosed(const io::Netlist& deck, const io::CaseFile& c, const SimulateOptions& opt, RowSink& out,
                          std::ostream& log) {
  require_times(opt);
  // --route picks the exact model: dense (the forced tower) or sparse (the state equations)
  const EnclosureModel model = opt.route == Route::dense    ? EnclosureModel::dense
                               : opt.route == Route::sparse ? EnclosureModel::state
                                                            : EnclosureModel::automatic;
  CertifiedMotion cm = certified_motion(deck, c, opt.initial, opt.step, 256, model, &log);
  if (!cm.flow)
    throw io::InputError(deck.file +
                         ": simulate --certified: expected a circuit whose motion dcad encloses, found: " + cm.why);
  const std::size_t nb = deck.rlc.branches.size(), n = 3 * nb;
  std::vector<std::string> names = with_time(c.variables);
  names.insert(names.end(), {"rad_q", "rad_v", "rad_p"});
  out.header(names);
  const Q h = certified::rational_of(opt.step);
  const long steps = static_cast<long>(std::floor(opt.tstop / opt.step + 1e-9));
  double worst[3] = {0, 0, 0}, scale[3] = {0, 0, 0};
  std::vector<double> row;
  for (long k = 0; k <= steps; ++k) {
    try {
      cm.flow->advance_to(h * k);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(deck.file + ": simulate --certified: " + e.what());
    }
    const std::vector<certified::Enclosure> x = cm.flow->state();
    double rad[3] = {0, 0, 0};
    row.assign(1, static_cast<double>(k) * opt.step);
    for (std::size_t i = 0; i < n; ++i) {
      row.push_back(x[i].mid);
      rad[i / nb] =
          std::max(rad[i / nb], io::printed_radius(x[i].mid, x[i].rad));  // the printed decimals hold the value
      scale[i / nb] = std::max(scale[i / nb], std::abs(x[i].mid));
    }
    for (int kind = 0; kind < 3; ++kind) {
      row.push_back(rad[kind]);
      worst[kind] = std::max(worst[kind], rad[kind]);
    }
    out.row(row);
  }
  Summary sum;
  sum.rows = steps + 1;
  sum.estimate_kind =
      "rigorous: the largest enclosure radius relative to the largest value of its kind (charges, currents, flux "
      "linkages)";
  for (int kind = 0; kind < 3; ++kind) {
    const double r = scale[kind] > 0 ? worst[kind] / scale[kind] : worst[kind];
    if (r >= sum.error_estimate)
      sum.error_estimate = r, sum.worst_variable = kind == 0 ? "q_" : kind == 1 ? "v_" : "p_";
  }
  log << "simulate --certified: every value is the midpoint of a rigorous enclosure (Arb balls on the exact "
      << cm.model << " model); radii rad_q, rad_v, rad_p per row; " << cm.flow->exponentials()
      << " matrix exponentials, " << cm.flow->restarts() << " restarts against wrapping\n";
  return sum;
}

}  // namespace dcad::api
