#include "nav/calibration/pose_csv.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace nav::calibration {
namespace {

/// The comma-separated fields of `line`, trimmed of spaces.
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream stream(line);
  while (std::getline(stream, field, ',')) {
    const auto first = field.find_first_not_of(" \t\r");
    const auto last = field.find_last_not_of(" \t\r");
    fields.push_back(first == std::string::npos ? "" : field.substr(first, last - first + 1));
  }
  return fields;
}

bool to_number(const std::string& text, double& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && std::isfinite(value);
}

/// Calls `record(fields, line_number)` for every data line; stops at the first error.
template <typename Record>
Status for_each_record(const std::string& path, std::size_t columns, Record record) {
  std::ifstream file(path);
  if (!file) return Error{.message = "cannot open the file", .file = path};
  std::string line;
  for (int line_number = 1; std::getline(file, line); ++line_number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::vector<std::string> fields = split(line);
    if (fields.size() != columns) {
      return Error{.message = "expected " + std::to_string(columns) + " comma-separated fields, found " +
                              std::to_string(fields.size()),
                   .file = path,
                   .line = line_number};
    }
    if (Status status = record(fields, line_number); !status) return status;
  }
  return Done{};
}

Status read_numbers(const std::vector<std::string>& fields, std::size_t first, double* values, const std::string& path,
                    int line) {
  for (std::size_t i = first; i < fields.size(); ++i) {
    if (!to_number(fields[i], values[i - first])) {
      return Error{.message = "not a finite number: '" + fields[i] + "'",
                   .file = path,
                   .line = line,
                   .field = "column " + std::to_string(i + 1)};
    }
  }
  return Done{};
}

}  // namespace

Result<std::vector<RecordedPose>> read_pose_csv(const std::string& path) {
  std::vector<RecordedPose> poses;
  Status status = for_each_record(path, 9, [&](const std::vector<std::string>& fields, int line) -> Status {
    double time_s = 0.0;
    if (!to_number(fields[0], time_s))
      return Error{
          .message = "not a time in seconds: '" + fields[0] + "'", .file = path, .line = line, .field = "column 1"};
    double values[7];
    if (Status numbers = read_numbers(fields, 2, values, path, line); !numbers) return numbers;
    const Eigen::Quaterniond q(values[3], values[4], values[5], values[6]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      return Error{.message = "quaternion is not unit", .file = path, .line = line, .field = "columns 6-9"};
    poses.push_back({static_cast<TimeNs>(std::llround(time_s * 1e9)), fields[1],
                     make_transform(q, {values[0], values[1], values[2]})});
    return Done{};
  });
  if (!status) return status.error();
  return poses;
}

Result<std::vector<Eigen::Vector3d>> read_point_csv(const std::string& path) {
  std::vector<Eigen::Vector3d> points;
  Status status = for_each_record(path, 3, [&](const std::vector<std::string>& fields, int line) -> Status {
    double values[3];
    if (Status numbers = read_numbers(fields, 0, values, path, line); !numbers) return numbers;
    points.emplace_back(values[0], values[1], values[2]);
    return Done{};
  });
  if (!status) return status.error();
  return points;
}

std::vector<Transform> poses_of(const std::vector<RecordedPose>& poses, const std::string& tool) {
  std::vector<Transform> selected;
  for (const RecordedPose& pose : poses) {
    if (tool.empty() || pose.tool == tool) selected.push_back(pose.pose);
  }
  return selected;
}

Status write_pose_csv(const std::string& path, const std::vector<RecordedPose>& poses) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) return Error{.message = "cannot create the file", .file = path};
  std::fputs("# time_s,tool,x_m,y_m,z_m,qw,qx,qy,qz (tracker_from_tool)\n", file);
  for (const RecordedPose& pose : poses) {
    const Eigen::Quaterniond q(pose.pose.rotation());
    const Eigen::Vector3d t = pose.pose.translation();
    std::fprintf(file, "%.9f,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", static_cast<double>(pose.time_ns) * 1e-9,
                 pose.tool.c_str(), t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z());
  }
  return std::fclose(file) == 0 ? Status(Done{}) : Status(Error{.message = "cannot write the file", .file = path});
}

}  // namespace nav::calibration
