#include "nav/calibration/nwire_phantom.hpp"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

namespace nav::calibration {
namespace {

/// 1-based line of byte `offset` in `text`.
int line_of(const std::string& text, std::size_t offset) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n'));
}

/// The value of attribute `name` in the element that starts at `start` (up to its '>').
std::optional<std::string> attribute(const std::string& xml, std::size_t start, const std::string& name) {
  const std::size_t end = xml.find('>', start);
  const std::string element = xml.substr(start, end == std::string::npos ? std::string::npos : end - start);
  std::size_t at = 0;
  while ((at = element.find(name + "=\"", at)) != std::string::npos) {
    if (at > 0 &&
        (element[at - 1] == ' ' || element[at - 1] == '\n' || element[at - 1] == '\t' || element[at - 1] == '\r')) {
      const std::size_t value_start = at + name.size() + 2;
      const std::size_t value_end = element.find('"', value_start);
      if (value_end == std::string::npos) return std::nullopt;
      return element.substr(value_start, value_end - value_start);
    }
    at += name.size();
  }
  return std::nullopt;
}

std::optional<std::vector<double>> numbers(const std::string& text, std::size_t count) {
  std::istringstream stream(text);
  std::vector<double> values;
  double value = 0.0;
  while (stream >> value) values.push_back(value);
  if (!stream.eof() || values.size() != count) return std::nullopt;
  return values;
}

}  // namespace

Result<NWirePhantom> parse_nwire_phantom(const std::string& xml, const std::string& path) {
  NWirePhantom phantom;
  const std::size_t definition = xml.find("<PhantomDefinition");
  if (definition == std::string::npos)
    return Error{.message = "no phantom definition", .file = path, .field = "PhantomDefinition"};
  std::size_t pattern_at = definition;
  while ((pattern_at = xml.find("<Pattern", pattern_at + 1)) != std::string::npos) {
    const int line = line_of(xml, pattern_at);
    if (attribute(xml, pattern_at, "Type") != "NWire")
      return Error{.message = "only NWire patterns are supported", .file = path, .line = line, .field = "Pattern"};
    const std::size_t pattern_end = xml.find("</Pattern>", pattern_at);
    NWirePattern pattern;
    std::size_t wire_at = pattern_at;
    for (PhantomWire& wire : pattern) {
      wire_at = xml.find("<Wire", wire_at + 1);
      if (wire_at == std::string::npos || wire_at > pattern_end)
        return Error{.message = "an N-wire pattern needs three wires", .file = path, .line = line, .field = "Pattern"};
      const auto front = numbers(attribute(xml, wire_at, "EndPointFront").value_or(""), 3);
      const auto back = numbers(attribute(xml, wire_at, "EndPointBack").value_or(""), 3);
      if (!front || !back)
        return Error{.message = "expected EndPointFront and EndPointBack, 3 numbers each (mm)",
                     .file = path,
                     .line = line_of(xml, wire_at),
                     .field = "Wire"};
      wire.front_m = 1e-3 * Eigen::Vector3d((*front)[0], (*front)[1], (*front)[2]);
      wire.back_m = 1e-3 * Eigen::Vector3d((*back)[0], (*back)[1], (*back)[2]);
    }
    const Eigen::Vector3d first = (pattern[0].back_m - pattern[0].front_m).normalized();
    const Eigen::Vector3d last = (pattern[2].back_m - pattern[2].front_m).normalized();
    if (first.cross(last).norm() > 1e-6)
      return Error{
          .message = "the outer wires of a pattern must be parallel", .file = path, .line = line, .field = "Pattern"};
    phantom.patterns.push_back(pattern);
  }
  if (phantom.patterns.empty())
    return Error{
        .message = "no N-wire pattern", .file = path, .line = line_of(xml, definition), .field = "PhantomDefinition"};

  std::size_t transform_at = 0;
  while ((transform_at = xml.find("<Transform", transform_at + 1)) != std::string::npos) {
    if (attribute(xml, transform_at, "From") != "Phantom" || attribute(xml, transform_at, "To") != "Reference")
      continue;
    const auto matrix = numbers(attribute(xml, transform_at, "Matrix").value_or(""), 16);
    if (!matrix)
      return Error{.message = "expected a 4x4 Matrix (16 numbers)",
                   .file = path,
                   .line = line_of(xml, transform_at),
                   .field = "Transform"};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        phantom.reference_from_phantom.linear()(r, c) = (*matrix)[static_cast<std::size_t>(4 * r + c)];
      phantom.reference_from_phantom.translation()(r) = 1e-3 * (*matrix)[static_cast<std::size_t>(4 * r + 3)];
    }
    return phantom;
  }
  return Error{.message = "no Phantom-to-Reference transform", .file = path, .field = "CoordinateDefinitions"};
}

Result<NWirePhantom> load_nwire_phantom(const std::string& path) {
  std::ifstream file(path);
  if (!file) return Error{.message = "cannot open", .file = path};
  const std::string xml((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  return parse_nwire_phantom(xml, path);
}

Eigen::Vector3d middle_wire_point(const NWirePattern& pattern, const Eigen::Vector2d& first_px,
                                  const Eigen::Vector2d& middle_px, const Eigen::Vector2d& last_px) {
  const double ratio = (middle_px - first_px).norm() / (last_px - first_px).norm();
  // Across the parallel wires' direction the dots divide the outer wires' offset in `ratio`;
  // along it the middle wire's own position follows from its slope.
  const Eigen::Vector3d along = (pattern[0].back_m - pattern[0].front_m).normalized();
  const auto across = [&](const Eigen::Vector3d& v) -> Eigen::Vector3d { return v - v.dot(along) * along; };
  const Eigen::Vector3d target = (1.0 - ratio) * across(pattern[0].front_m) + ratio * across(pattern[2].front_m);
  const Eigen::Vector3d slope = across(pattern[1].back_m - pattern[1].front_m);
  const double s = slope.dot(target - across(pattern[1].front_m)) / slope.squaredNorm();
  return pattern[1].front_m + s * (pattern[1].back_m - pattern[1].front_m);
}

}  // namespace nav::calibration
