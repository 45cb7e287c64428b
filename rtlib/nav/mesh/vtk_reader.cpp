#include "nav/mesh/vtk_reader.hpp"

#include <algorithm>
#include <limits>

#include "nav/mesh/text_lines.hpp"
#include "nav/mesh/vtk_grid_reader.hpp"

namespace nav {
namespace {

using detail::VtkArray;
using detail::VtkGridArrays;

constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max();

/// True for a token that looks like a section keyword (CELL_TYPES), not a garbled number.
bool is_keyword(std::string_view token) {
  return token.size() > 3 &&
         std::all_of(token.begin(), token.end(), [](char c) { return (c >= 'A' && c <= 'Z') || c == '_'; });
}

/// Reads `count` values (spread over any number of lines) into `array`, keeping their text.
template <typename T>
bool read_values(TextScanner& scanner, std::int64_t count, const std::string& field, VtkArray<T>& array) {
  array.field = field;
  array.first_line = scanner.line();
  const std::size_t start = scanner.position();
  array.values.reserve(std::min(static_cast<std::size_t>(count), scanner.remaining() / 2));
  for (std::int64_t i = 0; i < count; ++i) {
    if (is_keyword(scanner.peek())) {
      return scanner.fail(field, "found '" + std::string(scanner.peek()) + "' after " + std::to_string(i) + " of " +
                                     std::to_string(count) + " values");
    }
    T value{};
    if (!scanner.read(value, field)) return false;
    array.values.push_back(value);
  }
  array.text = scanner.text_since(start);
  return true;
}

/// Line 1 "# vtk DataFile Version x.y", line 2 a title, line 3 ASCII, line 4 DATASET UNSTRUCTURED_GRID.
bool read_header(TextScanner& scanner) {
  const auto first = scanner.take_until('\n');
  if (!first || !first->starts_with("# vtk DataFile Version")) {
    return scanner.fail("header", "the first line is not '# vtk DataFile Version x.y'");
  }
  scanner.advance(1);
  if (scanner.at_end()) return scanner.fail("title", "unexpected end of file");
  scanner.skip_line();
  std::string_view format;
  if (!scanner.read(format, "format")) return false;
  if (format != "ASCII")
    return scanner.fail("format", "'" + std::string(format) + "' is not supported (ASCII is read)");
  std::string_view dataset;
  if (!scanner.end_line("format") || !scanner.expect("DATASET", "DATASET") ||
      !scanner.read(dataset, "DATASET", Within::line)) {
    return false;
  }
  if (dataset != "UNSTRUCTURED_GRID") {
    return scanner.fail("DATASET", "'" + std::string(dataset) + "' is not supported (UNSTRUCTURED_GRID is read)");
  }
  return scanner.end_line("DATASET");
}

bool read_points(TextScanner& scanner, VtkGridArrays& grid) {
  std::int64_t count = 0;
  std::string_view type;
  return scanner.read_in_range(count, 0, kMaxCount, "POINTS", Within::line) &&
         scanner.read(type, "POINTS", Within::line) && scanner.end_line("POINTS") &&
         read_values(scanner, 3 * count, "POINTS", grid.points);
}

/// Stores `spans` as the grid's cells, or records their Error.
bool take_spans(TextScanner& scanner, Result<std::vector<detail::VtkCellSpan>> spans, VtkGridArrays& grid) {
  if (!spans) return scanner.fail(spans.error());
  grid.cells = std::move(spans.value());
  return true;
}

/// CELLS n size, then either n cells as "count i0 i1 ..." or (5.1) OFFSETS and CONNECTIVITY arrays.
bool read_cells(TextScanner& scanner, VtkGridArrays& grid) {
  std::int64_t count = 0;
  std::int64_t size = 0;
  if (!scanner.read_in_range(count, 0, kMaxCount, "CELLS", Within::line) ||
      !scanner.read_in_range(size, 0, kMaxCount, "CELLS", Within::line) || !scanner.end_line("CELLS")) {
    return false;
  }
  if (scanner.peek() != "OFFSETS") {
    return read_values(scanner, size, "CELLS", grid.connectivity) &&
           take_spans(
               scanner,
               detail::cell_spans_from_counts(grid.connectivity, static_cast<std::size_t>(count), scanner.path()),
               grid);
  }
  VtkArray<std::int64_t> offsets;
  std::string_view type;
  return scanner.expect("OFFSETS", "OFFSETS") && scanner.read(type, "OFFSETS", Within::line) &&
         read_values(scanner, count, "OFFSETS", offsets) && scanner.expect("CONNECTIVITY", "CONNECTIVITY") &&
         scanner.read(type, "CONNECTIVITY", Within::line) &&
         read_values(scanner, size, "CONNECTIVITY", grid.connectivity) &&
         take_spans(scanner,
                    detail::cell_spans_from_offsets(offsets, true, grid.connectivity.values.size(), scanner.path()),
                    grid);
}

bool read_cell_types(TextScanner& scanner, VtkGridArrays& grid) {
  std::int64_t count = 0;
  return scanner.read_in_range(count, 0, kMaxCount, "CELL_TYPES", Within::line) && scanner.end_line("CELL_TYPES") &&
         read_values(scanner, count, "CELL_TYPES", grid.types);
}

/// FIELD name n, then n arrays "name components tuples type" each followed by its values.
bool skip_field_data(TextScanner& scanner) {
  std::string_view token;
  std::int64_t array_count = 0;
  if (!scanner.read(token, "FIELD", Within::line) ||
      !scanner.read_in_range(array_count, 0, kMaxCount, "FIELD", Within::line)) {
    return false;
  }
  for (std::int64_t a = 0; a < array_count; ++a) {
    std::int64_t components = 0;
    std::int64_t tuples = 0;
    if (!scanner.read(token, "FIELD") || !scanner.read_in_range(components, 0, kMaxCount, "FIELD", Within::line) ||
        !scanner.read_in_range(tuples, 0, kMaxCount, "FIELD", Within::line) ||
        !scanner.read(token, "FIELD", Within::line)) {
      return false;
    }
    for (std::int64_t v = 0; v < components * tuples; ++v) {
      if (!scanner.read(token, "FIELD")) return false;
    }
  }
  return true;
}

/// METADATA is followed by lines up to a blank line.
void skip_metadata(TextScanner& scanner) {
  scanner.skip_line();
  while (!scanner.at_line_end()) scanner.skip_line();
  scanner.skip_line();
}

/// Reads the dataset's sections up to its attribute data (or the end of the file).
bool read_sections(TextScanner& scanner, VtkGridArrays& grid) {
  bool has_points = false;
  bool has_cells = false;
  bool has_types = false;
  while (!scanner.at_end()) {
    std::string_view keyword;
    scanner.read(keyword, "keyword");
    bool ok = true;
    if (keyword == "POINTS") {
      ok = !has_points && read_points(scanner, grid);
      has_points = true;
    } else if (keyword == "CELLS") {
      ok = !has_cells && read_cells(scanner, grid);
      has_cells = true;
    } else if (keyword == "CELL_TYPES") {
      ok = !has_types && read_cell_types(scanner, grid);
      has_types = true;
    } else if (keyword == "FIELD") {
      ok = skip_field_data(scanner);
    } else if (keyword == "METADATA") {
      skip_metadata(scanner);
    } else if (keyword == "POINT_DATA" || keyword == "CELL_DATA") {
      break;
    } else {
      return scanner.fail("keyword", "unexpected keyword '" + std::string(keyword) + "'");
    }
    if (!ok) return scanner.fail(keyword, "section given twice");
  }
  if (!has_points) return scanner.fail("POINTS", "missing POINTS section");
  if (!has_cells) return scanner.fail("CELLS", "missing CELLS section");
  if (!has_types) return scanner.fail("CELL_TYPES", "missing CELL_TYPES section");
  return true;
}

}  // namespace

Result<TetMesh> parse_vtk_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit) {
  TextScanner scanner(path, text);
  VtkGridArrays grid;
  if (!read_header(scanner) || !read_sections(scanner, grid)) return scanner.error();
  return detail::tet_mesh_from_vtk_grid(grid, path, metres_per_unit(unit));
}

Result<TetMesh> load_vtk_tet_mesh(const std::string& path, LengthUnit unit) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_vtk_tet_mesh(text.value(), path, unit);
}

}  // namespace nav
