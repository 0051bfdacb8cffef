#include "dcad/io/problem.hpp"

#include "forms.hpp"
#include "json_input.hpp"

#include <cctype>
#include <fstream>

namespace dcad::io {

std::vector<std::string> Problem::variables() const {
  return form == Form::expression || form == Form::implicit ? expression.system.state_names()
         : form == Form::dae                                ? dae.variables
                                                            : linear.variables;
}

std::string Problem::name() const {
  return form == Form::expression || form == Form::implicit ? expression.name
         : form == Form::dae                                ? dae.name
         : form == Form::netlist                            ? netlist.title
                                                            : linear.name;
}

namespace {

Problem from_json(const nlohmann::json& j, const std::string& file) {
  Problem p;
  p.file = file;
  if (is_dae_case(j)) {
    p.form = Form::dae;
    p.dae = read_dae_case(j, file);
  } else if (is_implicit_case(j)) {
    p.form = Form::implicit;
    p.expression = read_implicit_case(j, file);
  } else if (is_expression_case(j)) {
    p.form = Form::expression;
    p.expression = read_lagrangian_case(j, file);
  } else {
    p.form = Form::linear;
    p.linear = read_case(j, file);
  }
  return p;
}

Problem from_netlist(Netlist deck) {
  Problem p;
  p.form = Form::netlist;
  p.file = deck.file;
  p.linear = netlist_case(deck, false);  // the names; a route that needs the dense system builds it
  p.netlist = std::move(deck);
  return p;
}

}  // namespace

namespace {
/// A case file is JSON: its first character that is not white space is '{' (or the file is named .json);
/// anything else is read as a deck (.hspice, .pspice, .deck, .gc … as the SPICEs' own tests name them).
bool looks_like_json_case(const std::string& file) {
  const std::string json = ".json";
  if (file.size() >= json.size() && file.compare(file.size() - json.size(), json.size(), json) == 0) return true;
  std::ifstream in(file, std::ios::binary);
  if (!in) return true;  // the JSON reader names the file it cannot open
  for (char ch; in.get(ch);)
    if (!std::isspace(static_cast<unsigned char>(ch))) return ch == '{';
  return true;
}
}  // namespace

Problem problem(CaseFile c) {
  Problem p;
  p.form = Form::linear;
  p.file = c.file;
  p.linear = std::move(c);
  return p;
}

Problem problem(const reference::LinearSystem<Rational>& s, std::vector<std::string> variables, std::string name) {
  CaseFile c;
  c.name = std::move(name);
  c.n = s.d.n;
  if (variables.empty())
    for (std::size_t i = 0; i < c.n; ++i) variables.push_back("x" + std::to_string(i + 1));
  c.variables = std::move(variables);
  c.has_dirac = true;
  c.dirac.form = "basis";
  c.dirac.path = "LinearSystem::d";
  c.dirac.g = s.d.d.basis();
  c.energy = {s.hessian, s.gradient, s.constant};
  return problem(std::move(c));
}

Problem problem(DaeCase c) {
  if (c.f.empty()) c.f.assign(c.equations(), reference::expr::number(Rational(0)));
  if (c.initial.empty()) c.initial.assign(c.variables.size(), std::nullopt);
  Problem p;
  p.form = Form::dae;
  p.file = c.file;
  p.dae = std::move(c);
  return p;
}

Problem problem(LagrangianCase c) {
  Problem p;
  p.form = c.system.implicit ? Form::implicit : Form::expression;
  p.file = c.file;
  p.expression = std::move(c);
  return p;
}

Problem read_problem(const std::string& file, const ReadOptions& options) {
  if (is_netlist_file(file) || !looks_like_json_case(file)) return from_netlist(read_netlist(file, options));
  return from_json(read_json_file(file), file);
}

Problem parse_netlist(const std::string& text, const std::string& name, const std::string& directory,
                      const ReadOptions& options) {
  return from_netlist(read_netlist_text(text, name, directory, options));
}

Problem parse_case(const std::string& text, const std::string& name) {
  return from_json(parse_json_exact(text, name), name);
}

}  // namespace dcad::io
