// reference::inspect: what a `dirac` case's structure is (CEF §4), exactly.
#include "dcad/reference/pipeline/linear.hpp"
#include "dcad/reference/solve.hpp"

namespace dcad::reference {

Inspection inspect(const io::CaseFile& c) {
  Inspection r;
  r.backend = Backend::reference;
  r.certified = yes;  // every decision exact
  r.file = c.file;
  r.name = c.name;
  r.n = c.n;
  r.form = c.dirac.form;
  const DiracStructure<Rational> d = pipeline::dirac_of<Rational>(c.dirac);
  r.why = dirac_defect(d);
  r.valid = r.why.empty();
  if (!r.valid) return r;
  const PresymplecticForm<Rational> w = dirac_form(d);
  r.dim_e = static_cast<long>(w.space.dim());
  r.rank_omega = static_cast<long>(form_rank(w));
  r.dim_ker_omega = static_cast<long>(form_kernel(w).dim());
  r.presymplectic = is_presymplectic(d);
  r.poisson = is_poisson(d);
  return r;
}

}  // namespace dcad::reference
