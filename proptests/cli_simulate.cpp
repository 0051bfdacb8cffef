// `dcad simulate` as a user runs it: the 4-port against its analytic solution, ngspice as a peer,
// forced decks (R, sources) against closed forms, ngspice and their own structure (issue 12).
#include "cli_run.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>
#include <map>
#include <string>
#include <tuple>

#include <unistd.h>

TEST(Simulate, FourPortAnalyticAndEnergy) {
  const Outcome r = run("simulate " + std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.cir --tstop 1000 --step 0.1");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "t,q_L1,q_C1,q_C2,q_C3,v_L1,v_C1,v_C2,v_C3,p_L1,p_C1,p_C2,p_C3");
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 10001u);
  const double l = 2, c1 = 3, c2 = 5, c3 = 7, u0 = 3, w = std::sqrt((c1 + c2 + c3) / (l * c2 * (c1 + c3)));
  const auto energy = [&](const std::vector<double>& x) {
    return 0.5 * l * x[5] * x[5] + x[2] * x[2] / (2 * c1) + x[3] * x[3] / (2 * c2) + x[4] * x[4] / (2 * c3);
  };
  double worst = 0, drift = 0;
  for (const auto& x : rows) {
    const double t = x[0];
    const double i = -u0 * std::sin(w * t) / (l * w), v2 = 2 - u0 * (1 - std::cos(w * t)) / (l * w * w * c2);
    worst = std::max({worst, std::abs(x[5] - i), std::abs(x[3] / c2 - v2)});
    drift = std::max(drift, std::abs(energy(x) - energy(rows[0])) / energy(rows[0]));
  }
  EXPECT_LT(worst, 1e-9);  // ~100 periods; rounding only
  EXPECT_LT(drift, 1e-11);
  std::cout << "4-port over 10^4 steps: max error " << worst << ", relative energy drift " << drift << "\n";
}

// Issue 30: simulate on the dae form.  Hessenberg index 2 (cases/dae-hessenberg-index-2.json) from
// x1 = 0, x2 = 1/4 given: by hand x1 = -sin t, x2' = -x1 = sin t so x2 = 1/4 + 1 - cos t, and y =
// -cos t - x2 on M_2 — the start's y = -5/4 is completed, and told on the log.  A start off M_c is
// bad input naming the constraint.
TEST(Simulate, DaeFollowsItsClosedFormFromACompletedStart) {
  const std::string c = write_temp("dcad_dae_sim.json", R"J({"dcad": 1, "variables": ["x1", "x2", "y"],
    "dae": {"E": [["1","0","0"],["0","1","0"],["0","0","0"]], "A": [["0","1","1"],["-1","0","0"],["1","0","0"]], "f": ["0","0","sin(t)"], "time": "t"},
    "initial": {"x1": "0", "x2": "1/4"}})J");
  const Outcome r = run("simulate " + c + " --tstop 10 --step 0.01");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "t,x1,x2,y");
  EXPECT_NE(r.err.find("y = -1.25 (completed)"), std::string::npos) << r.err;
  const auto rows = csv_rows(r.out);
  ASSERT_EQ(rows.size(), 1001u);
  double worst = 0;
  for (const auto& x : rows) {
    const double t = x[0], x2 = 0.25 + 1 - std::cos(t);
    worst = std::max({worst, std::abs(x[1] + std::sin(t)), std::abs(x[2] - x2), std::abs(x[3] + std::cos(t) + x2)});
  }
  EXPECT_LT(worst, 1e-8);
  const std::string off = write_temp("dcad_dae_off.json", R"J({"dcad": 1, "variables": ["x", "y"],
    "dae": {"E": [["1","0"],["0","0"]], "A": [["-1","1"],["1","1"]], "f": ["0","-exp(-t)"], "time": "t"}, "initial": {"x": "0.3", "y": "0.2"}})J");
  const Outcome bad = run("simulate " + off + " --tstop 1 --step 0.5");
  EXPECT_EQ(bad.rc, 1) << bad.out;
  EXPECT_NE(bad.err.find("/initial: expected values on M_c"), std::string::npos) << bad.err;
}

// Issue 30, the implicit form: the pendulum in its index-3 and index-2 formulations is one motion (two
// formulations of one system, each reduced by dcad), and along it the length x² + y² = 1 (the index-3
// constraint, only a first integral of the index-2 one) and the energy ½(u² + w²) + g y are conserved
// (Hairer–Wanner VII.1).  Every completed value is reported.
TEST(Simulate, ImplicitPendulumFormulationsAreOneMotion) {
  const std::string i3 = (fs::path(DCAD_SOURCE_DIR) / "cases/implicit-pendulum-index-3.json").string();
  const std::string i2 = write_temp("dcad_pendulum_i2.json", R"J({"dcad": 1, "parameters": {"g": "981/100"},
    "implicit": {"coordinates": ["x", "y", "u", "w", "lam"],
                 "equations": ["v_x - u", "v_y - w", "v_u + lam*x", "v_w + lam*y + g", "x*u + y*w"]},
    "initial": {"x": "3/5", "y": "-4/5", "u": "0", "w": "0"}})J");
  const Outcome a = run("simulate " + i3 + " --tstop 0.5 --step 0.125");
  const Outcome b = run("simulate " + i2 + " --tstop 0.5 --step 0.125");
  ASSERT_EQ(a.rc, 0) << a.err;
  ASSERT_EQ(b.rc, 0) << b.err;
  EXPECT_EQ(a.out.substr(0, a.out.find('\n')), "t,x,y,u,w,lam");
  EXPECT_NE(a.err.find("lam = 7.848"), std::string::npos) << a.err;  // g·4/5 at rest: completed
  EXPECT_NE(a.err.find("(completed)"), std::string::npos) << a.err;
  const auto ra = csv_rows(a.out), rb = csv_rows(b.out);
  ASSERT_EQ(ra.size(), 5u);
  ASSERT_EQ(rb.size(), 5u);
  const double g = 9.81, e0 = g * -0.8;
  double worst = 0;
  for (std::size_t k = 0; k < ra.size(); ++k) {
    const auto& x = ra[k];
    worst = std::max(
        {worst, std::abs(x[1] * x[1] + x[2] * x[2] - 1), std::abs(0.5 * (x[3] * x[3] + x[4] * x[4]) + g * x[2] - e0)});
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - rb[k][i]) / 10);
  }
  EXPECT_LT(worst, 1e-8);
  EXPECT_GT(std::abs(ra.back()[1] - 0.6), 0.1);  // it moved
}

