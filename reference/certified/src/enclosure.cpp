// MotionEnclosure (enclosure.hpp): ball arithmetic with Arb.  Every operation on a ball returns a ball
// that contains the exact result, so every value below contains the exact motion; the code only
// chooses the route (Taylor step, cached exponential, restart) that keeps the balls narrow.
#include "dcad/certified/enclosure.hpp"

#include "balls.hpp"

#include <arb.h>
#include <arb_mat.h>
#include <flint/fmpq.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace dcad::certified {

namespace {

using namespace detail;

void set_qm(BallMat& out, const QM& q, slong prec) {
  for (reference::Index i = 0; i < q.rows(); ++i)
    for (reference::Index j = 0; j < q.cols(); ++j)
      set_q(out.at(static_cast<slong>(i), static_cast<slong>(j)), q(i, j), prec);
}

}  // namespace

Q rational_of(double t) {
  Q q(t);  // mpq from a double is exact
  return q;
}

struct MotionEnclosure::Impl {
  ForcedMotionData data;
  slong prec = 256;
  std::size_t n = 0, m = 0, dm = 0, nz = 0, nu = 0;
  BallMat g{0, 0};                                             ///< balanced generator D⁻¹ G D
  BallMat x0{0, 0}, bt{0, 0}, vy{0, 0}, vu{0, 0}, wout{0, 0};  ///< exact data; W: exosystem → u_ext
  BallMat z{0, 0}, z_left{0, 0},
      z_piece{0, 0};    ///< balanced states (columns) now, before a corner's jump, at the piece's start
  std::vector<Q> dual;  ///< D (exact powers of two)
  Q t = 0, piece = 0;
  bool corner = false;
  bool zero = false;  ///< the motion is identically 0, proved exactly (zero_motion)
  std::map<Q, std::unique_ptr<BallMat>> cache;
  long restarts = 0, exps = 0;

  void reset(BallMat& a, slong r, slong c) {
    arb_mat_clear(a.m);
    arb_mat_init(a.m, r, c);
  }

  /// Exosystem of source j at the exact time s (right limit), into rows dm+1+3j … of column `col`.
  void exo_at(BallMat& out, std::size_t j, const Q& s) {
    const io::Waveform& w = data.waveforms[j];
    arb_ptr w0 = out.at(static_cast<slong>(dm + 1 + 3 * j), 0), w1 = out.at(static_cast<slong>(dm + 2 + 3 * j), 0),
            w2 = out.at(static_cast<slong>(dm + 3 + 3 * j), 0);
    arb_zero(w0), arb_zero(w1), arb_zero(w2);
    if (w.is_exp()) {  // EXP(V1 V2 TD1 TAU1 TD2 TAU2), right limit: (V1, 0, 0) before TD1; from it e1 = (V1 − V2)
                       // e^{−(s−TD1)/TAU1}
      const Q &v1 = w.p[0], &v2 = w.p[1], &td1 = w.p[2], &tau1 = w.p[3], &td2 = w.p[4], &tau2 = w.p[5];
      set_q(w0, v1, prec);
      if (s < td1) return;
      const auto decayed = [&](arb_ptr out, const Q& amplitude, const Q& from, const Q& tau) {
        Ball e;
        set_q(e.v, -(s - from) / tau, prec);
        arb_exp(e.v, e.v, prec);
        set_q(out, amplitude, prec);
        arb_mul(out, out, e.v, prec);
      };
      decayed(w1, v1 - v2, td1, tau1);
      if (s <
          td2) {  // V2 + (V1 − V2) e^{…} up to TD2, then V1 + … + (V2 − V1) e^{−(s−TD2)/TAU2} (ngspice's vsrcload.c)
        set_q(w0, v2, prec);
        return;
      }
      decayed(w2, v2 - v1, td2, tau2);
      return;
    }
    if (!w.is_sine()) {
      Q v, slope;
      w.exact_piece(s, v, slope);
      set_q(w0, v, prec);
      set_q(w1, slope, prec);
      return;
    }
    // SIN(VO VA FREQ TD THETA PHASE): VO + VA sin φ before TD; then (VO, Re z, Im z)
    Ball pi, phi, va;
    arb_const_pi(pi.v, prec);
    set_q(phi.v, w.p[5] / 180, prec);
    arb_mul(phi.v, phi.v, pi.v, prec);
    set_q(va.v, w.p[1], prec);
    set_q(w0, w.p[0], prec);
    if (s < w.p[3]) {
      Ball sn;
      arb_sin(sn.v, phi.v, prec);
      arb_addmul(w0, va.v, sn.v, prec);
      return;
    }
    Ball tau, ang, amp, sn, cs;
    set_q(tau.v, s - w.p[3], prec);
    set_q(ang.v, 2 * w.p[2], prec);  // ω τ + φ, ω = 2π FREQ
    arb_mul(ang.v, ang.v, pi.v, prec);
    arb_mul(ang.v, ang.v, tau.v, prec);
    arb_add(ang.v, ang.v, phi.v, prec);
    set_q(amp.v, -w.p[4], prec);  // VA e^{−θ τ}
    arb_mul(amp.v, amp.v, tau.v, prec);
    arb_exp(amp.v, amp.v, prec);
    arb_mul(amp.v, amp.v, va.v, prec);
    arb_sin_cos(sn.v, cs.v, ang.v, prec);
    arb_mul(w1, amp.v, cs.v, prec);
    arb_mul(w2, amp.v, sn.v, prec);
  }

