// navtool calib probe: N-wire probe spatial calibration from a PLUS recording of the phantom
// and its device-set XML (phantom definition and registration); optionally validated on an
// independent recording; writes the image-to-probe joint into the station URDF.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/nwire_calibration.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/plus_transform.hpp"

namespace navtool {
namespace {

/// The tracked frames of a recording with valid image, probe and reference poses.
nav::Result<std::vector<nav::calibration::TrackedImage>> tracked_frames(const nav::ultrasound::PlusSequence& sequence,
                                                                        const CalibOptions& options) {
  const std::string probe_name = options.get("--probe", "ProbeToTracker");
  const std::string reference_name = options.get("--reference", "ReferenceToTracker");
  const auto* probe = sequence.find_transform(probe_name);
  const auto* reference = sequence.find_transform(reference_name);
  if (probe == nullptr)
    return nav::Error{.message = "no such transform in the recording", .file = sequence.path, .field = probe_name};
  if (reference == nullptr)
    return nav::Error{.message = "no such transform in the recording", .file = sequence.path, .field = reference_name};
  std::vector<nav::calibration::TrackedImage> frames;
  for (std::size_t i = 0; i < sequence.frames_read; ++i) {
    if (!probe->valid[i] || !reference->valid[i] || !sequence.image_valid[i]) continue;
    frames.push_back({sequence.frame(i), static_cast<int>(sequence.width_px), static_cast<int>(sequence.height_px),
                      nav::ultrasound::rigid_transform_m(probe->matrices_mm[i]),
                      nav::ultrasound::rigid_transform_m(reference->matrices_mm[i])});
  }
  return frames;
}

}  // namespace

int calib_probe(const std::vector<std::string>& args) {
  const auto options = CalibOptions::parse(args, {"--recording", "--phantom", "--validation", "--probe", "--reference",
                                                  "--min-frames", "--urdf", "--out", "--joint"});
  if (!options) return exit_bad_input;
  if (!options->has("--recording")) return report_error({"--recording FILE.mha is required", "", 0, "--recording"});
  if (!options->has("--phantom")) return report_error({"--phantom DEVICESET.xml is required", "", 0, "--phantom"});
  const auto phantom = nav::calibration::load_nwire_phantom(options->get("--phantom"));
  if (!phantom) return report_error(phantom.error());
  const auto recording = nav::ultrasound::read_plus_sequence(options->get("--recording"));
  if (!recording) return report_error(recording.error());
  const auto frames = tracked_frames(recording.value(), *options);
  if (!frames) return report_error(frames.error());
  const std::string min_frames_text = options->get("--min-frames", "10");
  char* end = nullptr;
  const unsigned long min_frames = std::strtoul(min_frames_text.c_str(), &end, 10);
  if (end == min_frames_text.c_str() || *end != '\0' || min_frames == 0) {
    return report_error({"expected a positive whole number", "", 0, "--min-frames"});
  }
  const auto result = nav::calibration::nwire_calibration(frames.value(), phantom.value(), min_frames);
  if (!result) {
    nav::Error error = result.error();
    error.file = options->get("--recording");
    return report_error(error);
  }
  const nav::calibration::ProbeCalibration& calibration = result.value().calibration;
  const Eigen::Vector3d t = calibration.probe_from_image.translation();
  const Eigen::Vector3d rpy = nav::calibration::rotation_to_rpy(calibration.probe_from_image.linear());
  std::printf("image to probe: xyz %.6f %.6f %.6f m, rpy %.6f %.6f %.6f rad\n", t.x(), t.y(), t.z(), rpy.x(), rpy.y(),
              rpy.z());
  std::printf("pixel spacing %.5f x %.5f mm\n", 1e3 * calibration.spacing_m.x(), 1e3 * calibration.spacing_m.y());
  std::printf(
      "phantom found in %zu of %zu frames; %zu points, %zu outliers, RMS residual %.3f mm; uncertainty "
      "%.3f mm over the image (1 sigma, %zu bootstrap fits)\n",
      result.value().frames_segmented, result.value().frames_total, calibration.points, calibration.outliers,
      1e3 * calibration.rms_residual_m, 1e3 * result.value().uncertainty_m, result.value().bootstrap_fits);
  if (options->has("--validation")) {
    const auto validation = nav::ultrasound::read_plus_sequence(options->get("--validation"));
    if (!validation) return report_error(validation.error());
    const auto validation_frames = tracked_frames(validation.value(), *options);
    if (!validation_frames) return report_error(validation_frames.error());
    const auto points =
        nav::calibration::nwire_points(validation_frames.value(), phantom.value(), result.value().correspondence);
    if (points.points.empty())
      return report_error(
          {"the phantom was not found in the validation recording", options->get("--validation"), 0, "frames"});
    const auto check = nav::calibration::validate_probe_calibration(calibration, points.points);
    std::printf(
        "validation: %zu of %zu frames, %zu points, reprojection error mean %.3f RMS %.3f max %.3f mm; as PLUS "
        "reports it (the lowest 95 %%) mean %.3f SD %.3f mm\n",
        points.frames_segmented, points.frames_total, check.points, 1e3 * check.mean_error_m, 1e3 * check.rms_error_m,
        1e3 * check.max_error_m, 1e3 * check.lowest95_mean_error_m, 1e3 * check.lowest95_sd_error_m);
  }
  if (!options->has("--urdf")) return exit_ok;
  return write_calibration(*options, options->get("--joint", "probe_marker_to_image"), calibration.probe_from_image,
                           calibration.rms_residual_m);
}

}  // namespace navtool
