// navdevice: a device of the station as a process of its own, a DDS participant on the
// scene's domain and topic names, with the project's network rules.
//   navdevice sim --scene FILE [--seconds S] [--domain D] [--no-wait]
//       the simulated patient: the scene's full-order liver (generated or its mesh file)
//       breathing under a needle insertion, watched by a simulated tracker (nav/tool_pose)
//       and a synthetic B-mode scanner (nav/ultrasound_frame), with its truth on
//       nav/ground_truth (for navtool evaluate; a station never reads it). It waits (up to
//       --wait-s, default 60) for a running station (its health) unless --no-wait, then plays.
//   navdevice ndi --scene FILE [--serial DEVICE | --tcp HOST:PORT] [--seconds S] [--domain D] [--no-wait]
//       an NDI tracker (combined API): every port handle enabled, BX polled at the scene's
//       rate, the poses of the handles the scene maps to tools (devices.tracker.port_handles)
//       on nav/tool_pose; TSTOP when stopped.
//   navdevice apriltag --scene FILE [--seconds S] [--domain D] [--no-wait]
//       a camera (device, video or image sequence) watching tag36h11 markers: each tool's tag
//       (devices.tracker.tags) solved with the scene's intrinsics on nav/tool_pose.
//   navdevice capture --scene FILE [--source INDEX|VIDEO|PATTERN] [--seconds S] [--domain D] [--no-wait]
//       a frame grabber, video or image sequence (OpenCV capture) as the scanner: frames
//       clipped to the scene's rectangle at its pixel spacing on nav/ultrasound_frame.
//   navdevice plus --scene FILE [--recording FILE] [--fast] [--transform NAME=ROLE]... [--domain D] [--no-wait]
//       a PLUS sequence recording (.mha / .nrrd) played as scanner and tracker: its frames
//       (nav/ultrasound_frame, their own size and spacing) and its tracked transforms as the
//       scene's tools (nav/tool_pose), at the recorded intervals or --fast.
//   navdevice plusserver --scene FILE [--recording FILE] [--fast] [--seconds S]
//       the same recording served over OpenIGTLink as a PlusServer serves it (TRANSFORMs by
//       their recorded names, IMAGEs), where the scene's openigtlink.plus says: to navbridge igtl.
//   navdevice load --scene FILE [--factor F] [--seconds S] [--domain D]
//       a load on the station's host for soak runs: poses and frames at F (4) times the scene's
//       rates on topics of its own, read back and filtered, on the scene's I/O core.
// Each prints a status line a second, stops cleanly on SIGINT and SIGTERM, and exits 0 when
// done, 1 naming the device when it fails, 2 on a usage error.
#include <cstdio>
#include <string>
#include <vector>

#include "apriltag_device.hpp"
#include "capture_device.hpp"
#include "load_device.hpp"
#include "ndi_device.hpp"
#include "plus_device.hpp"
#include "plusserver_device.hpp"
#include "sim_device.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args.front() == "sim") return navdevice::run_sim({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "apriltag") return navdevice::run_apriltag({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "capture") return navdevice::run_capture({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "ndi") return navdevice::run_ndi({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "plus") return navdevice::run_plus({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "plusserver") return navdevice::run_plusserver({args.begin() + 1, args.end()});
  if (!args.empty() && args.front() == "load") return navdevice::run_load({args.begin() + 1, args.end()});
  std::fprintf(
      stderr,
      "usage: navdevice sim --scene FILE [--seconds S] [--domain D] [--no-wait] [--wait-s S]\n"
      "       navdevice apriltag --scene FILE [--seconds S] [--domain D] [--no-wait] [--wait-s S]\n"
      "       navdevice capture --scene FILE [--source INDEX|VIDEO|PATTERN] [--seconds S] [--domain D] [--no-wait]\n"
      "       navdevice ndi --scene FILE [--serial DEVICE | --tcp HOST:PORT] [--seconds S] [--domain D] [--no-wait]\n"
      "       navdevice plus --scene FILE [--recording FILE] [--fast] [--transform NAME=ROLE]... [--domain D] "
      "[--no-wait]\n"
      "       navdevice plusserver --scene FILE [--recording FILE] [--fast] [--seconds S]\n"
      "       navdevice load --scene FILE [--factor F] [--seconds S] [--domain D]\n");
  return 2;
}
