// Reading JSON with exact numbers — dcad::io's own (nlohmann_json is private to the readers; the
// pipeline's result reader for `dcad check` shares it inside the build tree).
#pragma once

#include "dcad/io/case_file.hpp"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dcad::io {

/// Parses JSON text keeping every non-integer number as its exact source text (a string), so
/// that 0.1 is read as 1/10, not as the double nearest to it.
/// Nesting deeper than 64 levels is refused (a case needs 4).
nlohmann::json parse_json_exact(const std::string& text, const std::string& file);
/// parse_json_exact of a file's contents (InputError if it cannot be read).
nlohmann::json read_json_file(const std::string& file);
/// The file's contents (InputError if it cannot be read).
std::string slurp(const std::string& file);

/// A reading context: file name plus JSON path, for messages.
struct Where {
  std::string file, path;
  Where operator/(const std::string& key) const { return {file, path + "/" + key}; }
  Where operator/(std::size_t i) const { return {file, path + "/" + std::to_string(i)}; }
  [[noreturn]] void fail(const std::string& expected, const std::string& found) const;
};

/// The allowed name closest to `key` (edit distance, case-insensitive) if it is close enough to be a
/// likely misspelling, else "".
std::string nearest_name(const std::string& key, const std::vector<std::string>& allowed);

/// Bad input unless every key of the object `j` is one of `allowed` (a misspelt key would otherwise
/// be ignored and another system solved); the message suggests the nearest allowed key.
void require_known_keys(const nlohmann::json& j, const Where& at, const std::vector<std::string>& allowed);

/// The optional "published" block of a case gathered from a published source (the DAE benchmark set,
/// cases/published/): {"source": text, "index": integer ≥ 0, "interval": [t0, t1], "solution": {"t": number,
/// "values": {name: number}}}, every key but "source" optional, names among `names`, numbers exact strings.
/// Provenance and the source's own values: checked, not used by the solvers (bench/published_daes.py compares).
void check_published(const nlohmann::json& j, const Where& root, const std::vector<std::string>& names);

Rational read_number(const nlohmann::json& j, const Where& at);
QMatrix read_matrix(const nlohmann::json& j, const Where& at, long rows = -1, long cols = -1);
std::string describe(const nlohmann::json& j);
std::vector<Rational> read_vector(const nlohmann::json& j, const Where& at, long size);

}  // namespace dcad::io
