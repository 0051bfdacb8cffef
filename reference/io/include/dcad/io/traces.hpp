// Another simulator's transient output (CONTRACT "Checking a simulator's waveform"): ngspice raw files
// (binary and ASCII, from `-r` or `write`), ngspice `wrdata` tables (with `set wr_vecnames`), gnucap's
// `.print tran` tables, and CSV whose first column is time.  Read as written — the file's own time
// points and vector names; nothing is interpolated or renamed here.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace dcad::io {

struct Traces {
  std::string file;
  std::string format;              ///< "ngspice raw (binary)", "ngspice raw (ascii)", "ngspice wrdata", "gnucap", "csv"
  std::vector<std::string> names;  ///< the vectors after time, as the file names them
  std::vector<double> time;        ///< the file's time points (nondecreasing)
  std::vector<std::vector<double>> values;  ///< values[k][i]: vector k at time[i]
  /// Lines skipped inside the table, each "FILE:LINE: \"text\"" (gnucap writes step-control messages such
  /// as "zero time step" between its rows; the rows after them are read, and the check says so).
  std::vector<std::string> skipped;
  /// What the reader took beyond the format's letter, each said by `dcad check` ("FILE: …"): an ngspice raw
  /// file whose header says 'No. Points: 0' and whose data follows (a run the simulator aborted).
  std::vector<std::string> notes;
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

/// A simulator's output read point by point in time order, in chunks: `dcad check` in bounded memory
/// whatever the file's size.  An ngspice binary raw file whose one plot is the transient (what `ngspice -b
/// -r` writes) is read from disk as it goes; every other file is read whole (read_traces) and served from
/// memory.  Times are checked as they come (finite, nondecreasing: InputError naming the point).
class TraceStream {
 public:
  virtual ~TraceStream() = default;
  const std::string& file() const { return file_; }
  const std::string& format() const { return format_; }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& skipped() const { return skipped_; }
  const std::vector<std::string>& notes() const { return notes_; }
  std::size_t points() const { return points_; }
  double first_time() const { return first_; }
  double last_time() const { return last_; }
  /// Back to the first point (a check reads the file once per enclosure precision).
  virtual void rewind() = 0;
  /// The next (up to) `max` points: their times in `t`, vector k's values in `v[k]`; false at the end.
  virtual bool next(std::size_t max, std::vector<double>& t, std::vector<std::vector<double>>& v) = 0;

 protected:
  std::string file_, format_;
  std::vector<std::string> names_, skipped_, notes_;
  std::size_t points_ = 0;
  double first_ = 0, last_ = 0;
};

/// FILE as a stream (the formats and errors of read_traces).
std::unique_ptr<TraceStream> open_traces(const std::string& file);
/// Traces already in memory as a stream (`t` must outlive it), validated first (validate).
std::unique_ptr<TraceStream> stream_of(const Traces& t);

/// Whether the file's content is JSON (a result for `dcad check RESULT FILE`) rather than traces.
bool looks_like_json(const std::string& file);

/// A number as gnucap prints it: a decimal with an optional scale letter (a f p n u m K Meg G T),
/// e.g. "10.n", "-3.4567m", "1.2K".  False when `text` is not one.
bool parse_scaled(const std::string& text, double& value);

}  // namespace dcad::io
