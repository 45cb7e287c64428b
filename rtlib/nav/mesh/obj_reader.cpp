#include "nav/mesh/obj_reader.hpp"

#include <cstdint>
#include <vector>

#include "nav/mesh/text_lines.hpp"

namespace nav {
namespace {

/// Reads a 'v' record's x y z (a w or colour values after them are ignored).
bool read_vertex(TextScanner& scanner, double metres_per_unit, std::vector<Point3>& vertices_m) {
  Point3 point{};
  for (double& coordinate : point) {
    if (!scanner.read(coordinate, "v", Within::line)) return false;
    coordinate *= metres_per_unit;
  }
  vertices_m.push_back(point);
  scanner.skip_line();
  return true;
}

/// Reads one face corner ("i", "i/t", "i//n" or "i/t/n") as a 0-based vertex index.
bool read_corner(TextScanner& scanner, std::size_t vertex_count, std::int32_t& index) {
  std::string_view token;
  if (!scanner.read(token, "f", Within::line)) return false;
  const std::string_view vertex_part = token.substr(0, token.find('/'));
  const auto parsed = parse_int(vertex_part);
  if (!parsed) return scanner.fail("f", "'" + std::string(token) + "' is not a vertex index");
  const auto count = static_cast<std::int64_t>(vertex_count);
  const std::int64_t zero_based = *parsed > 0 ? *parsed - 1 : count + *parsed;
  if (*parsed == 0 || zero_based < 0 || zero_based >= count) {
    return scanner.fail("f", "vertex index " + std::to_string(*parsed) + " is out of range (" + std::to_string(count) +
                                 " vertices defined so far)");
  }
  index = static_cast<std::int32_t>(zero_based);
  return true;
}

/// Reads an 'f' record and appends its fan triangulation.
bool read_face(TextScanner& scanner, std::vector<std::int32_t>& corners, TriSurface& surface) {
  corners.clear();
  while (!scanner.at_line_end()) {
    std::int32_t index = 0;
    if (!read_corner(scanner, surface.vertices_m.size(), index)) return false;
    corners.push_back(index);
  }
  if (corners.size() < 3) {
    return scanner.fail("f", "a face needs at least 3 vertices, found " + std::to_string(corners.size()));
  }
  for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
    surface.triangles.push_back({corners[0], corners[k], corners[k + 1]});
  }
  scanner.skip_line();
  return true;
}

}  // namespace

Result<TriSurface> parse_obj_surface(std::string_view text, const std::string& path, LengthUnit unit) {
  TextScanner scanner(path, text);
  TriSurface surface;
  std::vector<std::int32_t> corners;
  const double scale = metres_per_unit(unit);
  while (!scanner.at_end()) {
    std::string_view keyword;
    scanner.read(keyword, "obj", Within::line);
    bool ok = true;
    if (keyword == "v") {
      ok = read_vertex(scanner, scale, surface.vertices_m);
    } else if (keyword == "f") {
      ok = read_face(scanner, corners, surface);
    } else {
      scanner.skip_line();
    }
    if (!ok) return scanner.error();
  }
  if (surface.triangles.empty()) {
    scanner.fail("f", "no faces found");
    return scanner.error();
  }
  return surface;
}

Result<TriSurface> load_obj_surface(const std::string& path, LengthUnit unit) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_obj_surface(text.value(), path, unit);
}

}  // namespace nav
