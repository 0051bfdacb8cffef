// io::validate: a Problem built in code is held to what the readers guarantee of one read from a file
// (issue 45 §5) — sizes, names, indices and the shape of every formula — so that no route ever solves a
// different system than the one given.  Each message names the struct field, what was expected and what
// was found.
#include "dcad/io/problem.hpp"
#include "dcad/io/traces.hpp"

#include <cmath>

#include <set>
#include <string>
#include <unordered_set>
#include <vector>

namespace dcad::io {

namespace {

[[noreturn]] void bad(const std::string& file, const std::string& field, const std::string& expected,
                      const std::string& found) {
  throw InputError((file.empty() ? std::string("<problem built in code>") : file) + ": " + field + ": expected " +
                   expected + ", found " + found);
}

std::string n_of(std::size_t n) { return std::to_string(n); }
std::string shape(const QMatrix& m) { return n_of(m.rows()) + "x" + n_of(m.cols()); }

void names(const std::string& file, const std::string& field, const std::vector<std::string>& v, std::size_t n) {
  if (v.size() != n) bad(file, field, n_of(n) + " names", n_of(v.size()));
  std::set<std::string> seen;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i].empty()) bad(file, field + "[" + n_of(i) + "]", "a non-empty name", "\"\"");
    if (!seen.insert(v[i]).second) bad(file, field + "[" + n_of(i) + "]", "a new name", "\"" + v[i] + "\" twice");
  }
}

void matrix(const std::string& file, const std::string& field, const QMatrix& m, std::size_t rows, std::size_t cols) {
  if (m.rows() != rows || m.cols() != cols) bad(file, field, n_of(rows) + "x" + n_of(cols), shape(m));
}

void columns(const std::string& file, const std::string& field, const QMatrix& m, std::size_t cols) {
  if (m.rows() > 0 && m.cols() != cols) bad(file, field, "rows of " + n_of(cols) + " numbers", shape(m));
}

template <class V>
void length(const std::string& file, const std::string& field, const V& v, std::size_t n) {
  if (v.size() != n) bad(file, field, n_of(n) + " entries", n_of(v.size()));
}

/// Every node of a formula is complete (operands present, an operation dcad knows) and every variable
/// index below `variables`.
void formula(const std::string& file, const std::string& field, const reference::expr::Expr& e, std::size_t variables) {
  using reference::expr::ExprOp;
  if (!e) bad(file, field, "a formula", "none (a null Expr)");
  std::vector<const reference::expr::ExprNode*> todo{e.get()};
  std::unordered_set<const reference::expr::ExprNode*> seen;
  while (!todo.empty()) {
    const reference::expr::ExprNode* x = todo.back();
    todo.pop_back();
    if (!seen.insert(x).second) continue;
    const bool binary = x->op == ExprOp::Add || x->op == ExprOp::Sub || x->op == ExprOp::Mul || x->op == ExprOp::Div;
    const bool unary = x->op == ExprOp::Neg || x->op == ExprOp::Pow || x->op == ExprOp::Sin || x->op == ExprOp::Cos ||
                       x->op == ExprOp::Exp || x->op == ExprOp::Sqrt;
    if (x->op == ExprOp::Variable && x->var >= variables)
      bad(file, field, "variables numbered below " + n_of(variables), "variable " + n_of(x->var));
    if (!binary && !unary && x->op != ExprOp::Number && x->op != ExprOp::Variable)
      bad(file, field, "a known operation", "operation " + n_of(static_cast<std::size_t>(x->op)));
    if ((binary || unary) && !x->a) bad(file, field, "an operand", "a null operand");
    if (binary && !x->b) bad(file, field, "a second operand", "a null operand");
    if (x->a) todo.push_back(x->a.get());
    if (x->b) todo.push_back(x->b.get());
  }
}

