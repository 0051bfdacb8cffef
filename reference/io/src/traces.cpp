// Simulator output readers (dcad/io/traces.hpp).
#include "dcad/io/traces.hpp"

#include "dcad/io/input_error.hpp"
#include "dcad/io/report.hpp"

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <memory>

namespace dcad::io {

namespace {

[[noreturn]] void bad(const std::string& where, const std::string& expected, const std::string& found) {
  throw InputError(where + ": expected " + expected + ", found " + found);
}

std::string at_line(const std::string& file, std::size_t line) { return file + ":" + std::to_string(line); }

std::string shown(const std::string& s) {
  std::string t = s.size() > 60 ? s.substr(0, 60) + "…" : s;
  return "'" + t + "'";
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::string lower(std::string s) {
  for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return s;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> w;
  std::string x;
  while (in >> x) w.push_back(x);
  return w;
}

/// The trimmed fields of a comma-separated line; commas inside parentheses or double quotes do not
/// split (a header's "v(in,out)"), and the quotes are removed.
std::vector<std::string> comma_fields(const std::string& l) {
  std::vector<std::string> w(1);
  int depth = 0;
  bool quoted = false;
  for (char ch : l) {
    if (ch == '"')
      quoted = !quoted;
    else if (!quoted && ch == '(')
      ++depth, w.back() += ch;
    else if (!quoted && ch == ')')
      --depth, w.back() += ch;
    else if (!quoted && depth <= 0 && ch == ',')
      w.emplace_back();
    else
      w.back() += ch;
  }
  for (std::string& f : w) f = trim(f);
  return w;
}

/// A plain floating-point number (all of `text`), finite.
bool plain(const std::string& text, double& v) {
  if (text.empty()) return false;
  const char* s = text.c_str();
  char* end = nullptr;
  v = std::strtod(s, &end);
  return end == s + text.size() && std::isfinite(v);
}

/// Lines with their numbers (1-based), text split at '\n' (a trailing '\r' dropped).
struct Lines {
  std::vector<std::string> text;
  explicit Lines(const std::string& all, std::size_t limit = std::string::npos) {
    std::size_t s = 0;
    const std::size_t end = std::min(limit, all.size());
    while (s < end) {
      std::size_t e = all.find('\n', s);
      if (e == std::string::npos || e > end) e = end;
      std::string l = all.substr(s, e - s);
      if (!l.empty() && l.back() == '\r') l.pop_back();
      text.push_back(l);
      s = e + 1;
    }
  }
};

/// Times t ≥ 0, nondecreasing; `line_of[i]` is point i's line in the file (tables), else the point's number is named.
void check_times(const Traces& t, const std::vector<std::size_t>& line_of = {}) {
  if (t.time.empty()) bad(t.file, "at least one time point", "none");
  const auto where = [&](std::size_t i) {
    return line_of.empty() ? t.file + ": point " + std::to_string(i + 1) : at_line(t.file, line_of[i]);
  };
  for (std::size_t i = 0; i < t.time.size(); ++i) {
    if (t.time[i] < 0) bad(where(i), "times t >= 0 (the flow starts at 0)", "t = " + float_text(t.time[i]));
    if (i && t.time[i] < t.time[i - 1])
      bad(where(i), "nondecreasing times", "t = " + float_text(t.time[i]) + " after " + float_text(t.time[i - 1]));
  }
}

// ---------------------------------------------------------------- ngspice raw
/// An ngspice ascii raw file's `npoints` points from `pos` ("index value" then a value per line, blank lines
/// between points) into `data`; bad input names the line.
void read_ascii_points(const std::string& text, const std::string& file, const std::vector<std::string>& names,
                       long npoints, bool complex, std::size_t& pos, std::size_t& line_no, std::vector<double>& data) {
  for (long p = 0; p < npoints; ++p) {
    for (std::size_t k = 0; k < names.size(); ++k) {
      std::vector<std::string> w;
      while (w.empty()) {  // ngspice separates points by a blank line
        if (pos >= text.size())
          bad(file, std::to_string(npoints) + " points", std::to_string(p) + ": the file is truncated");
        std::size_t e = text.find('\n', pos);
        if (e == std::string::npos) e = text.size();
        w = words(text.substr(pos, e - pos));
        pos = e + 1;
        ++line_no;
      }
      if (k == 0) w.erase(w.begin());  // the point's index
      if (complex) bad(at_line(file, line_no), "a real (transient) plot", "a complex one");
      if (w.size() != 1)
        bad(at_line(file, line_no), "one value of " + names[k],
            w.empty() ? "none" : shown(w[0]) + (w.size() > 1 ? " and more" : ""));
      double v = 0;
      if (!plain(w[0], v)) bad(at_line(file, line_no), "a number for " + names[k], shown(w[0]));
      data.push_back(v);
    }
  }
}

/// A binary plot's points after 'No. Points: 0': ngspice writes the count when the run ends, so a run it
/// aborted ("Timestep too small") leaves 0 with the points it wrote after it — read, with a note.  0 where
/// the next plot follows (its 'Title:' or 'Plotname:').
long aborted_points(const std::string& text, std::size_t pos, std::size_t per, const std::string& file,
                    std::vector<std::string>& notes) {
  const std::size_t left = text.size() - std::min(pos, text.size());
  const std::size_t ahead = text.find_first_not_of(" \t\r\n", std::min(pos, text.size()));
  const std::string after = ahead == std::string::npos ? "" : lower(text.substr(ahead, 9));
  if (after.rfind("title:", 0) == 0 || after == "plotname:") return 0;
  if (left % (per * sizeof(double)) != 0)
    bad(file, "'No. Points: 0' and then whole points of " + std::to_string(per) + " doubles (an aborted run)",
        std::to_string(left) + " bytes, not a multiple of " + std::to_string(per * sizeof(double)));
  const long n = static_cast<long>(left / (per * sizeof(double)));
  notes.push_back(file + ": 'No. Points: 0' with " + std::to_string(n) +
                  " points after it: a run the simulator aborted (ngspice leaves the count at 0 then); "
                  "its points up to there are checked");
  return n;
}

/// A raw file's plot header, from `pos` up to its "Values:" or "Binary:" line (both advanced past it).
struct RawHeader {
  std::string plotname, flags;
  long npoints = -1;
  std::vector<std::string> names;
  bool binary = false, found_data = false;
};

RawHeader read_raw_header(const std::string& text, const std::string& file, std::size_t& pos, std::size_t& line_no) {
  RawHeader h;
  long nvars = -1;
  while (pos < text.size()) {
    std::size_t e = text.find('\n', pos);
    if (e == std::string::npos) e = text.size();
    std::string l = text.substr(pos, e - pos);
    if (!l.empty() && l.back() == '\r') l.pop_back();
    pos = e + 1;
    ++line_no;
    const std::string key = lower(trim(l.substr(0, l.find(':') == std::string::npos ? 0 : l.find(':') + 1)));
    const std::string val = l.find(':') == std::string::npos ? "" : trim(l.substr(l.find(':') + 1));
    if (key == "plotname:")
      h.plotname = val;
    else if (key == "flags:")
      h.flags = lower(val);
    else if (key == "no. variables:") {
      double count = 0;
      if (!plain(val, count) || (nvars = std::atol(val.c_str())) < 1)
        bad(at_line(file, line_no), "a positive number of variables", shown(val));
    } else if (key == "no. points:") {
      h.npoints = std::atol(val.c_str());
      if (h.npoints < 0) bad(at_line(file, line_no), "a number of points", shown(val));
    } else if (key == "variables:") {
      if (nvars < 1) bad(at_line(file, line_no), "'No. Variables:' before 'Variables:'", "none");
      for (long k = 0; k < nvars; ++k) {
        std::size_t e2 = text.find('\n', pos);
        if (e2 == std::string::npos)
          bad(at_line(file, line_no + 1), std::to_string(nvars) + " variable lines", "the end of the file");
        const std::vector<std::string> w = words(text.substr(pos, e2 - pos));
        pos = e2 + 1;
        ++line_no;
        if (w.size() < 3) bad(at_line(file, line_no), "'index name type'", shown(w.empty() ? "" : w[0]));
        h.names.push_back(w[1]);
      }
    } else if (key == "values:" || key == "binary:") {
      h.binary = key == "binary:";
      h.found_data = true;
      break;
    }
  }
  return h;
}

Traces raw(const std::string& text, const std::string& file) {
  // plots follow one another; take the first transient one
  std::size_t pos = 0;
  std::size_t line_no = 0;
  while (pos < text.size()) {
    Traces t;
    t.file = file;
    RawHeader h = read_raw_header(text, file, pos, line_no);
    const std::string &plotname = h.plotname, &flags = h.flags;
    const std::vector<std::string>& names = h.names;
    const bool binary = h.binary, found_data = h.found_data;
    long npoints = h.npoints;
    if (!found_data) bad(file, "an ngspice raw file with 'Values:' or 'Binary:' after its header", "no data section");
    if (npoints < 0 || names.empty())
      bad(at_line(file, line_no), "'No. Points:' and 'Variables:' before the data", "neither");
    const bool complex = flags.find("complex") != std::string::npos;
    const bool transient = lower(plotname).find("transient") != std::string::npos;
    const std::size_t per = static_cast<std::size_t>(names.size()) * (complex ? 2 : 1);
    if (complex && transient) bad(file, "a real transient plot", "complex values (flags: " + flags + ")");
    std::vector<double> data;
    const std::size_t left = text.size() - std::min(pos, text.size());
    if (binary && npoints == 0 && left > 0) npoints = aborted_points(text, pos, per, file, t.notes);
    if (static_cast<double>(npoints) * static_cast<double>(per) * (binary ? 8.0 : 2.0) >
        static_cast<double>(left))  // 2 bytes: a digit and a separator
      bad(file,
          std::to_string(npoints) + " points of " + std::to_string(per) + " values after '" +
              (binary ? "Binary:" : "Values:") + "' (the header's count)",
          std::to_string(left) + " bytes: the file is truncated");
    data.reserve(per * static_cast<std::size_t>(npoints));
    if (binary) {
      const std::size_t need = per * static_cast<std::size_t>(npoints) * sizeof(double);
      if (left < need)
        bad(file,
            std::to_string(npoints) + " points of " + std::to_string(per) + " doubles (" + std::to_string(need) +
                " bytes) after 'Binary:'",
            std::to_string(text.size() - std::min(pos, text.size())) + " bytes: the file is truncated");
      data.resize(per * static_cast<std::size_t>(npoints));
      if (need > 0) std::memcpy(data.data(), text.data() + pos, need);  // (no points: data() may be null)
      pos += need;
    } else {
      read_ascii_points(text, file, names, npoints, complex, pos, line_no, data);
    }
    // after the points: nothing, or the next plot's header (the header's count is the truth of the data)
    const std::size_t next = text.find_first_not_of(" \t\r\n", std::min(pos, text.size()));
    if (next != std::string::npos && lower(text.substr(next, 6)) != "title:" &&
        lower(text.substr(next, 9)) != "plotname:")
      bad(file, std::to_string(npoints) + " points as 'No. Points:' says, then the end of the file or another plot",
          "more data after them (" + std::to_string(text.size() - next) + " bytes)");
    if (!transient) continue;  // an operating point or another analysis before the transient plot
    if (next != std::string::npos &&
        lower(text.substr(std::min(pos, text.size()))).find("transient") != std::string::npos)
      bad(file, "one transient plot (dcad checks one run against its deck)",
          "another transient plot after '" + plotname + "': write one plot per file");
    if (lower(names[0]) != "time") bad(file, "time as the raw file's first variable", shown(names[0]));
    t.format = binary ? "ngspice raw (binary)" : "ngspice raw (ascii)";
    t.names.assign(names.begin() + 1, names.end());
    t.values.assign(t.names.size(), std::vector<double>(static_cast<std::size_t>(npoints)));
    for (long p = 0; p < npoints; ++p) {
      const double* row = data.data() + static_cast<std::size_t>(p) * per;
      if (!std::isfinite(row[0])) bad(file, "finite times", "a non-finite time at point " + std::to_string(p + 1));
      t.time.push_back(std::abs(row[0]));  // ngspice marks a breakpoint's time negative in some versions
      for (std::size_t k = 1; k < names.size(); ++k) t.values[k - 1][static_cast<std::size_t>(p)] = row[k];
    }
    check_times(t);
    return t;
  }
  bad(file, "a transient plot in the ngspice raw file", "none (only other analyses)");
}

// ---------------------------------------------------------------- tables: wrdata, gnucap, CSV
using Parse = bool (*)(const std::string&, double&);

/// Rows of numbers after a header line `head` (1-based line `first`), split by `split`.
Traces table(const Lines& lines, std::size_t head, const std::vector<std::string>& header, const std::string& file,
             const std::string& format, Parse number, bool commas, bool stop_at_text) {
  Traces t;
  t.file = file;
  t.format = format;
  std::vector<std::vector<double>> cols(header.size());
  std::vector<std::size_t> line_of;
  for (std::size_t i = head + 1; i < lines.text.size(); ++i) {
    const std::string l = trim(lines.text[i]);
    if (l.empty()) continue;
    const std::vector<std::string> w = commas ? comma_fields(l) : words(l);
    double first = 0;
    if (stop_at_text && !number(w[0], first)) {
      if (l[0] == '#') break;  // gnucap: the next analysis's header ("#Time …")
      // gnucap: a message between rows ("zero time step", "newtime=… rejectedtime=…"): the table goes on
      // after it — stopping there read 47 of 10^4 rows and passed the run (issue 28's corpus, tight settings)
      t.skipped.push_back(at_line(file, i + 1) + ": \"" + l + "\"");
      continue;
    }
    if (w.size() != header.size())
      bad(at_line(file, i + 1), std::to_string(header.size()) + " columns as in the header", std::to_string(w.size()));
    for (std::size_t k = 0; k < w.size(); ++k) {
      double v = 0;
      if (!number(w[k], v))
        bad(at_line(file, i + 1), "a number in column " + std::to_string(k + 1) + " (" + header[k] + ")", shown(w[k]));
      cols[k].push_back(v);
    }
    line_of.push_back(i + 1);
  }
  t.time = cols[0];
  for (std::size_t k = 1; k < header.size(); ++k) {
    t.names.push_back(header[k]);
    t.values.push_back(cols[k]);
  }
  check_times(t, line_of);
  return t;
}

Traces wrdata(const Lines& lines, std::size_t head, const std::string& file) {
  const std::vector<std::string> h = words(lines.text[head]);
  // `set wr_singlescale`: time, then the vectors; otherwise (time, vector) pairs
  bool pairs = h.size() >= 2 && h.size() % 2 == 0;
  for (std::size_t k = 0; pairs && k < h.size(); k += 2) pairs = lower(h[k]) == "time";
  Traces all = table(lines, head, h, file, "ngspice wrdata", plain, false, false);
  if (!pairs) return all;
  Traces t;
  t.file = file;
  t.format = all.format;
  t.time = all.time;
  for (std::size_t k = 1; k < h.size(); k += 2) {
    if (k > 1) {  // the repeated time column must be the first one
      const std::vector<double>& again = all.values[k - 2];
      for (std::size_t i = 0; i < again.size(); ++i)
        if (again[i] != t.time[i])
          bad(at_line(file, head + 2 + i), "the same time in every (time, vector) pair",
              "t = " + std::to_string(again[i]) + " beside " + std::to_string(t.time[i]));
    }
    t.names.push_back(h[k]);
    t.values.push_back(all.values[k - 1]);
  }
  return t;
}

}  // namespace

bool parse_scaled(const std::string& text, double& value) {
  std::size_t n = 0;
  const char* s = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (end == s) return false;
  n = static_cast<std::size_t>(end - s);
  const std::string rest = text.substr(n);
  double scale = 1;
  if (rest.empty())
    scale = 1;
  else if (rest == "a")
    scale = 1e-18;
  else if (rest == "f")
    scale = 1e-15;
  else if (rest == "p")
    scale = 1e-12;
  else if (rest == "n")
    scale = 1e-9;
  else if (rest == "u")
    scale = 1e-6;
  else if (rest == "m")
    scale = 1e-3;
  else if (rest == "K" || rest == "k")
    scale = 1e3;
  else if (rest == "Meg" || rest == "MEG" || rest == "meg")
    scale = 1e6;
  else if (rest == "G")
    scale = 1e9;
  else if (rest == "T")
    scale = 1e12;
  else
    return false;
  value = v * scale;
  return std::isfinite(value);
}

Traces parse_traces(const std::string& text, const std::string& file) {
  // raw files begin with "Title:" (binary data follows a text header: look at the header only)
  const std::size_t lead = text.find_first_not_of(" \t\r\n");
  if (lead == std::string::npos)
    bad(file, "a simulator's output (ngspice raw or wrdata, gnucap .print, CSV)", "an empty file");
  if (lower(text.substr(lead, 6)) == "title:") return raw(text, file);
  const bool complete = text.back() == '\n';  // ngspice's and gnucap's tables end every line
  const std::size_t binary_at = text.find("\nBinary:");
  const Lines lines(text, binary_at == std::string::npos ? std::string::npos : binary_at);
  for (std::size_t i = 0; i < lines.text.size(); ++i) {
    const std::string l = trim(lines.text[i]);
    if (l.empty()) continue;
    if (!complete && (lower(l.substr(0, 5)) == "#time" || lower(words(l)[0]) == "time") &&
        l.find(',') == std::string::npos)
      bad(file, "a table whose last line ends with a newline, as ngspice and gnucap write them",
          "a last line without one: the file is truncated");
    if (lower(l.substr(0, 5)) == "#time") {  // gnucap: "#Time  v(out) ...", after its banner
      std::vector<std::string> h = words(l);
      h[0] = "time";
      return table(lines, i, h, file, "gnucap", parse_scaled, false, true);
    }
    const std::vector<std::string> w = words(l);
    double v = 0;
    const std::string first = l.find(',') == std::string::npos ? "" : lower(comma_fields(l)[0]);
    if (first == "time" || first == "t") {  // CSV: the first column is time
      return table(lines, i, comma_fields(l), file, "csv", plain, true, false);
    }
    if (lower(w[0]) == "time") return wrdata(lines, i, file);
    if (plain(w[0], v))
      bad(at_line(file, i + 1),
          "a header line naming the vectors (ngspice: `set wr_vecnames` before `wrdata`; CSV: a header row whose first "
          "column is time)",
          "numbers");
    // gnucap's banner and the deck's title come before its table
    if (i > 40) break;
  }
  bad(file,
      "a simulator's output: an ngspice raw file (Title: …), a wrdata table with `set wr_vecnames`, gnucap's .print "
      "table (#Time …) or CSV with a time column",
      "none of these");
}

Traces read_traces(const std::string& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw InputError(file + ": expected a simulator's output file, found a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": expected a readable file, found none");
  std::ostringstream s;
  s << in.rdbuf();
  return parse_traces(s.str(), file);
}

namespace {

/// Traces in memory, served in chunks (borrowed, or owned when read from a file).
class MemoryStream final : public TraceStream {
 public:
  MemoryStream(const Traces& t, std::unique_ptr<Traces> owned) : owned_(std::move(owned)), t_(owned_ ? *owned_ : t) {
    file_ = t_.file, format_ = t_.format, names_ = t_.names, skipped_ = t_.skipped, notes_ = t_.notes,
    points_ = t_.time.size();
    first_ = t_.time.empty() ? 0.0 : t_.time.front(), last_ = t_.time.empty() ? 0.0 : t_.time.back();
  }
  void rewind() override { pos_ = 0; }
  bool next(std::size_t max, std::vector<double>& t, std::vector<std::vector<double>>& v) override {
    const std::size_t n = std::min(max, points_ - std::min(pos_, points_));
    t.assign(t_.time.begin() + static_cast<std::ptrdiff_t>(pos_),
             t_.time.begin() + static_cast<std::ptrdiff_t>(pos_ + n));
    v.resize(t_.values.size());
    for (std::size_t k = 0; k < v.size(); ++k)
      v[k].assign(t_.values[k].begin() + static_cast<std::ptrdiff_t>(pos_),
                  t_.values[k].begin() + static_cast<std::ptrdiff_t>(pos_ + n));
    pos_ += n;
    return n > 0;
  }

 private:
  std::unique_ptr<Traces> owned_;
  const Traces& t_;
  std::size_t pos_ = 0;
};

/// An ngspice binary raw file's only plot, a real transient, read from disk `max` points at a time.
class RawStream final : public TraceStream {
 public:
  RawStream(const std::string& file, std::ifstream in, std::streamoff data, std::size_t per, std::size_t points,
            std::vector<std::string> names)
      : in_(std::move(in)), data_(data), per_(per) {
    file_ = file, format_ = "ngspice raw (binary)", names_ = std::move(names), points_ = points;
    first_ = time_at(0), last_ = time_at(points - 1);
    rewind();
  }
  void rewind() override {
    pos_ = 0;
    previous_ = -HUGE_VAL;
    in_.clear();
    in_.seekg(data_);
  }
  bool next(std::size_t max, std::vector<double>& t, std::vector<std::vector<double>>& v) override {
    const std::size_t n = std::min(max, points_ - pos_);
    buffer_.resize(n * per_);
    if (n > 0 &&
        !in_.read(reinterpret_cast<char*>(buffer_.data()), static_cast<std::streamsize>(n * per_ * sizeof(double))))
      bad(file_, std::to_string(points_) + " points after 'Binary:'",
          "a read error at point " + std::to_string(pos_ + 1));
    t.resize(n);
    v.assign(per_ - 1, std::vector<double>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const double* row = buffer_.data() + i * per_;
      // as read_traces: ngspice marks a breakpoint's time negative in some versions
      if (!std::isfinite(row[0]))
        bad(file_, "finite times", "a non-finite time at point " + std::to_string(pos_ + i + 1));
      t[i] = std::abs(row[0]);
      if (t[i] < previous_)
        bad(file_ + ": point " + std::to_string(pos_ + i + 1), "nondecreasing times",
            "t = " + float_text(t[i]) + " after " + float_text(previous_));
      previous_ = t[i];
      for (std::size_t k = 1; k < per_; ++k) v[k - 1][i] = row[k];
    }
    pos_ += n;
    return n > 0;
  }

 private:
  double time_at(std::size_t point) {
    double x = 0;
    in_.clear();
    in_.seekg(data_ + static_cast<std::streamoff>(point * per_ * sizeof(double)));
    if (!in_.read(reinterpret_cast<char*>(&x), sizeof x) || !std::isfinite(x))
      bad(file_, "finite times", "a non-finite time at point " + std::to_string(point + 1));
    return std::abs(x);
  }
  std::ifstream in_;
  std::streamoff data_;
  std::size_t per_, pos_ = 0;
  double previous_ = -HUGE_VAL;
  std::vector<double> buffer_;
};

/// The stream of an ngspice binary raw file whose one plot is a real transient with time first and
/// exactly its points after 'Binary:', or null (read_traces then reads it, and says what is wrong).
std::unique_ptr<TraceStream> raw_stream(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::string line, plotname, flags;
  long nvars = -1, npoints = -1;
  std::vector<std::string> names;
  if (!std::getline(in, line) || lower(trim(line)).rfind("title:", 0) != 0) return nullptr;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t colon = line.find(':');
    const std::string key = lower(trim(line.substr(0, colon == std::string::npos ? 0 : colon + 1)));
    const std::string val = colon == std::string::npos ? "" : trim(line.substr(colon + 1));
    if (key == "plotname:")
      plotname = lower(val);
    else if (key == "flags:")
      flags = lower(val);
    else if (key == "no. variables:") {
      double count = 0;
      if (!plain(val, count)) return nullptr;  // read_traces says what is wrong
      nvars = std::atol(val.c_str());
    } else if (key == "no. points:")
      npoints = std::atol(val.c_str());
    else if (key == "variables:") {
      if (nvars < 1 || nvars > 1000000) return nullptr;
      for (long k = 0; k < nvars; ++k) {
        if (!std::getline(in, line)) return nullptr;
        const std::vector<std::string> w = words(line);
        if (w.size() < 3) return nullptr;
        names.push_back(w[1]);
      }
    } else if (key == "values:") {
      return nullptr;
    } else if (key == "binary:") {
      break;
    }
  }
  if (!in || line.rfind("Binary:", 0) != 0 || npoints < 1 || names.size() < 2 ||
      static_cast<long>(names.size()) != nvars)
    return nullptr;
  if (plotname.find("transient") == std::string::npos || flags.find("complex") != std::string::npos ||
      lower(names[0]) != "time")
    return nullptr;
  const std::streamoff data = in.tellg();
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  const std::size_t per = names.size();
  if (ec || data < 0 ||
      static_cast<double>(size) !=
          static_cast<double>(data) + static_cast<double>(npoints) * static_cast<double>(per) * 8.0)
    return nullptr;
  names.erase(names.begin());
  return std::make_unique<RawStream>(file, std::move(in), data, per, static_cast<std::size_t>(npoints),
                                     std::move(names));
}

}  // namespace

std::unique_ptr<TraceStream> open_traces(const std::string& file) {
  std::error_code ec;
  if (!std::filesystem::is_directory(file, ec)) {
    std::ifstream probe(file, std::ios::binary);
    if (probe)
      if (std::unique_ptr<TraceStream> s = raw_stream(file)) return s;
  }
  auto owned = std::make_unique<Traces>(read_traces(file));
  const Traces& t = *owned;
  return std::make_unique<MemoryStream>(t, std::move(owned));
}

std::unique_ptr<TraceStream> stream_of(const Traces& t) {
  validate(t);
  return std::make_unique<MemoryStream>(t, nullptr);
}

bool looks_like_json(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  char ch = 0;
  while (in.get(ch))
    if (!std::isspace(static_cast<unsigned char>(ch))) return ch == '{' || ch == '[';
  return false;
}

}  // namespace dcad::io
