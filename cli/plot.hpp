// `dcad simulate --plot OUT.png`: a PNG of chosen columns of the simulation CSV, drawn by gnuplot
// (Debian package gnuplot-nox, installed by .ci/setup).
#pragma once

#include <string>
#include <vector>

namespace dcad::cli {

/// The names of `wanted` (comma-separated; empty = every q_* column, or every column if none) as
/// 1-based CSV columns of `header` (column 1 is t).  Throws std::invalid_argument naming an unknown one.
std::vector<std::size_t> plot_columns(const std::vector<std::string>& header, const std::string& wanted);

/// Runs gnuplot on the CSV file; returns "" or what went wrong.
std::string plot_png(const std::string& csv_file, const std::vector<std::string>& header,
                     const std::vector<std::size_t>& columns, const std::string& png, const std::string& title);

/// `dcad check WAVEFORM DECK --plot OUT.png`: one panel per vector of `names` — the simulator's values
/// (points), the exact waveform (line) and the worst point marked — from a CSV t, found_1, exact_1, ….
std::string plot_check_png(const std::string& csv_file, const std::vector<std::string>& names,
                           const std::vector<double>& worst_t, const std::vector<double>& worst_found,
                           const std::string& png, const std::string& title);

}  // namespace dcad::cli