void linear(const CaseFile& c) {
  const std::string& f = c.file;
  if (!c.has_dirac && !c.has_pontryagin && !c.has_constrained)
    bad(f, "CaseFile", "one of has_dirac, has_pontryagin, has_constrained", "none set");
  if (c.has_dirac + c.has_pontryagin + c.has_constrained > 1)
    bad(f, "CaseFile", "one form", "several of has_dirac, has_pontryagin, has_constrained");
  const std::size_t n = c.n;
  names(f, "CaseFile::variables", c.variables, n);
  if (c.has_pontryagin) {
    const PontryaginInput& p = c.pontryagin;
    if (3 * p.n != n) bad(f, "CaseFile::n", n_of(3 * p.n) + " (3 x pontryagin.n)", n_of(n));
    columns(f, "pontryagin.k", p.k, p.n);
    matrix(f, "pontryagin.vv", p.vv, p.n, p.n);
    matrix(f, "pontryagin.qv", p.qv, p.n, p.n);
    matrix(f, "pontryagin.qq", p.qq, p.n, p.n);
    length(f, "pontryagin.q", p.q, p.n);
    length(f, "pontryagin.v", p.v, p.n);
    if (p.has_forces) {
      matrix(f, "pontryagin.fq", p.fq, p.n, p.n);
      matrix(f, "pontryagin.fv", p.fv, p.n, p.n);
    }
  } else {
    matrix(f, "energy.hessian", c.energy.hessian, n, n);
    length(f, "energy.gradient", c.energy.gradient, n);
  }
  if (c.has_constrained) {
    matrix(f, "constrained.w", c.constrained.w, n, n);
    columns(f, "constrained.primary", c.constrained.primary, n + 1);
  }
  if (c.has_dirac) {
    const DiracInput& d = c.dirac;
    if (d.form == "presymplectic") {
      matrix(f, "dirac.w", d.w, n, n);
    } else if (d.form == "distribution") {
      columns(f, "dirac.b", d.b, n);
      matrix(f, "dirac.w", d.w, n, n);
    } else if (d.form == "poisson") {
      matrix(f, "dirac.p", d.p, n, n);
    } else if (d.form == "basis") {
      matrix(f, "dirac.g", d.g, n, 2 * n);
    } else {
      bad(f, "dirac.form", "presymplectic, distribution, poisson or basis", "\"" + d.form + "\"");
    }
  }
  for (std::size_t i = 0; i < c.coordinates.size(); ++i)
    if (c.coordinates[i] >= n)
      bad(f, "CaseFile::coordinates[" + n_of(i) + "]", "a variable index below " + n_of(n), n_of(c.coordinates[i]));
  if (!c.initial.empty()) length(f, "CaseFile::initial", c.initial, n);
}

void waveform(const std::string& f, const std::string& field, const Waveform& w) {
  const std::size_t k = w.p.size();
  const bool ok = w.kind == Waveform::Kind::dc      ? k == 1
                  : w.kind == Waveform::Kind::sin   ? k == 6
                  : w.kind == Waveform::Kind::pulse ? k == 7
                  : w.kind == Waveform::Kind::pwl   ? k >= 2 && k % 2 == 0
                  : w.kind == Waveform::Kind::exp   ? k == 6
                  : w.kind == Waveform::Kind::sffm  ? k == 5
                                                    : false;
  if (!ok)
    bad(f, field + ".p",
        "the parameters of its kind (DC 1, SIN 6, PULSE 7, PWL pairs, EXP 6, SFFM 5; Waveform::complete fills SIN's "
        "and PULSE's)",
        n_of(k) + " values");
  if (w.kind == Waveform::Kind::sffm && !(w.p[2] > 0 && w.p[4] > 0 && w.p[3] >= 0))
    bad(f, field + ".p", "SFFM with FC > 0, FS > 0, MDI >= 0", w.text);
  if (w.kind == Waveform::Kind::pulse && !(w.p[3] > 0 && w.p[4] > 0 && w.p[5] >= 0 && w.p[6] > 0 && w.p[2] >= 0))
    bad(f, field + ".p", "PULSE with TD >= 0, TR > 0, TF > 0, PW >= 0, PER > 0", w.text);
  if (w.kind == Waveform::Kind::exp && (w.p[3] == 0 || w.p[5] == 0))
    bad(f, field + ".p", "EXP with TAU1 and TAU2 nonzero", w.text);
  if (w.kind == Waveform::Kind::exp && w.p[4] < w.p[2] && w.p[0] != w.p[1])
    bad(f, field + ".p", "EXP with TD2 >= TD1 (else a step at TD1)", w.text);
  if (w.kind == Waveform::Kind::sin && w.p[2] < 0) bad(f, field + ".p", "SIN with FREQ >= 0", w.text);
}

