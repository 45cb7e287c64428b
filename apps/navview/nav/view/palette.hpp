#pragma once
// The colours of navview's drawings (OpenCV BGR order), shared with the tests that look
// for them in the pixels.
#include <opencv2/core/types.hpp>

namespace nav::view::palette {

inline const cv::Scalar kNeedle{0, 255, 255};            // yellow
inline const cv::Scalar kTarget{0, 0, 255};              // red
inline const cv::Scalar kUncertainty{255, 128, 0};       // azure
inline const cv::Scalar kForce{255, 0, 255};             // magenta: the force on the needle's tip
inline const cv::Scalar kSurface{150, 170, 230};         // flesh, lit head-on
inline const cv::Scalar kSurfaceBackground{40, 25, 20};  // dark blue-gray
inline const cv::Scalar kText{255, 255, 255};
inline const cv::Scalar kStatusHealthy{40, 110, 40};   // dark green: the station runs healthy
inline const cv::Scalar kStatusDegraded{30, 30, 170};  // dark red: degraded, a flag raised or stopped
inline const cv::Scalar kStatusIdle{90, 90, 90};       // gray: an input nothing was received from yet
inline const cv::Scalar kHelpBackground{70, 50, 40};   // the keyboard help's boxes

}  // namespace nav::view::palette
