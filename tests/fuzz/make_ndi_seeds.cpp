// Writes the seeds of the ndi_reply fuzz target into the folder given: BX and TX replies
// with every tool state, a PHSR reply, a framed OKAY.
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz/seed_generator.hpp"
#include "nav/trackers/ndi_protocol.hpp"

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  namespace ndi = nav::trackers::ndi;
  ndi::TrackingReply reply;
  reply.handles = {{0x01, nav::trackers::ToolState::ok, {1, 0, 0, 0}, {1.5, -2.25, -1000.0}, 0.12, 0x21, 5},
                   {0x02, nav::trackers::ToolState::partly_out_of_volume, {0, 1, 0, 0}, {0, 0, -900}, 0.3, 0xA1, 5},
                   {0x03, nav::trackers::ToolState::missing, {1, 0, 0, 0}, {}, 0.0, 0x21, 5},
                   {0x04, nav::trackers::ToolState::disabled, {1, 0, 0, 0}, {}, 0.0, 0, 0}};
  const auto write = [&](const char* name, const std::string& bytes) {
    std::ofstream file(folder / name, std::ios::binary);
    file << bytes;
    return static_cast<bool>(file);
  };
  return write("bx", ndi::encode_bx(reply)) && write("tx", ndi::frame_reply(ndi::encode_tx(reply))) &&
         write("phsr", ndi::frame_reply(ndi::encode_phsr({{0x01, 0x031}, {0x02, 0x001}}))) &&
         write("okay", ndi::frame_reply("OKAY"));
}
