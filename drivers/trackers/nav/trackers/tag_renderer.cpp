// render_tags (declared in apriltag_tracker.hpp): the synthetic camera frames. With a lens
// distortion, the ideal pinhole image is rendered on a canvas wide enough for the whole
// undistorted field of view, then resampled through the lens (cv::remap).
#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "nav/trackers/apriltag_tracker.hpp"

namespace nav::trackers {
namespace {

constexpr int kSupersample = 4;

/// For each pixel of a width_px x height_px image seen through `camera`'s lens, where its
/// ray falls in the ideal pinhole image (pixels); and the margin (pixels, on every side)
/// an ideal canvas needs to hold all of them.
cv::Mat ideal_pixel_map(const CameraIntrinsics& camera, int width_px, int height_px, int& margin_px) {
  cv::Mat map(height_px, width_px, CV_32FC2);
  double outside_px = 0.0;
  for (int v = 0; v < height_px; ++v) {
    for (int u = 0; u < width_px; ++u) {
      const Eigen::Vector2d ideal = undistort_pixel(camera, Eigen::Vector2d(u, v));
      map.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(ideal.x()), static_cast<float>(ideal.y()));
      outside_px =
          std::max({outside_px, -ideal.x(), -ideal.y(), ideal.x() - (width_px - 1), ideal.y() - (height_px - 1)});
    }
  }
  margin_px = static_cast<int>(std::ceil(outside_px)) + 2;
  return map;
}

}  // namespace

GrayImage render_tags(const std::vector<TagRendering>& tags, double tag_size_m, const CameraIntrinsics& camera,
                      int width_px, int height_px, double noise_grey, std::uint64_t seed) {
  constexpr int kPixelsPerCell = 8;
  int margin_px = 0;
  cv::Mat ideal_map;
  if (!camera.distortion.is_zero()) ideal_map = ideal_pixel_map(camera, width_px, height_px, margin_px);
  const double margin_high_px = kSupersample * margin_px;
  apriltag_family_t* family = tag36h11_create();
  const int cells = family->total_width;
  const double cell_m = tag_size_m / family->width_at_border;
  // Camera of the supersampled ideal image (pixel centres at integers in both images), on a
  // canvas with the lens's margin on every side.
  const double offset_high_px = 0.5 * (kSupersample - 1) + margin_high_px;
  cv::Matx33d k_high(kSupersample * camera.fx_px, 0.0, kSupersample * camera.cx_px + offset_high_px, 0.0,
                     kSupersample * camera.fy_px, kSupersample * camera.cy_px + offset_high_px, 0.0, 0.0, 1.0);
  // Template pixel (u, v) -> tag plane metres (x, y), the tag centred on the origin.
  const double metres_per_pixel = cell_m / kPixelsPerCell;
  const double offset_m = (0.5 / kPixelsPerCell - cells / 2.0) * cell_m;
  const cv::Matx33d template_to_tag(metres_per_pixel, 0.0, offset_m, 0.0, metres_per_pixel, offset_m, 0.0, 0.0, 1.0);
  cv::Mat high((height_px + 2 * margin_px) * kSupersample, (width_px + 2 * margin_px) * kSupersample, CV_8UC1,
               cv::Scalar(150));
  for (const TagRendering& tag : tags) {
    image_u8_t* code = apriltag_to_image(family, static_cast<uint32_t>(tag.id));
    const cv::Mat cells_image(code->height, code->width, CV_8UC1, code->buf, static_cast<std::size_t>(code->stride));
    cv::Mat pattern;
    cv::resize(cells_image, pattern, cv::Size(), kPixelsPerCell, kPixelsPerCell, cv::INTER_NEAREST);
    const Eigen::Matrix3d r = tag.camera_from_tag.rotation();
    const Eigen::Vector3d t = tag.camera_from_tag.translation();
    const cv::Matx33d plane(r(0, 0), r(0, 1), t.x(), r(1, 0), r(1, 1), t.y(), r(2, 0), r(2, 1), t.z());
    const cv::Matx33d homography = k_high * plane * template_to_tag;
    cv::warpPerspective(pattern, high, cv::Mat(homography), high.size(), cv::INTER_LINEAR, cv::BORDER_TRANSPARENT);
    image_u8_destroy(code);
  }
  tag36h11_destroy(family);
  if (!ideal_map.empty()) {
    // The map at the supersampled pixels: bilinear between the image's pixel centres (the
    // resize's centre convention matches the supersampling's), in canvas coordinates.
    cv::Mat high_map;
    cv::resize(ideal_map, high_map, cv::Size(width_px * kSupersample, height_px * kSupersample), 0.0, 0.0,
               cv::INTER_LINEAR);
    high_map = high_map * kSupersample + cv::Scalar(offset_high_px, offset_high_px);
    cv::Mat seen;
    cv::remap(high, seen, high_map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(150));
    high = seen;
  }
  cv::Mat low;
  cv::resize(high, low, cv::Size(width_px, height_px), 0.0, 0.0, cv::INTER_AREA);
  cv::GaussianBlur(low, low, cv::Size(3, 3), 0.8);
  cv::Mat noisy(low.size(), CV_32F);
  cv::RNG rng(seed);
  rng.fill(noisy, cv::RNG::NORMAL, 0.0, noise_grey);
  cv::Mat grey;
  low.convertTo(grey, CV_32F);
  grey += noisy;
  grey.convertTo(low, CV_8U);  // saturating
  GrayImage image{width_px, height_px, std::vector<std::uint8_t>(low.total())};
  std::copy(low.datastart, low.dataend, image.pixels.begin());
  return image;
}

}  // namespace nav::trackers
