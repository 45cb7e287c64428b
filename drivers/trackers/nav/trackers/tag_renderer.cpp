// render_tags (declared in apriltag_tracker.hpp): the synthetic camera frames.
#include <apriltag/apriltag.h>
#include <apriltag/common/image_u8.h>
#include <apriltag/tag36h11.h>

#include <algorithm>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "nav/trackers/apriltag_tracker.hpp"

namespace nav::trackers {

GrayImage render_tags(const std::vector<TagRendering>& tags, double tag_size_m, const CameraIntrinsics& camera,
                      int width_px, int height_px, double noise_grey, std::uint64_t seed) {
  constexpr int kSupersample = 4;
  constexpr int kPixelsPerCell = 8;
  apriltag_family_t* family = tag36h11_create();
  const int cells = family->total_width;
  const double cell_m = tag_size_m / family->width_at_border;
  // Camera of the supersampled image: pixel centres at integers in both images.
  cv::Matx33d k_high(kSupersample * camera.fx_px, 0.0, kSupersample * camera.cx_px + 0.5 * (kSupersample - 1), 0.0,
                     kSupersample * camera.fy_px, kSupersample * camera.cy_px + 0.5 * (kSupersample - 1), 0.0, 0.0, 1.0);
  // Template pixel (u, v) -> tag plane metres (x, y), the tag centred on the origin.
  const double metres_per_pixel = cell_m / kPixelsPerCell;
  const double offset_m = (0.5 / kPixelsPerCell - cells / 2.0) * cell_m;
  const cv::Matx33d template_to_tag(metres_per_pixel, 0.0, offset_m, 0.0, metres_per_pixel, offset_m, 0.0, 0.0, 1.0);
  cv::Mat high(height_px * kSupersample, width_px * kSupersample, CV_8UC1, cv::Scalar(150));
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