  /// Balances column z in place: entries divided by D.
  void to_balanced(BallMat& col) {
    for (std::size_t i = 0; i < nz; ++i) {
      Ball d;
      set_q(d.v, dual[i], prec);
      arb_div(col.at(static_cast<slong>(i), 0), col.at(static_cast<slong>(i), 0), d.v, prec);
    }
  }

  /// The exosystem part of the balanced state z at the exact time s (start of a piece).
  void reset_exo(const Q& s) {
    BallMat full(static_cast<slong>(nz), 1);
    arb_one(full.at(static_cast<slong>(dm), 0));
    for (std::size_t j = 0; j < m; ++j) exo_at(full, j, s);
    to_balanced(full);
    for (std::size_t i = dm; i < nz; ++i) arb_set(z.at(static_cast<slong>(i), 0), full.at(static_cast<slong>(i), 0));
  }

  /// The largest radius of the (balanced) state, and the largest |midpoint| so far in the run (`scale`):
  /// wrapping is measured against the state's size over the run, not against a state decaying to 0
  /// (whose relative width grows however it is computed, and would restart at every step).
  double width(const BallMat& col) {
    double r = 0;
    for (slong i = 0; i < static_cast<slong>(nz); ++i) {
      const arb_srcptr e = arb_mat_entry(col.m, i, 0);
      r = std::max(r, mag_get_d(arb_radref(e)));
      scale = std::max(scale, std::abs(arf_get_d(arb_midref(e), ARF_RND_NEAR)));
    }
    return std::isfinite(r) ? r : HUGE_VAL;
  }
  double scale = 0, floor = 0;

  void exp_of(BallMat& out, const Q& delta) {
    Ball d;
    set_q(d.v, delta, prec);
    arb_mat_scalar_mul_arb(out.m, g.m, d.v, prec);
    arb_mat_exp(out.m, out.m, prec);
    ++exps;
  }

  /// z ← exp(G δ) z by the Taylor series with its remainder bounded: for a = ‖G δ‖∞ ≤ 1 the tail from
  /// order K is at most ‖z‖∞ a^K / K! · 1/(1 − a/(K+1)) ≤ 2 ‖z‖∞ a^K / K! in every entry.
  bool taylor(const Q& delta) {
    Ball d;
    set_q(d.v, delta, prec);
    mag_t a, nzm, tail, tmp;
    mag_init(a), mag_init(nzm), mag_init(tail), mag_init(tmp);
    arb_mat_bound_inf_norm(a, g.m);
    arb_get_mag(tmp, d.v);
    mag_mul(a, a, tmp);
    const double ad = mag_get_d(a);
    bool ok = ad <= 1;
    if (ok) {
      long k = 1;  // smallest K with a^K/K! < 2^-(prec+8)
      double lg = 0;
      while (k < 400) {
        lg += std::log2(std::max(ad, 1e-300)) - std::log2(static_cast<double>(k));
        if (lg < -static_cast<double>(prec + 8)) break;
        ++k;
      }
      ok = k < 400;
      if (ok) {
        BallMat term(static_cast<slong>(nz), 1), next(static_cast<slong>(nz), 1), sum(static_cast<slong>(nz), 1),
            gd(static_cast<slong>(nz), static_cast<slong>(nz));
        arb_mat_scalar_mul_arb(gd.m, g.m, d.v, prec);
        arb_mat_set(term.m, z.m);
        arb_mat_set(sum.m, z.m);
        for (long j = 1; j < k; ++j) {
          arb_mat_mul(next.m, gd.m, term.m, prec);
          arb_mat_scalar_div_si(term.m, next.m, j, prec);
          arb_mat_add(sum.m, sum.m, term.m, prec);
        }
        mag_zero(nzm);
        for (slong i = 0; i < static_cast<slong>(nz); ++i) {
          arb_get_mag(tmp, z.at(i, 0));
          mag_max(nzm, nzm, tmp);
        }
        mag_pow_ui(tail, a, static_cast<ulong>(k));
        mag_rfac_ui(tmp, static_cast<ulong>(k));
        mag_mul(tail, tail, tmp);
        mag_mul(tail, tail, nzm);
        mag_mul_2exp_si(tail, tail, 1);
        for (slong i = 0; i < static_cast<slong>(nz); ++i) arb_add_error_mag(sum.at(i, 0), tail);
        arb_mat_swap(z.m, sum.m);
      }
    }
    mag_clear(a), mag_clear(nzm), mag_clear(tail), mag_clear(tmp);
    return ok;
  }

