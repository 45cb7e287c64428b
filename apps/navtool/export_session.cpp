// navtool export: a DDS recording of a session (navtool record) as ParaView files. Each
// deformed surface the station published is a display step; at each step the deformed liver
// surface (the scene's triangles, with each vertex's displacement from rest), the needle's
// centreline (with its tip force), the tumour now and ahead (with their 1-sigma radii) and the
// newest ultrasound frame, placed where the tracked probe held it (the station's chain), are
// written as VTK XML files, and session.pvd makes them a time series (seconds from the first
// step). Damaged records are skipped and counted; a surface of another scene is refused.
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/image_placement.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/target_sigma.hpp"
#include "vtk_xml.hpp"

namespace navtool {
namespace {

/// The newest sample of each kind seen so far in the recording.
struct Newest {
  std::optional<nav::dds::NeedleState> needle;
  std::optional<nav::dds::TargetPrediction> tumour_now, tumour_ahead;
  std::unique_ptr<nav::dds::UltrasoundFrame> frame = std::make_unique<nav::dds::UltrasoundFrame>();
  bool frame_seen = false;
  std::uint64_t frame_number = 0;  ///< frames seen: a new one gets a file of its own
};

PolyData surface_data(const nav::dds::DeformedSurface& surface, const nav::station::DisplaySurface& rest) {
  PolyData data;
  FloatArray displacement{"displacement_m", 3, {}};
  for (std::size_t i = 0; i < surface.vertex_count; ++i) {
    data.points.push_back(surface.vertex_positions_m[i]);
    for (std::size_t k = 0; k < 3; ++k)
      displacement.values.push_back(static_cast<float>(surface.vertex_positions_m[i][k] - rest.rest_m[i][k]));
  }
  for (const auto& t : rest.triangles)
    data.triangles.push_back(
        {static_cast<std::uint32_t>(t[0]), static_cast<std::uint32_t>(t[1]), static_cast<std::uint32_t>(t[2])});
  data.point_data.push_back(std::move(displacement));
  return data;
}

PolyData needle_data(const nav::dds::NeedleState& needle) {
  PolyData data;
  std::vector<std::uint32_t> line;
  for (std::uint32_t i = 0; i < needle.point_count; ++i) {
    const auto& p = needle.shape_points_m[i];
    data.points.push_back({static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
    line.push_back(i);
  }
  if (!line.empty()) data.lines.push_back(std::move(line));
  FloatArray force{"tip_force_n", 3, {}};  // at the tip, zero along the shaft
  for (std::uint32_t i = 0; i < needle.point_count; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      force.values.push_back(i + 1 == needle.point_count ? static_cast<float>(needle.tip_force_n[k]) : 0.0f);
  data.point_data.push_back(std::move(force));
  return data;
}

PolyData tumour_data(const Newest& newest) {
  PolyData data;
  data.vertices = true;
  FloatArray radius{"sigma_radius_m", 1, {}}, horizon{"horizon_s", 1, {}};
  for (const auto* p :
       {newest.tumour_now ? &*newest.tumour_now : nullptr, newest.tumour_ahead ? &*newest.tumour_ahead : nullptr}) {
    if (p == nullptr) continue;
    data.points.push_back({static_cast<float>(p->position_m[0]), static_cast<float>(p->position_m[1]),
                           static_cast<float>(p->position_m[2])});
    radius.values.push_back(static_cast<float>(nav::station::sigma_radius_m(p->covariance_m2)));
    horizon.values.push_back(static_cast<float>(1e-9 * static_cast<double>(p->horizon_ns)));
  }
  data.point_data.push_back(std::move(radius));
  data.point_data.push_back(std::move(horizon));
  return data;
}

PlacedImage image_data(const nav::dds::UltrasoundFrame& frame, const nav::RigidPose& model_from_image) {
  PlacedImage image;
  image.width_px = frame.width_px;
  image.height_px = frame.height_px;
  image.spacing_m = frame.pixel_spacing_m;
  for (int k = 0; k < 3; ++k) image.origin_m[static_cast<std::size_t>(k)] = model_from_image.position_m[k];
  const Eigen::Matrix3d axes = model_from_image.rotation.toRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) image.direction[static_cast<std::size_t>(3 * r + c)] = axes(r, c);
  image.pixels = {frame.pixels.data(), frame.pixel_count()};
  return image;
}

/// Decodes `record` into `sample`; false when it does not decode (counted as damaged).
template <typename Sample>
bool decode(const nav::dds::RecordedSample& record, Sample& sample) {
  return nav::dds::decode_sample(record.payload.data(), record.payload.size(), sample) == nav::dds::SampleFault::none;
}

}  // namespace

int export_session(const std::vector<std::string>& args) {
  const auto options = CalibOptions::parse(args, {"--recording", "--scene", "--out"});
  if (!options) return exit_bad_input;
  if (!options->has("--recording") || !options->has("--scene") || !options->has("--out"))
    return report_error({"--recording FILE.navrec, --scene FILE and --out DIR are required", "", 0, "--recording"});
  auto scene = nav::station::load_scene(options->get("--scene"));
  if (!scene) return report_error(scene.error());
  auto mesh = nav::station::make_station_mesh(scene.value());
  if (!mesh) return report_error(mesh.error());
  auto rest = nav::station::make_display_surface(mesh.value());
  if (!rest) return report_error(rest.error());
  auto placement = nav::station::ImagePlacement::create(scene.value());
  if (!placement) return report_error(placement.error());
  auto reader = nav::dds::RecordingReader::open(options->get("--recording"));
  if (!reader) return report_error(reader.error());
  if (reader.value()->damage())
    std::fprintf(stderr, "navtool export: %s; exporting its intact part\n",
                 reader.value()->damage()->describe().c_str());
  const std::filesystem::path out = options->get("--out");
  std::error_code made;
  std::filesystem::create_directories(out, made);
  if (made) return report_error({"cannot create the directory: " + made.message(), out.string(), 0, "--out"});

  Newest newest;
  std::vector<SeriesEntry> series;
  std::optional<nav::TimeNs> first_ns;
  std::string frame_file;
  std::size_t steps = 0, damaged = 0, other_scene = 0, steps_unplaced = 0;
  const auto write = [&](const std::string& name, const std::string& text) {
    const nav::Status written = nav::write_text_file((out / name).string(), text);
    if (!written) std::fprintf(stderr, "navtool export: %s\n", written.error().describe().c_str());
    return written.ok();
  };
  auto surface = std::make_unique<nav::dds::DeformedSurface>();
  nav::dds::ToolPose pose;
  nav::dds::NeedleState needle;
  nav::dds::TargetPrediction prediction;
  for (std::size_t i = 0; i < reader.value()->record_count(); ++i) {
    auto record = reader.value()->read(i);
    if (!record) {
      ++damaged;
      continue;
    }
    bool decoded = true;
    switch (record.value().topic) {
      case nav::dds::Topic::tool_pose:
        if ((decoded = decode(record.value(), pose))) placement.value().add_pose(pose);
        break;
      case nav::dds::Topic::ultrasound_frame:
        if ((decoded = decode(record.value(), *newest.frame))) newest.frame_seen = true, ++newest.frame_number;
        break;
      case nav::dds::Topic::needle_state:
        if ((decoded = decode(record.value(), needle))) newest.needle = needle;
        break;
      case nav::dds::Topic::target_prediction:
        if ((decoded = decode(record.value(), prediction)))
          (prediction.horizon_ns == 0 ? newest.tumour_now : newest.tumour_ahead) = prediction;
        break;
      case nav::dds::Topic::deformed_surface: {
        if (!(decoded = decode(record.value(), *surface))) break;
        if (surface->vertex_count != rest.value().rest_m.size()) {
          ++other_scene;
          break;
        }
        if (!first_ns) first_ns = surface->source_time_ns;
        const double time_s = 1e-9 * static_cast<double>(surface->source_time_ns - *first_ns);
        char step[16];
        std::snprintf(step, sizeof(step), "%06zu", steps);
        const std::string surface_file = std::string("surface_") + step + ".vtp";
        if (!write(surface_file, format_polydata(surface_data(*surface, rest.value())))) return exit_bad_input;
        series.push_back({time_s, 0, "liver_surface", surface_file});
        if (newest.needle) {
          const std::string file = std::string("needle_") + step + ".vtp";
          if (!write(file, format_polydata(needle_data(*newest.needle)))) return exit_bad_input;
          series.push_back({time_s, 1, "needle", file});
        }
        if (newest.tumour_now || newest.tumour_ahead) {
          const std::string file = std::string("tumour_") + step + ".vtp";
          if (!write(file, format_polydata(tumour_data(newest)))) return exit_bad_input;
          series.push_back({time_s, 2, "tumour", file});
        }
        if (newest.frame_seen) {
          const std::string file = "ultrasound_" + std::to_string(newest.frame_number) + ".vti";
          if (file != frame_file) {  // a new frame: placed where the probe held it when it was taken
            const auto model_from_image = placement.value().model_from_image(newest.frame->source_time_ns);
            if (model_from_image && write(file, format_image(image_data(*newest.frame, *model_from_image))))
              frame_file = file;
            else
              ++steps_unplaced;  // tried again at the next step: a later pose may place it
          }
          if (frame_file == file) series.push_back({time_s, 3, "ultrasound", file});
        }
        ++steps;
        break;
      }
      default:
        break;
    }
    damaged += decoded ? 0 : 1;
  }
  if (steps == 0)
    return report_error({"the recording holds no deformed surface of this scene's liver (" +
                             std::to_string(other_scene) + " of another scene)",
                         options->get("--recording"), 0, "deformed_surface"});
  if (!write("session.pvd", format_collection(series))) return exit_bad_input;
  std::printf(
      "navtool export: %zu display steps, %zu files in %s (session.pvd); %zu steps whose newest frame had no probe "
      "pose, %zu surfaces of another scene, %zu damaged records skipped\n",
      steps, series.size(), out.string().c_str(), steps_unplaced, other_scene, damaged);
  return exit_ok;
}

}  // namespace navtool
