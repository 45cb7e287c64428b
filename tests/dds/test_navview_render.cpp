// navview's drawing, without DDS: a known scene rendered into the composite puts the needle,
// the target, its uncertainty ellipse and the surface on the pixels computed by hand, the
// model frame's geometry taken into the frame's image frame by its placement; the
// 3-D panel paints the nearer of two overlapping triangles whatever their order; and the
// PNG files navview writes are well-formed and read back unchanged.
#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <vector>

#include <opencv2/core.hpp>

#include "nav/core/health.hpp"
#include "nav/view/composite.hpp"
#include "nav/view/frame_overlay.hpp"
#include "nav/view/palette.hpp"
#include "nav/view/png_file.hpp"
#include "test_navview_scene.hpp"

namespace nav::view {
namespace {

using namespace testing;

/// The scene's geometry is given in the frame's image frame: the identity placement.
const ImageFromModel kImageIsModel{};

cv::Vec3b at(const cv::Mat& image, double x, double y) {
  return image.at<cv::Vec3b>(static_cast<int>(std::lround(y)), static_cast<int>(std::lround(x)));
}

TEST(NavviewRender, NeedleIsDrawnAlongItsPathAndNowhereElse) {
  const auto frame = scene_frame();
  const dds::NeedleState needle = scene_needle();
  Composer composer(scene_options(), {});
  const cv::Mat& image = composer.render({frame.get(), &needle, nullptr, nullptr, &kImageIsModel});
  ASSERT_EQ(image.rows, kPanelHeightPx);
  ASSERT_EQ(image.cols, 240 + kPanelHeightPx);
  for (int y = expected::kNeedleTop.y + 2; y <= expected::kNeedleBottom.y - 2; ++y) {
    EXPECT_TRUE(near_colour(image.at<cv::Vec3b>(y, expected::kNeedleTop.x), palette::kNeedle)) << "row " << y;
    EXPECT_EQ(image.at<cv::Vec3b>(y, expected::kNeedleTop.x + 4), cv::Vec3b(kFrameGray, kFrameGray, kFrameGray))
        << "row " << y;
  }
  EXPECT_EQ(image.at<cv::Vec3b>(expected::kNeedleBottom.y + 4, expected::kNeedleTop.x),
            cv::Vec3b(kFrameGray, kFrameGray, kFrameGray))
      << "beyond the tip";
}

TEST(NavviewRender, ModelFrameGeometryIsDrawnWhereThePlacementPutsTheFrame) {
  // The image frame turned a quarter turn about z and moved: the needle and target given in the
  // model frame land on the same pixels as the image-frame scene; the covariance turns with it.
  const ImageFromModel image_from_model{{0, -1, 0, 1, 0, 0, 0, 0, 1}, {0.02, -0.01, 0.005}};
  const auto to_model = [&](const dds::Vector3& image_m) {  // R^T (p - t)
    const dds::Vector3 d{image_m[0] - 0.02, image_m[1] + 0.01, image_m[2] - 0.005};
    return dds::Vector3{d[1], -d[0], d[2]};
  };
  const auto frame = scene_frame();
  dds::NeedleState needle = scene_needle();
  for (std::uint32_t i = 0; i < needle.point_count; ++i) needle.shape_points_m[i] = to_model(needle.shape_points_m[i]);
  dds::TargetPrediction prediction = scene_prediction();
  prediction.position_m = to_model(prediction.position_m);
  prediction.covariance_m2 = {9e-6, 0, 0, 0, 16e-6, 0, 0, 0, 1e-6};  // x and y swapped by the quarter turn
  Composer composer(scene_options(), {});
  const cv::Mat& image = composer.render({frame.get(), &needle, &prediction, nullptr, &image_from_model});
  for (int y = expected::kNeedleTop.y + 2; y <= expected::kNeedleBottom.y - 2; ++y)
    EXPECT_TRUE(near_colour(image.at<cv::Vec3b>(y, expected::kNeedleTop.x), palette::kNeedle)) << "row " << y;
  const cv::Point target = expected::kTarget;
  EXPECT_TRUE(near_colour(image.at<cv::Vec3b>(target), palette::kTarget, 0));
  EXPECT_TRUE(near_colour(at(image, target.x + expected::kEllipseHalfAxisXPx, target.y), palette::kUncertainty));
  EXPECT_TRUE(near_colour(at(image, target.x, target.y + expected::kEllipseHalfAxisYPx), palette::kUncertainty));
  // Without a placement the frame is drawn bare: nothing can be placed on it.
  Composer bare(scene_options(), {});
  const cv::Mat& unplaced = bare.render({frame.get(), &needle, &prediction, nullptr, nullptr});
  EXPECT_EQ(unplaced.at<cv::Vec3b>((expected::kNeedleTop.y + expected::kNeedleBottom.y) / 2, expected::kNeedleTop.x),
            cv::Vec3b(kFrameGray, kFrameGray, kFrameGray));
  EXPECT_EQ(unplaced.at<cv::Vec3b>(target), cv::Vec3b(kFrameGray, kFrameGray, kFrameGray));
}

TEST(NavviewRender, TargetAndItsUncertaintyEllipseAreWhereTheCovarianceSays) {
  const auto frame = scene_frame();
  const dds::TargetPrediction prediction = scene_prediction();
  Composer composer(scene_options(), {});
  const cv::Mat& image = composer.render({frame.get(), nullptr, &prediction, nullptr, &kImageIsModel});
  const cv::Point target = expected::kTarget;
  const cv::Vec3b gray(kFrameGray, kFrameGray, kFrameGray);
  EXPECT_TRUE(near_colour(image.at<cv::Vec3b>(target), palette::kTarget, 0));
  // On the ellipse: the ends of both axes (x: 9.8 px, y: 14.7 px from the target).
  EXPECT_TRUE(near_colour(at(image, target.x + expected::kEllipseHalfAxisXPx, target.y), palette::kUncertainty));
  EXPECT_TRUE(near_colour(at(image, target.x - expected::kEllipseHalfAxisXPx, target.y), palette::kUncertainty));
  EXPECT_TRUE(near_colour(at(image, target.x, target.y + expected::kEllipseHalfAxisYPx), palette::kUncertainty));
  EXPECT_TRUE(near_colour(at(image, target.x, target.y - expected::kEllipseHalfAxisYPx), palette::kUncertainty));
  // Inside it (between marker and ellipse) and outside it, the frame shows through.
  EXPECT_EQ(at(image, target.x, target.y + 10), gray);
  EXPECT_EQ(at(image, target.x + 13, target.y), gray);
  EXPECT_EQ(at(image, target.x, target.y + 19), gray);
}

TEST(NavviewRender, EllipseFollowsACorrelatedCovariance) {
  // Variances 25 and 4 px^2 along the diagonals: the major axis points at 45 degrees.
  const auto frame = scene_frame();
  dds::TargetPrediction prediction = scene_prediction();
  const double major_m2 = 25e-6, minor_m2 = 4e-6;  // x spacing 1 mm: 1 px = 1e-3 m
  prediction.covariance_m2 = {0.5 * (major_m2 + minor_m2),
                              0.5 * (major_m2 - minor_m2),
                              0,
                              0.5 * (major_m2 - minor_m2),
                              0.5 * (major_m2 + minor_m2),
                              0,
                              0,
                              0,
                              1e-6};
  frame->pixel_spacing_m = {1e-3, 1e-3};
  const PanelEllipse ellipse = uncertainty_ellipse(FramePanelMapping::for_frame(*frame, kPanelHeightPx), prediction);
  EXPECT_NEAR(ellipse.major_axis_angle_deg, 45.0, 1e-9);
  EXPECT_NEAR(ellipse.half_axis_major_px, 2.4477468306808166 * 5.0, 1e-9);
  EXPECT_NEAR(ellipse.half_axis_minor_px, 2.4477468306808166 * 2.0, 1e-9);
}

TEST(NavviewRender, ScaledFramesKeepPixelEdgesAligned) {
  auto frame = scene_frame();
  frame->height_px = 400;  // shown at half size in a 200-pixel panel
  frame->width_px = 300;
  const FramePanelMapping mapping = FramePanelMapping::for_frame(*frame, kPanelHeightPx);
  EXPECT_EQ(mapping.panel_width_px(*frame), 150);
  const cv::Point2d corner = mapping.to_panel({-0.5e-3, -0.25e-3, 0.0});  // the frame's top-left edge
  EXPECT_NEAR(corner.x, -0.5, 1e-12);
  EXPECT_NEAR(corner.y, -0.5, 1e-12);
  const cv::Point2d centre = mapping.to_panel({0.100, 0.100, 0.0});  // frame pixel (100, 200)
  EXPECT_NEAR(centre.x, 49.75, 1e-12);
  EXPECT_NEAR(centre.y, 99.75, 1e-12);
}

TEST(NavviewRender, SurfaceAndTargetAreDrawnWhereProjected) {
  const auto frame = scene_frame();
  const auto surface = scene_surface();
  dds::TargetPrediction prediction = scene_prediction();
  prediction.position_m = {0.05, -0.05, 0.01};
  Composer composer(scene_options(), scene_triangles());
  const cv::Mat& image = composer.render({frame.get(), nullptr, &prediction, surface.get(), &kImageIsModel});
  const double centre = 99.5;
  const double x0 = expected::kSurfacePanelX + centre;
  const double half_side = 0.1 * expected::kSurfacePxPerM;  // 63.6 px
  // Head-on, the square is fully lit; around it the background shows.
  EXPECT_TRUE(near_colour(at(image, x0 - 30, centre + 30), palette::kSurface, 2));
  EXPECT_TRUE(near_colour(at(image, x0 - half_side + 3, centre - half_side + 3), palette::kSurface, 2));
  EXPECT_TRUE(near_colour(at(image, x0 - half_side - 4, centre), palette::kSurfaceBackground, 0));
  EXPECT_TRUE(near_colour(at(image, x0, centre + half_side + 4), palette::kSurfaceBackground, 0));
  // The target at (0.05, -0.05): right of and below the centre (panel y grows downwards).
  const double offset = 0.05 * expected::kSurfacePxPerM;
  EXPECT_TRUE(near_colour(at(image, x0 + offset, centre + offset), palette::kTarget, 0));
  EXPECT_TRUE(near_colour(at(image, x0 - offset, centre + offset), palette::kSurface, 2));
}

TEST(NavviewRender, NearerTriangleHidesTheFartherWhateverTheirOrder) {
  // A head-on square at z = -0.05 behind a triangle tilted 60 degrees about y, nearer the
  // viewer; the tilted one is lit at cos 60 = half the headlight.
  auto surface = std::make_unique<dds::DeformedSurface>();
  surface->vertex_count = 7;
  const float s60 = 0.8660254f, c60 = 0.5f;
  const std::array<std::array<float, 3>, 7> vertices = {{{-0.1f, -0.1f, -0.05f},
                                                         {0.1f, -0.1f, -0.05f},
                                                         {0.1f, 0.1f, -0.05f},
                                                         {-0.1f, 0.1f, -0.05f},
                                                         {-0.04f * c60, -0.04f, 0.05f - 0.04f * s60},
                                                         {0.04f * c60, -0.04f, 0.05f + 0.04f * s60},
                                                         {0.0f, 0.04f, 0.05f}}};
  std::copy(vertices.begin(), vertices.end(), surface->vertex_positions_m.begin());
  const cv::Scalar tilted = palette::kSurface * (0.3 + 0.7 * 0.5);
  for (const SurfaceTriangles& triangles :
       {SurfaceTriangles{{0, 1, 2}, {0, 2, 3}, {4, 5, 6}}, SurfaceTriangles{{4, 5, 6}, {0, 1, 2}, {0, 2, 3}}}) {
    Composer composer(scene_options(), triangles);
    const cv::Mat& image = composer.render({nullptr, nullptr, nullptr, surface.get()});
    const cv::Mat panel = image(cv::Rect(image.cols - kPanelHeightPx, 0, kPanelHeightPx, kPanelHeightPx));
    EXPECT_TRUE(near_colour(at(panel, 99.5, 99.5), tilted, 2)) << "the tilted triangle is in front";
    EXPECT_TRUE(near_colour(at(panel, 99.5 + 40, 99.5), palette::kSurface, 2)) << "the square beside it";
  }
}

TEST(NavviewRender, TheStationsHealthIsABandGreenOnlyWhileItRunsHealthy) {
  Composer composer(scene_options(), scene_triangles());
  const auto band_colour = [](const cv::Mat& image) { return image.at<cv::Vec3b>(image.rows - 2, 1); };
  dds::StationHealth health;
  health.mode = dds::StationMode::running;
  EXPECT_TRUE(near_colour(band_colour(composer.render({}, &health)), palette::kStatusHealthy, 0));
  health.flags = static_cast<std::uint32_t>(HealthFlag::bad_sample);  // running, but a refused sample held
  health.boundary.malformed = 3;
  EXPECT_TRUE(near_colour(band_colour(composer.render({}, &health)), palette::kStatusDegraded, 0));
  health.mode = dds::StationMode::degraded;
  health.flags = static_cast<std::uint32_t>(HealthFlag::stale_input);
  const cv::Mat& degraded = composer.render({}, &health);
  EXPECT_TRUE(near_colour(band_colour(degraded), palette::kStatusDegraded, 0));
  int text_pixels = 0;  // the band says it in white
  for (int x = 0; x < degraded.cols; ++x)
    text_pixels += near_colour(degraded.at<cv::Vec3b>(degraded.rows - 11, x), palette::kText, 60) ? 1 : 0;
  EXPECT_GT(text_pixels, 20);
  EXPECT_EQ(band_colour(composer.render({})), cv::Vec3b(0, 0, 0));  // no health yet: no band
}

TEST(NavviewRender, AnInputInTroubleTurnsTheBandAndIsNamedOnIt) {
  CompositeOptions wide = scene_options();  // a band long enough for every word
  wide.panel_height_px = 600;
  Composer composer(wide, scene_triangles());
  const auto band_colour = [](const cv::Mat& image) { return image.at<cv::Vec3b>(image.rows - 2, 1); };
  const auto text_pixels = [](const cv::Mat& image) {  // white pixels in the band
    int count = 0;
    for (int y = image.rows - 20; y < image.rows; ++y)
      for (int x = 0; x < image.cols; ++x) count += near_colour(image.at<cv::Vec3b>(y, x), palette::kText, 60) ? 1 : 0;
    return count;
  };
  dds::StationHealth health;
  health.mode = dds::StationMode::running;
  const auto needle = static_cast<std::size_t>(dds::StationInput::needle);
  health.input_flags[needle] = static_cast<std::uint32_t>(HealthFlag::bad_sample);  // the input alone
  EXPECT_TRUE(near_colour(band_colour(composer.render({}, &health)), palette::kStatusDegraded, 0));
  // The same red band with and without the input named: its name and flags are the extra text.
  health.flags = static_cast<std::uint32_t>(HealthFlag::bad_sample);
  const int named_text = text_pixels(composer.render({}, &health));
  health.input_flags[needle] = 0;
  const int unnamed_text = text_pixels(composer.render({}, &health));
  std::printf("band text: %d white pixels, %d with \" | needle: bad_sample\"\n", unnamed_text, named_text);
  EXPECT_GT(named_text, unnamed_text + 100);  // about 20 characters more
}

TEST(NavviewRender, WithoutAnyInputThePanelsAreBlank) {
  Composer composer(scene_options(), scene_triangles());
  const cv::Mat& image = composer.render({});
  EXPECT_EQ(image.cols, 2 * kPanelHeightPx);
  EXPECT_EQ(image.at<cv::Vec3b>(100, 100), cv::Vec3b(0, 0, 0));
  EXPECT_TRUE(near_colour(image.at<cv::Vec3b>(100, 300), palette::kSurfaceBackground, 0));
}

/// The bytes of a file.
std::vector<std::uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint32_t big_endian(const std::vector<std::uint8_t>& bytes, std::size_t at) {
  return (std::uint32_t{bytes[at]} << 24) | (std::uint32_t{bytes[at + 1]} << 16) | (std::uint32_t{bytes[at + 2]} << 8) |
         bytes[at + 3];
}

TEST(NavviewPng, FilesAreWellFormedAndReadBackUnchanged) {
  const auto frame = scene_frame();
  const dds::NeedleState needle = scene_needle();
  const dds::TargetPrediction prediction = scene_prediction();
  const auto surface = scene_surface();
  CompositeOptions options = scene_options();
  options.captions = true;
  Composer composer(options, scene_triangles());
  const cv::Mat image = composer.render({frame.get(), &needle, &prediction, surface.get(), &kImageIsModel}).clone();
  const std::string path = ::testing::TempDir() + "navview_render_test.png";
  ASSERT_TRUE(write_png(path, image).ok());

  // Checked by hand against the PNG specification: signature, IHDR, CRCs, IDAT size.
  const std::vector<std::uint8_t> bytes = file_bytes(path);
  ASSERT_GT(bytes.size(), 8u + 25u + 12u + 12u);
  EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 8),
            (std::vector<std::uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}));
  EXPECT_EQ(big_endian(bytes, 8), 13u);
  EXPECT_EQ(std::string(bytes.begin() + 12, bytes.begin() + 16), "IHDR");
  EXPECT_EQ(big_endian(bytes, 16), static_cast<std::uint32_t>(image.cols));
  EXPECT_EQ(big_endian(bytes, 20), static_cast<std::uint32_t>(image.rows));
  EXPECT_EQ(bytes[24], 8);  // bit depth
  EXPECT_EQ(bytes[25], 2);  // truecolour
  EXPECT_EQ(big_endian(bytes, 29), crc32(0L, &bytes[12], 17));
  const std::size_t idat = 33;
  ASSERT_EQ(std::string(bytes.begin() + idat + 4, bytes.begin() + idat + 8), "IDAT");
  const std::uint32_t idat_length = big_endian(bytes, idat);
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(image.rows) * (1 + 3 * static_cast<std::size_t>(image.cols)));
  uLongf raw_size = static_cast<uLongf>(raw.size());
  ASSERT_EQ(uncompress(raw.data(), &raw_size, &bytes[idat + 8], idat_length), Z_OK);
  EXPECT_EQ(raw_size, raw.size());
  // Row 100, pixel 120 (the target, red) in RGB order after the row's filter byte.
  const std::size_t target = 100 * (1 + 3 * static_cast<std::size_t>(image.cols)) + 1 + 3 * 120;
  EXPECT_EQ(raw[target], 255);
  EXPECT_EQ(raw[target + 2], 0);
  EXPECT_EQ(std::string(bytes.end() - 8, bytes.end() - 4), "IEND");

  auto read = read_png(path);
  ASSERT_TRUE(read.ok()) << read.error().describe();
  EXPECT_EQ(cv::norm(read.value(), image, cv::NORM_INF), 0.0);
}

TEST(NavviewPng, DamagedFileIsRefusedWithTheChunkOffset) {
  const std::string path = ::testing::TempDir() + "navview_damaged.png";
  cv::Mat gray(16, 16, CV_8UC1, cv::Scalar(7));
  ASSERT_TRUE(write_png(path, gray).ok());
  auto intact = read_png(path);
  ASSERT_TRUE(intact.ok());
  EXPECT_EQ(intact.value().at<std::uint8_t>(15, 15), 7);
  std::vector<std::uint8_t> bytes = file_bytes(path);
  bytes[33 + 10] ^= 0x40;  // inside the IDAT data
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  const auto damaged = read_png(path);
  ASSERT_FALSE(damaged.ok());
  EXPECT_NE(damaged.error().describe().find("CRC mismatch at byte offset 33"), std::string::npos)
      << damaged.error().describe();
}

}  // namespace
}  // namespace nav::view
