// dcad_sweep: every method on every family where methods fail (issue 6), against the exact answer.
//
//   dcad_sweep [--quick] [--out DIR] [--seed S] [--reps R]
//       writes DIR/sweep.csv (one row per family × parameter × method) and DIR/instances.jsonl
//       (the presymplectic instances, exact, for the Python peers in bench/peers/).
//   dcad_sweep --adversarial COUNT [--seed S]
//       only `certified` against the exact answer on COUNT instances cycling through all families;
//       prints the number of wrong answers (the goal is 0) and of exact recomputations.
//
// Wrong = dims or solution rank differ from the planted answer (or from the reference where
// nothing is planted), or the method threw.  Angle = the largest principal angle between T M_k
// computed and exact, maximized over the tower (π/2 where the dimensions differ).
#include "methods.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace fam = dcad::families;
using dcad::bench::Outcome;

namespace {

struct Exact {
  std::vector<long> dims;
  long solution_rank = 0;
  std::vector<Eigen::MatrixXd> tower;
};

bool wrong(const Outcome& o, const Exact& e) {
  return o.failed || o.dims != e.dims || o.solution_rank != e.solution_rank;
}

double tower_angle(const Outcome& o, const Exact& e) {
  if (o.failed || o.dims != e.dims) return 1.5707963267948966;
  double worst = 0;
  for (std::size_t k = 0; k < e.tower.size(); ++k)
    worst = std::max(worst, dcad::bench::largest_angle(o.tower[k], e.tower[k]));
  return worst;
}

std::string json_matrix(const fam::QM& m) {
  std::string s = "[";
  for (dcad::reference::Index i = 0; i < m.rows(); ++i) {
    s += i ? ",[" : "[";
    for (dcad::reference::Index j = 0; j < m.cols(); ++j) s += (j ? ",\"" : "\"") + m(i, j).str() + "\"";
    s += "]";
  }
  return s + "]";
}

/// T M_k bases (columns) as [[row, …], …] per k, in double: the peers' angles are against these.
std::string json_tower(const std::vector<Eigen::MatrixXd>& t) {
  std::string s = "[";
  char buf[32];
  for (std::size_t k = 0; k < t.size(); ++k) {
    s += k ? ",[" : "[";
    for (Eigen::Index i = 0; i < t[k].rows(); ++i) {
      s += i ? ",[" : "[";
      for (Eigen::Index j = 0; j < t[k].cols(); ++j) {
        std::snprintf(buf, sizeof buf, "%s%.17g", j ? "," : "", t[k](i, j));
        s += buf;
      }
      s += "]";
    }
    s += "]";
  }
  return s + "]";
}

void progress(long done, long total, const std::string& what) {
  static long shown = -1;  // redraw only when the percentage changes (logs stay short)
  const long pct = total ? 100 * done / total : 100;
  if (pct == shown && done != total) return;
  shown = pct;
  const int width = 30, fill = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r[%s%s] %3ld%%  %-40s", std::string(fill, '#').c_str(), std::string(width - fill, ' ').c_str(),
               total ? 100 * done / total : 100, what.c_str());
  if (done == total) std::fprintf(stderr, "\n");
}

struct Plan {
  std::string family;
  std::vector<double> params;
  int reps;
  std::function<fam::Instance(double, std::mt19937_64&)> make;
};