  /// exp(G 2^e), each by its own exponential (not by squaring, which widens geometrically), computed once.
  std::map<long, std::unique_ptr<BallMat>> binary;
  /// z ← exp(G δ) z for a dyadic δ = Σ 2^e (a difference of two doubles: a simulator's time step) as the
  /// product of the exp(G 2^e) of its binary digits — at most 64 matrix–vector products from exponentials
  /// shared by every step, where a simulator's steps are all distinct (ngspice's tight runs: one
  /// exponential per time point took 35 s for 20,000 points).  False when δ is not dyadic or has more
  /// than 64 digits, or the digits reach beyond 2^±400 (then one exponential of its own).
  bool by_binary_powers(const Q& delta) { return by_binary_powers(delta, z); }
  bool by_binary_powers(const Q& delta, BallMat& v) {
    using boost::multiprecision::mpz_int;
    const mpz_int num = boost::multiprecision::numerator(delta), den = boost::multiprecision::denominator(delta);
    if (num <= 0 || (den & (den - 1)) != 0) return false;                   // not dyadic
    const long shift = static_cast<long>(boost::multiprecision::msb(den));  // δ = num · 2^-shift
    std::vector<long> exps;
    for (long bit = 0; bit <= static_cast<long>(boost::multiprecision::msb(num)); ++bit)
      if (boost::multiprecision::bit_test(num, static_cast<unsigned>(bit))) exps.push_back(bit - shift);
    if (exps.size() > 64 || exps.front() < -400 || exps.back() > 400) return false;
    for (long e : exps) {
      auto it = binary.find(e);
      if (it == binary.end()) {
        auto m = std::make_unique<BallMat>(static_cast<slong>(nz), static_cast<slong>(nz));
        exp_of(*m, e >= 0 ? Q(mpz_int(1) << e) : Q(1, mpz_int(1) << -e));
        it = binary.emplace(e, std::move(m)).first;
      }
      BallMat next(static_cast<slong>(nz), 1);
      arb_mat_mul(next.m, it->second->m, v.m, prec);
      arb_mat_swap(v.m, next.m);
    }
    return true;
  }

  /// z at time `to` in the current piece (no corner in (t, to]).
  void flow_to(const Q& to) {
    if (to == t) return;
    const Q delta = to - t;
    auto it = cache.find(delta);
    if (it != cache.end()) {
      BallMat next(static_cast<slong>(nz), 1);
      arb_mat_mul(next.m, it->second->m, z.m, prec);
      arb_mat_swap(z.m, next.m);
    } else if (!taylor(delta) && !by_binary_powers(delta)) {
      auto e = std::make_unique<BallMat>(static_cast<slong>(nz), static_cast<slong>(nz));
      exp_of(*e, delta);
      BallMat next(static_cast<slong>(nz), 1);
      arb_mat_mul(next.m, e->m, z.m, prec);
      arb_mat_swap(z.m, next.m);
      if (cache.size() < 32) cache.emplace(delta, std::move(e));
    }
    // a repeated step gets its own exponential (a uniform grid: one product per row)
    if (it == cache.end() && cache.size() < 32 && ++seen[delta] == 3 && !cache.count(delta)) {
      auto e = std::make_unique<BallMat>(static_cast<slong>(nz), static_cast<slong>(nz));
      exp_of(*e, delta);
      cache.emplace(delta, std::move(e));
    }
    t = to;
    // wrapping: once from the piece's start, when the width has grown beyond 2^(−prec/2) of the state's
    // scale and well beyond what the last restart left (a restart that cannot narrow it is not repeated)
    const double w = width(z);
    if (w > std::ldexp(scale, -static_cast<int>(prec / 2)) && w > 1024 * floor) {
      restart();
      ++restarts;
      floor = width(z);
    }
    if (!anchored) {  // the first point of the piece: later restarts start from here (one step from its start)
      arb_mat_set(z_piece.m, z.m);
      piece = t;
      anchored = true;
      anchor_width = width(z);
    }
  }
  std::map<Q, int> seen;
  bool anchored = false;
  double anchor_width = 0;
  /// Before a corner: the state recomputed from the anchor when it has widened 2^16-fold since, so that
  /// the next piece does not start from a wrapped state (widths would ratchet up piece after piece).
  void refresh() {
    if (anchored && t > piece && width(z) > 65536 * anchor_width) {
      restart();
      ++restarts;
    }
  }
  /// exp(G δ·2^k) of a cached step δ, each by its own exponential
  std::map<Q, std::vector<std::unique_ptr<BallMat>>> powers;

