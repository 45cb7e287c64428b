// navview as a display a user drives, without a window: the view control orbits, zooms, resets
// and shows its help as documented; the 3-D panel follows it pixel for pixel (a zoom notch
// scales the surface by 1.15, an orbit of 60 degrees narrows and dims the square by cos 60, a
// reset gives back the first picture); and the station's health names each input's state and
// age in words, on the colour of its state.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/core.hpp>

#include "nav/core/health.hpp"
#include "nav/dds/health_text.hpp"
#include "nav/view/composite.hpp"
#include "nav/view/palette.hpp"
#include "test_navview_scene.hpp"

namespace nav::view {
namespace {

using namespace testing;

/// The 3-D panel of a composite without a frame (a square of kPanelHeightPx on the right).
cv::Mat surface_panel(const cv::Mat& image) {
  return image(cv::Rect(image.cols - kPanelHeightPx, 0, kPanelHeightPx, kPanelHeightPx)).clone();
}

}  // namespace

TEST(NavviewView, ControlOrbitsZoomsResetsAndTogglesHelp) {
  ViewControl view(30.0, 20.0);
  view.drag(20.0, 10.0);  // right and down: the surface turns right (the eye goes left) and tips towards the eye
  EXPECT_DOUBLE_EQ(view.azimuth_deg(), 30.0 - 20.0 * ViewControl::kDegreesPerDragPx);
  EXPECT_DOUBLE_EQ(view.elevation_deg(), 20.0 + 10.0 * ViewControl::kDegreesPerDragPx);
  view.drag(0.0, 1000.0);  // never over the pole
  EXPECT_DOUBLE_EQ(view.elevation_deg(), 89.0);
  view.drag(720.0, 0.0);  // a full turn and back to the same azimuth, kept within (-180, 180]
  EXPECT_NEAR(view.azimuth_deg(), 20.0, 1e-9);
  view.wheel(2);
  EXPECT_NEAR(view.zoom(), ViewControl::kZoomPerStep * ViewControl::kZoomPerStep, 1e-12);
  view.key(ViewKey::zoom_out);
  EXPECT_NEAR(view.zoom(), ViewControl::kZoomPerStep, 1e-12);
  view.wheel(-1000);
  EXPECT_DOUBLE_EQ(view.zoom(), ViewControl::kMinZoom);
  view.key(ViewKey::orbit_left);
  EXPECT_NEAR(view.azimuth_deg(), 20.0 + ViewControl::kDegreesPerKey, 1e-9);
  EXPECT_FALSE(view.help_shown());
  view.key(ViewKey::help);
  EXPECT_TRUE(view.help_shown());
  view.key(ViewKey::reset);
  EXPECT_DOUBLE_EQ(view.azimuth_deg(), 30.0);
  EXPECT_DOUBLE_EQ(view.elevation_deg(), 20.0);
  EXPECT_DOUBLE_EQ(view.zoom(), 1.0);
  EXPECT_TRUE(view.help_shown());  // the help stays until h again
  EXPECT_FALSE(view.quit_requested());
  view.key(ViewKey::quit);
  EXPECT_TRUE(view.quit_requested());
}

// The head-on square spans 2 x 63.6 px (expected::kSurfacePxPerM); a zoom notch makes it 1.15
// times wider; orbiting 60 degrees shows it at cos 60 of its width, lit at 0.3 + 0.7 cos 60 of
// the head-on colour; a reset gives back the first picture exactly.
TEST(NavviewView, ThePanelFollowsTheView) {
  const auto surface = scene_surface();
  Composer composer(scene_options(), scene_triangles());
  const DisplayInputs inputs{nullptr, nullptr, nullptr, surface.get(), nullptr};
  const cv::Mat first = surface_panel(composer.render(inputs));
  const double head_on_px = 2.0 * 0.1 * expected::kSurfacePxPerM;
  EXPECT_NEAR(surface_width_px(first), head_on_px, 2.0);

  composer.view().wheel(1);
  const int zoomed_px = surface_width_px(surface_panel(composer.render(inputs)));
  EXPECT_NEAR(zoomed_px, ViewControl::kZoomPerStep * head_on_px, 2.0);

  composer.view().wheel(-1);
  composer.view().drag(60.0 / ViewControl::kDegreesPerDragPx, 0.0);
  const cv::Mat turned = surface_panel(composer.render(inputs));
  EXPECT_NEAR(surface_width_px(turned), 0.5 * head_on_px, 2.0);
  EXPECT_TRUE(near_colour(turned.at<cv::Vec3b>(kPanelHeightPx / 2, kPanelHeightPx / 2), palette::kSurface * 0.65, 2));

  composer.view().key(ViewKey::reset);
  const cv::Mat reset = surface_panel(composer.render(inputs));
  EXPECT_EQ(cv::norm(reset, first, cv::NORM_INF), 0.0);
  std::printf("square across the panel: %d px head-on (%.1f by hand), %d px a notch closer, %d px turned 60 deg\n",
              surface_width_px(first), head_on_px, zoomed_px, surface_width_px(turned));
}

TEST(NavviewView, HelpIsShownOnRequestAndHintedInAWindow) {
  const auto surface = scene_surface();
  const DisplayInputs inputs{nullptr, nullptr, nullptr, surface.get(), nullptr};
  CompositeOptions options = scene_options();
  Composer headless(options, scene_triangles());
  EXPECT_EQ(pixels_of(surface_panel(headless.render(inputs)), palette::kHelpBackground), 0);  // PNGs: no hint
  options.interactive = true;
  Composer window(options, scene_triangles());
  const int hint_px = pixels_of(surface_panel(window.render(inputs)), palette::kHelpBackground);
  window.view().key(ViewKey::help);
  const int help_px = pixels_of(surface_panel(window.render(inputs)), palette::kHelpBackground);
  std::printf("help boxes: %d px as a hint, %d px with the help shown\n", hint_px, help_px);
  EXPECT_GT(hint_px, 200);
  EXPECT_GT(help_px, 5 * hint_px);  // one box per line of kViewHelpLines
}

TEST(NavviewView, EachInputsStateAndAgeInWords) {
  dds::StationHealth health;
  health.mode = dds::StationMode::degraded;
  health.input_age_ns = {12 * kNsPerMs, 40 * kNsPerMs, dds::StationHealth::kNoSampleYet, 1400 * kNsPerMs};
  health.input_flags[3] = static_cast<std::uint32_t>(HealthFlag::stale_input);
  EXPECT_EQ(dds::input_state_words(health, dds::StationInput::needle), "needle: healthy, 12 ms ago");
  EXPECT_EQ(dds::input_state_words(health, dds::StationInput::respiratory), "respiratory: nothing received yet");
  EXPECT_EQ(dds::input_state_words(health, dds::StationInput::ultrasound), "ultrasound: stale_input, 1.4 s ago");
  health.input_age_ns[0] = 300 * kNsPerSecond;
  EXPECT_EQ(dds::input_state_words(health, dds::StationInput::needle), "needle: healthy, 5 min ago");
}

// The input lines stack above the band in the 3-D panel's lower left, needle first: each line's
// box is green while its input is healthy, red with a flag raised, gray while nothing came.
TEST(NavviewView, InputLinesAreColouredByTheirState) {
  Composer composer(scene_options(), scene_triangles());
  dds::StationHealth health;
  health.mode = dds::StationMode::running;
  health.input_age_ns = {12 * kNsPerMs, 40 * kNsPerMs, dds::StationHealth::kNoSampleYet, 1400 * kNsPerMs};
  health.input_flags[3] = static_cast<std::uint32_t>(HealthFlag::stale_input);
  const cv::Mat panel = surface_panel(composer.render({}, &health));
  const cv::Scalar expected[] = {palette::kStatusHealthy, palette::kStatusHealthy, palette::kStatusIdle,
                                 palette::kStatusDegraded};
  const int line_px = 17 + 2, band_px = 22;
  for (int i = 0; i < 4; ++i) {
    const int bottom_row = kPanelHeightPx - band_px - 2 - (3 - i) * line_px - 1;
    EXPECT_TRUE(near_colour(panel.at<cv::Vec3b>(bottom_row, 5), expected[i], 0))
        << "input " << i << " at row " << bottom_row << ": " << panel.at<cv::Vec3b>(bottom_row, 5);
  }
}

}  // namespace nav::view
