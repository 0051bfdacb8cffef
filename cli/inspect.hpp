// `dcad inspect`: what a Dirac structure is (CEF §4), by either backend.
#pragma once

#include "dcad/io/case_file.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dcad::cli {

struct InspectReport {
  std::string backend;
  bool certified = true;  ///< every rank decision exact, or certain in the fast sense
  bool valid = false;
  std::string why;        ///< why D is not a Dirac structure
  std::size_t n = 0;
  std::string form;
  long dim_e = -1, rank_omega = -1, dim_ker_omega = -1;
  bool presymplectic = false, poisson = false;
  std::vector<std::string> uncertain;  ///< outputs whose decision was uncertain (fast)
  std::vector<std::string> evidence;   ///< the decisions behind them
};

InspectReport inspect_reference(const io::CaseFile& c);
InspectReport inspect_fast(const io::CaseFile& c);

nlohmann::json to_json(const InspectReport& r);
std::string to_text(const InspectReport& r, const io::CaseFile& c);

}  // namespace dcad::cli
