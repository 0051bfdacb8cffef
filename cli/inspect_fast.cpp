#include "dcad/fast/dirac.hpp"
#include "inspect.hpp"

namespace fast = dcad::fast;

namespace dcad::cli {

namespace {

/// Rounds an exact input matrix to double and records in `opt` whether that was exact and whether
/// the data is well scaled (fast::Options: both are hypotheses of a certain rank deficiency).
Eigen::MatrixXd to_double(const io::QMatrix& m, fast::Options& opt) {
  Eigen::MatrixXd d(m.rows(), m.cols());
  for (std::size_t i = 0; i < m.rows(); ++i)
    for (std::size_t k = 0; k < m.cols(); ++k) {
      d(i, k) = m(i, k).convert_to<double>();
      if (io::Rational(d(i, k)) != m(i, k)) opt.input_exact = false;
    }
  fast::assess_input(d, opt);
  return d;
}

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
  fa::DiracStructure d;
  if (in.form == "presymplectic") {
    d = fa::dirac_from_presymplectic(to_double(in.w, opt));
  } else if (in.form == "distribution") {
    const Eigen::MatrixXd b = to_double(in.b, opt), w = to_double(in.w, opt);
    d = fa::dirac_from_distribution(fa::Subspace::span(b.transpose(), -1, opt), w);
  } else if (in.form == "poisson") {
    d = fa::dirac_from_poisson(to_double(in.p, opt));
  } else {
    const Eigen::MatrixXd g = to_double(in.g, opt);
    d = {static_cast<int>(g.cols() / 2), fa::Subspace::span(g.transpose(), -1, opt)};
  }
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