  /// z from the anchor (z_piece at `piece`) in one go: by binary powers of a repeated step δ when t − piece
  /// is a multiple j of it (at most log2 j products: a uniform grid restarts for the cost of a few
  /// products), else by one exponential exp(G (t − piece)).
  void restart() {
    const Q d = t - piece;
    for (const auto& [delta, e] : cache) {
      const Q j = d / delta;
      if (j <= 0 || boost::multiprecision::denominator(j) != 1 || j > Q(1L << 40)) continue;
      boost::multiprecision::mpz_int left = boost::multiprecision::numerator(j);
      auto& pw = powers[delta];
      if (pw.empty()) {
        pw.push_back(std::make_unique<BallMat>(static_cast<slong>(nz), static_cast<slong>(nz)));
        arb_mat_set(pw[0]->m, e->m);
      }
      BallMat acc(static_cast<slong>(nz), 1), next(static_cast<slong>(nz), 1);
      arb_mat_set(acc.m, z_piece.m);
      for (std::size_t k = 0; left != 0; ++k, left >>= 1) {
        if (k == pw.size()) {
          pw.push_back(std::make_unique<BallMat>(static_cast<slong>(nz), static_cast<slong>(nz)));
          exp_of(*pw[k],
                 delta * Q(boost::multiprecision::mpz_int(1) << k));  // not by squaring: that widens geometrically too
        }
        if ((left & 1) != 0) {
          arb_mat_mul(next.m, pw[k]->m, acc.m, prec);
          arb_mat_swap(acc.m, next.m);
        }
      }
      arb_mat_swap(z.m, acc.m);
      return;
    }
    BallMat from(static_cast<slong>(nz), 1);  // at most 64 products from the anchor, by the shared binary powers
    arb_mat_set(from.m, z_piece.m);
    if (by_binary_powers(d, from)) {
      arb_mat_swap(z.m, from.m);
      return;
    }
    BallMat e(static_cast<slong>(nz), static_cast<slong>(nz));
    exp_of(e, d);
    arb_mat_mul(z.m, e.m, z_piece.m, prec);
  }

  std::optional<Q> next_corner(const Q& after) const {
    std::optional<Q> best;
    for (const io::Waveform& w : data.waveforms) {
      const std::optional<Q> c = w.next_corner(after);
      if (c && (!best || *c < *best)) best = c;
    }
    return best;
  }

