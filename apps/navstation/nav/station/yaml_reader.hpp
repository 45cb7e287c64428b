#pragma once
// Checked reading of one YAML map of a scene (private to nav_station: yaml-cpp stays out of
// the public headers). A MapReader hands out its keys by name, converts and range-checks
// their values, and at finish() refuses keys nobody asked for and repeated keys. A failure
// throws SceneFailure, which parse_scene turns into its Error: the file, the node's line,
// the key path and the column.
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav::station::detail {

/// An Error thrown inside the parser, caught at its boundary.
struct SceneFailure {
  Error error;
};

/// The error for `node` (or, when it has no position, `fallback`) at key path `path`.
[[noreturn]] void fail(const std::string& file, const YAML::Node& node, const YAML::Mark& fallback,
                       const std::string& path, const std::string& message);

/// A range a number must lie in; `open_low` excludes the low end.
struct Range {
  double low;
  double high;
  bool open_low = false;
};

/// The keys of one YAML map, read by name.
class MapReader {
 public:
  /// Fails unless `node` is a map; `path` is its key path ("" for the document).
  MapReader(std::string file, YAML::Node node, std::string path, YAML::Mark fallback);

  bool has(const std::string& key) const;
  /// Whether an optional key is given (and counts it as asked for).
  bool optional(const std::string& key);
  /// The child node under `key`; a missing key fails.
  YAML::Node required(const std::string& key);
  /// The child's key path ("liver.model").
  std::string path_of(const std::string& key) const;
  /// A map child, as a reader; a missing key fails.
  MapReader map(const std::string& key);
  /// Where this map starts (1-based line).
  int line() const;
  const std::string& file() const { return file_; }
  const YAML::Mark& mark() const { return mark_; }

  /// A number in `range` (finite); `fallback` when the key is missing.
  double number(const std::string& key, Range range, double fallback);
  /// A required number in `range`.
  double number(const std::string& key, Range range);
  /// An integer within [low, high]; `fallback` when the key is missing.
  long long integer(const std::string& key, long long low, long long high, long long fallback);
  /// A required integer within [low, high].
  long long integer(const std::string& key, long long low, long long high);
  bool boolean(const std::string& key, bool fallback);
  /// A non-empty string scalar; `fallback` when missing (a missing key fails if
  /// `fallback` is null).
  std::string text(const std::string& key, const char* fallback = nullptr);
  /// One of `choices` (the index), or `fallback` when the key is missing (required if < 0).
  int choice(const std::string& key, std::initializer_list<const char*> choices, int fallback = -1);
  /// Three numbers [x, y, z], each finite.
  Point3 point(const std::string& key);
  /// A sequence of `count` numbers, each within `range`.
  std::vector<double> numbers(const std::string& key, std::size_t count, Range range);

  /// Fails on a key that was never asked for, or a key given twice.
  void finish() const;

  /// Fails at `key` (or at this map when `key` is empty) with `message`.
  [[noreturn]] void fail_at(const std::string& key, const std::string& message) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string path_;
  YAML::Mark mark_;
  std::set<std::string> asked_;
};

/// A string value of `node` (a scalar), or a failure naming `path`.
std::string scalar_text(const std::string& file, const YAML::Node& node, const YAML::Mark& fallback,
                        const std::string& path);

}  // namespace nav::station::detail
