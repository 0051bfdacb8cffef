// fast::solve: each input form dispatched once, to the fast twin's route.
#include "dcad/fast/pointwise.hpp"
#include "dcad/fast/solve.hpp"

namespace dcad::fast {

Solution solve_linear(const io::CaseFile& c, const Parts& parts, const Options& options);
Solution solve_forced_netlist(const io::Netlist& deck, const std::vector<std::string>& variables,
                              const Options& options);
Solution solve_forced_case(const io::CaseFile& c, const Options& options);
Solution solve_dae(const io::DaeCase& c, const Options& options);

Solution solve(const io::Problem& p, const Parts& parts, const Options& opt) {
  io::validate(p);
  Solution s;
  if (p.form() == io::Form::expression) {
    s = solve_expression(p.expression(), opt);
  } else if (p.form() == io::Form::implicit) {
    s = solve_implicit(p.expression(), opt);
  } else if (p.form() == io::Form::dae) {
    s = solve_dae(p.dae(), opt);
  } else if (p.form() == io::Form::netlist) {
    s = p.netlist().forced ? solve_forced_netlist(p.netlist(), p.linear().variables, opt)
                           : solve_lc(p.netlist(), p.linear(), parts, opt);
    s.circuit = io::circuit_facts(p.netlist());
  } else {
    const io::CaseFile& c = p.linear();
    s = io::at_input(c, [&] {
      return c.has_pontryagin && c.pontryagin.has_forces ? solve_forced_case(c, opt) : solve_linear(c, parts, opt);
    });
  }
  if (p.form() == io::Form::netlist &&
      !p.netlist().rounded.empty()) {  // irrational values: exact only for the rounded deck
    s.certified = unknown;
    s.note += (s.note.empty() ? "" : "; ") + io::rounded_note(p.netlist());
  }
  s.backend = Backend::fast;
  uncertain_exact_entries(s);
  s.warnings = p.warnings();
  keep_parts(s, parts);
  return s;
}

}  // namespace dcad::fast
