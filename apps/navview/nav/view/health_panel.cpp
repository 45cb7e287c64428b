#include "nav/view/health_panel.hpp"

#include <opencv2/imgproc.hpp>

#include "nav/dds/health_text.hpp"
#include "nav/view/palette.hpp"
#include "nav/view/text_box.hpp"

namespace nav::view {

void draw_status_band(cv::Mat& canvas, const dds::StationHealth& health) {
  cv::Mat band = canvas(cv::Rect(0, canvas.rows - kStatusBandPx, canvas.cols, kStatusBandPx));
  band.setTo(dds::station_healthy(health) ? palette::kStatusHealthy : palette::kStatusDegraded);
  draw_text(band, dds::health_summary(health), {6, kStatusBandPx - 7});
}

void draw_input_lines(cv::Mat& panel, const dds::StationHealth& health) {
  int bottom_px = panel.rows - kStatusBandPx - 2;
  for (std::size_t i = dds::kStationInputCount; i-- > 0;) {
    const auto input = static_cast<dds::StationInput>(i);
    const cv::Scalar& background = health.input_flags[i] != 0 ? palette::kStatusDegraded
                                   : health.input_age_ns[i] == dds::StationHealth::kNoSampleYet
                                       ? palette::kStatusIdle
                                       : palette::kStatusHealthy;
    bottom_px -= draw_text_box(panel, dds::input_state_words(health, input), {4, bottom_px}, background) + 2;
  }
}

}  // namespace nav::view
