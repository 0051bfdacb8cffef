// dcad::Truth — the one three-valued verdict of every decision the fast twin makes (FLINT's truth_t,
// CGAL's Uncertain<bool>): yes, no, or unknown.  A yes/no question that floating point may not settle
// (is this form nondegenerate? does this subspace contain that one? does a source condition hold?)
// answers a Truth; a computed object (a rank, a subspace, a tower) carries `Truth certain`: yes when
// every decision behind it was certain, unknown when one was not.
//
// Verdicts are combined by the operators below, written once (Kleene's strong three-valued logic),
// never by `&&` chains at the call sites, and a Truth never converts to bool silently: ask yes(),
// no() or unknown().  An unknown is a result ("don't know"), not an error.
#pragma once

#include <stdexcept>

namespace dcad {

class Truth {
 public:
  enum class Value : unsigned char { yes, no, unknown };
  /// No default (issue 47): every Truth says what it starts as — `= yes` where a certainty starts that later
  /// decisions may put in doubt, `= unknown` where nothing is proved yet.
  Truth() = delete;
  constexpr Truth(Value v) : v_(v) {}  // NOLINT: dcad::yes, dcad::no, dcad::unknown below
  /// A certain answer.
  static constexpr Truth of(bool b) { return Truth(b ? kYes : kNo); }
  /// The answer `guess` if `certain` is yes, else unknown.
  static constexpr Truth decided(bool guess, Truth certain) { return certain.yes() ? of(guess) : Truth(kUnknown); }

  constexpr bool yes() const { return v_ == kYes; }          ///< certainly true
  constexpr bool no() const { return v_ == kNo; }            ///< certainly false
  constexpr bool unknown() const { return v_ == kUnknown; }  ///< undecided
  constexpr bool known() const { return v_ != kUnknown; }
  /// The answer of a known Truth; std::logic_error on unknown (CGAL's make_certain): for callers that
  /// have already branched on unknown().
  bool value() const {
    if (v_ == kUnknown) throw std::logic_error("dcad::Truth::value: the answer is unknown");
    return v_ == kYes;
  }
  explicit operator bool() const = delete;  // never silently: yes(), no() or unknown()

  /// Both: no if either is no, yes if both are yes, else unknown.
  friend constexpr Truth operator&(Truth a, Truth b) {
    return a.no() || b.no() ? Truth(kNo) : a.yes() && b.yes() ? Truth(kYes) : Truth(kUnknown);
  }
  /// Either: yes if either is yes, no if both are no, else unknown.
  friend constexpr Truth operator|(Truth a, Truth b) {
    return a.yes() || b.yes() ? Truth(kYes) : a.no() && b.no() ? Truth(kNo) : Truth(kUnknown);
  }
  friend constexpr Truth operator!(Truth a) { return a.yes() ? Truth(kNo) : a.no() ? Truth(kYes) : Truth(kUnknown); }
  Truth& operator&=(Truth b) { return *this = *this & b; }
  Truth& operator|=(Truth b) { return *this = *this | b; }
  friend constexpr bool operator==(Truth a, Truth b) { return a.v_ == b.v_; }
  friend constexpr bool operator!=(Truth a, Truth b) { return a.v_ != b.v_; }

  /// "yes", "no" or "unknown".
  constexpr const char* text() const { return v_ == kYes ? "yes" : v_ == kNo ? "no" : "unknown"; }

 private:
  static constexpr Value kYes = Value::yes, kNo = Value::no, kUnknown = Value::unknown;
  Value v_ = kYes;
};

inline constexpr Truth yes{Truth::Value::yes};
inline constexpr Truth no{Truth::Value::no};
inline constexpr Truth unknown{Truth::Value::unknown};

// Kleene's strong tables, checked where they are written (every pair; an unknown on either side of &
// under a yes, or of | under a no, is unknown).
static_assert((yes & yes) == yes && (yes & no) == no && (no & yes) == no && (no & no) == no, "&: known");
static_assert((yes & unknown) == unknown && (unknown & yes) == unknown && (unknown & unknown) == unknown, "&: unknown");
static_assert((no & unknown) == no && (unknown & no) == no, "&: no decides");
static_assert((no | no) == no && (yes | no) == yes && (no | yes) == yes && (yes | yes) == yes, "|: known");
static_assert((no | unknown) == unknown && (unknown | no) == unknown && (unknown | unknown) == unknown, "|: unknown");
static_assert((yes | unknown) == yes && (unknown | yes) == yes, "|: yes decides");
static_assert((!yes) == no && (!no) == yes && (!unknown) == unknown, "!");
static_assert(Truth::decided(true, unknown) == unknown && Truth::decided(false, yes) == no, "decided");

}  // namespace dcad
