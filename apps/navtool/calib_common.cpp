#include "calib_common.hpp"

#include <algorithm>
#include <cstdio>

#include "commands.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"

namespace navtool {

std::optional<CalibOptions> CalibOptions::parse(const std::vector<std::string>& args,
                                                const std::vector<std::string>& known) {
  CalibOptions options;
  for (std::size_t i = 0; i < args.size(); i += 2) {
    if (std::find(known.begin(), known.end(), args[i]) == known.end()) {
      std::fprintf(stderr, "navtool: unknown option '%s'\n", args[i].c_str());
      return std::nullopt;
    }
    if (i + 1 >= args.size()) {
      std::fprintf(stderr, "navtool: option '%s' needs a value\n", args[i].c_str());
      return std::nullopt;
    }
    options.values[args[i]] = args[i + 1];
  }
  return options;
}

std::string CalibOptions::get(const std::string& name, const std::string& fallback) const {
  const auto found = values.find(name);
  return found == values.end() ? fallback : found->second;
}

nav::Result<std::vector<nav::calibration::RecordedPose>> read_recorded_tool_poses(const std::string& path) {
  auto reader = nav::dds::RecordingReader::open(path);
  if (!reader) return reader.error();
  if (reader.value()->damage())
    std::fprintf(stderr, "navtool calib: note: %s\n", reader.value()->damage()->describe().c_str());
  std::vector<nav::calibration::RecordedPose> poses;
  nav::dds::ToolPose sample;
  for (std::size_t i = 0; i < reader.value()->record_count(); ++i) {
    auto record = reader.value()->read(i);
    if (!record) {
      std::fprintf(stderr, "navtool calib: note: skipped %s\n", record.error().describe().c_str());
      continue;
    }
    if (record.value().topic != nav::dds::Topic::tool_pose) continue;
    const auto& bytes = record.value().payload;
    if (nav::dds::decode_sample(bytes.data(), bytes.size(), sample) != nav::dds::SampleFault::none) {
      std::fprintf(stderr, "navtool calib: note: skipped the undecodable pose at byte %llu\n",
                   static_cast<unsigned long long>(record.value().offset));
      continue;
    }
    nav::calibration::RecordedPose pose;
    pose.time_ns = sample.source_time_ns;
    pose.tool = std::to_string(sample.tool_id);
    pose.pose.translation() = Eigen::Vector3d(sample.position_m[0], sample.position_m[1], sample.position_m[2]);
    const auto& q = sample.orientation_wxyz;
    pose.pose.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    poses.push_back(pose);
  }
  if (poses.empty())
    return nav::Error{.message = "the recording holds no tool pose", .file = path, .field = "nav/tool_pose"};
  return poses;
}

nav::Result<std::vector<nav::calibration::RecordedPose>> read_poses_option(const CalibOptions& options) {
  if (options.has("--poses") == options.has("--recording")) {
    return nav::Error{.message = "give exactly one of --poses FILE.csv and --recording FILE.navrec",
                      .field = "--poses"};
  }
  if (options.has("--poses")) return nav::calibration::read_pose_csv(options.get("--poses"));
  return read_recorded_tool_poses(options.get("--recording"));
}

int report_error(const nav::Error& error) {
  std::fprintf(stderr, "navtool: %s\n", error.describe().c_str());
  return exit_bad_input;
}

int write_calibration(const CalibOptions& options, const std::string& joint,
                      const nav::calibration::Transform& parent_from_child, double residual_m) {
  if (!options.has("--urdf")) return report_error({"--urdf FILE is required to write the result", "", 0, "--urdf"});
  auto tree = nav::calibration::FrameTree::load(options.get("--urdf"));
  if (!tree) return report_error(tree.error());
  const nav::calibration::CalibrationRecord record{nav::calibration::utc_timestamp(), residual_m};
  if (auto set = tree.value().set_calibration(joint, parent_from_child, record); !set) return report_error(set.error());
  const std::string out = options.get("--out", options.get("--urdf"));
  if (auto saved = tree.value().save(out); !saved) return report_error(saved.error());
  std::printf("wrote joint %s to %s\n", joint.c_str(), out.c_str());
  return exit_ok;
}

}  // namespace navtool