  /// At the corner t of the sources whose next corner after `before` it is: σ is continuous (a ramp's
  /// corner, a sine's start at TD), σ' jumps, so σ'' carries a Dirac delta of weight Δσ' and y jumps by
  /// A_u's σ'' column times it.  A σ''' column would carry δ' (not a function): refused, as simulate does.
  void cross_corner(const Q& before) {
    arb_mat_set(z_left.m, z.m);
    const auto unbalanced_exo = [&](BallMat& exo) {
      for (std::size_t i = 0; i < 1 + 3 * m; ++i) {
        Ball d;
        set_q(d.v, dual[dm + i], prec);
        arb_mul(exo.at(static_cast<slong>(i), 0), z.at(static_cast<slong>(dm + i), 0), d.v, prec);
      }
    };
    BallMat exo_b(static_cast<slong>(1 + 3 * m), 1), exo_a(static_cast<slong>(1 + 3 * m), 1),
        ub(static_cast<slong>(nu), 1), ua(static_cast<slong>(nu), 1);
    unbalanced_exo(exo_b);  // the left exosystem state is the flow's own
    reset_exo(t);
    unbalanced_exo(exo_a);
    arb_mat_mul(ub.m, wout.m, exo_b.m, prec);
    arb_mat_mul(ua.m, wout.m, exo_a.m, prec);
    for (std::size_t j = 0; j < m; ++j) {
      const std::optional<Q> own = data.waveforms[j].next_corner(before);
      if (!own || *own != t) continue;
      for (long d = 3; d <= data.orders; ++d)
        for (std::size_t i = 0; i < dm; ++i)
          if (data.au(static_cast<reference::Index>(i),
                      static_cast<reference::Index>(1 + static_cast<std::size_t>(d) * m + j)) != 0)
            throw std::invalid_argument(data.waveforms[j].element +
                                        " has corners and the motion needs its derivative of order " +
                                        std::to_string(d) + " (a derivative of a Dirac delta)");
      if (data.orders < 2) continue;
      Ball jump;
      arb_sub(jump.v, ua.at(static_cast<slong>(1 + m + j), 0), ub.at(static_cast<slong>(1 + m + j), 0), prec);
      const reference::Index col = static_cast<reference::Index>(1 + 2 * m + j);
      for (std::size_t i = 0; i < dm; ++i) {
        if (data.au(static_cast<reference::Index>(i), col) == 0) continue;
        Ball c, dd;
        set_q(c.v, data.au(static_cast<reference::Index>(i), col), prec);
        set_q(dd.v, dual[i], prec);
        arb_mul(c.v, c.v, jump.v, prec);
        arb_div(c.v, c.v, dd.v, prec);
        arb_add(z.at(static_cast<slong>(i), 0), z.at(static_cast<slong>(i), 0), c.v, prec);
      }
    }
    arb_mat_set(z_piece.m, z.m);
    piece = t;
    anchored = false;
    corner = true;
  }
};

