#include "inspect.hpp"

#include <sstream>

namespace dcad::cli {

nlohmann::json to_json(const InspectReport& r) {
  nlohmann::json j = {{"dcad", 1}, {"backend", r.backend}, {"certified", r.certified}, {"n", r.n},
                      {"form", r.form}, {"valid", r.valid}};
  if (!r.valid) {
    j["why"] = r.why;
    return j;
  }
  j["dim_E_D"] = r.dim_e;
  j["rank_omega_D"] = r.rank_omega;
  j["dim_ker_omega_D"] = r.dim_ker_omega;
  j["presymplectic"] = r.presymplectic;
  j["poisson"] = r.poisson;
  if (!r.uncertain.empty()) {
    j["uncertain"] = r.uncertain;
    j["evidence"] = r.evidence;
  }
  return j;
}

std::string to_text(const InspectReport& r, const io::CaseFile& c) {
  std::ostringstream o;
  const auto yes = [](bool b) { return b ? "yes" : "no"; };
  o << c.file << (c.name.empty() ? "" : " (" + c.name + ")") << ": D on R^" << r.n << " given as `" << r.form
    << "`, backend " << r.backend << "\n";
  o << "  Dirac structure (CEF Lemma 4.1): " << yes(r.valid) << (r.valid ? "" : " -- " + r.why) << "\n";
  if (r.valid) {
    o << "  dim E_D          = " << r.dim_e << "\n";
    o << "  rank omega_D     = " << r.rank_omega << "\n";
    o << "  dim ker omega_D  = " << r.dim_ker_omega << "\n";
    o << "  from a presymplectic form (E_D = R^" << r.n << "): " << yes(r.presymplectic) << "\n";
    o << "  from a Poisson bivector (D meets V+0 in 0): " << yes(r.poisson) << "\n";
  }
  o << "  certified: " << yes(r.certified) << "\n";
  for (const std::string& e : r.evidence) o << "  uncertain " << e << "\n";
  return o.str();
}

}  // namespace dcad::cli
