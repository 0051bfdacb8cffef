// A generated system as a CONTRACT case file, logged by properties (RC_LOG, shown only when a
// property fails) as one line "dcad case: {…}", so that `dcad cases freeze LOG NAME` turns the shrunk
// counterexample into a golden case with the reference's expectations.
#pragma once

#include "dcad/reference/circuit.hpp"
#include "dcad/reference/dirac_bergmann.hpp"
#include "dcad/reference/system.hpp"
#include "gen.hpp"

#include <sstream>
#include <string>

namespace dcad::test {

inline std::string json_matrix(const QM& m) {
  std::ostringstream o;
  o << "[";
  for (Index i = 0; i < m.rows(); ++i) {
    o << (i ? ", [" : "[");
    for (Index j = 0; j < m.cols(); ++j) o << (j ? ", \"" : "\"") << m(i, j).str() << "\"";
    o << "]";
  }
  o << "]";
  return o.str();
}

inline std::string json_vector(const std::vector<Q>& v) {
  std::ostringstream o;
  o << "[";
  for (Index i = 0; i < v.size(); ++i) o << (i ? ", \"" : "\"") << v[i].str() << "\"";
  o << "]";
  return o.str();
}

/// `dirac` (basis form) + `energy`.
inline std::string case_json(const reference::LinearSystem<Q>& s) {
  return "dcad case: {\"dcad\": 1, \"name\": \"counterexample\", \"dirac\": {\"basis\": " + json_matrix(s.d.d.basis()) +
         "}, \"energy\": {\"hessian\": " + json_matrix(s.hessian) + ", \"gradient\": " + json_vector(s.gradient) +
         ", \"constant\": \"" + s.constant.str() + "\"}}\n";
}

/// `pontryagin` (an LC circuit, CEF §6).
inline std::string case_json(const reference::PontryaginInput<Q>& p) {
  return "dcad case: {\"dcad\": 1, \"name\": \"counterexample\", \"pontryagin\": {\"Q\": " + std::to_string(p.n) +
         ", \"constraints\": " + json_matrix(p.k) + ", \"lagrangian\": {\"vv\": " + json_matrix(p.vv) +
         ", \"qv\": " + json_matrix(p.qv) + ", \"qq\": " + json_matrix(p.qq) + ", \"q\": " + json_vector(p.q) +
         ", \"v\": " + json_vector(p.v) + "}}}\n";
}

/// `constrained` (N, Ω, E, M) with M = {a·x = b} (CEF §2), and `energy`.
inline std::string case_json(const reference::ConstrainedSystem<Q>& s) {
  return "dcad case: {\"dcad\": 1, \"name\": \"counterexample\", \"constrained\": {\"symplectic\": " +
         json_matrix(s.omega) + ", \"primary\": " + json_matrix(s.primary) +
         "}, \"energy\": {\"hessian\": " + json_matrix(s.hessian) + ", \"gradient\": " + json_vector(s.gradient) +
         "}}\n";
}

}  // namespace dcad::test