namespace {

/// σ ≡ 0: every value the waveform takes is 0 (its levels, amplitudes and points).
bool identically_zero(const io::Waveform& w) {
  switch (w.kind) {
    case io::Waveform::Kind::dc: return w.p[0] == 0;
    case io::Waveform::Kind::pwl:
      for (std::size_t i = 1; i < w.p.size(); i += 2)
        if (w.p[i] != 0) return false;
      return true;
    default: return w.p.size() >= 2 && w.p[0] == 0 && w.p[1] == 0;  // SIN, SFFM (VO, VA); PULSE, EXP (V1, V2)
  }
}

/// Whether the motion is identically 0, decided exactly: y' = A_y y + A_u u, x = X0 u + Bᵀ y,
/// ẋ = V_y y + V_u u with u = (1, σ, σ', …) = (1, 0, 0, …) when every source is identically 0, so y ≡ 0
/// (the linear equation's unique solution from y(0) = 0 when A_u's constant column is 0) and x ≡ ẋ ≡ 0
/// when X0's and V_u's constant columns are 0 too.  Then every value is 0 with radius 0, not a ball
/// of rounding around it (dcad check: "a vector that is exactly 0 and found exactly 0 agrees").
bool zero_motion(const ForcedMotionData& data, const std::vector<Q>& y0) {
  for (const Q& v : y0)
    if (v != 0) return false;
  for (const io::Waveform& w : data.waveforms)
    if (!identically_zero(w)) return false;
  for (const QM* m : {&data.x0, &data.au, &data.vu})
    for (reference::Index i = 0; i < m->rows(); ++i)
      if (m->cols() > 0 && (*m)(i, 0) != 0) return false;
  return true;
}

/// The sources whose exosystem the enclosure carries; throws std::invalid_argument naming the one it does not.
void require_enclosable(const std::vector<io::Waveform>& waveforms) {
  for (const io::Waveform& w : waveforms) {
    if (w.kind == io::Waveform::Kind::pulse && (w.p[3] <= 0 || w.p[4] <= 0))
      throw std::invalid_argument(w.element + ": a PULSE with TR or TF = 0 jumps; its enclosure is not built");
    if (const auto t = w.step_at())
      throw std::invalid_argument(w.element + ": a step at t = " + t->str() + " s; its enclosure is not built");
    if (w.is_sffm())
      throw std::invalid_argument(
          w.element + ": an SFFM source (frequency modulated: no finite exosystem); its enclosure is not built");
    if (w.is_exp() && w.period > 0)
      throw std::invalid_argument(w.element + ": a periodic EXP (gnucap's period=); its enclosure is not built");
    if (w.is_exp() && (w.p[3] == 0 || w.p[5] == 0))  // validate() refuses it before: a step, no exosystem
      throw std::invalid_argument(w.element + ": an EXP with TAU1 or TAU2 = 0 (a step); its enclosure is not built");
    if (w.is_sine() && w.p[2] == 0)
      throw std::invalid_argument(
          w.element +
          ": a SIN with FREQ = 0 (ngspice reads it as 1/TSTOP, dcad as a constant); its enclosure is not built");
  }
}

/// The exosystem of the sources: its generator S (a constant, and per source a rotation with decay for SIN, two
/// decays for EXP, a ramp for PWL/PULSE pieces) and W, the map from its state to u_ext = (1, σ, σ', …) —
/// exo_output/exo_generator in simulate, in balls.
void build_exosystem(const ForcedMotionData& data, std::size_t m, slong p, BallMat& wout, BallMat& sgen) {
  arb_one(wout.at(0, 0));
  for (std::size_t j = 0; j < m; ++j) {
    const io::Waveform& w = data.waveforms[j];
    const slong c = static_cast<slong>(1 + 3 * j);
    if (w.is_sine()) {
      Ball om, dec;
      arb_const_pi(om.v, p);
      Ball f;
      set_q(f.v, 2 * w.p[2], p);
      arb_mul(om.v, om.v, f.v, p);
      set_q(dec.v, -w.p[4], p);
      arb_set(sgen.at(c + 1, c + 1), dec.v);
      arb_set(sgen.at(c + 2, c + 2), dec.v);
      arb_neg(sgen.at(c + 1, c + 2), om.v);
      arb_set(sgen.at(c + 2, c + 1), om.v);
      BallMat mm(2, 2), pw(2, 2), tmp(2, 2);
      arb_set(mm.at(0, 0), dec.v), arb_neg(mm.at(0, 1), om.v), arb_set(mm.at(1, 0), om.v), arb_set(mm.at(1, 1), dec.v);
      arb_mat_one(pw.m);
      for (long d = 0; d <= data.orders; ++d) {
        const slong row = static_cast<slong>(1 + static_cast<std::size_t>(d) * m + j);
        if (d == 0) arb_one(wout.at(row, c));
        arb_set(wout.at(row, c + 1), pw.at(1, 0));
        arb_set(wout.at(row, c + 2), pw.at(1, 1));
        arb_mat_mul(tmp.m, mm.m, pw.m, p);
        arb_mat_swap(pw.m, tmp.m);
      }
    } else if (w.is_exp()) {  // (c, e1, e2) with ė_k = −e_k / TAU_k; σ = c + e1 + e2, σ^{(d)} = (−1/TAU1)^d e1 +
                              // (−1/TAU2)^d e2
      const Q r1 = -1 / w.p[3], r2 = -1 / w.p[5];
      set_q(sgen.at(c + 1, c + 1), r1, p);
      set_q(sgen.at(c + 2, c + 2), r2, p);
      Q p1 = 1, p2 = 1;
      for (long d = 0; d <= data.orders; ++d, p1 *= r1, p2 *= r2) {
        const slong row = static_cast<slong>(1 + static_cast<std::size_t>(d) * m + j);
        if (d == 0) arb_one(wout.at(row, c));
        set_q(wout.at(row, c + 1), p1, p);
        set_q(wout.at(row, c + 2), p2, p);
      }
    } else {
      arb_one(sgen.at(c, c + 1));
      arb_one(wout.at(static_cast<slong>(1 + j), c));
      if (data.orders >= 1) arb_one(wout.at(static_cast<slong>(1 + m + j), c + 1));
    }
  }
}

}  // namespace