void netlist(const Problem& p) {
  const Netlist& d = p.netlist();
  const std::string& f = d.file;
  const std::size_t nb = d.rlc.branches.size();
  if (nb == 0) bad(f, "Netlist::rlc.branches", "at least one element", "none");
  length(f, "Netlist::circuit.branches", d.circuit.branches, nb);
  length(f, "Netlist::initial", d.initial, nb);
  if (d.circuit.nodes != d.rlc.nodes || d.node_names.size() != d.rlc.nodes)
    bad(f, "Netlist::rlc.nodes", n_of(d.node_names.size()) + " (one per node name, as circuit.nodes)",
        n_of(d.rlc.nodes));
  if (d.rlc.sources != d.waveforms.size())
    bad(f, "Netlist::rlc.sources", n_of(d.waveforms.size()) + " (one per waveform)", n_of(d.rlc.sources));
  const long nodes = static_cast<long>(d.rlc.nodes);
  for (std::size_t b = 0; b < nb; ++b) {
    const auto& r = d.rlc.branches[b];
    const std::string at = "Netlist::rlc.branches[" + n_of(b) + "]";
    if (r.from < -1 || r.from >= nodes || r.to < -1 || r.to >= nodes)
      bad(f, at, "nodes in -1 (ground) ... " + n_of(d.rlc.nodes - 1),
          std::to_string(r.from) + " and " + std::to_string(r.to));
    const auto& c = d.circuit.branches[b];
    if (c.from != r.from || c.to != r.to)
      bad(f, "Netlist::circuit.branches[" + n_of(b) + "]", "the nodes of rlc.branches[" + n_of(b) + "]", "others");
    const bool source = r.kind == reference::RlcKind::voltage || r.kind == reference::RlcKind::current;
    if (source && r.source >= d.waveforms.size())
      bad(f, at + ".source", "a waveform index below " + n_of(d.waveforms.size()), n_of(r.source));
    if ((r.kind == reference::RlcKind::capacitor || r.kind == reference::RlcKind::resistor) && r.value == 0)
      bad(f, at + ".value", "a nonzero capacitance or resistance", "0");
  }
  for (std::size_t j = 0; j < d.waveforms.size(); ++j)
    waveform(f, "Netlist::waveforms[" + n_of(j) + "]", d.waveforms[j]);
  for (std::size_t m = 0; m < d.rlc.mutuals.size(); ++m) {
    const auto& mu = d.rlc.mutuals[m];
    if (mu.a >= nb || mu.b >= nb || mu.a == mu.b || d.rlc.branches[mu.a].kind != reference::RlcKind::inductor ||
        d.rlc.branches[mu.b].kind != reference::RlcKind::inductor)
      bad(f, "Netlist::rlc.mutuals[" + n_of(m) + "]", "two different inductor branches",
          n_of(mu.a) + " and " + n_of(mu.b));
  }
  for (std::size_t i = 0; i < d.node_ic.size(); ++i)
    if (d.node_ic[i].first < 0 || d.node_ic[i].first >= nodes)
      bad(f, "Netlist::node_ic[" + n_of(i) + "]", "a node index in 0 ... " + n_of(d.rlc.nodes - 1),
          std::to_string(d.node_ic[i].first));
  names(f, "CircuitCase::names.variables (q_, v_, p_ per branch)", p.linear().variables, 3 * nb);
}

