// The only translation unit of the CLI that instantiates the reference on mpq_rational.
#include "dcad/reference/dirac.hpp"
#include "inspect.hpp"

namespace dcad::cli {

namespace ref = dcad::reference;
using Q = ref::Rational;

ref::DiracStructure<Q> reference_dirac(const io::DiracInput& d) {
  if (d.form == "presymplectic") return ref::dirac_from_presymplectic(d.w);
  if (d.form == "distribution") return ref::dirac_from_distribution(ref::Subspace<Q>::span(d.b), d.w);
  if (d.form == "poisson") return ref::dirac_from_poisson(d.p);
  return {d.g.cols() / 2, ref::Subspace<Q>::span(d.g)};  // `basis`: validated by the caller
}

InspectReport inspect_reference(const io::CaseFile& c) {
  InspectReport r;
  r.backend = "reference";
  r.n = c.n;
  r.form = c.dirac.form;
  const ref::DiracStructure<Q> d = reference_dirac(c.dirac);
  r.why = ref::dirac_defect(d);
  r.valid = r.why.empty();
  if (!r.valid) return r;
  const ref::PresymplecticForm<Q> w = ref::dirac_form(d);
  r.dim_e = static_cast<long>(w.space.dim());
  r.rank_omega = static_cast<long>(ref::form_rank(w));
  r.dim_ker_omega = static_cast<long>(ref::form_kernel(w).dim());
  r.presymplectic = ref::is_presymplectic(d);
  r.poisson = ref::is_poisson(d);
  return r;
}

}  // namespace dcad::cli