// Cross-check with ngspice (Debian package, installed by .ci/setup): the same 4-port deck, ngspice at
// reltol 1e-10 with the deck's IC= (uic), resampled on dcad's grid (linearize).  ngspice is good to
// about 5e-7 relative here (issue 4); dcad is exact up to rounding.
TEST(Simulate, AgreesWithNgspice) {
  if (std::system("command -v ngspice > /dev/null 2>&1") != 0)
    FAIL() << "ngspice not installed: run bash .ci/setup (the README's test command does)";
  std::string deck = slurp(fs::path(DCAD_SOURCE_DIR) / "cases/lc-4port.cir");
  deck = deck.substr(0, deck.find(".tran"));
  const std::string data = temp_path("dcad_ngspice.txt");
  std::filesystem::remove(data);
  deck +=
      ".options reltol=1e-10 abstol=1e-15 vntol=1e-12\n.tran 1m 10 0 1m uic\n.control\nset numdgt=16\nrun\n"
      "linearize v(2) i(l1)\nwrdata " +
      data + " v(2) i(l1)\n.endc\n.end\n";
  const std::string deck_file = write_temp("dcad_ngspice.cir", deck);
  std::system(("ngspice -b " + deck_file + " > /dev/null 2>&1").c_str());  // exits 1 for "no .print lines"
  std::istringstream ng(slurp(data));
  std::vector<std::array<double, 4>> rows;
  for (std::array<double, 4> r{}; ng >> r[0] >> r[1] >> r[2] >> r[3];) rows.push_back(r);
  ASSERT_GE(rows.size(), 10001u) << "ngspice wrote no data";
  const Outcome d = run("simulate " + std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.cir --tstop 10 --step 0.001");
  ASSERT_EQ(d.rc, 0) << d.err;
  const auto ours = csv_rows(d.out);
  double ev = 0, ei = 0, sv = 0, si = 0;
  for (std::size_t k = 0; k < ours.size(); ++k) {
    ASSERT_NEAR(rows[k][0], ours[k][0], 1e-9);
    ev = std::max(ev, std::abs(rows[k][1] - ours[k][3] / 5));  // V(2) = q_C2 / C2
    ei = std::max(ei, std::abs(rows[k][3] - ours[k][5]));      // i(L1) = v_L1
    sv = std::max(sv, std::abs(rows[k][1]));
    si = std::max(si, std::abs(rows[k][3]));
  }
  std::cout << "ngspice vs dcad on the 4-port: V_C2 " << ev / sv << ", I_L " << ei / si << " (relative)\n";
  EXPECT_LT(ev / sv, 5e-7);
  EXPECT_LT(ei / si, 5e-7);
}

// Random small circuits (fixed seed, DCAD_PROP_SCALE more of them) in ngspice and in dcad: a shunt
// capacitor at every node (so no inductor-only cutset, and every inductor current is an admissible
// initial value), random extra L and C branches (parallel ones and capacitor loops included), IC=
// from random node potentials (KVL holds on every loop) and random inductor currents.  Compared:
// every node voltage (= q/C of its shunt capacitor) and every inductor current.
TEST(Simulate, RandomCircuitsAgreeWithNgspice) {
  if (std::system("command -v ngspice > /dev/null 2>&1") != 0)
    FAIL() << "ngspice not installed: run bash .ci/setup (the README's test command does)";
  const char* scale = std::getenv("DCAD_PROP_SCALE");
  const int circuits = 4 * (scale ? std::max(1, std::atoi(scale)) : 1);
  std::mt19937 rng(20261122);
  const auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  double worst = 0, worst_loose = 0;
  int tight = 0;
  for (int k = 0; k < circuits; ++k) {
    const int nodes = pick(2, 4);
    std::vector<int> potential(nodes + 1, 0);
    for (int i = 1; i <= nodes; ++i) potential[i] = pick(-3, 3);
    std::ostringstream deck;
    std::vector<std::string> inductors;
    deck << "random LC circuit " << k << "\n";
    int id = 0;
    const auto node = [](int i) { return i == 0 ? std::string("0") : "n" + std::to_string(i); };
    const auto capacitor = [&](int a, int b) {
      deck << "C" << ++id << " " << node(a) << " " << node(b) << " " << pick(1, 5)
           << " IC=" << potential[a] - potential[b] << "\n";
    };
    for (int i = 1; i <= nodes; ++i) capacitor(i, 0);  // C1 … C_nodes: node voltages
    const int extra = pick(2, 5);
    for (int e = 0; e < extra || inductors.empty(); ++e) {
      const int a = pick(0, nodes), b = pick(0, nodes);
      if (a == b) continue;
      if (pick(0, 2) == 0) {
        capacitor(a, b);
      } else {
        inductors.push_back("L" + std::to_string(++id));
        deck << inductors.back() << " " << node(a) << " " << node(b) << " " << pick(1, 3) << " IC=" << pick(-2, 2)
             << "\n";
      }
    }
    const std::string base = deck.str();
    const std::string data = temp_path("dcad_ngspice_random_" + std::to_string(k) + ".txt");
    std::filesystem::remove(data);
    std::string vectors;
    for (int i = 1; i <= nodes; ++i) vectors += " v(" + node(i) + ")";
    for (const std::string& l : inductors) vectors += " i(" + l + ")";
    // ngspice aborts ("timestep too small") on some capacitor loops at reltol 1e-10: then 1e-6
    std::string reltol = "1e-10", file;
    std::vector<std::vector<double>> rows;
    for (const std::string tol : {"1e-10", "1e-6"}) {
      reltol = tol;
      std::filesystem::remove(data);
      const std::string spice =
          base + ".options reltol=" + tol +
          " abstol=1e-15 vntol=1e-12 trtol=1\n.tran 1m 10 0 1m uic\n.control\nset numdgt=16\nrun\n"
          "linearize" +
          vectors + "\nwrdata " + data + vectors + "\n.endc\n.end\n";
      file = write_temp("dcad_random_" + std::to_string(k) + ".cir", spice);
      std::system(("ngspice -b " + file + " > /dev/null 2>&1").c_str());
      const std::size_t width = 2 * (nodes + inductors.size());
      std::istringstream ng(slurp(data));
      rows.clear();
      for (std::vector<double> r(width); [&] {
             for (double& x : r)
               if (!(ng >> x)) return false;
             return true;
           }();)
        rows.push_back(r);
      if (rows.size() >= 10001u && rows[1][0] > 0 && (rows[1][1] != 0 || rows[0][1] == 0)) break;  // not aborted
    }
    const std::size_t width = 2 * (nodes + inductors.size());
    ASSERT_GE(rows.size(), 10001u) << "ngspice wrote no data for\n" << base;
    const Outcome d = run("simulate " + file + " --tstop 10 --step 0.001");
    ASSERT_EQ(d.rc, 0) << d.err << "\n" << base;
    const std::vector<std::string> header = [&] {
      std::vector<std::string> h;
      std::istringstream line(d.out.substr(0, d.out.find('\n')));
      for (std::string cell; std::getline(line, cell, ',');) h.push_back(cell);
      return h;
    }();
    const auto column = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
    };
    const auto ours = csv_rows(d.out);
    std::vector<double> err(width / 2, 0), size(width / 2, 0);
    std::vector<double> cap(nodes + 1);
    for (std::string line : split_lines(base))
      if (line[0] == 'C' && std::stoi(line.substr(1)) <= nodes)
        cap[std::stoi(line.substr(1))] = std::stod(line.substr(line.find(" 0 ") + 3));
    for (std::size_t t = 0; t < ours.size(); ++t) {
      ASSERT_NEAR(rows[t][0], ours[t][0], 1e-9);
      for (int i = 1; i <= nodes; ++i) {
        const double v = ours[t][column("q_C" + std::to_string(i))] / cap[i];
        err[i - 1] = std::max(err[i - 1], std::abs(rows[t][2 * (i - 1) + 1] - v));
        size[i - 1] = std::max(size[i - 1], std::abs(v));
      }
      for (std::size_t l = 0; l < inductors.size(); ++l) {
        const double i = ours[t][column("v_" + inductors[l])];
        err[nodes + l] = std::max(err[nodes + l], std::abs(rows[t][2 * (nodes + l) + 1] - i));
        size[nodes + l] = std::max(size[nodes + l], std::abs(i));
      }
    }
    double rel = 0;  // relative to the largest signal of the circuit
    const double scale_all = *std::max_element(size.begin(), size.end());
    for (double e : err) rel = std::max(rel, e / std::max(scale_all, 1e-300));
    std::cout << "random circuit " << k << ": ngspice reltol " << reltol << ", max relative difference " << rel << "\n";
    if (reltol == "1e-10") {
      worst = std::max(worst, rel);
      ++tight;
      EXPECT_LT(rel, 2e-6) << base;  // measured up to 9e-7 over 20 circuits (5e-7 on the 4-port): ngspice's error
    } else {
      worst_loose = std::max(worst_loose, rel);
      EXPECT_LT(rel, 1e-5) << base;
    }
  }
  std::cout << circuits << " random circuits, ngspice vs dcad: " << tight << " at ngspice reltol 1e-10, worst " << worst
            << "; " << circuits - tight
            << " only at reltol 1e-6 (ngspice aborts on their capacitor loops at 1e-10), worst " << worst_loose << "\n";
  EXPECT_GE(tight, 1);
}

TEST(Simulate, PlotWritesAPng) {
  const std::string deck = std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.cir";
  EXPECT_EQ(run("simulate " + deck + " --tstop 1 --step 0.1 --plot /tmp/dcad_x.png --plot-vars q_C1,nope").rc, 2);
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    FAIL() << "gnuplot not installed: run bash .ci/setup (the README's test command does)";
  const std::string png = temp_path("dcad_plot.png");
  std::filesystem::remove(png);
  const Outcome r = run("simulate " + deck + " --tstop 20 --step 0.01 --plot " + png + " --plot-vars q_C1,q_C2,v_L1");
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_EQ(csv_rows(r.out).size(), 2001u);  // the CSV still goes to stdout
  EXPECT_EQ(slurp(png).substr(1, 3), "PNG");
}

