// libFuzzer target for the OpenIGTLink reader: the input is one message as a sender could
// forge it (58-byte header, then a body, v3's extended header and metadata included), checked
// and read as the bridge would.
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
  const auto range = igtl::content_range(header.value(), body);
  if (!range.ok()) return 0;
  const auto content = body.subspan(range.value().offset, range.value().bytes);
  (void)igtl::tool_pose_from_transform(header.value(), content, 1);
  if (const auto elements = igtl::tracking_elements(header.value(), content); elements.ok())
    for (const auto& element : elements.value()) (void)igtl::tool_pose_from_element(header.value(), element, 1);
  static const auto frame = std::make_unique<nav::dds::UltrasoundFrame>();
  (void)igtl::ultrasound_frame_from_image(header.value(), content, 1, *frame);
  return 0;
}
