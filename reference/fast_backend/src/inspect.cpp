// fast::inspect: what a `dirac` case's structure is (CEF §4), in double with each decision's verdict.
#include "dcad/fast/dirac.hpp"
#include "dcad/fast/exact.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/reference/solve.hpp"

#include <sstream>

namespace dcad::fast {

namespace {

void note(Inspection& r, const std::string& what, Truth certain, const std::string& evidence) {
  if (certain.yes()) return;
  r.certified = unknown;
  r.uncertain.push_back(what);
  if (!evidence.empty()) r.evidence.push_back(what + ": " + evidence);
}

/// The answers a rank decision can change, as text.
std::string answers(const Inspection& r) {
  std::ostringstream o;
  o << (r.valid ? "valid" : "not valid");
  if (r.valid)
    o << ", dim E_D " << r.dim_e << ", rank omega_D " << r.rank_omega << ", dim ker omega_D " << r.dim_ker_omega
      << (r.presymplectic ? ", presymplectic" : "") << (r.poisson ? ", Poisson" : "");
  return o.str();
}

/// As fast::solve's (solve.cpp): a certain inspection rests on zeros decided in double, which the separation hypothesis
/// of fast/rank.hpp assumes and integer data of height 10^6 break; the exact reference::inspect confirms it up to 2000
/// variables, and otherwise it is not certified.
void confirm(const io::CaseFile& c, Inspection& r) {
  if (!r.certified.yes()) return;
  std::string why;
  if (c.n > 2000) {
    why = "decided in double and not confirmed exactly beyond 2000 variables (--backend reference decides exactly)";
  } else {
    const Inspection e = reference::inspect(c);
    if (answers(e) == answers(r)) return;
    why = "the exact reference finds " + answers(e) + " where double found " + answers(r) +
          " (the separation hypothesis of dcad/fast/rank.hpp failed)";
  }
  r.certified = unknown;
  r.uncertain.push_back("confirmation");
  r.evidence.push_back("confirmation: " + why);
}

}  // namespace

Inspection inspect(const io::CaseFile& c, const Options& options) {
  namespace fa = dcad::fast;
  Inspection r;
  r.backend = Backend::fast;
  r.certified = yes;  // until a decision below is not certain (note)
  r.file = c.file;
  r.name = c.name;
  r.n = c.n;
  r.form = c.dirac.form;
  fa::Options opt = options;
  const io::DiracInput& in = c.dirac;
  const fa::DiracStructure d = fast::to_fast(in, opt);
  const fa::DiracCheck check = fa::dirac_defect(d, opt);
  r.valid = check.valid.yes() || (check.valid.unknown() && check.why.empty());  // the likely answer when unknown
  r.why = check.why;
  note(r, "valid", check.valid.known() ? yes : unknown, d.d.evidence().describe());
  if (!r.valid) {
    if (opt.confirm_exactly) confirm(c, r);
    return r;
  }
  const fa::PresymplecticForm w = fa::dirac_form(d, opt);
  r.dim_e = w.space.dim();
  note(r, "dim_E_D", w.space.certain(), w.space.evidence().describe());
  const fa::RankDecision rk = fa::form_rank(w, opt);
  r.rank_omega = rk.rank;
  note(r, "rank_omega_D", rk.certain, rk.describe());
  const fa::Subspace ker = fa::form_kernel(w, opt);
  r.dim_ker_omega = ker.dim();
  note(r, "dim_ker_omega_D", ker.certain(), "");
  const Truth pre = fa::is_presymplectic(d, opt), poi = fa::is_poisson(d, opt);
  // the likely answers where a verdict is unknown: from the dimensions decided
  r.presymplectic = pre.known() ? pre.value() : r.dim_e == static_cast<long>(c.n);
  r.poisson = poi.known() ? poi.value() : fa::Subspace::span_columns(d.alpha_part(), 1.0, opt).dim() == d.n;
  note(r, "presymplectic", pre.known() ? yes : unknown, "");
  note(r, "poisson", poi.known() ? yes : unknown, "");
  if (opt.confirm_exactly) confirm(c, r);
  return r;
}

}  // namespace dcad::fast