// A netlist's state off M_c jumps onto it at t = 0 (CONTRACT "Circuit initial state"): C1 = 3 at 1 V
// and C3 = 7 at 5 V in parallel (the KVLPC loop C1–C3) share their charge 3 + 35 through an impulsive
// current around the loop — none through L1 — and meet at (3·1 + 7·5)/10 = 3.8 V: q_C1 = 11.4,
// q_C3 = 26.6; C2 and the inductor's flux keep theirs.  stderr names the jumps and the constraint.
TEST(Simulate, InitialConditionOffMcJumpsOntoIt) {
  std::string deck = slurp(fs::path(DCAD_SOURCE_DIR) / "cases/lc-4port.cir");
  deck.replace(deck.find("C3 1 2 7 IC=1"), 13, "C3 1 2 7 IC=5");
  const std::string file = write_temp("dcad_bad_ic.cir", deck);
  std::string err;
  const auto rows = simulate_rows(file, "--tstop 1 --step 0.1", &err);
  ASSERT_EQ(rows.size(), 11u) << err;
  EXPECT_NEAR(rows[0].at("q_C1"), 11.4, 1e-14);
  EXPECT_NEAR(rows[0].at("q_C3"), 26.6, 1e-14);
  EXPECT_EQ(rows[0].at("q_C2"), 10);
  EXPECT_EQ(rows[0].at("p_L1"), 0);
  EXPECT_NE(err.find("jump at t = 0: q_C1 from 3.0 to 11.4, forced by q_C1 - 3/7*q_C3 = 0"), std::string::npos) << err;
  EXPECT_EQ(err.find("jump at t = 0: q_C2"), std::string::npos) << err;
  EXPECT_EQ(run("simulate " + file + " --tstop 1 --step 0").rc, 1);
}

// A perfectly coupled transformer (k = 1, 10 µH and 40 µH, 1 nF on each winding) with L1 IC=1m and
// nothing on L2 (CONTRACT's example): the flux linkages are kept (no impulsive voltage can pass the
// capacitors), p = Φ i = (10 nWb, 20 nWb); M_c adds the ideal transformer's current ratio
// i_L2 = 2 i_L1 (C1 = C2), so i_L1 + 2 i_L2 = 1 mA gives 0.2 mA and 0.4 mA — ngspice's start too.
TEST(Simulate, PerfectTransformerKeepsItsFluxThroughTheJump) {
  const std::string file = write_temp(
      "dcad_k1.cir", "k = 1\nL1 a 0 10u IC=1m\nL2 b 0 40u\nK1 L1 L2 1\nC1 a 0 1n\nC2 b 0 1n\n.tran 1n 1u uic\n.end\n");
  std::string err;
  const auto rows = simulate_rows(file, "--tstop 1n --step 1n", &err);
  ASSERT_EQ(rows.size(), 2u) << err;
  EXPECT_NEAR(rows[0].at("v_L1"), 2e-4, 1e-19);
  EXPECT_NEAR(rows[0].at("v_L2"), 4e-4, 1e-19);
  EXPECT_NEAR(rows[0].at("p_L1"), 1e-8, 1e-23);
  EXPECT_NEAR(rows[0].at("p_L2"), 2e-8, 1e-23);
  EXPECT_NE(err.find("initial state: uic"), std::string::npos) << err;
  EXPECT_NE(err.find("jump at t = 0: v_L1 from 0.001 to 0.00020000000000000001"), std::string::npos) << err;
}

