#pragma once
// VTK's XML files, which ParaView opens: PolyData (.vtp), ImageData (.vti) and the collection
// (.pvd) that makes a time series of them. Arrays are inline in VTK's "binary" format: base64
// of a UInt32 byte count followed by the little-endian values (file version 0.1, whose cell
// offsets are the end of each cell).
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace navtool {

/// A named point-data array of float values, `components` per point.
struct FloatArray {
  std::string name;
  int components = 1;
  std::vector<float> values;
};

/// Points and their cells: each point a vertex cell, polylines, or triangles.
struct PolyData {
  std::vector<std::array<float, 3>> points;
  bool vertices = false;                          ///< one vertex cell per point
  std::vector<std::vector<std::uint32_t>> lines;  ///< polylines through point indices
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<FloatArray> point_data;
};

/// The .vtp text of `data`.
std::string format_polydata(const PolyData& data);

/// One 8-bit image placed in space: pixel (i, j) at origin + direction * (i sx, j sy, 0).
struct PlacedImage {
  std::uint32_t width_px = 0;
  std::uint32_t height_px = 0;
  std::array<double, 2> spacing_m{};
  std::array<double, 3> origin_m{};      ///< the first pixel's centre
  std::array<double, 9> direction{};     ///< the image axes as columns, row-major
  std::span<const std::uint8_t> pixels;  ///< row after row, width_px x height_px
  std::string scalars_name = "intensity";
};

/// The .vti text of `image` (its Direction, which VTK 9 reads, places it).
std::string format_image(const PlacedImage& image);

/// One file of a time series: its time, its part (what it shows) and its path, relative to
/// the .pvd.
struct SeriesEntry {
  double time_s = 0.0;
  int part = 0;
  std::string name;  ///< the part's name (ParaView shows it)
  std::string file;
};

/// The .pvd text of a time series.
std::string format_collection(const std::vector<SeriesEntry>& entries);

}  // namespace navtool
