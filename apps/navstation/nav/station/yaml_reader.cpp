#include "nav/station/yaml_reader.hpp"

#include <cmath>
#include <map>

namespace nav::station::detail {

namespace {

std::string number_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

std::string range_text(const Range& range) {
  return std::string(range.open_low ? "(" : "[") + number_text(range.low) + ", " + number_text(range.high) + "]";
}

}  // namespace

void fail(const std::string& file, const YAML::Node& node, const YAML::Mark& fallback, const std::string& path,
          const std::string& message) {
  const YAML::Mark mark = node.IsDefined() && !node.Mark().is_null() ? node.Mark() : fallback;
  Error error{message, file, mark.is_null() ? 0 : mark.line + 1, path};
  if (!mark.is_null()) error.message += " (column " + std::to_string(mark.column + 1) + ")";
  throw SceneFailure{std::move(error)};
}

std::string scalar_text(const std::string& file, const YAML::Node& node, const YAML::Mark& fallback,
                        const std::string& path) {
  if (!node.IsScalar()) fail(file, node, fallback, path, "expected a single value");
  return node.Scalar();
}

MapReader::MapReader(std::string file, YAML::Node node, std::string path, YAML::Mark fallback)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)), mark_(fallback) {
  if (node_.IsDefined() && !node_.Mark().is_null()) mark_ = node_.Mark();
  if (!node_.IsMap()) fail(file_, node_, mark_, path_.empty() ? "(document)" : path_, "expected a map of keys");
}

std::string MapReader::path_of(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

int MapReader::line() const { return mark_.is_null() ? 0 : mark_.line + 1; }

bool MapReader::has(const std::string& key) const {
  const YAML::Node& map = node_;
  return map[key].IsDefined() && !map[key].IsNull();
}

bool MapReader::optional(const std::string& key) {
  asked_.insert(key);
  return has(key);
}

void MapReader::fail_at(const std::string& key, const std::string& message) const {
  const YAML::Node& map = node_;
  fail(file_, key.empty() ? map : map[key], mark_, key.empty() ? path_ : path_of(key), message);
}

YAML::Node MapReader::required(const std::string& key) {
  asked_.insert(key);
  const YAML::Node& map = node_;
  const YAML::Node child = map[key];
  if (!child.IsDefined() || child.IsNull()) fail(file_, YAML::Node(), mark_, path_of(key), "missing required key");
  return child;
}

MapReader MapReader::map(const std::string& key) { return MapReader(file_, required(key), path_of(key), mark_); }

double MapReader::number(const std::string& key, Range range) {
  const YAML::Node child = required(key);
  const std::string text = scalar_text(file_, child, mark_, path_of(key));
  double value = 0.0;
  if (!YAML::convert<double>::decode(child, value) || !std::isfinite(value))
    fail(file_, child, mark_, path_of(key), "expected a finite number, got '" + text + "'");
  const bool above_low = range.open_low ? value > range.low : value >= range.low;
  if (!above_low || value > range.high)
    fail(file_, child, mark_, path_of(key), number_text(value) + " is outside " + range_text(range));
  return value;
}

double MapReader::number(const std::string& key, Range range, double fallback) {
  if (!has(key)) {
    asked_.insert(key);
    return fallback;
  }
  return number(key, range);
}

long long MapReader::integer(const std::string& key, long long low, long long high, long long fallback) {
  asked_.insert(key);
  return has(key) ? integer(key, low, high) : fallback;
}

long long MapReader::integer(const std::string& key, long long low, long long high) {
  const YAML::Node child = required(key);
  const std::string text = scalar_text(file_, child, mark_, path_of(key));
  long long value = 0;
  if (!YAML::convert<long long>::decode(child, value))
    fail(file_, child, mark_, path_of(key), "expected an integer, got '" + text + "'");
  if (value < low || value > high)
    fail(file_, child, mark_, path_of(key),
         std::to_string(value) + " is outside [" + std::to_string(low) + ", " + std::to_string(high) + "]");
  return value;
}

bool MapReader::boolean(const std::string& key, bool fallback) {
  asked_.insert(key);
  if (!has(key)) return fallback;
  const YAML::Node child = required(key);
  const std::string text = scalar_text(file_, child, mark_, path_of(key));
  bool value = false;
  if (!YAML::convert<bool>::decode(child, value))
    fail(file_, child, mark_, path_of(key), "expected true or false, got '" + text + "'");
  return value;
}

std::string MapReader::text(const std::string& key, const char* fallback) {
  asked_.insert(key);
  if (!has(key) && fallback != nullptr) return fallback;
  const YAML::Node child = required(key);
  std::string value = scalar_text(file_, child, mark_, path_of(key));
  if (value.empty()) fail(file_, child, mark_, path_of(key), "must not be empty");
  return value;
}

int MapReader::choice(const std::string& key, std::initializer_list<const char*> choices, int fallback) {
  asked_.insert(key);
  if (!has(key) && fallback >= 0) return fallback;
  const YAML::Node child = required(key);
  const std::string value = scalar_text(file_, child, mark_, path_of(key));
  std::string listed;
  int index = 0;
  for (const char* name : choices) {
    if (value == name) return index;
    listed += (index++ == 0 ? "" : "|") + std::string(name);
  }
  fail(file_, child, mark_, path_of(key), "'" + value + "' is not one of " + listed);
}

std::vector<double> MapReader::numbers(const std::string& key, std::size_t count, Range range) {
  const YAML::Node child = required(key);
  if (!child.IsSequence() || child.size() != count)
    fail(file_, child, mark_, path_of(key), "expected a list of " + std::to_string(count) + " numbers");
  std::vector<double> values;
  for (std::size_t i = 0; i < count; ++i) {
    const std::string at = path_of(key) + "[" + std::to_string(i) + "]";
    const YAML::Node item = child[i];
    const std::string text = scalar_text(file_, item, child.Mark(), at);
    double value = 0.0;
    if (!YAML::convert<double>::decode(item, value) || !std::isfinite(value))
      fail(file_, item, child.Mark(), at, "expected a finite number, got '" + text + "'");
    const bool above_low = range.open_low ? value > range.low : value >= range.low;
    if (!above_low || value > range.high)
      fail(file_, item, child.Mark(), at, number_text(value) + " is outside " + range_text(range));
    values.push_back(value);
  }
  return values;
}

Point3 MapReader::point(const std::string& key) {
  const std::vector<double> v = numbers(key, 3, Range{-1e3, 1e3});
  return {v[0], v[1], v[2]};
}

void MapReader::finish() const {
  std::map<std::string, int> seen;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const YAML::Node key = it->first;
    if (!key.IsScalar()) fail(file_, key, mark_, path_.empty() ? "(document)" : path_, "keys must be plain names");
    const std::string name = key.Scalar();
    if (++seen[name] > 1) fail(file_, key, mark_, path_of(name), "key given twice");
    if (asked_.count(name) == 0) fail(file_, key, mark_, path_of(name), "unknown key");
  }
}

}  // namespace nav::station::detail
