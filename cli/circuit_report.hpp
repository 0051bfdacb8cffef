// The circuit part of `dcad solve` on a netlist: CONTRACT keys and the report for people (CEF §6).
#pragma once

#include "dcad/io/netlist.hpp"
#include "solve.hpp"

namespace dcad::cli {

nlohmann::json circuit_json(const io::Netlist& n, const SolveReport& r);
std::string circuit_text(const io::Netlist& n, const SolveReport& r);

}  // namespace dcad::cli