// SPICE's operating point (a .tran without uic): a series RLC on a 1 V DC supply starts with the
// capacitor charged to 1 V and no current, and stays there; --initial uic starts it from rest (the
// closed form of cases/rlc-series.cir); and a DC current source into a node with only capacitors has
// no operating point (exit 1, naming the law that fails).
TEST(Simulate, OperatingPointAsSpiceComputesIt) {
  const std::string deck = slurp(fs::path(DCAD_SOURCE_DIR) / "cases/rlc-series.cir");
  std::string op = deck;
  op.replace(op.find(" uic"), 4, "");
  const std::string file = write_temp("dcad_op.cir", op);
  std::string err;
  const auto rows = simulate_rows(file, "--tstop 1e-4 --step 1e-5", &err);
  ASSERT_EQ(rows.size(), 11u) << err;
  for (const auto& r : rows) {
    EXPECT_NEAR(r.at("q_C1"), 1e-6, 1e-18);
    EXPECT_NEAR(r.at("v_L1"), 0, 1e-15);
  }
  EXPECT_NE(err.find("initial state: the DC operating point (.tran without uic at"), std::string::npos) << err;
  // the exact solution is constant, so the run's true error is rounding: the estimate must say so (it
  // said 1.42 — the currents and fluxes are zero and were measured against their own rounding)
  const std::size_t at = err.find("estimated error ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_LT(std::stod(err.substr(at + 16)), 1e-12) << err;
  const auto rest = simulate_rows(file, "--tstop 1e-4 --step 1e-5 --initial uic", &err);
  ASSERT_EQ(rest.size(), 11u) << err;
  EXPECT_EQ(rest[0].at("q_C1"), 0);
  EXPECT_GT(rest[10].at("v_L1"), 1e-4);  // i(t) = V/(L wd) e^(-at) sin(wd t) > 0 on (0, pi/wd)
  // `.ic` holds its node through the operating point as ngspice does (a source there: KCL at the node
  // is the source's): a 2 V divider of 1k/1k with .ic v(2)=0.5 starts its capacitor at 0.5 V, not 1 V
  const std::string held =
      write_temp("dcad_op_ic.cir",
                 "divider with .ic\nV1 1 0 DC 2\nR1 1 2 1k\nR2 2 0 1k\nC1 2 0 1n\n.ic v(2)=0.5\n.tran 1n 1u\n.end\n");
  const auto ic = simulate_rows(held, "--tstop 1n --step 1n", &err);
  ASSERT_EQ(ic.size(), 2u) << err;
  EXPECT_NEAR(ic[0].at("q_C1"), 0.5e-9, 1e-24) << err;
  EXPECT_NEAR(ic[0].at("v_R1"), 1.5e-3, 1e-18) << err;  // (2 − 0.5)/1k once released
  const std::string none = write_temp("dcad_no_op.cir", "no DC path\nI1 0 a DC 1m\nC1 a 0 1n\n.tran 1n 1u\n.end\n");
  const Outcome r = run("simulate " + none + " --tstop 1u --step 1n");
  expect_input_error(r, none, "expected a DC operating point at t = 0", "a current source charging a capacitor");
}

// Series RLC from rest (cases/rlc-series.cir) against the closed form; the energy balance
// dE/dt = <F, q̇> (YM §4: −R v² dissipated, the source's V v supplied) holds at every row.
TEST(Forced, SeriesRlcMatchesClosedForm) {
  std::string err;
  const auto rows =
      simulate_rows(std::string(DCAD_SOURCE_DIR) + "/cases/rlc-series.cir", "--tstop 1e-3 --step 1e-6", &err);
  const double R = 10, L = 1e-3, C = 1e-6, V = 1, a = R / (2 * L), w0 = 1 / std::sqrt(L * C),
               wd = std::sqrt(w0 * w0 - a * a);
  double ei = 0, eq = 0, mi = 0, mq = 0;
  for (const auto& r : rows) {
    const double t = r.at("t"), i = V / (L * wd) * std::exp(-a * t) * std::sin(wd * t),
                 q = C * V * (1 - std::exp(-a * t) * (std::cos(wd * t) + a / wd * std::sin(wd * t)));
    ei = std::max(ei, std::abs(r.at("v_L1") - i));
    eq = std::max(eq, std::abs(r.at("q_C1") - q));
    mi = std::max(mi, std::abs(i));
    mq = std::max(mq, std::abs(q));
    EXPECT_DOUBLE_EQ(r.at("v_V1"), -r.at("v_L1"));  // KCL: one loop current
  }
  ASSERT_EQ(rows.size(), 1001u);
  EXPECT_LT(ei / mi, 1e-11);
  EXPECT_LT(eq / mq, 1e-11);
  EXPECT_LT(case_value(err, "holds to "), 1e-12) << err;
}

// Times as SPICE users write them (1m, 1u) give the same rows as 1e-3, 1e-6; a negative --tstop is
// bad input on every simulate route (the forced route printed "-9999999999 rows" with exit 0).
TEST(Simulate, TimesTakeSpiceSuffixesAndAreChecked) {
  const std::string deck = std::string(DCAD_SOURCE_DIR) + "/cases/rlc-series.cir";
  const Outcome plain = run("simulate " + deck + " --tstop 1e-4 --step 1e-6"),
                spice = run("simulate " + deck + " --tstop 0.1m --step 1u");
  ASSERT_EQ(plain.rc, 0) << plain.err;
  EXPECT_EQ(spice.rc, 0) << spice.err;
  EXPECT_EQ(spice.out, plain.out);
  for (const std::string& file : {deck, std::string(DCAD_SOURCE_DIR) + "/cases/lc-4port.cir"}) {
    const Outcome neg = run("simulate " + file + " --tstop -1 --step 1e-6");
    EXPECT_EQ(neg.rc, 1) << file;
    EXPECT_NE(neg.err.find("0 <= --tstop"), std::string::npos) << neg.err;
  }
  const Outcome bad = run("simulate " + deck + " --tstop 1e-3 --step fast");
  EXPECT_EQ(bad.rc, 2);
  EXPECT_NE(bad.err.find("--step: expected a time in seconds"), std::string::npos) << bad.err;
}

// RL step response: i(t) = V/R (1 − e^{−Rt/L}) (cases/rl-step.cir).
TEST(Forced, RlStepMatchesClosedForm) {
  const auto rows = simulate_rows(std::string(DCAD_SOURCE_DIR) + "/cases/rl-step.cir", "--tstop 5e-4 --step 1e-6");
  double e = 0;
  for (const auto& r : rows)
    e = std::max(e, std::abs(r.at("v_L1") - 5.0 / 100 * (1 - std::exp(-100 * r.at("t") / 10e-3))));
  EXPECT_LT(e / 0.05, 1e-12);
}

// RL driven by a damped sine (ngspice's SIN THETA): L i' + R i = V e^{−θt} sin ωt from i(0) = 0 has
// i = Im[V e^{st}/(R + Ls)] − Im[V/(R + Ls)] e^{−Rt/L}, s = −θ + iω. The exosystem carries the sine's
// decay on both of its components. Killed by: exo_generator's s(c+2, c+2) = decay dropped (seed-26 survivor [66]).
TEST(Forced, RlDampedSineMatchesClosedForm) {
  const std::string deck = write_temp(
      "dcad_rl_damped.cir", "RL driven by a damped sine\nV1 in 0 SIN(0 5 1k 0 500)\nR1 in a 100\nL1 a 0 10m\n.end\n");
  const std::string energy = write_temp("dcad_rl_damped_energy.csv", "");
  std::string err;
  const auto rows = simulate_rows(deck, "--tstop 4m --step 1u --energy " + energy, &err);
  const double V = 5, R = 100, L = 10e-3;
  const std::complex<double> s(-500, 2 * M_PI * 1000), z = V / (R + L * s);
  double e = 0, mag = 0;
  for (const auto& r : rows) {
    const double t = r.at("t"), i = (z * std::exp(s * t)).imag() - z.imag() * std::exp(-R * t / L);
    e = std::max(e, std::abs(r.at("v_L1") - i));
    mag = std::max(mag, std::abs(i));
  }
  ASSERT_EQ(rows.size(), 4001u);
  EXPECT_LT(e / mag, 1e-11) << "largest |i| " << mag;
  // YM §4's power balance dE/dt = ⟨−R v + V(t), q̇⟩ at every row, with the source's value at t.
  // Killed by: the sources' power taken from u's constant slot instead of σ(t) (seed-26 survivor [70];
  // the series RLC's DC 1 V cannot tell 1 from σ).
  EXPECT_LT(case_value(err, "holds to "), 1e-12) << err;
  // ... and integrated: E(T) − E(0) = W_forces + W_sources (+ W_affine) up to the trapezoid's error on
  // the output rows ((h ω)²/12 ≈ 3e-6 relative at h = 1 µs, ω = 2π kHz). Columns: t, E, the three powers,
  // the three works. Killed by: the sources' work integrated with weight 1/3 (seed-26 survivor [150]).
  const auto energy_rows = csv_rows(slurp(energy));
  ASSERT_EQ(energy_rows.size(), 4001u);
  const std::vector<double>&first = energy_rows.front(), &last = energy_rows.back();
  ASSERT_EQ(last.size(), 8u);
  const double w_forces = last[5], w_sources = last[6], w_affine = last[7];
  EXPECT_LT(w_forces, 0) << "the resistor dissipates";
  EXPECT_NEAR(last[1] - first[1], w_forces + w_sources + w_affine,
              1e-4 * std::max(std::abs(w_forces), std::abs(w_sources)))
      << "E(0) = " << first[1] << ", E(T) = " << last[1] << ", W_forces = " << w_forces
      << ", W_sources = " << w_sources;
}

// V1 (a PULSE with 1 ms edges) across C1 = 3 µF, feeding L1 = 1 mH in series with L2 = −1 mH ∥ C2 = 1 µF:
// L1 + L2 = 0 cancels the loop's inductance (CEF Remark 6.7: non-physical). By hand, from KVL and KCL (not
// from dcad's tower): V1 = L1 i_L1' + q_C2/C2 and i_L1 = i_C2 + i_L2 with L2 i_L2' = q_C2/C2 give
// L1 i_C2' = V1 (as L1 + L2 = 0), so v̇_C2 = 1000 V1(t) (v = current), q̇_C2 = v_C2, i_L1' = 1000 V1 − 10^9 q_C2;
// at node a the source carries −(i_C1 + i_L1), with i_C1 = C1 V1': v̇_V1 = 10^9 q_C2 − 1000 V1 − 3·10⁻⁶ V1''
// (dcad solve prints the same). Closed form: v_C2 = 1000 ∫V1, q_C2 = ∫v_C2 and v_V1 = ∫(10^9 q_C2 − 1000 V1)
// − 3·10⁻⁶ V1'(t): the source
// current jumps by −C1 ΔV1' at every corner (C1's current follows V1's slope; a row at a corner is the
// value after it). The corners are where M_c(t) moves with σ' (V §3): the rows there must be exact.
TEST(Forced, SourceCurrentJumpsAtPulseCorners) {
  const std::string deck =
      write_temp("dcad_pulse_corners.cir",
                 "cancelling inductors behind a CV loop\nV1 a 0 PULSE(0 1 1m 1m 1m 2m 10m)\nC1 a 0 3u\nL1 a b 1m\n"
                 "C2 b 0 1u\nL2 b 0 -1m\n.end\n");
  const auto rows = simulate_rows(deck, "--tstop 6m --step 10u");
  ASSERT_EQ(rows.size(), 601u);
  struct Piece {
    double t0, t1, a, b;  // V1 = a + b (t − t0) on [t0, t1)
  };
  const std::vector<Piece> pieces{
      {0, 1e-3, 0, 0}, {1e-3, 2e-3, 0, 1000}, {2e-3, 4e-3, 1, 0}, {4e-3, 5e-3, 1, -1000}, {5e-3, 1e-2, 0, 0}};
  double worst = 0, mag = 0, worst_c = 0, mag_c = 0;
  for (const auto& r : rows) {
    const double t = r.at("t");
    double v = 0, q = 0, w = 0, slope = 0;
    for (const Piece& p : pieces) {
      const double tau = std::min(t, p.t1) - p.t0;
      if (tau < 0) break;
      w += 1e9 * (q * tau + v * tau * tau / 2 + 1000 * (p.a * tau * tau * tau / 6 + p.b * tau * tau * tau * tau / 24)) -
           1000 * (p.a * tau + p.b * tau * tau / 2);
      q += v * tau + 1000 * (p.a * tau * tau / 2 + p.b * tau * tau * tau / 6);
      v += 1000 * (p.a * tau + p.b * tau * tau / 2);
      slope = p.b;
      if (t < p.t1 - 1e-12) break;
    }
    worst = std::max(worst, std::abs(r.at("v_V1") - (w - 3e-6 * slope)));
    mag = std::max(mag, std::abs(w));
    worst_c = std::max({worst_c, std::abs(r.at("v_C2") - v), std::abs(r.at("q_C2") - q) * 1e3});
    mag_c = std::max(mag_c, std::abs(v));
  }
  EXPECT_LT(worst / mag, 1e-12) << "largest |v_V1| " << mag << ", a jump of C1 ΔV1' is 3e-3";
  EXPECT_LT(worst_c / mag_c, 1e-12);
}

// A current source in an LI cutset (cases/li-cutset-isource.cir): KCL on the cutset holds along the
// trajectory, and the source branch carries exactly I(t) (a PULSE with 1 µs edges).
TEST(Forced, CurrentSourceFixesItsCutset) {
  const auto rows =
      simulate_rows(std::string(DCAD_SOURCE_DIR) + "/cases/li-cutset-isource.cir", "--tstop 3e-3 --step 1e-7");
  for (const auto& r : rows) {
    const double t = r.at("t");
    double i = 0;
    const double tau = std::fmod(t, 2e-3);
    i = tau < 1e-6       ? 1e-3 * tau / 1e-6
        : tau < 1.001e-3 ? 1e-3
        : tau < 1.002e-3 ? 1e-3 * (1 - (tau - 1.001e-3) / 1e-6)
                         : 0;
    EXPECT_NEAR(r.at("v_I1"), i, 1e-15 + 1e-9 * std::abs(i)) << "t = " << t;
    EXPECT_NEAR(r.at("v_L1") + r.at("v_L2"), r.at("v_I1"), 1e-15) << "t = " << t;
  }
}

// The report explains an inconsistent source configuration by element names.
TEST(Forced, InconsistentSourcesAreNamed) {
  const Outcome r = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/source-loop-inconsistent.cir");
  EXPECT_EQ(r.rc, 0);
  EXPECT_NE(r.out.find("loop of voltage sources +V2 -V1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("V1(t) - V2(t) = 0: FAILS"), std::string::npos) << r.out;
  const Outcome cv = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/cv-loop-sin.cir");
  EXPECT_NE(cv.out.find("CV loop +C1 -V1"), std::string::npos) << cv.out;
  const Outcome li = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/li-cutset-isource.cir");
  EXPECT_NE(li.out.find("LI cutset"), std::string::npos) << li.out;
}

// The tower of a CV loop written with the sources' jets (cases/cv-loop-sin.cir, C1 = 1u, C2 = 2u
// across V1): KVL around each loop on M_2, q_C/C = V1(t), and its time derivative on M_3,
// v_C = C V1'(t) (V §3: M_k(t) moves with the sources). Killed by: jet terms printed under the next
// jet's name (seed-26 survivor [96]; no test read a source term of a printed equation).
TEST(Forced, CvLoopTowerReadsKvlWithTheSourcesJets) {
  const Outcome r = run("solve " + std::string(DCAD_SOURCE_DIR) + "/cases/cv-loop-sin.cir --with none");
  ASSERT_EQ(r.rc, 0) << r.err;
  for (const char* eq : {"1000000*q_C1 - V1(t) = 0", "500000*q_C2 - V1(t) = 0", "-v_C1 + 1/1000000*V1'(t) = 0",
                         "-v_C2 + 1/500000*V1'(t) = 0"})
    EXPECT_NE(r.out.find(eq), std::string::npos) << eq << "\n" << r.out;
}

// A source's own current is KCL of its load: V1 across R1 = 1k and C1 = 1u draws V1/R1 + C1 V1'(t),
// so d/dt q_V1 = −V1(t)/1000 − V1'(t)/1000000 (the first coordinate, the only row with V1').
// Killed by: the scan for the jet orders that occur skipping the first row (seed-26 survivor [114]:
// the V1' term vanished from the printed equations of motion and from the JSON's S).
TEST(Forced, SourceCurrentIsKclOfItsLoad) {
  const std::string deck =
      write_temp("dcad_v_rc.cir", "V source across RC\nV1 a 0 SIN(0 1 1k)\nR1 a 0 1k\nC1 a 0 1u\n.end\n");
  const Outcome r = run("solve " + deck);
  ASSERT_EQ(r.rc, 0) << r.err;
  EXPECT_NE(r.out.find("d/dt q_V1 = -1/1000*V1(t) - 1/1000000*V1'(t)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("d/dt q_R1 = 1/1000*V1(t)"), std::string::npos) << r.out;
}

// ngspice on the same deck: its trapezoidal answer agrees with dcad's exact flow to its own
// tolerance (reltol 1e-6, tmax 100 ns), on the series RLC, the CV loop driven by a sine and the LI
// cutset fed by a pulsed current source.
TEST(Forced, AgreesWithNgspice) {
  if (std::system("command -v ngspice > /dev/null 2>&1") != 0) GTEST_SKIP() << "ngspice not installed";
  for (const auto& [deck, probe, var] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"rlc-series.cir", "i(l1)", "v_L1"},
                                                                      {"cv-loop-sin.cir", "i(l1)", "v_L1"},
                                                                      {"li-cutset-isource.cir", "i(l1)", "v_L1"}}) {
    const fs::path dir = fs::temp_directory_path() / ("dcad_ng_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ifstream src(std::string(DCAD_SOURCE_DIR) + "/cases/" + deck);
    std::ofstream ng(dir / "ng.cir");
    for (std::string line; std::getline(src, line);)
      if (line.rfind(".tran", 0) != 0 && line.rfind(".end", 0) != 0) ng << line << "\n";
    ng << ".options reltol=1e-6 abstol=1e-15\n.tran 1u 1m 0 100n uic\n.control\nset wr_singlescale\nrun\nlinearize "
       << probe << "\nwrdata " << (dir / "ng.txt").string() << " " << probe << "\n.endc\n.end\n";
    ng.close();
    // ngspice -b exits 1 on a deck whose output is written by .control (no .print): read the data
    (void)std::system(
        ("ngspice -b " + (dir / "ng.cir").string() + " > " + (dir / "ng.log").string() + " 2>&1").c_str());
    std::ifstream data(dir / "ng.txt");
    std::vector<std::pair<double, double>> ngs;
    for (double t, i; data >> t >> i;) ngs.emplace_back(t, i);
    ASSERT_GT(ngs.size(), 100u);
    const auto rows = simulate_rows(std::string(DCAD_SOURCE_DIR) + "/cases/" + deck, "--tstop 1e-3 --step 1e-6");
    double e = 0, mag = 0;
    for (std::size_t k = 0; k < rows.size() && k < ngs.size(); ++k) {
      ASSERT_NEAR(ngs[k].first, rows[k].at("t"), 1e-12);
      e = std::max(e, std::abs(ngs[k].second - rows[k].at(var)));
      mag = std::max(mag, std::abs(rows[k].at(var)));
    }
    EXPECT_LT(e / mag, 1e-3) << deck;
    fs::remove_all(dir);
  }
}

// A `pontryagin` case with `forces` (YM §4): two masses tied by v1 = v2 and damped on the first
// (cases/damped-constrained-pair.json). The trajectory is the damped oscillator of its description
// and the energy the damper dissipates is what E loses.
TEST(Forced, DampedConstrainedPairMatchesClosedForm) {
  const std::string file = std::string(DCAD_SOURCE_DIR) + "/cases/damped-constrained-pair.json";
  const std::string energy = write_temp("dcad_energy.csv", "");
  std::string err;
  const auto rows = simulate_rows(file, "--tstop 10 --step 0.01 --energy " + energy, &err);
  const double w = std::sqrt(10.0 / 3 - 0.25);
  double e = 0;
  for (const auto& r : rows) {
    const double t = r.at("t"), q = std::exp(-t / 2) * (std::cos(w * t) + std::sin(w * t) / (2 * w));
    e = std::max({e, std::abs(r.at("q1") - q), std::abs(r.at("q2") - q)});
  }
  EXPECT_LT(e, 1e-12);
  EXPECT_LT(case_value(err, "holds to "), 1e-12) << err;
  std::istringstream in(slurp(energy));
  std::string line, last;
  while (std::getline(in, line)) last = line;
  std::vector<double> col;
  std::istringstream l(last);
  for (std::string c; std::getline(l, c, ',');) col.push_back(std::stod(c));
  ASSERT_EQ(col.size(), 8u);
  EXPECT_NEAR(5.0 - col[1], -col[5], 1e-5);  // E(0) − E(T) = −W_forces (trapezoid on a 0.01 grid)
  // every route agrees; the unforced pipeline would have said dims [6, 3] too, but with no damping
  const Outcome fast = run("solve " + file + " --backend fast --json");
  ASSERT_EQ(fast.rc, 0) << fast.err;
  EXPECT_EQ(nlohmann::json::parse(fast.out)["dims"], nlohmann::json::parse("[6, 3]"));
}

// The issue-7 promise for forced decks: the same series RLC (Q = 1/R √(L/C) = 5 at every scale) at
// nH/fF, µH/nF and H/F meets its closed form to the same relative accuracy.
TEST(Forced, SeriesRlcAtEveryScale) {
  struct Scale {
    const char* l;
    const char* c;
    double lv, cv;
  };
  for (const Scale& s :
       {Scale{"10n", "100f", 10e-9, 100e-15}, Scale{"10u", "100n", 10e-6, 100e-9}, Scale{"10", "100m", 10.0, 0.1}}) {
    const double r = std::sqrt(s.lv / s.cv) / 5, v = 3;
    std::ostringstream deck;
    deck.precision(17);
    deck << "series RLC at " << s.l << "H " << s.c << "F\nV1 in 0 DC 3\nR1 in a " << r << "\nL1 a b " << s.l
         << "\nC1 b 0 " << s.c << "\n.end\n";
    const std::string file = write_temp("dcad_scale_rlc.cir", deck.str());
    const double period = 2 * M_PI * std::sqrt(s.lv * s.cv);
    std::ostringstream args;
    args.precision(17);
    args << "--tstop " << 3 * period << " --step " << period / 200;
    const auto rows = simulate_rows(file, args.str());
    const double a = r / (2 * s.lv), w0 = 1 / std::sqrt(s.lv * s.cv), wd = std::sqrt(w0 * w0 - a * a);
    double e = 0, mag = 0;
    for (const auto& row : rows) {
      const double t = row.at("t"), i = v / (s.lv * wd) * std::exp(-a * t) * std::sin(wd * t);
      e = std::max(e, std::abs(row.at("v_L1") - i));
      mag = std::max(mag, std::abs(i));
    }
    EXPECT_LT(e / mag, 1e-11) << s.l << "H, " << s.c << "F";
  }
}

// dcad check on a forced deck compares the equations of motion with their source terms: another
// simulator's result with the source's sign flipped (the classic SPICE convention slip) is caught.
TEST(Forced, CheckCatchesAFlippedSourceTerm) {
  const std::string deck = std::string(DCAD_SOURCE_DIR) + "/cases/rlc-series.cir";
  const Outcome r = run("solve " + deck + " --backend reference --json");
  ASSERT_EQ(r.rc, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  const Outcome same = run("check " + write_temp("dcad_forced_ok.json", j.dump()) + " " + deck);
  EXPECT_EQ(same.rc, 0) << same.out;
  EXPECT_NE(same.out.find("reduced.sources.S"), std::string::npos) << same.out;
  auto& s = j["reduced"]["sources"]["S"];
  for (auto& row : s)
    for (auto& x : row) {
      const std::string t = x.get<std::string>();
      x = t == "0" ? t : t[0] == '-' ? t.substr(1) : "-" + t;
    }
  const Outcome flipped = run("check " + write_temp("dcad_forced_bad.json", j.dump()) + " " + deck);
  EXPECT_EQ(flipped.rc, 3) << flipped.out;
  EXPECT_NE(flipped.out.find("reduced.sources.S: differs"), std::string::npos) << flipped.out;
}

// The exact flow does not depend on the output step, across PULSE corners and period boundaries.
// Regression: k·PER computed in double fell just short of the boundary, the substep took the
// waveform's previous piece, and one ramp per period was lost (5e-6 A on a 1 mA pulse, found by
// comparing steps 1 µs and 100 ns on a current source feeding an LI cutset).
TEST(Forced, StepIndependentAcrossPulseCorners) {
  const std::string deck = std::string(DCAD_SOURCE_DIR) + "/cases/li-cutset-isource.cir";
  const auto coarse = simulate_rows(deck, "--tstop 2.5e-3 --step 1e-6"),
             fine = simulate_rows(deck, "--tstop 2.5e-3 --step 1e-7");
  ASSERT_EQ(coarse.size(), 2501u);
  ASSERT_EQ(fine.size(), 25001u);
  double e = 0, mag = 0;
  for (std::size_t k = 0; k < coarse.size(); ++k)
    for (const char* v : {"v_L1", "v_L2", "q_C1"}) {
      e = std::max(e, std::abs(coarse[k].at(v) - fine[10 * k].at(v)));
      mag = std::max(mag, std::abs(coarse[k].at(v)));
    }
  EXPECT_LT(e / mag, 1e-10);
}

namespace {

/// Largest difference of the named columns between two runs, relative to the largest value.
double relative_gap(const std::vector<std::map<std::string, double>>& a,
                    const std::vector<std::map<std::string, double>>& b, std::initializer_list<const char*> columns) {
  EXPECT_EQ(a.size(), b.size());
  double gap = 0, mag = 0;
  for (std::size_t k = 0; k < std::min(a.size(), b.size()); ++k)
    for (const char* c : columns) {
      gap = std::max(gap, std::abs(a[k].at(c) - b[k].at(c)));
      mag = std::max(mag, std::abs(a[k].at(c)));
    }
  return mag > 0 ? gap / mag : 1.0;
}

std::string series_rlc(const std::string& name, const std::string& sources) {
  return write_temp(name + ".cir",
                    "series RLC, " + name + "\n" + sources + "R1 mid a 10\nL1 a b 1m\nC1 b 0 1u\n.end\n");
}

}  // namespace

// A PULSE is the PWL through its corners: the exact flow cuts its substeps at all four corners of every
// period (rise start, rise end, fall start, fall end), so both decks give the same rows.  Corners off
// the output grid; a corner left out (mutation test: the end of the fall) integrates a kink as a line.
// "DC 0.25" before PULSE is the operating point only (as in ngspice): the transient is the PULSE.
TEST(Forced, PulseEqualsItsPwlTwin) {
  const double td = 10.5e-6, tr = 3.3e-6, pw = 20.1e-6, tf = 7.7e-6, per = 50e-6;
  std::ostringstream pwl;
  pwl << std::setprecision(17) << "PWL(0 0";
  for (int k = 0; k < 4; ++k) {
    const double b = td + k * per;
    pwl << " " << b << " 0 " << b + tr << " 1 " << b + tr + pw << " 1 " << b + tr + pw + tf << " 0";
  }
  pwl << ")";
  const std::string pulse = series_rlc("dcad_pulse", "V1 mid 0 DC 0.25 PULSE(0 1 10.5u 3.3u 7.7u 20.1u 50u)\n"),
                    twin = series_rlc("dcad_pwl", "V1 mid 0 " + pwl.str() + "\n");
  const auto a = simulate_rows(pulse, "--tstop 200u --step 2u"), b = simulate_rows(twin, "--tstop 200u --step 2u");
  ASSERT_EQ(a.size(), 101u);
  EXPECT_LT(relative_gap(a, b, {"v_L1", "q_C1"}), 1e-9);
}

// Superposition: from rest, the response to two sources is the sum of the responses to each (the circuit
// is linear).  Two waveforms of different kinds share the exosystem; each has its own three states.
TEST(Forced, TwoSourcesSuperpose) {
  const std::string both = series_rlc("dcad_both", "V1 in 0 SIN(0 1 10k)\nV2 mid in PULSE(0 0.5 5u 2u 2u 10u 40u)\n"),
                    sine = series_rlc("dcad_sine", "V1 in 0 SIN(0 1 10k)\nV2 mid in DC 0\n"),
                    pulse = series_rlc("dcad_pulse2", "V1 in 0 DC 0\nV2 mid in PULSE(0 0.5 5u 2u 2u 10u 40u)\n");
  const std::string args = "--tstop 300u --step 3u";
  const auto ab = simulate_rows(both, args), a = simulate_rows(sine, args), b = simulate_rows(pulse, args);
  ASSERT_EQ(ab.size(), 101u);
  auto sum = a;
  for (std::size_t k = 0; k < sum.size() && k < b.size(); ++k)
    for (const char* c : {"v_L1", "q_C1"}) sum[k][c] += b[k].at(c);
  EXPECT_LT(relative_gap(ab, sum, {"v_L1", "q_C1"}), 1e-9);
  EXPECT_GT(relative_gap(a, sum, {"v_L1", "q_C1"}), 1e-2);  // both sources matter
}

// A SIN whose delay lies within rounding (5e-18 s) past an output time starts inside the next substep:
// its exosystem state is read at the substep's midpoint and carried back to the substep's start.  The
// rows equal those of the delay on the grid.
TEST(Forced, SinDelayWithinRoundingOfAnOutputTime) {
  const std::string on = series_rlc("dcad_sin_on", "V1 mid 0 SIN(0 1 10k 100u)\n"),
                    off = series_rlc("dcad_sin_off", "V1 mid 0 SIN(0 1 10k 1.00000000000005e-4)\n");
  const auto a = simulate_rows(on, "--tstop 500u --step 10u"), b = simulate_rows(off, "--tstop 500u --step 10u");
  ASSERT_EQ(a.size(), 51u);
  EXPECT_LT(relative_gap(a, b, {"v_L1", "q_C1"}), 1e-9);
}

// A capacitor across a source is on M_c(0) when charged to the source's value: q_C = C σ(0) (KVL of
// the loop, YM §4).  At C = 1u and 1n this is q_C = 1/1000000 and 3/2000000000, which the source's
// value taken in double (1e-6 ≠ 1/1000000) used to refuse as "off M_c(0)" — exact at realistic
// values, where every unit-valued test passed.  DC, PWL, and SIN at a quarter-turn phase (σ(0) = VO + VA).
TEST(Forced, CapacitorChargedToItsSourceIsOnMc) {
  const auto deck = [](const std::string& name, const std::string& c, const std::string& v) {
    return write_temp(name, "cap across a source\nC1 a 0 " + c + "\nV1 a 0 " + v + "\nR1 a 0 1k\n.end\n");
  };
  std::string err;
  const auto dc = simulate_rows(deck("dcad_cap_dc.cir", "1u IC=1", "DC 1"), "--tstop 1m --step 0.25m", &err);
  ASSERT_EQ(dc.size(), 5u) << err;
  for (const auto& row : dc) {
    EXPECT_NEAR(row.at("q_C1"), 1e-6, 1e-21);
    EXPECT_NEAR(row.at("v_R1"), 1e-3, 1e-18);  // 1 V across 1k
  }
  const auto sine =
      simulate_rows(deck("dcad_cap_sin.cir", "1n IC=1.5", "SIN(0.5 1 1k 0 0 90)"), "--tstop 1m --step 0.25m", &err);
  ASSERT_EQ(sine.size(), 5u) << err;
  EXPECT_NEAR(sine[0].at("q_C1"), 1.5e-9, 1e-24);
  EXPECT_NEAR(sine[2].at("q_C1"), 1e-9 * (0.5 + std::cos(2 * M_PI * 1e3 * 5e-4)), 1e-20);  // σ(t) = 0.5 + sin(ωt + π/2)
  const auto ramp =
      simulate_rows(deck("dcad_cap_pwl.cir", "1u IC=0.1", "PWL(0 0.1 1m 2.1)"), "--tstop 1m --step 0.25m", &err);
  ASSERT_EQ(ramp.size(), 5u) << err;
  EXPECT_NEAR(ramp[2].at("q_C1"), 1.1e-6, 1e-20);  // σ(0.5m) = 1.1 V
  EXPECT_NEAR(ramp[2].at("v_C1"), 2e-3, 1e-17);    // C σ' = 1u · 2000 V/s
  // a capacitor at 2 V across an ideal 1 V source takes the source's voltage at once (CONTRACT "Circuit
  // initial state": an impulsive current around the loop C1 V1 moves its charge to C·V = 1 µC)
  const std::string off = deck("dcad_cap_off.cir", "1u IC=2", "DC 1");
  const auto jumped = simulate_rows(off, "--tstop 1m --step 0.25m", &err);
  ASSERT_EQ(jumped.size(), 5u) << err;
  EXPECT_NEAR(jumped[0].at("q_C1"), 1e-6, 1e-21);
  EXPECT_NE(err.find("jump at t = 0: q_C1 from 1.9999999999999999e-06 to 9.9999999999999995e-07, forced by q_C1 - "
                     "1/1000000*V1(t) = 0"),
            std::string::npos)
      << err;
}

// An irrational mutual inductance (k·√(Lx·Ly) with L = 1u, 2u, 3u) is rounded to 80 digits, and three
// couplings of −1/2 make the inductance matrix singular whatever the L are (the coupling matrix has the
// kernel (1, 1, 1)): rounded, it reads as regular and the dense route's tower is the rounded circuit's.
// No backend may certify it.  With L = 1u each the same deck is exact, and its tower is derived by hand
// as the perfect transformer's: n = 6, 3 nodes: M_1 = 2n − 3 = 9, Φ's kernel gives the KVL combination
// Σ q_C/C = 0 (M_2: 8) and its derivative on the currents (M_3: 7) — certified on every backend.
TEST(Forced, IrrationalCouplingIsNotCertifiedWhereItDecides) {
  const auto deck = [](const std::string& l2, const std::string& l3) {
    return "three windings\nL1 1 0 1u\nC1 1 0 1n\nL2 2 0 " + l2 + "\nC2 2 0 1n\nL3 3 0 " + l3 +
           "\nC3 3 0 1n\nK12 L1 L2 -0.5\nK13 L1 L3 -0.5\nK23 L2 L3 -0.5\n.end\n";
  };
  const std::string rounded = write_temp("dcad_k3_rounded.cir", deck("2u", "3u")),
                    exact = write_temp("dcad_k3_exact.cir", deck("1u", "1u"));
  for (const std::string backend : {"reference", "fast", "certified"}) {
    const Outcome r = run("solve " + rounded + " --json --backend " + backend);
    ASSERT_EQ(r.rc, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["certified"].get<bool>()) << backend << " " << j["dims"];
    EXPECT_NE(j["note"].get<std::string>().find("rounded to 80 digits"), std::string::npos)
        << backend << " " << j["note"];
    const Outcome e = run("solve " + exact + " --json --backend " + backend);
    ASSERT_EQ(e.rc, 0) << e.err;
    const nlohmann::json k = nlohmann::json::parse(e.out);
    EXPECT_TRUE(k["certified"].get<bool>()) << backend << " " << k["note"];
    EXPECT_EQ(k["dims"], nlohmann::json::parse("[18, 9, 8, 7]")) << backend;
  }
}

// SIN(VO VA FREQ TD THETA PHASE) holds VO + VA sin(PHASE) before TD, as ngspice does (dcad held VO: a
// current source SIN(1m 2m 200k 1u 0 90) into 1k || 1n started at 1 V where ngspice starts at 3 V).
// Before TD the source is 3 mA, and the operating point charges C1 to 3 mA · 1k = 3 V: q = 3 nC.
TEST(Forced, SineHoldsItsPhaseBeforeItsDelay) {
  const std::string deck =
      write_temp("dcad_sin_td.cir", "isin\nI1 0 a SIN(1m 2m 200k 1u 0 90)\nR1 a 0 1k\nC1 a 0 1n\n.tran 10n 3u\n.end\n");
  std::string err;
  const auto rows = simulate_rows(deck, "--tstop 1u --step 0.25u", &err);
  ASSERT_EQ(rows.size(), 5u) << err;
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    EXPECT_NEAR(rows[k].at("v_I1"), 3e-3, 1e-15) << rows[k].at("t");
    EXPECT_NEAR(rows[k].at("q_C1"), 3e-9, 1e-20) << rows[k].at("t");
  }
}

// ngspice's tests/general/rc.cir: PULSE(0 1) takes PW = PER = TSTOP, so the pulse steps back to 0 at TSTOP
// itself.  The dense route refuses it as it refuses a step inside the run (and as simulate --certified
// does): its last row took the step's right side in the jets but not in the flow and printed q_C1 = -0.001
// for 0.999.  Ended a step before, the run is the RC's closed form: q(t) = 1·(t − 1 + e^{−t}) / 0.1 on the
// rise (TR = 0.1), then 1 − (1 − q(0.1)) e^{−(t − 0.1)}.
TEST(Simulate, PulseCutAtTheLastRowIsRefusedAndBeforeItIsTheClosedForm) {
  const std::string deck =
      write_temp("rc_pulse_default.cir", "rc\nV1 1 0 PULSE(0 1)\nR1 1 2 1\nC1 2 0 1\n.tran 0.1 7\n.end\n");
  expect_input_error(run("simulate " + deck + " --tstop 7 --step 0.1"), deck, "steps from 1 to V1 = 0 at t = 7",
                     "the step on the last row");
  const auto rows = simulate_rows(deck, "--tstop 6.9 --step 0.1 --vars q_C1");
  ASSERT_EQ(rows.size(), 70u);
  const double q1 = (0.1 - 1 + std::exp(-0.1)) / 0.1;
  for (const auto& row : rows) {
    const double t = row.at("t");
    const double exact = t <= 0.1 ? (t - 1 + std::exp(-t)) / 0.1 : 1 - (1 - q1) * std::exp(-(t - 0.1));
    EXPECT_NEAR(row.at("q_C1"), exact, 1e-12) << "t = " << t;
  }
}

// An EXP source is enclosed (issue 45 §1: EXP is analytic, so the enclosures take it): an RC charged through
// EXP(1 3 1m 2m 6m 0.5m) from uic, whose current i = (V − v_C)/R follows from τc v' = V − v segment by segment:
// on a segment from s0 with V = c + Σ a_k e^{−(t−t_k)/τ_k}, v = c + Σ a_k τ_k/(τ_k − τc) e^{−(t−t_k)/τ_k} + (the
// rest at s0) e^{−(t−s0)/τc}.  The certified midpoints hold it to 1e-15 of the 1 mA scale, the double route
// too (its σ' jumps at TD1 and TD2 were read off TD ± δ: 3e-10 off).
// A PWL repeated from R= (ngspice) drives an RC: the flow is the closed form of v' = (u − v)/RC on each linear
// piece of u, u(t) = a + b (t − t0): v = u − b RC + (v0 − a + b RC) e^{−(t−t0)/RC}, the pieces repeated from R.
// Found by `dcad check` of gnucap's output of the generator deck this twin writes out: the enclosure took the
// last point's hold (slope 0) instead of the repeat's rise there and certified 218.97 for 198.23 at t = 45.
// Killed by: exact_piece at the last point ignoring R=.
TEST(Simulate, RepeatedPwlIsEnclosedThroughItsRepeats) {
  const std::string deck =
      write_temp("rc_pwl_repeat.cir",
                 "rc pwl repeat\nV1 1 0 PWL(0 4 2 4 5 214 15 214 17 190 22 190 25 214 35 214 37 190 42 190) R=22\n"
                 "R1 1 2 10\nC1 2 0 1\n.end\n");
  std::vector<std::pair<double, double>> u = {{0, 4}, {2, 4}, {5, 214}, {15, 214}, {17, 190}, {22, 190}};
  for (double shift : {20.0, 40.0})
    for (const auto& [t, v] : std::vector<std::pair<double, double>>{{25, 214}, {35, 214}, {37, 190}, {42, 190}})
      u.push_back({t + shift - 20, v});
  const double tau = 10;
  const auto exact = [&](double t) {
    double v = 4;  // the operating point: u(0) = 4 across the capacitor
    for (std::size_t k = 0; k + 1 < u.size(); ++k) {
      const double b = (u[k + 1].second - u[k].second) / (u[k + 1].first - u[k].first), e = std::min(t, u[k + 1].first);
      v = u[k].second + b * (e - u[k].first) - b * tau +
          (v - u[k].second + b * tau) * std::exp(-(e - u[k].first) / tau);
      if (t <= u[k + 1].first) return v;
    }
    return v;
  };
  for (const char* how : {"", " --certified"}) {
    const std::vector<std::map<std::string, double>> rows =
        simulate_rows(deck, std::string("--tstop 60 --step 1 --initial op --vars q_C1") + how);
    ASSERT_EQ(rows.size(), 61u) << how;
    for (const auto& row : rows)
      EXPECT_NEAR(row.at("q_C1"), exact(row.at("t")), 1e-9 * 220) << how << " t = " << row.at("t");
  }
}

TEST(Simulate, ExpSourceIsEnclosedAndHoldsItsClosedForm) {
  const std::string deck =
      write_temp("rc_exp.cir", "rc exp\nV1 a 0 EXP(1 3 1m 2m 6m 0.5m)\nR1 a b 1k\nC1 b 0 1u\n.end\n");
  const double V1 = 1, V2 = 3, td1 = 1e-3, t1 = 2e-3, td2 = 6e-3, t2 = 0.5e-3, tc = 1e-3, R = 1e3;
  struct Term {
    double a, from, tau;
  };
  const auto segment = [&](double t, double s0, double v0, double c, const std::vector<Term>& terms) {
    double v = c, rest = v0 - c;
    for (const Term& k : terms) {
      const double g = k.a * k.tau / (k.tau - tc);
      v += g * std::exp(-(t - k.from) / k.tau);
      rest -= g * std::exp(-(s0 - k.from) / k.tau);
    }
    return v + rest * std::exp(-(t - s0) / tc);
  };
  const std::vector<Term> first{{V1 - V2, td1, t1}}, second{{V1 - V2, td1, t1}, {V2 - V1, td2, t2}};
  const double v_td1 = V1 * (1 - std::exp(-td1 / tc)), v_td2 = segment(td2, td1, v_td1, V2, first);
  const auto current = [&](double t) {
    if (t < td1) return V1 * std::exp(-t / tc) / R;
    if (t < td2) return (V2 + (V1 - V2) * std::exp(-(t - td1) / t1) - segment(t, td1, v_td1, V2, first)) / R;
    const double v = V1 + (V1 - V2) * std::exp(-(t - td1) / t1) + (V2 - V1) * std::exp(-(t - td2) / t2);
    return (v - segment(t, td2, v_td2, V1, second)) / R;
  };
  for (const char* how : {"", " --certified"}) {
    const Outcome o = run("simulate " + deck + " --tstop 10m --step 0.25m --vars v_C1" + how);
    ASSERT_EQ(o.rc, 0) << how << o.err;
    std::istringstream rows(o.out);
    std::string line;
    std::getline(rows, line);
    long n = 0;
    while (std::getline(rows, line)) {
      double t = 0, i = 0;
      ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf", &t, &i), 2) << line;
      EXPECT_NEAR(i, current(t), 1e-18) << how << " at " << line;  // 1e-15 of the 1 mA scale
      ++n;
    }
    EXPECT_EQ(n, 41) << how;
  }
}

// `simulate --certified`: what it cannot enclose is exit 1 naming why (never a plain double run
// passed off as enclosed), a case file is a usage error; --vars may name the radius columns; the
// series RLC's enclosed current holds its closed form i(t) = V/(L wd) e^(−αt) sin(wd t) (cases/rlc-series.cir).
TEST(Simulate, CertifiedEnclosesOrSaysWhyNot) {
  std::string ladder = "201 branches\nV1 n0 0 DC 1\n";
  for (int k = 0; k < 66; ++k)
    ladder += "R" + std::to_string(k) + " n" + std::to_string(k) + " m" + std::to_string(k) + " 1\nL" +
              std::to_string(k) + " m" + std::to_string(k) + " n" + std::to_string(k + 1) + " 1u\nC" +
              std::to_string(k) + " n" + std::to_string(k + 1) + " 0 1n\n";
  ladder += "R66 n66 0 1\nR67 n66 0 1\n";
  const Outcome big = run("simulate " + write_temp("ladder201.cir", ladder + ".end\n") +
                          " --tstop 1u --step 1n --certified --initial uic");
  EXPECT_EQ(big.rc, 1) << big.err;
  EXPECT_NE(big.err.find("up to 200 branches"), std::string::npos) << big.err;
  // the dense model asked for beyond its 60 branches; and a k = 1 coupling beyond them (outside the state equations)
  std::string k1 = "62 branches\nV1 a 0 DC 1\nR0 a b 1\nL1 b 0 10u\nL2 c 0 40u\nK1 L1 L2 1\nR1 c 0 1\n";
  for (int k = 0; k < 56; ++k) k1 += "R" + std::to_string(k + 2) + " c n" + std::to_string(k) + " 1\n";
  const Outcome dense = run("simulate " + write_temp("ladder201d.cir", ladder + ".end\n") +
                            " --tstop 1u --step 1n --certified --route dense --initial uic");
  EXPECT_EQ(dense.rc, 1) << dense.err;
  EXPECT_NE(dense.err.find("the dense model is built up to 60 branches"), std::string::npos) << dense.err;
  const Outcome coupled =
      run("simulate " + write_temp("k1-62.cir", k1 + ".end\n") + " --tstop 1u --step 1n --certified --initial uic");
  EXPECT_EQ(coupled.rc, 1) << coupled.err;
  EXPECT_NE(coupled.err.find("couplings |k| < 1"), std::string::npos) << coupled.err;
  const Outcome pi =
      run("simulate " + write_temp("sin30.cir", "phase 30\nV1 a 0 SIN(0 1 1k 0 0 30)\nR1 a b 1k\nC1 b 0 1u\n.end\n") +
          " --tstop 1m --step 1u --certified");
  EXPECT_EQ(pi.rc, 1) << pi.err;
  EXPECT_NE(pi.err.find("involves pi"), std::string::npos) << pi.err;
  const Outcome json = run("simulate " + std::string(DCAD_SOURCE_DIR) +
                           "/cases/harmonic-oscillator.json --tstop 1 --step 0.1 --certified");
  EXPECT_EQ(json.rc, 2) << json.err;
  const Outcome ok = run("simulate " + std::string(DCAD_SOURCE_DIR) +
                         "/cases/rlc-series.cir --tstop 1m --step 10u --certified --vars v_L1,rad_v");
  ASSERT_EQ(ok.rc, 0) << ok.err;
  std::istringstream rows(ok.out);
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line, "t,v_L1,rad_v");
  const double V = 1, R = 10, L = 1e-3, C = 1e-6, alpha = R / (2 * L), wd = std::sqrt(1 / (L * C) - alpha * alpha);
  long n = 0;
  while (std::getline(rows, line)) {
    double t = 0, i = 0, rad = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf", &t, &i, &rad), 3) << line;
    EXPECT_LE(rad, 1e-15 * 0.032) << line;  // the rounding of the printed double, of a current of at most 32 mA
    EXPECT_NEAR(i, V / (L * wd) * std::exp(-alpha * t) * std::sin(wd * t), 1e-14) << line;
    ++n;
  }
  EXPECT_EQ(n, 101);
}

// A motion that leaves its formulas' domain: x' = -1 from x = 1 with y = sqrt(x) reaches x = 0 at t = 1, where sqrt
// is not differentiable and beyond which it is not real.  Substeps are refined first (a stage outside the domain
// may only mean a step too long: the published Akzo Nobel problem on the test set's grid of 18 now runs through,
// bench/published_daes.py); where 4096 of them still leave it, exit 1 names the file, the time and the cause — it
// was exit 4, "internal error, please report" (issue 51).
TEST(Simulate, AStageOutsideTheFormulasDomainIsNamedNotInternal) {
  const std::string c = write_temp("leaves-domain.json", R"J({"dcad": 1, "name": "leaves-domain",
    "implicit": {"coordinates": ["x", "y"], "equations": ["v_x + 1", "y - sqrt(x)"], "time": "t"},
    "initial": {"x": "1"}})J");
  expect_input_error(run("simulate " + c + " --tstop 2 --step 0.5"), c, "domain", "a motion that leaves sqrt's domain");
}
