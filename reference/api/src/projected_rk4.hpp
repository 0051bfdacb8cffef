// RK4 on a vector field whose every evaluation projects the state onto M_c (the pointwise algorithms'
// own Newton completion), with Richardson step doubling per output step: shared by simulate on the
// expression form (simulate_lagrangian.cpp) and on the implicit form (simulate_implicit.cpp).
// Field: `At f(t, y)` with At::x the projection of y (its first y.size() entries are y's coordinates)
// and At::dx = d/dt of y's coordinates there.
#pragma once

#include "simulate.hpp"

#include "dcad/io/input_error.hpp"
#include "dcad/io/report.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <ostream>
#include <vector>

namespace dcad::api::projected {

inline std::vector<double> axpy(const std::vector<double>& y, double h, const std::vector<double>& k) {
  std::vector<double> out(y);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] += h * k[i];
  return out;
}

/// One RK4 step from (t, y) with y on M_c; returns the projection of the result onto M_c and
/// accumulates the size of that projection (relative) in `drift`.
template <class Field>
std::vector<double> rk4(Field& f, double t, const std::vector<double>& y, double h, double& drift) {
  const auto k1 = f(t, y).dx, k2 = f(t + h / 2, axpy(y, h / 2, k1)).dx, k3 = f(t + h / 2, axpy(y, h / 2, k2)).dx,
             k4 = f(t + h, axpy(y, h, k3)).dx;
  std::vector<double> next(y);
  for (std::size_t i = 0; i < y.size(); ++i) next[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  const auto p = f(t + h, next).x;
  double scale = 1, d = 0;
  for (std::size_t i = 0; i < next.size(); ++i) {
    scale = std::max(scale, std::abs(next[i]));
    d = std::max(d, std::abs(p[i] - next[i]));
  }
  drift = std::max(drift, d / scale);
  return std::vector<double>(p.begin(), p.begin() + static_cast<long>(next.size()));
}

inline double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0, s = 1;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, std::abs(a[i] - b[i]));
    s = std::max(s, std::abs(a[i]));
  }
  return d / s;
}

/// One row, flushed (rows are streamed: a user watching the file, or a pipe, sees them as they
/// come), and a progress line on the log every 2 s.
inline void write_row(RowSink& out, std::ostream& log, double time, const std::vector<double>& x, double tstop,
                      std::chrono::steady_clock::time_point& last) {
  std::vector<double> values = {time};
  values.insert(values.end(), x.begin(), x.end());
  out.row(values);
  out.flush();
  if (std::chrono::steady_clock::now() - last > std::chrono::seconds(2)) {
    last = std::chrono::steady_clock::now();
    log << "simulate: t = " << io::float_text(time) << " of " << io::float_text(tstop) << "\n";
  }
}

/// The running totals of one integration.
struct Richardson {
  long m = 1;  ///< substeps of the last output step (halved again where they agree far better)
  double estimate = 0, drift = 0;
  long substeps = 0;
  /// Where the refinement is said while it runs (never a silent wait: an output step can take minutes of
  /// substeps on a stiff or nearly singular stretch): a line at most every 2 s, and a note where 4096 substeps
  /// still differ by more than 1e-9 (the step is kept; its difference is the run's estimate).
  std::ostream* log = nullptr;
  std::chrono::steady_clock::time_point said = std::chrono::steady_clock::now();
  long capped = 0;  ///< output steps kept at 4096 substeps above 1e-9
};

/// y from t to t1: m and 2m RK4 substeps, m doubling until the two agree to 1e-9 relative (or m = 4096);
/// the 2m result is kept, their difference is the step's error estimate.
template <class Field>
void output_step(Field& f, double t, double t1, std::vector<double>& y, Richardson& r) {
  for (;;) {
    std::vector<double> a = y, b = y;
    double da = 0, db = 0;
    const double h = (t1 - t) / static_cast<double>(r.m);
    try {  // a stage that leaves the field's domain (no point of M_c near it, a root of a negative, an overflow)
           // says the substep is too long, not that the motion ends: the output grid is not the integrator's step
      for (long j = 0; j < r.m; ++j) a = rk4(f, t + static_cast<double>(j) * h, a, h, da);
      for (long j = 0; j < 2 * r.m; ++j) b = rk4(f, t + static_cast<double>(j) * h / 2, b, h / 2, db);
    } catch (const io::InputError&) {
      if (r.m >= 4096) throw;
      r.m *= 2;
      continue;
    }
    const double err = distance(b, a);
    if (r.log && std::chrono::steady_clock::now() - r.said > std::chrono::seconds(2)) {
      *r.log << "simulate: from t = " << io::float_text(t) << " to " << io::float_text(t1) << ": " << 2 * r.m
             << " RK4 substeps differ from " << r.m << " by " << io::float_text(err) << " (relative; refining)\n";
      r.said = std::chrono::steady_clock::now();
    }
    if (err > 1e-9 && r.m >= 4096 && r.log && r.capped++ == 0)
      *r.log << "note: from t = " << io::float_text(t) << " to " << io::float_text(t1)
             << ": 8192 RK4 substeps still differ from 4096 by " << io::float_text(err)
             << " (relative): kept, and the run's error estimate says so (explicit RK4 on a stiff or nearly singular "
                "stretch)\n";
    if (err <= 1e-9 || r.m >= 4096) {
      r.estimate = std::max(r.estimate, err);
      r.drift = std::max(r.drift, db);
      r.substeps += 2 * r.m;
      y = b;
      if (r.m > 1 && err < 1e-12) r.m /= 2;
      return;
    }
    r.m *= 2;
  }
}

/// The run's summary, and its log line: rows, substeps, evaluations of `what`, the error estimate and the
/// largest projection (the log's caller may add to the line before its newline).
inline Summary summary(long rows, const Richardson& r, long evaluations, const std::string& what, std::ostream& log) {
  Summary sum;
  sum.rows = rows;
  sum.error_estimate = r.estimate;
  sum.worst_variable = "(Richardson: m and 2m RK4 substeps)";
  log << "simulate: " << sum.rows << " rows, " << r.substeps << " RK4 substeps, " << evaluations << " evaluations of "
      << what << "; estimated error " << io::float_text(r.estimate)
      << " per output step (relative), largest projection onto M_c " << io::float_text(r.drift)
      << " (relative: the drift RK4 made and the projection removed)";
  return sum;
}

}  // namespace dcad::api::projected
