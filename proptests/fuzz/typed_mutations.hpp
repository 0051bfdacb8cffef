// Issue 45 §5: typed inputs built in code, made malformed on purpose.  Each mutation takes a valid Problem
// (or Traces) of one form and breaks one thing a file reader would never let through: a size, a name, an
// index, a formula.  Every public entry point must then throw std::invalid_argument (io::InputError) —
// never crash, never answer, and above all never certify an answer to a problem that is not the one given.
// Used by the fuzz target fuzz_typed (the fuzzer's bytes choose the base, the mutations and their numbers)
// and by api_test's TypedInput.MalformedIsNeverAnswered (every mutation of every base, in ctest).
#pragma once

#include "dcad/api.hpp"

#include <cstdint>
#include <functional>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace dcad::fuzz {

/// Valid problems of every form, from text (the readers' guarantees hold for them).
inline std::vector<io::Problem> typed_bases() {
  return {
      io::parse_case(
          R"J({"dcad": 1, "variables": ["q", "p", "z"], "dirac": {"presymplectic": [["0","1","0"],["-1","0","0"],["0","0","0"]]},
                             "energy": {"hessian": [["1","0","0"],["0","1","0"],["0","0","0"]], "gradient": ["0","0","1"]}})J",
          "dirac.json"),
      io::parse_case(R"J({"dcad": 1, "pontryagin": {"Q": 2, "constraints": [["1","1"]],
                             "lagrangian": {"vv": [["1","0"],["0","2"]], "qq": [["-1","0"],["0","-3"]]}}})J",
                     "pontryagin.json"),
      io::parse_case(R"J({"dcad": 1, "constrained": {"symplectic": [["0","1"],["-1","0"]], "primary": [["0","1","0"]]},
                             "energy": {"hessian": [["1","0"],["0","1"]]}})J",
                     "constrained.json"),
      io::parse_netlist("tank and source\nV1 in 0 PULSE(0 1 0 1u 1u 5u 20u)\nR1 in a 1k\nL1 a b 1m IC=1m\nC1 b 0 "
                        "1n\nL2 b 0 2m\nK1 L1 L2 0.5\n"
                        ".tran 1u 40u\n.end\n",
                        "deck.cir"),
      io::parse_case(
          R"J({"dcad": 1, "variables": ["x1", "x2", "y"], "dae": {"E": [["1","0","0"],["0","1","0"],["0","0","0"]],
                             "A": [["0","1","1"],["-1","0","0"],["1","0","0"]], "f": ["0","0","sin(t)"], "time": "t"}})J",
          "dae.json"),
      io::parse_case(
          R"J({"dcad": 1, "parameters": {"g": "981/100"}, "implicit": {"coordinates": ["x", "y", "u", "w", "lam"],
                             "equations": ["v_x - u", "v_y - w", "v_u + lam*x", "v_w + lam*y + g", "x^2 + y^2 - 1"]}, "initial": {"x": "3/5", "y": "-4/5"}})J",
          "implicit.json"),
      io::parse_case(
          R"J({"dcad": 1, "lagrangian": {"coordinates": ["x"], "L": "1/2*v_x^2 - 1/2*x^2"}, "initial": {"x": "1"}})J",
          "lagrangian.json")};
}

/// The field a malformation of `p`'s form touches.  Two malformations of one field can undo each other
/// (pushing a duplicate name and popping it restores the valid problem), so a composition malforms each
/// field at most once.
inline unsigned malformed_field(const io::Problem& p, unsigned which) {
  switch (p.form()) {
    case io::Form::linear: return which % 8 <= 2 ? 0 : which % 8;  // 0, 1, 2: the variables
    case io::Form::netlist: return which % 8;
    case io::Form::dae: return which % 6 == 2 ? 0 : which % 6;  // 0, 2: the variables
    case io::Form::expression:
    case io::Form::implicit: return which % 6 == 5 ? 0 : which % 6;  // 0, 5: the names
  }
  return 0;
}