std::vector<Plan> plans(bool quick, int reps) {
  const int r = reps > 0 ? reps : (quick ? 6 : 40);
  std::vector<double> sizes =
      quick ? std::vector<double>{2, 4, 6, 8, 10} : std::vector<double>{2, 4, 6, 8, 10, 12, 16, 20, 32};
  return {
      {"graded",
       {1e2, 1e4, 1e6, 1e8, 1e10, 1e12, 1e14, 1e16},
       r,
       [](double k, std::mt19937_64& g) { return fam::graded(k, g); }},
      {"perturbed",
       {10, 20, 30, 40, 50, 60},
       r,
       [](double k, std::mt19937_64& g) { return fam::perturbed(static_cast<int>(k), g); }},
      {"tower",
       {1, 2, 3, 4, 5},
       r,
       [](double m, std::mt19937_64& g) { return fam::tower(static_cast<fam::Index>(m), g); }},
      {"lc", {0, 3, 6, 9, 12, 15}, r, [](double s, std::mt19937_64& g) { return fam::lc(s, g); }},
      {"cancel",
       {2, 4, 8, 12, 16},
       r,
       [](double d, std::mt19937_64& g) { return fam::cancel(static_cast<int>(d), g); }},
      {"size", sizes, std::max(2, r / 8),
       [](double m, std::mt19937_64& g) { return fam::graded(1e2, g, static_cast<fam::Index>(m), "size"); }},
  };
}

Exact exact_answer(const fam::Instance& in, const Outcome& ref) {
  Exact e{ref.dims, ref.solution_rank, ref.tower};
  if (in.planted && (in.dims != ref.dims || in.solution_rank != ref.solution_rank)) {
    std::fprintf(stderr, "\nGENERATOR BUG: %s(%g): planted answer differs from the reference\n", in.family.c_str(),
                 in.param);
    std::exit(1);
  }
  return e;
}

int adversarial(long count, unsigned long seed) {
  std::mt19937_64 rng(seed);
  const auto ps = plans(false, 1);
  long wrong_answers = 0, recomputed = 0, machine_words = 0, done = 0;
  std::map<std::string, long> per_family;
  while (done < count) {
    for (const Plan& p : ps) {
      if (p.family == "size") continue;
      for (double param : p.params) {
        if (done >= count) break;
        const fam::Instance in = p.make(param, rng);
        const Outcome c = dcad::bench::run_certified(in);
        Exact e;
        if (in.planted) {
          e.dims = in.dims;
          e.solution_rank = in.solution_rank;
        } else {
          const Outcome r = dcad::bench::run_mpq(in);  // independent of SmallRational
          e.dims = r.dims;
          e.solution_rank = r.solution_rank;
        }
        if (wrong(c, e)) {
          ++wrong_answers;
          std::fprintf(stderr, "\nWRONG: certified on %s(%g)\n", in.family.c_str(), param);
        }
        recomputed += c.recomputed;
        machine_words += c.machine_words;
        ++per_family[p.family];
        if (++done % 1000 == 0 || done == count) progress(done, count, "adversarial: certified vs exact");
      }
    }
  }
  std::printf(
      "certified on %ld adversarial instances (seed %lu): %ld wrong; %ld exact in machine words, %ld recomputed in "
      "fmpq\n",
      count, seed, wrong_answers, machine_words, recomputed);
  for (const auto& [f, n] : per_family) std::printf("  %s: %ld\n", f.c_str(), n);
  return wrong_answers == 0 ? 0 : 3;
}

}  // namespace

/// Runs per method and instance; the time reported is the fastest (mean_seconds: the mean over instances of that).
constexpr int kTimings = 3;

