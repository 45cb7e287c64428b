#include "nav/mesh/vtu_reader.hpp"

#include <algorithm>
#include <limits>

#include "nav/mesh/text_lines.hpp"
#include "nav/mesh/vtk_grid_reader.hpp"
#include "nav/mesh/xml_tag_reader.hpp"

namespace nav {
namespace {

using detail::VtkArray;
using detail::XmlRead;
using detail::XmlTag;

/// The element whose DataArrays are being read.
enum class Section { other, points, cells, cell_data };

/// What the file has given so far.
struct VtuState {
  detail::VtkGridArrays grid;
  VtkArray<std::int64_t> offsets;
  std::int64_t point_count = 0;
  std::int64_t cell_count = 0;
  Section section = Section::other;
  bool has_file = false;
  bool file_closed = false;
  bool has_piece = false;
};

/// Reads every value of a DataArray's text into `array`; the text starts on line `first_line`.
template <typename T>
bool read_array(TextScanner& scanner, std::string_view text, int first_line, std::string_view name,
                VtkArray<T>& array) {
  if (!array.field.empty()) return scanner.fail(name, "DataArray given twice");
  array.field = std::string(name);
  array.text = text;
  array.first_line = first_line;
  array.values.reserve(text.size() / 2);
  TextScanner values(scanner.path(), text, first_line);
  while (!values.at_end()) {
    T value{};
    if (!values.read(value, name)) return scanner.fail(values.error());
    array.values.push_back(value);
  }
  return true;
}

/// The array of `state` a DataArray fills (one of the two pointers set), chosen by section and Name;
/// neither for arrays the reader does not use.
struct Target {
  VtkArray<double>* reals = nullptr;
  VtkArray<std::int64_t>* integers = nullptr;
};

/// The target of a DataArray named `name` in the current section.
Target target_of(std::string_view name, VtuState& state) {
  switch (state.section) {
    case Section::points:
      return {&state.grid.points, nullptr};
    case Section::cells:
      if (name == "connectivity") return {nullptr, &state.grid.connectivity};
      if (name == "offsets") return {nullptr, &state.offsets};
      if (name == "types") return {nullptr, &state.grid.types};
      break;
    case Section::cell_data:
      if (name == kVtuRegionArray) return {nullptr, &state.grid.regions};
      break;
    case Section::other:
      break;
  }
  return {};
}

/// Checks a DataArray tag and reads its values into its target, if any.
bool read_data_array(TextScanner& scanner, const XmlTag& tag, VtuState& state) {
  const std::string_view name =
      state.section == Section::points ? "Points" : tag.attribute("Name").value_or("DataArray");
  const std::string_view format = tag.attribute("format").value_or("ascii");
  if (format != "ascii") {
    return scanner.fail(name, "format=\"" + std::string(format) + "\" DataArrays are not supported (only ascii)");
  }
  if (state.section == Section::points && tag.attribute("NumberOfComponents").value_or("1") != "3") {
    return scanner.fail(name, "Points need NumberOfComponents=\"3\"");
  }
  std::string_view text;
  const int first_line = scanner.line();
  if (!tag.self_closing) {
    const auto content = scanner.take_until('<');
    if (!content) return scanner.fail(name, "unexpected end of file inside the DataArray");
    text = *content;
  }
  const Target target = target_of(name, state);
  if (target.reals != nullptr) return read_array(scanner, text, first_line, name, *target.reals);
  if (target.integers != nullptr) return read_array(scanner, text, first_line, name, *target.integers);
  return true;
}

/// Reads a Piece's count attribute (NumberOfPoints, NumberOfCells).
bool read_count_attribute(TextScanner& scanner, const XmlTag& tag, std::string_view key, std::int64_t& count) {
  const auto parsed = parse_int(tag.attribute(key).value_or(""));
  if (!parsed || *parsed < 0 || *parsed > std::numeric_limits<std::int32_t>::max()) {
    return scanner.fail("Piece", "missing or invalid " + std::string(key));
  }
  count = *parsed;
  return true;
}

/// Acts on an opening (or self-closing) tag.
bool read_opening_tag(TextScanner& scanner, const XmlTag& tag, VtuState& state) {
  if (tag.name == "VTKFile") {
    state.has_file = true;
    const std::string_view type = tag.attribute("type").value_or("");
    if (type != "UnstructuredGrid") {
      return scanner.fail("VTKFile", "type '" + std::string(type) + "' is not supported (UnstructuredGrid is read)");
    }
    return true;
  }
  if (tag.name == "Piece") {
    if (state.has_piece) return scanner.fail("Piece", "files with more than one Piece are not supported");
    state.has_piece = true;
    return read_count_attribute(scanner, tag, "NumberOfPoints", state.point_count) &&
           read_count_attribute(scanner, tag, "NumberOfCells", state.cell_count);
  }
  if (tag.name == "AppendedData") return scanner.fail("AppendedData", "appended data is not supported (only ascii)");
  if (tag.name == "DataArray") return read_data_array(scanner, tag, state);
  if (tag.self_closing) return true;
  if (tag.name == "Points") state.section = Section::points;
  if (tag.name == "Cells") state.section = Section::cells;
  if (tag.name == "CellData") state.section = Section::cell_data;
  if (tag.name == "PointData") state.section = Section::other;
  return true;
}

/// Reads every tag of the file, with the DataArrays' values.
bool read_tags(TextScanner& scanner, VtuState& state) {
  XmlTag tag;
  while (true) {
    const XmlRead read = detail::read_xml_tag(scanner, tag);
    if (read == XmlRead::error) return false;
    if (read == XmlRead::end_of_text) return true;
    if (tag.closing) {
      if (tag.name == "VTKFile") state.file_closed = true;
      if (tag.name == "Points" || tag.name == "Cells" || tag.name == "CellData" || tag.name == "PointData") {
        state.section = Section::other;
      }
    } else if (!read_opening_tag(scanner, tag, state)) {
      return false;
    }
  }
}

/// Checks that the file was whole and had every array the mesh needs.
bool check_complete(TextScanner& scanner, const VtuState& state) {
  if (!state.has_file) return scanner.fail("VTKFile", "not a VTK XML file (no <VTKFile> tag)");
  if (!state.file_closed) return scanner.fail("VTKFile", "unexpected end of file before </VTKFile>");
  if (!state.has_piece) return scanner.fail("Piece", "missing <Piece>");
  if (state.grid.points.field.empty()) return scanner.fail("Points", "missing Points DataArray");
  if (state.grid.connectivity.field.empty()) return scanner.fail("connectivity", "missing connectivity DataArray");
  if (state.offsets.field.empty()) return scanner.fail("offsets", "missing offsets DataArray");
  if (state.grid.types.field.empty()) return scanner.fail("types", "missing types DataArray");
  return true;
}

/// Checks an array's length against the count its Piece declares.
template <typename T>
bool check_length(TextScanner& scanner, const VtkArray<T>& array, std::int64_t expected, std::string_view what) {
  const auto size = static_cast<std::int64_t>(array.values.size());
  if (size == expected) return true;
  return scanner.fail(array.error_at(scanner.path(), static_cast<std::size_t>(std::min(size, expected)),
                                     std::to_string(size) + " values, but the Piece declares " +
                                         std::to_string(expected) + " (" + std::string(what) + ")"));
}

}  // namespace

Result<TetMesh> parse_vtu_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit) {
  TextScanner scanner(path, text);
  VtuState state;
  if (!read_tags(scanner, state) || !check_complete(scanner, state) ||
      !check_length(scanner, state.grid.points, 3 * state.point_count, "3 per point") ||
      !check_length(scanner, state.offsets, state.cell_count, "1 per cell")) {
    return scanner.error();
  }
  auto spans = detail::cell_spans_from_offsets(state.offsets, false, state.grid.connectivity.values.size(), path);
  if (!spans) return spans.error();
  state.grid.cells = std::move(spans.value());
  return detail::tet_mesh_from_vtk_grid(state.grid, path, metres_per_unit(unit));
}

Result<TetMesh> load_vtu_tet_mesh(const std::string& path, LengthUnit unit) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_vtu_tet_mesh(text.value(), path, unit);
}

}  // namespace nav
