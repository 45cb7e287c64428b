// libFuzzer target for the station frame tree loader: the input is parsed as URDF text
// (tinyxml2 element checks, then urdfdom); a tree that loads is queried and saved back.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/calibration/frame_tree.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto tree = nav::calibration::FrameTree::parse(text, "fuzz-input");
  if (!tree.ok()) return 0;
  const std::vector<std::string> frames = tree.value().frames();
  if (frames.size() >= 2) (void)tree.value().lookup(frames.front(), frames.back(), 0);
  return 0;
}
