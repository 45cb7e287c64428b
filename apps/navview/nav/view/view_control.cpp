#include "nav/view/view_control.hpp"

#include <algorithm>
#include <cmath>

namespace nav::view {

ViewControl::ViewControl(double azimuth_deg, double elevation_deg)
    : initial_azimuth_deg_(azimuth_deg),
      initial_elevation_deg_(elevation_deg),
      azimuth_deg_(azimuth_deg),
      elevation_deg_(elevation_deg) {}

void ViewControl::orbit(double azimuth_step_deg, double elevation_step_deg) {
  azimuth_deg_ = std::remainder(azimuth_deg_ + azimuth_step_deg, 360.0);
  elevation_deg_ = std::clamp(elevation_deg_ + elevation_step_deg, -89.0, 89.0);  // never through the poles
}

void ViewControl::drag(double dx_px, double dy_px) { orbit(-kDegreesPerDragPx * dx_px, kDegreesPerDragPx * dy_px); }

void ViewControl::wheel(int notches) {
  zoom_ = std::clamp(zoom_ * std::pow(kZoomPerStep, notches), kMinZoom, kMaxZoom);
}

void ViewControl::key(ViewKey key) {
  switch (key) {
    case ViewKey::orbit_left:
      orbit(kDegreesPerKey, 0.0);
      break;
    case ViewKey::orbit_right:
      orbit(-kDegreesPerKey, 0.0);
      break;
    case ViewKey::orbit_up:
      orbit(0.0, -kDegreesPerKey);
      break;
    case ViewKey::orbit_down:
      orbit(0.0, kDegreesPerKey);
      break;
    case ViewKey::zoom_in:
      wheel(1);
      break;
    case ViewKey::zoom_out:
      wheel(-1);
      break;
    case ViewKey::reset:
      azimuth_deg_ = initial_azimuth_deg_;
      elevation_deg_ = initial_elevation_deg_;
      zoom_ = 1.0;
      break;
    case ViewKey::help:
      help_shown_ = !help_shown_;
      break;
    case ViewKey::quit:
      quit_requested_ = true;
      break;
  }
}

}  // namespace nav::view
