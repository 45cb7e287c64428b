#include "vtk_xml.hpp"

#include <cstring>
#include <sstream>

namespace navtool {
namespace {

/// Base64 (RFC 4648, padded) of `bytes`.
std::string base64(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t left = bytes.size() - i;
    const std::uint32_t group = (std::uint32_t{bytes[i]} << 16) | (left > 1 ? std::uint32_t{bytes[i + 1]} << 8 : 0) |
                                (left > 2 ? std::uint32_t{bytes[i + 2]} : 0);
    text += kAlphabet[(group >> 18) & 63];
    text += kAlphabet[(group >> 12) & 63];
    text += left > 1 ? kAlphabet[(group >> 6) & 63] : '=';
    text += left > 2 ? kAlphabet[group & 63] : '=';
  }
  return text;
}

/// A DataArray element of `values` (a trivially copyable type, little-endian on this host).
template <typename Value>
std::string data_array(const char* type, const std::string& name, int components, std::span<const Value> values) {
  const auto bytes = static_cast<std::uint32_t>(values.size_bytes());
  std::vector<std::uint8_t> raw(sizeof(bytes) + bytes);
  std::memcpy(raw.data(), &bytes, sizeof(bytes));
  if (bytes > 0) std::memcpy(raw.data() + sizeof(bytes), values.data(), bytes);
  std::ostringstream out;
  out << "<DataArray type=\"" << type << "\"" << (name.empty() ? "" : " Name=\"" + name + "\"")
      << " NumberOfComponents=\"" << components << "\" format=\"binary\">" << base64(raw) << "</DataArray>\n";
  return out.str();
}

/// A cell block (Verts, Lines, Polys) of `cells`, each a list of point indices.
std::string cells(const char* element, const std::vector<std::vector<std::uint32_t>>& list) {
  std::vector<std::int32_t> connectivity, offsets;
  for (const auto& cell : list) {
    for (const std::uint32_t point : cell) connectivity.push_back(static_cast<std::int32_t>(point));
    offsets.push_back(static_cast<std::int32_t>(connectivity.size()));
  }
  return std::string("<") + element + ">\n" + data_array<std::int32_t>("Int32", "connectivity", 1, connectivity) +
         data_array<std::int32_t>("Int32", "offsets", 1, offsets) + "</" + element + ">\n";
}

}  // namespace

std::string format_polydata(const PolyData& data) {
  std::vector<std::vector<std::uint32_t>> vertices, triangles;
  if (data.vertices)
    for (std::uint32_t i = 0; i < data.points.size(); ++i) vertices.push_back({i});
  for (const auto& t : data.triangles) triangles.push_back({t[0], t[1], t[2]});
  std::vector<float> coordinates;
  for (const auto& p : data.points) coordinates.insert(coordinates.end(), p.begin(), p.end());
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<PolyData>\n<Piece NumberOfPoints=\"" << data.points.size() << "\" NumberOfVerts=\"" << vertices.size()
      << "\" NumberOfLines=\"" << data.lines.size() << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << triangles.size()
      << "\">\n<PointData>\n";
  for (const FloatArray& array : data.point_data)
    out << data_array<float>("Float32", array.name, array.components, array.values);
  out << "</PointData>\n<Points>\n" << data_array<float>("Float32", "", 3, coordinates) << "</Points>\n";
  if (!vertices.empty()) out << cells("Verts", vertices);
  if (!data.lines.empty()) out << cells("Lines", data.lines);
  if (!triangles.empty()) out << cells("Polys", triangles);
  out << "</Piece>\n</PolyData>\n</VTKFile>\n";
  return out.str();
}

std::string format_image(const PlacedImage& image) {
  std::ostringstream out;
  out.precision(17);
  const std::string extent =
      "0 " + std::to_string(image.width_px - 1) + " 0 " + std::to_string(image.height_px - 1) + " 0 0";
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<ImageData WholeExtent=\"" << extent << "\" Origin=\"" << image.origin_m[0] << ' ' << image.origin_m[1] << ' '
      << image.origin_m[2] << "\" Spacing=\"" << image.spacing_m[0] << ' ' << image.spacing_m[1] << " 1\" Direction=\"";
  for (std::size_t k = 0; k < 9; ++k) out << (k > 0 ? " " : "") << image.direction[k];
  out << "\">\n<Piece Extent=\"" << extent << "\">\n<PointData Scalars=\"" << image.scalars_name << "\">\n"
      << data_array<std::uint8_t>("UInt8", image.scalars_name, 1, image.pixels)
      << "</PointData>\n<CellData>\n</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
  return out.str();
}

std::string format_collection(const std::vector<SeriesEntry>& entries) {
  std::ostringstream out;
  out.precision(9);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<Collection>\n";
  for (const SeriesEntry& entry : entries)
    out << "<DataSet timestep=\"" << entry.time_s << "\" group=\"\" part=\"" << entry.part << "\" name=\"" << entry.name
        << "\" file=\"" << entry.file << "\"/>\n";
  out << "</Collection>\n</VTKFile>\n";
  return out.str();
}

}  // namespace navtool
