// Arb's balls (libflint-arb-dev 2.23, LGPL) in place of Ball, measured on the sweep (issue 26).
// The same contract as Ball: a zero test answers only when every number of the ball agrees, and input
// numbers keep an exact shadow (fmpq) for the tests intervals cannot settle (ω_ij == −ω_ji at 1/3);
// otherwise Uncertain, and the run is recomputed exactly (fmpq).  Precision 53 bits, as Ball.
#include "ball.hpp"
#include "dcad/reference/fmpq.hpp"
#include "method_generic.hpp"

#include <arb.h>

#include <memory>

namespace dcad::bench {
namespace {

constexpr slong kPrec = 53;

class ArbBall {
 public:
  static constexpr const char* zero_test = "certified (Arb ball), or throws Uncertain";
  ArbBall() { arb_init(v_); }
  ArbBall(int k) {  // NOLINT: the algorithms write T(0), T(1)
    arb_init(v_);
    arb_set_si(v_, k);
  }
  ArbBall(const ArbBall& o) : shadow_(o.shadow_) {
    arb_init(v_);
    arb_set(v_, o.v_);
  }
  ArbBall& operator=(const ArbBall& o) {
    arb_set(v_, o.v_);
    shadow_ = o.shadow_;
    return *this;
  }
  ~ArbBall() { arb_clear(v_); }

  static ArbBall enclosing(const reference::Rational& q) {
    ArbBall b;
    const reference::Fmpq f = reference::Fmpq::from(q);
    arb_set_fmpq(b.v_, f.data(), kPrec);
    if (!arb_is_exact(b.v_)) b.shadow_ = std::make_shared<const reference::Fmpq>(f);
    return b;
  }
  double mid() const { return arf_get_d(arb_midref(v_), ARF_RND_NEAR); }

  ArbBall operator-() const {
    ArbBall b;
    arb_neg(b.v_, v_);
    if (shadow_) b.shadow_ = std::make_shared<const reference::Fmpq>(-*shadow_);
    return b;
  }
  friend ArbBall operator+(const ArbBall& a, const ArbBall& b) { return a.op(b, arb_add); }
  friend ArbBall operator-(const ArbBall& a, const ArbBall& b) { return a.op(b, arb_sub); }
  friend ArbBall operator*(const ArbBall& a, const ArbBall& b) { return a.op(b, arb_mul); }
  friend ArbBall operator/(const ArbBall& a, const ArbBall& b) {
    if (arb_contains_zero(b.v_)) throw Uncertain("division by an Arb ball that contains 0");
    return a.op(b, arb_div);
  }
  ArbBall& operator+=(const ArbBall& o) { return *this = *this + o; }
  ArbBall& operator-=(const ArbBall& o) { return *this = *this - o; }
  ArbBall& operator*=(const ArbBall& o) { return *this = *this * o; }
  ArbBall& operator/=(const ArbBall& o) { return *this = *this / o; }

  friend bool operator==(const ArbBall& a, const ArbBall& b) {
    const ArbBall d = a - b;
    if (arb_is_zero(d.v_)) return true;
    if (!arb_contains_zero(d.v_)) return false;
    if ((a.shadow_ || arb_is_exact(a.v_)) && (b.shadow_ || arb_is_exact(b.v_))) return a.exact() == b.exact();
    throw Uncertain("the Arb ball of a difference contains 0");
  }
  friend bool operator!=(const ArbBall& a, const ArbBall& b) { return !(a == b); }
  friend bool known_zero(const ArbBall& a) { return arb_is_zero(a.v_); }
  friend double pivot_weight(const ArbBall& a) { return arb_contains_zero(a.v_) ? 0.0 : std::abs(a.mid()); }

 private:
  template <class F>
  ArbBall op(const ArbBall& b, F f) const {
    ArbBall c;
    f(c.v_, v_, b.v_, kPrec);
    return c;
  }
  reference::Fmpq exact() const {  // only with a shadow or an exact ball
    if (shadow_) return *shadow_;
    reference::Fmpq q;
    arf_get_fmpq(q.data(), arb_midref(v_));
    return q;
  }
  arb_t v_;
  std::shared_ptr<const reference::Fmpq> shadow_;
};

template <class B>
Outcome run_balls(const families::Instance& in) {
  try {
    return run_generic<B>(
        in, [](const families::Q& q) { return B::enclosing(q); }, [](const B& b) { return b.mid(); });
  } catch (const Uncertain&) {
    Outcome o = run_fmpq(in);
    o.recomputed = true;
    return o;
  }
}

}  // namespace

Outcome run_arb(const families::Instance& in) { return run_balls<ArbBall>(in); }
Outcome run_ball(const families::Instance& in) { return run_balls<Ball>(in); }

}  // namespace dcad::bench
