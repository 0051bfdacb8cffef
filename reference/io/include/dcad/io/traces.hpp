// Another simulator's transient output (CONTRACT "Checking a simulator's waveform"): ngspice raw files
// (binary and ASCII, from `-r` or `write`), ngspice `wrdata` tables (with `set wr_vecnames`), gnucap's
// `.print tran` tables, and CSV whose first column is time.  Read as written — the file's own time
// points and vector names; nothing is interpolated or renamed here.
#pragma once

#include <string>
#include <vector>

namespace dcad::io {

struct Traces {
  std::string file;
  std::string format;                       ///< "ngspice raw (binary)", "ngspice raw (ascii)", "ngspice wrdata", "gnucap", "csv"
  std::vector<std::string> names;           ///< the vectors after time, as the file names them
  std::vector<double> time;                 ///< the file's time points (nondecreasing)
  std::vector<std::vector<double>> values;  ///< values[k][i]: vector k at time[i]
  /// Lines skipped inside the table, each "FILE:LINE: \"text\"" (gnucap writes step-control messages such
  /// as "zero time step" between its rows; the rows after them are read, and the check says so).
  std::vector<std::string> skipped;
};

/// Traces built in code held to what the readers guarantee: at least one time point, finite and
/// nondecreasing times, one name per vector and one value per time point in each (InputError naming the
/// field, expected and found).  dcad::api::check_waveform calls it first.
void validate(const Traces& t);

/// Reads FILE, recognising its format from its content.  Bad input (an unknown format, a truncated
/// file, a non-numeric value, times that decrease, an AC or complex plot) is InputError naming the
/// file, the line or byte offset, what was expected and what was found.
Traces read_traces(const std::string& file);
/// The same from text already read (`name` in messages).
Traces parse_traces(const std::string& text, const std::string& name);

/// Whether the file's content is JSON (a result for `dcad check RESULT FILE`) rather than traces.
bool looks_like_json(const std::string& file);

/// A number as gnucap prints it: a decimal with an optional scale letter (a f p n u m K Meg G T),
/// e.g. "10.n", "-3.4567m", "1.2K".  False when `text` is not one.
bool parse_scaled(const std::string& text, double& value);

}  // namespace dcad::io
