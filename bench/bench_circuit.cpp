// Benchmark (not a test): `dcad solve --backend fast` on large LC circuits, end to end in one process
// (read the netlist exactly, the graph route of CEF §6, the JSON result), for one family and size:
//   build/bench_circuit FAMILY BRANCHES
// FAMILY: ladder — N sections of a series inductor and two parallel shunt capacitors (3N branches,
//         N purely capacitive loops, c = 3);
//         grid — an R×R node grid, inductors along rows, capacitors along columns, every 8th row
//         branch a wire, the first and last rows tied to ground by capacitors (purely capacitive
//         loops through ground, empty loops where wires close a loop).
// Prints one CSV line: family,branches,nodes,read_s,tower_s,json_s,total_s,c,dim_Mc,peak_rss_mb.
// bench/circuit_scaling.sh runs the sizes 10^2 … 10^6 and fits the exponent.
#include "dcad/io/netlist.hpp"
#include "dcad/fast/solve.hpp"
#include "dcad/io/report.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string node(long i) { return i == 0 ? "0" : "n" + std::to_string(i); }

void ladder(std::ofstream& o, long branches) {
  const long sections = std::max(1L, branches / 3);
  for (long s = 1; s <= sections; ++s) {
    o << "L" << s << " " << node(s - 1) << " " << node(s) << " 1m\n";
    o << "CA" << s << " " << node(s) << " 0 1u\n";
    o << "CB" << s << " " << node(s) << " 0 2.2u\n";
  }
}

void grid(std::ofstream& o, long branches) {
  const long r = std::max(2L, static_cast<long>(std::lround(std::sqrt(branches / 2.0))));
  const auto id = [&](long i, long j) { return 1 + i * r + j; };
  long k = 0;
  for (long i = 0; i < r; ++i)
    for (long j = 0; j < r; ++j) {
      if (j + 1 < r) {
        if ((i * r + j) % 8 == 0) {
          o << "V" << ++k << " " << node(id(i, j)) << " " << node(id(i, j + 1)) << " 0\n";
        } else {
          o << "L" << ++k << " " << node(id(i, j)) << " " << node(id(i, j + 1)) << " 1m\n";
        }
      }
      if (i + 1 < r) o << "C" << ++k << " " << node(id(i, j)) << " " << node(id(i + 1, j)) << " 1u\n";
      if (i == 0 || i + 1 == r) o << "CG" << ++k << " " << node(id(i, j)) << " 0 10u\n";
    }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_circuit ladder|grid BRANCHES\n");
    return 2;
  }
  const std::string family = argv[1];
  const long branches = std::atol(argv[2]);
  const std::string deck = "/tmp/dcad_bench_" + family + "_" + std::to_string(branches) + ".cir";
  {
    std::ofstream o(deck);
    o << family << " benchmark circuit\n";
    if (family == "ladder") {
      ladder(o, branches);
    } else {
      grid(o, branches);
    }
    o << ".end\n";
  }
  const auto t0 = std::chrono::steady_clock::now();
  const dcad::io::Netlist n = dcad::io::read_netlist(deck);
  const double read_s = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  const dcad::io::CaseFile c = dcad::io::netlist_case(n, false);
  dcad::fast::Solution r = dcad::fast::solve_lc(n, c, {});
  r.circuit = dcad::io::circuit_facts(n);
  const double tower_s = seconds_since(t1);
  const auto t2 = std::chrono::steady_clock::now();
  const std::string json = dcad::io::result_json(dcad::io::printed(r));
  const double json_s = seconds_since(t2);
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  std::printf("%s,%zu,%zu,%.3f,%.3f,%.3f,%.3f,%ld,%ld,%.1f\n", family.c_str(), n.circuit.branches.size(),
              n.circuit.nodes + 1, read_s, tower_s, json_s, seconds_since(t0), r.steps, r.dims().back(),
              u.ru_maxrss / 1024.0);
  std::remove(deck.c_str());
  return json.empty() ? 1 : 0;
}
