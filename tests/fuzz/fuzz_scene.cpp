// libFuzzer target for the station scene loader: the input is parsed as a scene file
// (yaml-cpp, then the checked reading of every section). Nothing is built: building reads
// the files a scene names and meshes livers, which is not the parser's job.
#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/station/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto scene = nav::station::parse_scene(text, "fuzz/scene.yaml");
  if (!scene.ok()) (void)scene.error().describe();
  return 0;
}
