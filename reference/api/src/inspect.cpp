// dcad::api::inspect: the `dirac` case's structure by the twin asked for.
#include "dcad/api.hpp"

namespace dcad::api {

Inspection inspect(const io::Problem& p, Backend backend) {
  io::validate(p);
  if (p.form() == io::Form::expression)
    throw io::InputError(p.file +
                         ": /lagrangian: expected a linear case (dirac, pontryagin or constrained) here; the "
                         "expression form is taken by "
                         "solve, check and simulate, found the expression form");
  if (p.form() == io::Form::implicit)
    throw io::InputError(p.file +
                         ": /implicit: expected a case file with a `dirac` member for inspect, found the implicit form "
                         "(taken by solve, check and simulate)");
  if (p.form() == io::Form::dae)
    throw io::InputError(p.file +
                         ": /dae: expected a case file with a `dirac` member for inspect, found the dae form (taken by "
                         "solve and check)");
  if (p.form() == io::Form::netlist)
    throw io::InputError(p.file + ": expected a case file with a `dirac` member for inspect, found a netlist");
  const io::CaseFile& c = p.linear();
  if (!c.has_dirac)
    throw io::InputError(p.file + ": /dirac: expected a `dirac` member for inspect, found a " +
                         (c.has_pontryagin ? "`pontryagin`" : "`constrained`") + " case");
  try {
    return backend == Backend::fast ? fast::inspect(c) : reference::inspect(c);
  } catch (const io::InputError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    throw io::InputError(p.file + ": " + c.dirac.path + ": " + e.what());
  }
}

}  // namespace dcad::api