MotionEnclosure::MotionEnclosure(const ForcedMotionData& data, const std::vector<Q>& y0, long precision)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.data = data;
  s.prec = precision;
  s.n = static_cast<std::size_t>(data.x0.rows());
  s.m = data.waveforms.size();
  s.dm = static_cast<std::size_t>(data.basis.rows());
  s.nz = s.dm + 1 + 3 * s.m;
  s.nu = 1 + s.m * static_cast<std::size_t>(data.orders + 1);
  if (y0.size() != s.dm || static_cast<std::size_t>(data.ay.rows()) != s.dm ||
      static_cast<std::size_t>(data.au.cols()) != s.nu || static_cast<std::size_t>(data.vu.cols()) != s.nu ||
      (!data.balance.empty() && data.balance.size() != s.nz))
    throw std::invalid_argument("MotionEnclosure: inconsistent shapes");
  require_enclosable(data.waveforms);
  s.zero = zero_motion(data, y0);
  s.dual.resize(s.nz, Q(1));
  for (std::size_t i = 0; i < data.balance.size(); ++i) s.dual[i] = rational_of(data.balance[i]);
  const slong p = s.prec, nz = static_cast<slong>(s.nz), dm = static_cast<slong>(s.dm), nu = static_cast<slong>(s.nu);
  s.reset(s.x0, data.x0.rows(), data.x0.cols());
  set_qm(s.x0, data.x0, p);
  s.reset(s.bt, data.basis.cols(), data.basis.rows());
  set_qm(s.bt, data.basis.transpose(), p);
  s.reset(s.vy, data.vy.rows(), data.vy.cols());
  set_qm(s.vy, data.vy, p);
  s.reset(s.vu, data.vu.rows(), data.vu.cols());
  set_qm(s.vu, data.vu, p);
  // W (exosystem → u_ext) and the exosystem's generator S, as exo_output/exo_generator in simulate
  s.reset(s.wout, nu, static_cast<slong>(1 + 3 * s.m));
  BallMat sgen(static_cast<slong>(1 + 3 * s.m), static_cast<slong>(1 + 3 * s.m));
  build_exosystem(data, s.m, p, s.wout, sgen);
  const std::size_t m = s.m;
  // G = [[A_y, A_u W], [0, S]], balanced: D⁻¹ G D
  s.reset(s.g, nz, nz);
  BallMat ay(dm, dm), au(dm, nu), auw(dm, static_cast<slong>(1 + 3 * m));
  set_qm(ay, data.ay, p);
  set_qm(au, data.au, p);
  arb_mat_mul(auw.m, au.m, s.wout.m, p);
  for (slong i = 0; i < nz; ++i)
    for (slong j = 0; j < nz; ++j) {
      arb_ptr e = s.g.at(i, j);
      if (i < dm)
        arb_set(e, j < dm ? arb_mat_entry(ay.m, i, j) : arb_mat_entry(auw.m, i, j - dm));
      else if (j >= dm)
        arb_set(e, arb_mat_entry(sgen.m, i - dm, j - dm));
      Ball r;
      set_q(r.v, s.dual[static_cast<std::size_t>(j)] / s.dual[static_cast<std::size_t>(i)], p);
      arb_mul(e, e, r.v, p);
    }
  s.reset(s.z, nz, 1);
  s.reset(s.z_left, nz, 1);
  s.reset(s.z_piece, nz, 1);
  for (std::size_t i = 0; i < s.dm; ++i) set_q(s.z.at(static_cast<slong>(i), 0), y0[i] / s.dual[i], p);
  s.reset_exo(Q(0));
  arb_mat_set(s.z_piece.m, s.z.m);
  // the left limit at t = 0: the sources held at their value at 0 (σ' = σ'' = … = 0), as before a transient
  arb_mat_set(s.z_left.m, s.z.m);
  BallMat w(static_cast<slong>(1 + 3 * s.m), 1), u(nu, 1);
  for (std::size_t i = 0; i < 1 + 3 * s.m; ++i) {
    Ball d;
    set_q(d.v, s.dual[s.dm + i], p);
    arb_mul(w.at(static_cast<slong>(i), 0), s.z.at(static_cast<slong>(s.dm + i), 0), d.v, p);
  }
  arb_mat_mul(u.m, s.wout.m, w.m, p);
  for (std::size_t j = 0; j < s.m; ++j) {
    const slong c = static_cast<slong>(s.dm + 1 + 3 * j);
    Ball d;
    set_q(d.v, s.dual[static_cast<std::size_t>(c)], p);
    arb_div(s.z_left.at(c, 0), u.at(static_cast<slong>(1 + j), 0), d.v, p);
    arb_zero(s.z_left.at(c + 1, 0));
    arb_zero(s.z_left.at(c + 2, 0));
  }
  s.corner = true;
}

MotionEnclosure::~MotionEnclosure() = default;

