// libFuzzer target for the OpenIGTLink reader: the input is one message as a sender could
// forge it (58-byte header, then a body), checked and read as the bridge would.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "nav/igtl/igtl_wire.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace igtl = nav::igtl;
  const std::span<const std::uint8_t> bytes(data, size);
  if (bytes.size() < igtl::kHeaderBytes) return 0;
  const auto header = igtl::parse_header(bytes.first(igtl::kHeaderBytes));
  if (!header.ok()) return 0;
  const auto body = bytes.subspan(igtl::kHeaderBytes);
  (void)igtl::check_body(header.value(), body);  // the fuzzer rarely matches a CRC: read the body either way
  (void)igtl::tool_pose_from_transform(header.value(), body, 1);
  static const auto frame = std::make_unique<nav::dds::UltrasoundFrame>();
  (void)igtl::ultrasound_frame_from_image(header.value(), body, 1, *frame);
  return 0;
}
