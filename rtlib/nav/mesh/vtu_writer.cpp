#include "nav/mesh/vtu_writer.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <span>

#include "nav/mesh/vtu_reader.hpp"

namespace nav {
namespace {

constexpr std::uint8_t kVtkTetraType = 10;

/// Appends `values` as the body of an ascii DataArray with attributes `attributes`,
/// `per_line` values to a line.
template <typename T>
void append_data_array(std::string& out, const std::string& attributes, std::span<const T> values,
                       std::size_t per_line) {
  out += "        <DataArray " + attributes + " format=\"ascii\">\n";
  char buffer[32];
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i % per_line == 0) out += "          ";
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), values[i]);
    out.append(buffer, result.ptr);
    out += (i + 1) % per_line == 0 || i + 1 == values.size() ? '\n' : ' ';
  }
  out += "        </DataArray>\n";
}

Status check_field(const VtuField& field, std::size_t count, const char* where) {
  const std::string context = std::string(where) + " field '" + field.name + "'";
  if (field.name.empty() || field.name.find_first_of("<>&\"'") != std::string::npos) {
    return Error{.message = "a field name must be non-empty without <>&\"' characters", .field = context};
  }
  if (field.components < 1) return Error{.message = "components must be at least 1", .field = context};
  const std::size_t expected = static_cast<std::size_t>(field.components) * count;
  if (field.values.size() != expected) {
    return Error{.message = std::to_string(field.values.size()) + " values, expected " + std::to_string(expected),
                 .field = context};
  }
  for (std::size_t i = 0; i < field.values.size(); ++i) {
    if (!std::isfinite(field.values[i]))
      return Error{.message = "value " + std::to_string(i) + " is not finite", .field = context};
  }
  return Done{};
}

Status check_inputs(const TetMesh& mesh, const std::vector<VtuField>& point_fields,
                    const std::vector<VtuField>& cell_fields) {
  for (const Point3& p : mesh.nodes_m) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      return Error{.message = "a node coordinate is not finite", .field = "nodes_m"};
    }
  }
  for (const auto& tet : mesh.tets) {
    for (const std::int32_t node : tet) {
      if (node < 0 || static_cast<std::size_t>(node) >= mesh.nodes_m.size()) {
        return Error{.message = "node index " + std::to_string(node) + " is out of range", .field = "tets"};
      }
    }
  }
  if (!mesh.tet_regions.empty() && mesh.tet_regions.size() != mesh.tets.size()) {
    return Error{.message = "one region tag per element is needed", .field = "tet_regions"};
  }
  for (const VtuField& field : point_fields) {
    if (auto status = check_field(field, mesh.nodes_m.size(), "point"); !status) return status;
  }
  for (const VtuField& field : cell_fields) {
    if (auto status = check_field(field, mesh.tets.size(), "cell"); !status) return status;
    if (!mesh.tet_regions.empty() && field.name == kVtuRegionArray) {
      return Error{.message = "the name is taken by tet_regions", .field = "cell field '" + field.name + "'"};
    }
  }
  return Done{};
}

void append_fields(std::string& out, const std::vector<VtuField>& fields) {
  for (const VtuField& field : fields) {
    append_data_array<double>(
        out,
        "type=\"Float64\" Name=\"" + field.name + "\" NumberOfComponents=\"" + std::to_string(field.components) + "\"",
        field.values, static_cast<std::size_t>(field.components == 1 ? 6 : field.components));
  }
}

void append_cells(std::string& out, const TetMesh& mesh) {
  std::vector<std::int32_t> connectivity;
  std::vector<std::int32_t> offsets;
  connectivity.reserve(4 * mesh.tets.size());
  offsets.reserve(mesh.tets.size());
  for (const auto& tet : mesh.tets) {
    connectivity.insert(connectivity.end(), tet.begin(), tet.end());
    offsets.push_back(static_cast<std::int32_t>(connectivity.size()));
  }
  const std::vector<std::uint16_t> types(mesh.tets.size(), kVtkTetraType);
  out += "      <Cells>\n";
  append_data_array<std::int32_t>(out, "type=\"Int32\" Name=\"connectivity\"", connectivity, 4);
  append_data_array<std::int32_t>(out, "type=\"Int32\" Name=\"offsets\"", offsets, 8);
  append_data_array<std::uint16_t>(out, "type=\"UInt8\" Name=\"types\"", types, 16);
  out += "      </Cells>\n";
}

}  // namespace

Result<std::string> format_vtu(const TetMesh& mesh, const std::vector<VtuField>& point_fields,
                               const std::vector<VtuField>& cell_fields) {
  if (auto status = check_inputs(mesh, point_fields, cell_fields); !status) return status.error();
  std::string out;
  out += "<?xml version=\"1.0\"?>\n";
  out += "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n";
  out += "  <UnstructuredGrid>\n";
  out += "    <Piece NumberOfPoints=\"" + std::to_string(mesh.nodes_m.size()) + "\" NumberOfCells=\"" +
         std::to_string(mesh.tets.size()) + "\">\n";
  out += "      <PointData>\n";
  append_fields(out, point_fields);
  out += "      </PointData>\n";
  out += "      <CellData>\n";
  if (!mesh.tet_regions.empty()) {
    append_data_array<std::int32_t>(out, "type=\"Int32\" Name=\"" + std::string(kVtuRegionArray) + "\"",
                                    mesh.tet_regions, 8);
  }
  append_fields(out, cell_fields);
  out += "      </CellData>\n";
  out += "      <Points>\n";
  std::vector<double> coordinates_m;
  coordinates_m.reserve(3 * mesh.nodes_m.size());
  for (const Point3& p : mesh.nodes_m) coordinates_m.insert(coordinates_m.end(), p.begin(), p.end());
  append_data_array<double>(out, "type=\"Float64\" NumberOfComponents=\"3\"", coordinates_m, 3);
  out += "      </Points>\n";
  append_cells(out, mesh);
  out += "    </Piece>\n";
  out += "  </UnstructuredGrid>\n";
  out += "</VTKFile>\n";
  return out;
}

Status write_vtu(const std::string& path, const TetMesh& mesh, const std::vector<VtuField>& point_fields,
                 const std::vector<VtuField>& cell_fields) {
  auto text = format_vtu(mesh, point_fields, cell_fields);
  if (!text) {
    Error error = text.error();
    error.file = path;
    return error;
  }
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  if (!stream) return Error{.message = "cannot open file for writing", .file = path};
  stream.write(text.value().data(), static_cast<std::streamsize>(text.value().size()));
  stream.close();
  if (!stream) return Error{.message = "cannot write file", .file = path};
  return Done{};
}

}  // namespace nav
