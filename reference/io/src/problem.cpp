#include "dcad/io/problem.hpp"

#include "forms.hpp"
#include "json_input.hpp"

#include <cctype>
#include <fstream>

namespace dcad::io {

static_assert(
    std::variant_size_v<decltype(Problem::input)> == 5 &&
        std::is_same_v<std::variant_alternative_t<static_cast<std::size_t>(Form::implicit), decltype(Problem::input)>,
                       ImplicitCase>,
    "Problem::input's alternatives are in Form's order");

namespace {
[[noreturn]] void wrong_form(const Problem& p, const char* wanted) {
  static const char* const names[] = {"linear", "netlist", "expression", "dae", "implicit"};
  throw std::logic_error(std::string("Problem::") + wanted + "(): the problem (" + p.file + ") is of the form " +
                         (p.input.valueless_by_exception() ? "none" : names[p.input.index()]));
}
template <class P>
auto& linear_of(P& p) {
  if (auto* c = std::get_if<CaseFile>(&p.input)) return *c;
  if (auto* c = std::get_if<CircuitCase>(&p.input)) return c->names;
  wrong_form(p, "linear");
}
template <class P>
auto& expression_of(P& p) {
  if (auto* c = std::get_if<ExpressionCase>(&p.input)) return c->c;
  if (auto* c = std::get_if<ImplicitCase>(&p.input)) return c->c;
  wrong_form(p, "expression");
}
template <class T, class P>
auto& alternative(P& p, const char* wanted) {
  if (auto* c = std::get_if<T>(&p.input)) return *c;
  wrong_form(p, wanted);
}
}  // namespace

const CaseFile& Problem::linear() const { return linear_of(*this); }
CaseFile& Problem::linear() { return linear_of(*this); }
const Netlist& Problem::netlist() const { return alternative<CircuitCase>(*this, "netlist").deck; }
Netlist& Problem::netlist() { return alternative<CircuitCase>(*this, "netlist").deck; }
const LagrangianCase& Problem::expression() const { return expression_of(*this); }
LagrangianCase& Problem::expression() { return expression_of(*this); }
const DaeCase& Problem::dae() const { return alternative<DaeCase>(*this, "dae"); }
DaeCase& Problem::dae() { return alternative<DaeCase>(*this, "dae"); }

const std::vector<std::string>& Problem::warnings() const {
  static const std::vector<std::string> none;
  if (form() == Form::expression || form() == Form::implicit) return expression().warnings;
  return form() == Form::netlist ? netlist().warnings : none;
}

std::vector<std::string> Problem::variables() const {
  return form() == Form::expression || form() == Form::implicit ? expression().system.state_names()
         : form() == Form::dae                                  ? dae().variables
                                                                : linear().variables;
}

std::string Problem::name() const {
  return form() == Form::expression || form() == Form::implicit ? expression().name
         : form() == Form::dae                                  ? dae().name
         : form() == Form::netlist                              ? netlist().title
                                                                : linear().name;
}

namespace {

Problem from_json(const nlohmann::json& j, const std::string& file) {
  Problem p;
  p.file = file;
  if (is_dae_case(j))
    p.input = read_dae_case(j, file);
  else if (is_implicit_case(j))
    p.input = ImplicitCase{read_implicit_case(j, file)};
  else if (is_expression_case(j))
    p.input = ExpressionCase{read_lagrangian_case(j, file)};
  else
    p.input = read_case(j, file);
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
/// A Problem holding `in`, named `file` in messages.
template <class Input>
Problem holding(std::string file, Input in) {
  Problem p;
  p.file = std::move(file);
  p.input = std::move(in);
  return p;
}
}  // namespace

Problem problem(CaseFile c) {
  std::string file = c.file;
  return holding(std::move(file), std::move(c));
}

Problem problem(Netlist deck) {
  std::string file = deck.file;
  CaseFile names = netlist_case(deck, false);  // the names; a route that needs the dense system builds it
  return holding(std::move(file), CircuitCase{std::move(deck), std::move(names)});
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
  // f ≡ 0 where none is given, for a dense case (a sparse one's `rows` is validate's to check, not to trust here)
  if (c.f.empty() && c.dense) c.f.assign(c.equations(), reference::expr::number(Rational(0)));
  if (c.initial.empty()) c.initial.assign(c.variables.size(), std::nullopt);
  std::string file = c.file;
  return holding(std::move(file), std::move(c));
}

Problem problem(LagrangianCase c) {
  std::string file = c.file;
  if (c.system.implicit) return holding(std::move(file), ImplicitCase{std::move(c)});
  return holding(std::move(file), ExpressionCase{std::move(c)});
}

Problem read_problem(const std::string& file, const ReadOptions& options) {
  if (is_netlist_file(file) || !looks_like_json_case(file)) return problem(read_netlist(file, options));
  return from_json(read_json_file(file), file);
}

Problem parse_netlist(const std::string& text, const std::string& name, const std::string& directory,
                      const ReadOptions& options) {
  return problem(read_netlist_text(text, name, directory, options));
}

Problem parse_case(const std::string& text, const std::string& name) {
  return from_json(parse_json_exact(text, name), name);
}

}  // namespace dcad::io
