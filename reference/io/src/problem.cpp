#include "dcad/io/problem.hpp"

#include "forms.hpp"
#include "json_input.hpp"

namespace dcad::io {

std::vector<std::string> Problem::variables() const {
  return form == Form::expression || form == Form::implicit ? expression.system.state_names() : form == Form::dae ? dae.variables : linear.variables;
}

std::string Problem::name() const {
  return form == Form::expression || form == Form::implicit ? expression.name : form == Form::dae ? dae.name : form == Form::netlist ? netlist.title : linear.name;
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

Problem read_problem(const std::string& file) {
  if (is_netlist_file(file)) return from_netlist(read_netlist(file));
  return from_json(read_json_file(file), file);
}

Problem parse_netlist(const std::string& text, const std::string& name, const std::string& directory) {
  return from_netlist(read_netlist_text(text, name, directory));
}

Problem parse_case(const std::string& text, const std::string& name) { return from_json(parse_json_exact(text, name), name); }

}  // namespace dcad::io
