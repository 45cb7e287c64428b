// libFuzzer target for the NDI combined API reply decoders: the input is offered as a BX
// binary reply, as a framed text reply (CRC check, then TX and PHSR bodies) and as a bare
// TX body, as the driver would read them from an untrusted serial line.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "nav/trackers/ndi_protocol.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  namespace ndi = nav::trackers::ndi;
  (void)ndi::bx_reply_size(bytes);
  (void)ndi::decode_bx(bytes);
  (void)ndi::decode_tx(bytes);
  (void)ndi::decode_phsr(bytes);
  const auto body = ndi::check_reply(bytes);
  if (body.ok()) {
    (void)ndi::decode_tx(body.value());
    (void)ndi::decode_phsr(body.value());
  }
  return 0;
}
