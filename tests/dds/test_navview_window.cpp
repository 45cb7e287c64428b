// navview's window, driven as a user drives it, in a virtual X server (Xvfb): started with the
// demo scene and fed by a publisher in this process, its window shows the scene; a left drag
// of 120 px turns the square 60 degrees (half its width), h shows the keyboard help, r gives
// back the first view pixel for pixel, a wheel notch zooms by 1.15, the station's health turns
// the band red and names the stale input, and q closes it. The mouse and keys reach it as X
// events, and the screenshots are read back from the X server.
#include <gtest/gtest.h>

#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/keysym.h>
#undef Status  // Xlib's macro for int

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <thread>

#include <opencv2/core.hpp>

#include "child_process.hpp"
#include "dds_test_samples.hpp"
#include "nav/core/health.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/view/palette.hpp"
#include "nav/view/png_file.hpp"
#include "nav/view/view_control.hpp"
#include "navview_placing_pose.hpp"
#include "test_navview_scene.hpp"

namespace nav::view {
namespace {

using nav::testing::ChildProcess;
using namespace nav::view::testing;

const std::string kNavview = std::string(NAV_BIN_DIR) + "/navview";
const std::string kXvfb = "/usr/bin/Xvfb";
constexpr TimeNs kMatchTimeoutNs = 30 * kNsPerSecond;
constexpr std::uint32_t kDomain = 164;

/// A connection to the virtual X server, closed with the test.
struct XConnection {
  Display* display = nullptr;
  ~XConnection() {
    if (display != nullptr) XCloseDisplay(display);
  }
};

/// The top-level window named `name`, or 0.
Window find_window(Display* display, const char* name) {
  Window root = 0, parent = 0, *children = nullptr;
  unsigned count = 0;
  if (XQueryTree(display, DefaultRootWindow(display), &root, &parent, &children, &count) == 0) return 0;
  Window found = 0;
  for (unsigned i = 0; i < count && found == 0; ++i) {
    char* window_name = nullptr;
    if (XFetchName(display, children[i], &window_name) != 0 && window_name != nullptr) {
      if (std::string(window_name) == name) found = children[i];
      XFree(window_name);
    }
  }
  if (children != nullptr) XFree(children);
  return found;
}

/// What the X server shows of `window` (BGR), or an empty image.
cv::Mat screenshot(Display* display, Window window) {
  XWindowAttributes attributes;
  if (XGetWindowAttributes(display, window, &attributes) == 0 || attributes.map_state != IsViewable) return {};
  XImage* image = XGetImage(display, window, 0, 0, static_cast<unsigned>(attributes.width),
                            static_cast<unsigned>(attributes.height), AllPlanes, ZPixmap);
  if (image == nullptr) return {};
  cv::Mat bgr(attributes.height, attributes.width, CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x) {
      const unsigned long pixel = XGetPixel(image, x, y);
      bgr.at<cv::Vec3b>(y, x) = {static_cast<std::uint8_t>(pixel & 0xff),
                                 static_cast<std::uint8_t>((pixel >> 8) & 0xff),
                                 static_cast<std::uint8_t>((pixel >> 16) & 0xff)};
    }
  XDestroyImage(image);
  return bgr;
}

/// A mouse button pressed or released at (x, y) of `window`, as the X server would send it.
void send_button(Display* display, Window window, int type, unsigned button, int x, int y) {
  XEvent event{};
  event.xbutton.type = type;
  event.xbutton.display = display;
  event.xbutton.window = window;
  event.xbutton.button = button;
  event.xbutton.x = x;
  event.xbutton.y = y;
  event.xbutton.same_screen = True;
  event.xbutton.state = type == ButtonRelease ? Button1Mask : 0;
  XSendEvent(display, window, False, type == ButtonPress ? ButtonPressMask : ButtonReleaseMask, &event);
  XFlush(display);
}

void send_motion(Display* display, Window window, int x, int y) {
  XEvent event{};
  event.xmotion.type = MotionNotify;
  event.xmotion.display = display;
  event.xmotion.window = window;
  event.xmotion.x = x;
  event.xmotion.y = y;
  event.xmotion.state = Button1Mask;
  event.xmotion.same_screen = True;
  XSendEvent(display, window, False, Button1MotionMask, &event);
  XFlush(display);
}

void send_key(Display* display, Window window, KeySym symbol) {
  XEvent event{};
  event.xkey.type = KeyPress;
  event.xkey.display = display;
  event.xkey.window = window;
  event.xkey.keycode = XKeysymToKeycode(display, symbol);
  event.xkey.same_screen = True;
  XSendEvent(display, window, False, KeyPressMask, &event);
  XFlush(display);
}

/// The 3-D panel of a window showing the scene, below its caption and hint (rows 45 on).
cv::Mat surface_view(const cv::Mat& image) {
  return image(cv::Rect(expected::kSurfacePanelX, 45, kPanelHeightPx, kPanelHeightPx - 45)).clone();
}

}  // namespace

TEST(NavviewWindow, ADisplayAUserDrivesWithMouseAndKeys) {
  if (!std::filesystem::exists(kXvfb)) {
    if (nav::testing::running_under_ci()) GTEST_FAIL() << "Xvfb missing under CI (toolchain/install-deps.sh)";
    GTEST_SKIP() << "Xvfb is not installed";
  }
  const std::string base = ::testing::TempDir() + "navview_window_" + std::to_string(getpid());
  const std::string display_name = ":" + std::to_string(100 + getpid() % 400);
  ChildProcess xvfb({kXvfb, display_name, "-screen", "0", "800x600x24", "-nolisten", "tcp"}, base + "_xvfb.log");
  ASSERT_TRUE(xvfb.started());
  XConnection x;
  ASSERT_TRUE(dds::testing::wait_until(
      [&] { return (x.display = XOpenDisplay(display_name.c_str())) != nullptr || xvfb.ended(); },
      std::chrono::seconds(20)));
  ASSERT_NE(x.display, nullptr) << xvfb.log();

  const std::string square_obj = base + "_square.obj";
  write_scene_triangles_obj(square_obj);
  const std::string scene = base + "_demo.yaml";
  ASSERT_TRUE(write_text_file(scene, nav::testing::movable_demo_text()).ok());
  setenv("DISPLAY", display_name.c_str(), 1);
  ChildProcess navview({kNavview, "--period-ms", "20", "--duration-s", "120", "--surface-mesh", square_obj, "--unit",
                        "mm", "--panel-height", std::to_string(kPanelHeightPx), "--azimuth-deg", "0", "--elevation-deg",
                        "0", "--scene", scene, "--domain", std::to_string(kDomain)},
                       base + "_navview.log");
  ASSERT_TRUE(navview.started());

  auto station = dds::DdsNode::create(dds::testing::local_network(kDomain));
  ASSERT_TRUE(station.ok()) << station.error().describe();
  dds::DdsNode& node = *station.value();
  ASSERT_TRUE(SceneStream::advertise(node, kMatchTimeoutNs)) << navview.log();
  ASSERT_TRUE(node.advertise<dds::StationHealth>().ok());
  ASSERT_TRUE(node.wait_for_match(dds::Topic::station_health, 1, kMatchTimeoutNs)) << navview.log();

  SceneStream stream;
  std::optional<dds::StationHealth> health;
  Window window = 0;
  cv::Mat shown;
  // Publishes the scene once and looks at the window until `seen` holds for its picture.
  const auto publish_until = [&](const std::function<bool(const cv::Mat&)>& seen) {
    return dds::testing::wait_until(
        [&] {
          stream.publish(node);
          if (health) node.write(*health);
          std::this_thread::sleep_for(std::chrono::milliseconds(40));
          if (window == 0) window = find_window(x.display, "navview");
          if (window != 0) shown = screenshot(x.display, window);
          return !shown.empty() && seen(shown);
        },
        std::chrono::seconds(60));
  };

  ASSERT_TRUE(publish_until([](const cv::Mat& image) { return shows_scene(image); }))
      << "window " << window << ", " << shown.cols << " x " << shown.rows << "\n"
      << navview.log();
  const cv::Mat first = surface_view(shown);
  const double head_on_px = 2.0 * 0.1 * expected::kSurfacePxPerM;
  EXPECT_NEAR(surface_width_px(shown), head_on_px, 2.0);

  // A left drag of 120 px to the right: 60 degrees.
  const int drag_px = static_cast<int>(60.0 / ViewControl::kDegreesPerDragPx);
  send_button(x.display, window, ButtonPress, Button1, 300, 100);
  send_motion(x.display, window, 300 + drag_px / 2, 100);
  send_motion(x.display, window, 300 + drag_px, 100);
  send_button(x.display, window, ButtonRelease, Button1, 300 + drag_px, 100);
  EXPECT_TRUE(publish_until([&](const cv::Mat& image) {
    return std::abs(surface_width_px(image) - 0.5 * head_on_px) < 2.0;
  })) << "the square spans "
      << surface_width_px(shown) << " px after the drag";

  send_key(x.display, window, XK_h);
  EXPECT_TRUE(publish_until([](const cv::Mat& image) { return pixels_of(image, palette::kHelpBackground) > 5000; }))
      << pixels_of(shown, palette::kHelpBackground) << " px of help";
  const std::string help_png = base + "_help.png";
  EXPECT_TRUE(write_png(help_png, shown).ok());

  send_key(x.display, window, XK_h);
  send_key(x.display, window, XK_r);
  EXPECT_TRUE(publish_until([&](const cv::Mat& image) {
    return cv::norm(surface_view(image), first, cv::NORM_INF) == 0.0;
  })) << "the reset view differs from the first";

  send_button(x.display, window, ButtonPress, Button4, 300, 100);
  EXPECT_TRUE(publish_until([&](const cv::Mat& image) {
    return std::abs(surface_width_px(image) - ViewControl::kZoomPerStep * head_on_px) < 2.0;
  })) << "the square spans "
      << surface_width_px(shown) << " px after a wheel notch";

  health = dds::StationHealth{};
  health->mode = dds::StationMode::degraded;
  health->input_age_ns = {12 * kNsPerMs, 15 * kNsPerMs, dds::StationHealth::kNoSampleYet, 1400 * kNsPerMs};
  health->input_flags[3] = static_cast<std::uint32_t>(HealthFlag::stale_input);
  EXPECT_TRUE(publish_until([](const cv::Mat& image) {
    return near_colour(image.at<cv::Vec3b>(image.rows - 2, 1), palette::kStatusDegraded, 0) &&
           pixels_of(image, palette::kStatusIdle) > 100;
  })) << "no health shown";
  const std::string health_png = base + "_health.png";
  EXPECT_TRUE(write_png(health_png, shown).ok());
  std::printf("navview's window in Xvfb %s: %d x %d; screenshots %s and %s\n", display_name.c_str(), shown.cols,
              shown.rows, help_png.c_str(), health_png.c_str());

  send_key(x.display, window, XK_q);
  EXPECT_EQ(navview.wait(std::chrono::seconds(30)), 0) << navview.log();
  XCloseDisplay(x.display);  // before its server goes: Xlib ends a process whose server vanished
  x.display = nullptr;
  xvfb.signal(SIGTERM);
  EXPECT_EQ(xvfb.wait(std::chrono::seconds(10)), 0) << xvfb.log();
}

}  // namespace nav::view