void MotionEnclosure::advance_to(const Q& to) {
  Impl& s = *impl_;
  if (to < s.t) throw std::invalid_argument("MotionEnclosure::advance_to: time runs forward only");
  if (to == s.t) return;
  s.corner = false;
  while (true) {
    const std::optional<Q> c = s.next_corner(s.t);
    if (!c || *c > to) break;
    const Q before = s.t;
    s.flow_to(*c);
    s.refresh();
    s.cross_corner(before);
  }
  if (to > s.t) {
    s.flow_to(to);
    s.corner = false;
  }
  if (!s.corner) arb_mat_set(s.z_left.m, s.z.m);
}

const Q& MotionEnclosure::time() const { return impl_->t; }
bool MotionEnclosure::at_corner() const { return impl_->corner; }
long MotionEnclosure::restarts() const { return impl_->restarts; }
long MotionEnclosure::exponentials() const { return impl_->exps; }

std::vector<Q> MotionEnclosure::corners(const Q& until, std::size_t limit) const {
  std::vector<Q> out;
  Q at = 0;
  while (out.size() < limit) {
    const std::optional<Q> c = impl_->next_corner(at);
    if (!c || *c > until) break;
    out.push_back(*c);
    at = *c;
  }
  return out;
}

std::vector<Enclosure> MotionEnclosure::evaluate(const std::vector<Functional>& fs, bool left) const {
  const Impl& s = *impl_;
  const auto constant = [](const Functional& f) {
    return std::any_of(f.terms.begin(), f.terms.end(),
                       [](const Functional::Term& t) { return t.of == Functional::Of::u && t.index == 0; });
  };
  const auto in_range = [&](const Functional& f) {
    return std::all_of(f.terms.begin(), f.terms.end(),
                       [&](const Functional::Term& t) { return t.index < (t.of == Functional::Of::u ? s.nu : s.n); });
  };
  if (s.zero && std::none_of(fs.begin(), fs.end(), constant) && std::all_of(fs.begin(), fs.end(), in_range))
    return std::vector<Enclosure>(fs.size(), Enclosure{0, 0});  // (out of range: the general path throws)
  const slong p = s.prec, dm = static_cast<slong>(s.dm), nz = static_cast<slong>(s.nz), n = static_cast<slong>(s.n);
  const BallMat& zb = left && s.corner ? s.z_left : s.z;
  BallMat y(dm, 1), w(static_cast<slong>(1 + 3 * s.m), 1), u(static_cast<slong>(s.nu), 1), x(n, 1), xd(n, 1), tmp(n, 1);
  for (slong i = 0; i < nz; ++i) {
    Ball d;
    set_q(d.v, s.dual[static_cast<std::size_t>(i)], p);
    arb_ptr dst = i < dm ? y.at(i, 0) : w.at(i - dm, 0);
    arb_mul(dst, arb_mat_entry(zb.m, i, 0), d.v, p);
  }
  arb_mat_mul(u.m, s.wout.m, w.m, p);
  // x = X0 u + Bᵀ y (u: the first columns of u_ext), ẋ = V_y y + V_u u_ext
  BallMat uh(s.x0.cols(), 1);
  for (slong i = 0; i < s.x0.cols(); ++i) arb_set(uh.at(i, 0), u.at(i, 0));
  arb_mat_mul(x.m, s.x0.m, uh.m, p);
  arb_mat_mul(tmp.m, s.bt.m, y.m, p);
  arb_mat_add(x.m, x.m, tmp.m, p);
  arb_mat_mul(xd.m, s.vy.m, y.m, p);
  arb_mat_mul(tmp.m, s.vu.m, u.m, p);
  arb_mat_add(xd.m, xd.m, tmp.m, p);
  std::vector<Enclosure> out;
  out.reserve(fs.size());
  for (const Functional& f : fs) {
    Ball acc, c;
    for (const Functional::Term& term : f.terms) {
      set_q(c.v, term.coef, p);
      const BallMat& src = term.of == Functional::Of::x ? x : term.of == Functional::Of::xdot ? xd : u;
      if (static_cast<slong>(term.index) >= src.rows())
        throw std::invalid_argument("MotionEnclosure::evaluate: index out of range");
      arb_addmul(acc.v, c.v, arb_mat_entry(src.m, static_cast<slong>(term.index), 0), p);
    }
    out.push_back(enclosure_of(acc.v));
  }
  return out;
}

std::vector<Enclosure> MotionEnclosure::state(bool left) const {
  std::vector<Functional> fs(impl_->n);
  for (std::size_t i = 0; i < impl_->n; ++i) fs[i].terms.push_back({Functional::Of::x, i, Q(1)});
  return evaluate(fs, left);
}

}  // namespace dcad::certified
