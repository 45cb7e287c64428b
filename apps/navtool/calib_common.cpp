#include "calib_common.hpp"

#include <algorithm>
#include <cstdio>

#include "commands.hpp"

namespace navtool {

std::optional<CalibOptions> CalibOptions::parse(const std::vector<std::string>& args, const std::vector<std::string>& known) {
  CalibOptions options;
  for (std::size_t i = 0; i < args.size(); i += 2) {
    if (std::find(known.begin(), known.end(), args[i]) == known.end()) {
      std::fprintf(stderr, "navtool calib: unknown option '%s'\n", args[i].c_str());
      return std::nullopt;
    }
    if (i + 1 >= args.size()) {
      std::fprintf(stderr, "navtool calib: option '%s' needs a value\n", args[i].c_str());
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

int report_error(const nav::Error& error) {
  std::fprintf(stderr, "navtool calib: %s\n", error.describe().c_str());
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
