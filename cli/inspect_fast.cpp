#include "dcad/fast/dirac.hpp"
#include "convert_fast.hpp"
#include "inspect.hpp"

namespace fast = dcad::fast;

namespace dcad::cli {

namespace {

void note(InspectReport& r, const std::string& what, bool certain, const std::string& evidence) {
  if (certain) return;
  r.certified = false;
  r.uncertain.push_back(what);
  if (!evidence.empty()) r.evidence.push_back(what + ": " + evidence);
}

}  // namespace

InspectReport inspect_fast(const io::CaseFile& c) {
  namespace fa = dcad::fast;
  InspectReport r;
  r.backend = "fast";
  r.n = c.n;
  r.form = c.dirac.form;
  fa::Options opt;
  const io::DiracInput& in = c.dirac;
  const fa::DiracStructure d = fast_dirac(in, opt);
  const fa::DiracCheck check = fa::dirac_defect(d, opt);
  r.valid = check.valid.value;
  r.why = check.why;
  note(r, "valid", check.valid.certain, d.d.evidence().describe());
  if (!r.valid) return r;
  const fa::PresymplecticForm w = fa::dirac_form(d, opt);
  r.dim_e = w.space.dim();
  note(r, "dim_E_D", w.space.certain(), w.space.evidence().describe());
  const fa::RankDecision rk = fa::form_rank(w, opt);
  r.rank_omega = rk.rank;
  note(r, "rank_omega_D", rk.certain, rk.describe());
  const fa::Subspace ker = fa::form_kernel(w, opt);
  r.dim_ker_omega = ker.dim();
  note(r, "dim_ker_omega_D", ker.certain(), "");
  const fa::Answer pre = fa::is_presymplectic(d, opt), poi = fa::is_poisson(d, opt);
  r.presymplectic = pre.value;
  r.poisson = poi.value;
  note(r, "presymplectic", pre.certain, "");
  note(r, "poisson", poi.certain, "");
  return r;
}

}  // namespace dcad::cli