/// One malformation of `p` (chosen by `which`, `k` a number inside it), or false if `which` has none for
/// p's form.  Each is something no reader produces.
inline bool malform(io::Problem& p, unsigned which, unsigned k) {
  using io::Form;
  const auto pick = [&](std::size_t n) { return n ? k % n : 0; };
  switch (p.form()) {
    case Form::linear: {
      io::CaseFile& c = p.linear();
      switch (which % 8) {
        case 0:
          if (c.variables.empty()) return false;
          c.variables.pop_back();
          return true;
        case 1: c.variables.push_back("extra"); return true;
        case 2:
          if (c.variables.size() < 2) return false;
          c.variables[1] = c.variables[0];
          return true;
        case 3:
          if (c.has_pontryagin) return false;
          c.energy.gradient.pop_back();
          return true;
        case 4:
          if (c.has_pontryagin) return false;
          c.energy.hessian = io::QMatrix(c.n + 1, c.n);
          return true;
        case 5: c.coordinates.push_back(c.n + k % 5); return true;
        case 6: c.initial.assign(c.n + 1 + k % 3, io::Rational(0)); return true;
        default:
          if (c.has_pontryagin) {
            c.pontryagin.q.push_back(1);
            return true;
          }
          if (c.has_constrained) {
            c.constrained.primary = io::QMatrix(1, c.n);
            return true;
          }
          c.dirac.form = "nonsense";
          return true;
      }
    }
    case Form::netlist: {
      io::Netlist& d = p.netlist();
      const std::size_t nb = d.rlc.branches.size();
      switch (which % 8) {
        case 0: d.rlc.branches[pick(nb)].from = static_cast<long>(d.rlc.nodes + k % 4); return true;
        case 1: d.rlc.branches[pick(nb)].to = -2 - static_cast<long>(k % 3); return true;
        case 2: d.initial.pop_back(); return true;
        case 3:
          if (d.rlc.mutuals.empty()) return false;
          d.rlc.mutuals[0].b = nb + k % 3;
          return true;
        case 4:
          if (d.waveforms.empty()) return false;
          d.waveforms[0].p.pop_back();
          return true;
        case 5: p.linear().variables.pop_back(); return true;
        case 6:
          if (d.waveforms.empty()) return false;
          d.rlc.sources = d.waveforms.size() + 1;
          return true;
        default: d.node_ic.push_back({static_cast<long>(d.rlc.nodes + k % 3), io::Rational(1)}); return true;
      }
    }
    case Form::dae: {
      io::DaeCase& c = p.dae();
      switch (which % 6) {
        case 0: c.variables.pop_back(); return true;
        case 1:
          if (c.f.empty()) return false;
          c.f.pop_back();
          return true;
        case 2: c.variables.push_back(c.variables[0]); return true;
        case 3: c.a = io::QMatrix(c.e.rows() + 1, c.variables.size()); return true;
        case 4:
          c.f[pick(c.f.size())] = reference::expr::variable(1 + k % 3);
          return true;  // the time is variable 0: nothing else
        default:
          c.initial.assign(c.variables.size() + 1, std::nullopt);
          c.has_initial = true;
          return true;
      }
    }
    case Form::expression:
    case Form::implicit: {
      io::LagrangianCase& c = p.expression();
      reference::LagrangianSystem& s = c.system;
      switch (which % 6) {
        case 0: s.names.pop_back(); return true;
        case 1:
          if (s.constraints.empty()) {
            s.lagrangian = nullptr;
            return true;
          }
          s.constraints[pick(s.constraints.size())] = nullptr;
          return true;
        case 2:
          if (s.implicit) {
            s.constraints.push_back(reference::expr::variable(2 * s.n + 1 + k % 4));
            return true;
          }
          s.lagrangian = reference::expr::variable(2 * s.n + 1 + k % 4);
          return true;
        case 3: c.initial.pop_back(); return true;
        case 4: s.forces.assign(s.n + 1, reference::expr::number(0)); return true;
        default: s.names.push_back(s.names.empty() ? "x" : s.names[0]); return true;
      }
    }
  }
  return false;
}

/// Traces made malformed (the file readers never produce them).
inline io::Traces malformed_traces(unsigned which, unsigned k) {
  io::Traces t;
  t.names = {"v(a)"};
  t.time = {0, 1e-6, 2e-6};
  t.values = {{0, 0.5, 0.25}};
  switch (which % 5) {
    case 0:
      t.time.clear();
      t.values[0].clear();
      break;
    case 1: t.values[0].resize(k % 3); break;
    case 2: t.values.push_back({1, 2, 3}); break;
    case 3: t.time[1] = -1.0 - k; break;
    default: t.time[2] = std::numeric_limits<double>::quiet_NaN(); break;
  }
  return t;
}

/// Every public entry point on a malformed problem: true when each refused it as bad input.  Any answer
/// (a fortiori a certified one) returns false with `what`; a crash is the sanitizer's or the fuzzer's.
inline bool all_refuse(const io::Problem& p, std::string& what) {
  std::ostringstream sink;
  const std::vector<std::pair<std::string, std::function<void()>>> calls = {
      {"api::solve certified", [&] { (void)api::solve(p, api::Backend::certified); }},
      {"api::solve reference", [&] { (void)api::solve(p, api::Backend::reference); }},
      {"api::solve fast", [&] { (void)api::solve(p, api::Backend::fast); }},
      {"certified::solve", [&] { (void)certified::solve(p); }},
      {"reference::solve", [&] { (void)reference::solve(p); }},
      {"fast::solve", [&] { (void)fast::solve(p); }},
      {"api::check_text", [&] { (void)api::check_text(R"({"dims": [1], "steps": 0, "consistent": true})", p); }},
      {"api::simulate", [&] {
         api::SimulateOptions o;
         o.tstop = 1e-6, o.step = 1e-7;
         (void)api::simulate(p, o, sink, sink);
       }}};
  for (const auto& [name, call] : calls) {
    try {
      call();
      what = name + " answered a malformed " + p.file;
      return false;
    } catch (const std::invalid_argument&) {
    }
  }
  return true;
}

}  // namespace dcad::fuzz