void expression(const LagrangianCase& c) {
  const std::string& f = c.file;
  const reference::LagrangianSystem& s = c.system;
  const std::size_t n = s.n, vars = 2 * n + 1;
  names(f, "LagrangianCase::system.names", s.names, n);
  if (s.time_name.empty()) bad(f, "LagrangianCase::system.time_name", "a name", "\"\"");
  if (!s.implicit) formula(f, "LagrangianCase::system.lagrangian", s.lagrangian, vars);
  if (s.implicit && s.constraints.empty())
    bad(f, "LagrangianCase::system.constraints", "at least one equation", "none");
  for (std::size_t a = 0; a < s.constraints.size(); ++a)
    formula(f, "LagrangianCase::system.constraints[" + n_of(a) + "]", s.constraints[a], vars);
  if (!s.forces.empty()) length(f, "LagrangianCase::system.forces", s.forces, n);
  for (std::size_t i = 0; i < s.forces.size(); ++i)
    formula(f, "LagrangianCase::system.forces[" + n_of(i) + "]", s.forces[i], vars);
  length(f, "LagrangianCase::initial (q, v, t)", c.initial, vars);
  if (!c.initial_p.empty()) length(f, "LagrangianCase::initial_p", c.initial_p, n);
}

void dae(const DaeCase& c) {
  const std::string& f = c.file;
  const std::size_t n = c.variables.size();
  names(f, "DaeCase::variables", c.variables, n);
  if (n == 0) bad(f, "DaeCase::variables", "at least one variable", "none");
  const std::size_t m = c.equations();
  if (c.dense) {
    matrix(f, "DaeCase::e", c.e, c.e.rows(), n);
    matrix(f, "DaeCase::a", c.a, m, n);
  } else {
    if (c.rows < 0) bad(f, "DaeCase::rows", "a number of equations >= 0", std::to_string(c.rows));
    for (const auto* es : {&c.e_entries, &c.a_entries})
      for (std::size_t k = 0; k < es->size(); ++k) {
        const DaeCase::Entry& e = (*es)[k];
        if (e.row < 0 || e.row >= c.rows || e.col < 0 || static_cast<std::size_t>(e.col) >= n)
          bad(f, std::string(es == &c.e_entries ? "DaeCase::e_entries[" : "DaeCase::a_entries[") + n_of(k) + "]",
              "row < " + std::to_string(c.rows) + " and column < " + n_of(n),
              std::to_string(e.row) + ", " + std::to_string(e.col));
      }
  }
  length(f, "DaeCase::f (one per equation)", c.f, m);
  for (std::size_t i = 0; i < c.f.size(); ++i) formula(f, "DaeCase::f[" + n_of(i) + "]", c.f[i], 1);
  if (!c.initial.empty() || c.has_initial) length(f, "DaeCase::initial", c.initial, n);
}

}  // namespace

void validate(const Problem& p) {
  switch (p.form()) {
    case Form::linear: return linear(p.linear());
    case Form::netlist: return netlist(p);
    case Form::expression:
    case Form::implicit:
      if (p.expression().system.implicit != (p.form() == Form::implicit))
        bad(p.expression().file, "LagrangianCase::system.implicit",
            p.form() == Form::implicit ? "true for Form::implicit" : "false for Form::expression",
            p.expression().system.implicit ? "true" : "false");
      return expression(p.expression());
    case Form::dae: return dae(p.dae());
  }
  bad(p.file, "Problem::form", "linear, netlist, expression, dae or implicit",
      n_of(static_cast<std::size_t>(p.form())));
}

void validate(const Traces& t) {
  const std::string f = t.file.empty() ? "<traces built in code>" : t.file;
  if (t.time.empty()) bad(f, "Traces::time", "at least one time point", "none");
  for (std::size_t i = 0; i < t.time.size(); ++i) {
    if (!std::isfinite(t.time[i])) bad(f, "Traces::time[" + n_of(i) + "]", "a finite time", std::to_string(t.time[i]));
    if (i > 0 && t.time[i] < t.time[i - 1])
      bad(f, "Traces::time[" + n_of(i) + "]", "nondecreasing times",
          std::to_string(t.time[i]) + " after " + std::to_string(t.time[i - 1]));
  }
  if (t.values.size() != t.names.size())
    bad(f, "Traces::values", n_of(t.names.size()) + " vectors (one per name)", n_of(t.values.size()));
  for (std::size_t k = 0; k < t.values.size(); ++k)
    if (t.values[k].size() != t.time.size())
      bad(f, "Traces::values[" + n_of(k) + "] (" + t.names[k] + ")",
          n_of(t.time.size()) + " values (one per time point)", n_of(t.values[k].size()));
}

}  // namespace dcad::io
