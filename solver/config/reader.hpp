#pragma once
// Strict reader over a parsed TOML file: every lookup is recorded, so that after
// parsing, keys nobody asked for are reported (with the nearest known key as a
// suggestion). All errors name the file, the dotted key and what was expected.
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "core/types.hpp"

namespace narwhal {

// The values a numeric key accepts. Every number read from a case must be finite;
// a Range narrows it further, and its description goes into the error message.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range at_least(double lo) { return {lo, std::numeric_limits<double>::infinity(), false, false}; }
  static Range above(double lo) { return {lo, std::numeric_limits<double>::infinity(), true, false}; }
  static Range between(double lo, double hi) { return {lo, hi, false, false}; }
  static Range open(double lo, double hi) { return {lo, hi, true, true}; }
  bool contains(double v) const;
  std::string describe() const;  // "> 0", "between 1 and 1000", ...
};

class ConfigReader {
 public:
  // Parses `path` (a regular file: a device or a pipe would be read without end); a syntax
  // error is reported with its line and column.
  explicit ConfigReader(const std::string& path);
  ConfigReader(const std::string& text, const std::string& display_name);

  // Applies "dotted.key=value" (value in TOML syntax) before anything is read;
  // missing intermediate tables are created. A part may index an array of tables
  // ("grid.patch[2].range_j=[0, 8]"); the table must exist.
  void apply_override(const std::string& assignment);
  // `base = "other.toml"` (top level; a path relative to `base_dir`): this file's tables
  // laid over that file's, key by key (a value or an array replaces the base's; tables
  // merge), so that cases which differ from another in a few tables say only those. A
  // base may have a base (relative to its own directory), four deep at most. Call before
  // apply_override. Returns the bases as read, nearest first (none without one).
  struct BaseFile {
    std::string path, text;
  };
  std::vector<BaseFile> merge_base(const std::string& base_dir);

  const std::string& file() const { return file_; }
  const std::string& text() const { return text_; }

  bool has(const std::string& key) const;
  // Numbers are finite and inside `range`; integers are whole and inside `range`
  // (which for integers must lie within int). The error names the key and the range.
  Real number(const std::string& key, const std::string& what, const Range& range = {}) const;
  Real number_or(const std::string& key, Real fallback, const std::string& what, const Range& range = {}) const;
  int integer(const std::string& key, const std::string& what, const Range& range) const;
  int integer_or(const std::string& key, int fallback, const std::string& what, const Range& range) const;
  std::string string(const std::string& key, const std::string& what) const;
  // A string naming a file: relative to the folder of the file that set the key (a base's
  // own folder for a key the case takes from its base; the case's for its own keys and
  // for --set overrides).
  std::string file_path(const std::string& key, const std::string& what) const;
  std::string string_or(const std::string& key, const std::string& fallback, const std::string& what) const;
  bool boolean_or(const std::string& key, bool fallback, const std::string& what) const;
  // `count` finite numbers, each inside `range`.
  std::vector<Real> numbers(const std::string& key, const std::string& what, std::size_t count,
                            const Range& range = {}) const;
  // One or more finite numbers, each inside `range`.
  std::vector<Real> number_list(const std::string& key, const std::string& what, const Range& range = {}) const;
  std::vector<std::string> strings_or(const std::string& key, const std::vector<std::string>& fallback,
                                      const std::string& what) const;
  // Three finite numbers, each inside `range`.
  Vec3 vec3(const std::string& key, const std::string& what, const Range& range = {}) const;
  Vec3 vec3_or(const std::string& key, const Vec3& fallback, const std::string& what, const Range& range = {}) const;
  // A 0-based, half-open index range [first, end] of two integers, 0 <= first < end <= `max_end`.
  std::pair<int, int> index_range(const std::string& key, const std::string& what, int max_end) const;
  // Names of the sub-tables of `key` (e.g. the labels under [bc]).
  std::vector<std::string> subtables(const std::string& key) const;
  // Number of tables in an array of tables ([[periodic]]).
  std::size_t array_size(const std::string& key) const;

  // Throws naming every key that was never looked up.
  void reject_unknown_keys() const;

  [[noreturn]] void error(const std::string& key, const std::string& message) const;

 private:
  const toml::node* find(const std::string& key) const;
  void note(const std::string& key) const;
  void parse(const std::string& text);

  std::string file_, text_;
  toml::table root_;
  mutable std::set<std::string> known_;
  std::string base_dir_ = ".";                      // the case file's folder (merge_base)
  std::map<std::string, std::string> folder_of_;    // dotted key -> folder of the base that set it
};

// Levenshtein distance, for "did you mean" suggestions.
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace narwhal