int main(int argc, char** argv) {
  bool quick = false;
  std::string out = ".";
  unsigned long seed = 20261122;
  int reps = 0;
  long adv = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "dcad_sweep: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--quick")
      quick = true;
    else if (a == "--out")
      out = next();
    else if (a == "--seed")
      seed = std::stoul(next());
    else if (a == "--reps")
      reps = std::stoi(next());
    else if (a == "--adversarial")
      adv = std::stol(next());
    else {
      std::fprintf(stderr,
                   "usage: dcad_sweep [--quick] [--out DIR] [--seed S] [--reps R] | --adversarial COUNT [--seed S]\n");
      return 2;
    }
  }
  if (adv > 0) return adversarial(adv, seed);

  const std::vector<std::pair<std::string, dcad::bench::Method>> methods = {
      {"reference", dcad::bench::run_reference},
      {"bf100", dcad::bench::run_bf100},
      {"bf50", dcad::bench::run_bf50},
      {"naive", dcad::bench::run_naive},
      {"fast", dcad::bench::run_fast},
      {"certified", dcad::bench::run_certified},
      // the exact tiers, each alone (issue 26): machine words are `certified`'s first tier above
      {"tier_fmpq", dcad::bench::run_fmpq},
      {"tier_flint", dcad::bench::run_flint},
      {"tier_mpq", dcad::bench::run_mpq},
      {"tier_ball", dcad::bench::run_ball},
      {"tier_arb", dcad::bench::run_arb}};
  std::ofstream csv(out + "/sweep.csv"), jsonl(out + "/instances.jsonl");
  if (!csv || !jsonl) {
    std::fprintf(stderr, "dcad_sweep: cannot write to %s\n", out.c_str());
    return 2;
  }
  csv << "family,param,n,method,instances,wrong,wrong_claimed_certain,uncertain,recomputed,max_angle,mean_seconds,"
         "machine_words\n";
  std::mt19937_64 rng(seed);
  const auto ps = plans(quick, reps);
  long total = 0, done = 0;
  for (const Plan& p : ps) total += static_cast<long>(p.params.size()) * p.reps;
  for (const Plan& p : ps) {
    for (double param : p.params) {
      struct Acc {
        long wrong = 0, wrong_certain = 0, uncertain = 0, recomputed = 0, machine_words = 0;
        double angle = 0, seconds = 0;
      };
      std::vector<Acc> acc(methods.size());
      long n = 0;
      for (int r = 0; r < p.reps; ++r) {
        const fam::Instance in = p.make(param, rng);
        n = static_cast<long>(in.n());
        // each method's time on an instance is the best of kTimings consecutive runs (one run of
        // ~100 µs is dominated by cache state and by whichever method ran before it)
        std::vector<Outcome> outs(methods.size());
        for (std::size_t m = 0; m < methods.size(); ++m) {
          double best = std::numeric_limits<double>::infinity();
          for (int t = 0; t < kTimings; ++t) {
            const auto t0 = std::chrono::steady_clock::now();
            outs[m] = methods[m].second(in);
            best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
          }
          acc[m].seconds += best;
        }
        const Exact e = exact_answer(in, outs[0]);
        for (std::size_t m = 0; m < methods.size(); ++m) {
          acc[m].wrong += wrong(outs[m], e);
          acc[m].wrong_certain += wrong(outs[m], e) && !outs[m].uncertain;
          acc[m].uncertain += outs[m].uncertain;
          acc[m].recomputed += outs[m].recomputed;
          acc[m].machine_words += outs[m].machine_words;
          acc[m].angle = std::max(acc[m].angle, tower_angle(outs[m], e));
        }
        if (!in.pontryagin)
          jsonl << "{\"family\":\"" << in.family << "\",\"param\":" << param << ",\"omega\":" << json_matrix(in.omega)
                << ",\"hessian\":" << json_matrix(in.hessian) << ",\"dims\":[" <<
              [&] {
                std::string s;
                for (long d : e.dims) s += (s.empty() ? "" : ",") + std::to_string(d);
                return s;
              }()
                << "],\"solution_rank\":" << e.solution_rank << ",\"tower\":" << json_tower(e.tower) << "}\n";
        progress(++done, total, p.family + " " + std::to_string(param).substr(0, 8));
      }
      for (std::size_t m = 0; m < methods.size(); ++m)
        csv << p.family << ',' << param << ',' << n << ',' << methods[m].first << ',' << p.reps << ',' << acc[m].wrong
            << ',' << acc[m].wrong_certain << ',' << acc[m].uncertain << ',' << acc[m].recomputed << ',' << acc[m].angle
            << ',' << acc[m].seconds / p.reps << ',' << acc[m].machine_words << "\n";
    }
  }
  std::fprintf(stderr, "wrote %s/sweep.csv and %s/instances.jsonl (seed %lu)\n", out.c_str(), out.c_str(), seed);
  return 0;
}
