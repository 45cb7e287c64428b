#pragma once
// How the user looks at the 3-D panel: orbit, zoom and reset, driven by the window's mouse and
// keys, and whether the keyboard help is shown. Pure state, free of any window system, so that
// tests drive it as the window does.
#include <string_view>

namespace nav::view {

/// The keys navview acts on (the window maps its key symbols to these).
enum class ViewKey { orbit_left, orbit_right, orbit_up, orbit_down, zoom_in, zoom_out, reset, help, quit };

/// The 3-D panel's viewing angles and zoom, and the help overlay's visibility.
class ViewControl {
 public:
  static constexpr double kDegreesPerDragPx = 0.5;
  static constexpr double kDegreesPerKey = 10.0;
  static constexpr double kZoomPerStep = 1.15;  ///< one wheel notch or one + / - key
  static constexpr double kMinZoom = 0.1;
  static constexpr double kMaxZoom = 50.0;

  /// The view at `azimuth_deg`, `elevation_deg` and zoom 1 (the surface fitted to the panel),
  /// which reset() returns to.
  ViewControl(double azimuth_deg, double elevation_deg);

  /// A mouse drag of (dx, dy) pixels with the left button held: dragging right turns the
  /// surface to the right, dragging down tips its top towards the viewer.
  void drag(double dx_px, double dy_px);
  /// Wheel notches: positive zooms in.
  void wheel(int notches);
  /// A key press.
  void key(ViewKey key);

  double azimuth_deg() const { return azimuth_deg_; }
  double elevation_deg() const { return elevation_deg_; }
  double zoom() const { return zoom_; }
  bool help_shown() const { return help_shown_; }
  bool quit_requested() const { return quit_requested_; }

 private:
  void orbit(double azimuth_step_deg, double elevation_step_deg);

  double initial_azimuth_deg_, initial_elevation_deg_;
  double azimuth_deg_, elevation_deg_;
  double zoom_ = 1.0;
  bool help_shown_ = false;
  bool quit_requested_ = false;
};

/// The lines of the keyboard help, as the overlay shows them.
inline constexpr std::string_view kViewHelpLines[] = {"left drag or arrows: orbit", "wheel or + / -: zoom",
                                                      "r: reset the view", "h: show or hide this help",
                                                      "q or Esc: quit"};

}  // namespace nav::view
