#include "nav/trackers/ndi_protocol.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>

namespace nav::trackers::ndi {
namespace {

constexpr std::uint8_t kBxValid = 0x01;
constexpr std::uint8_t kBxMissing = 0x02;
constexpr std::uint8_t kBxDisabled = 0x04;
constexpr std::uint16_t kBxStart = 0xA5C4;

void put_u16(std::string& out, std::uint16_t value) {
  out += static_cast<char>(value & 0xFF);
  out += static_cast<char>(value >> 8);
}
void put_u32(std::string& out, std::uint32_t value) {
  for (int i = 0; i < 4; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFF);
}
void put_f32(std::string& out, double value) {
  const float single = static_cast<float>(value);
  std::uint32_t bits = 0;
  std::memcpy(&bits, &single, sizeof bits);
  put_u32(out, bits);
}

/// A cursor over untrusted bytes: every read checks the remaining length.
class Reader {
 public:
  explicit Reader(std::string_view bytes) : bytes_(bytes) {}
  bool u8(std::uint8_t& value) {
    if (pos_ + 1 > bytes_.size()) return false;
    value = static_cast<std::uint8_t>(bytes_[pos_++]);
    return true;
  }
  bool u16(std::uint16_t& value) {
    std::uint8_t lo = 0, hi = 0;
    if (!u8(lo) || !u8(hi)) return false;
    value = static_cast<std::uint16_t>(lo | (hi << 8));
    return true;
  }
  bool u32(std::uint32_t& value) {
    value = 0;
    for (int i = 0; i < 4; ++i) {
      std::uint8_t byte = 0;
      if (!u8(byte)) return false;
      value |= static_cast<std::uint32_t>(byte) << (8 * i);
    }
    return true;
  }
  bool f32(double& value) {
    std::uint32_t bits = 0;
    if (!u32(bits)) return false;
    float single = 0.0f;
    std::memcpy(&single, &bits, sizeof single);
    value = single;
    return std::isfinite(value);
  }
  /// `count` characters as a string_view.
  bool text(std::size_t count, std::string_view& out) {
    if (pos_ + count > bytes_.size()) return false;
    out = bytes_.substr(pos_, count);
    pos_ += count;
    return true;
  }
  bool starts_with(std::string_view prefix) const { return bytes_.substr(pos_).substr(0, prefix.size()) == prefix; }
  void skip(std::size_t count) { pos_ += count; }
  bool done() const { return pos_ == bytes_.size(); }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
};

bool parse_hex(std::string_view text, std::uint32_t& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  return error == std::errc() && end == text.data() + text.size();
}

/// A TX fixed-width signed decimal: sign then `digits` digits, scaled by 10^-decimals.
bool parse_signed(Reader& reader, std::size_t digits, double scale, double& value) {
  std::string_view text;
  if (!reader.text(digits + 1, text) || (text[0] != '+' && text[0] != '-')) return false;
  std::uint32_t magnitude = 0;
  const auto [end, error] = std::from_chars(text.data() + 1, text.data() + text.size(), magnitude, 10);
  if (error != std::errc() || end != text.data() + text.size()) return false;
  value = (text[0] == '-' ? -1.0 : 1.0) * magnitude * scale;
  return true;
}

void put_signed(std::string& out, double value, std::size_t digits, double inverse_scale) {
  const long long magnitude = std::llround(std::abs(value) * inverse_scale);
  char text[32];
  std::snprintf(text, sizeof text, "%c%0*lld", value < 0.0 ? '-' : '+', static_cast<int>(digits), magnitude);
  out += text;
}

std::string hex(std::uint32_t value, int width) {
  char text[16];
  std::snprintf(text, sizeof text, "%0*X", width, value);
  return text;
}

Error bad(const std::string& message, const std::string& field) { return Error{.message = message, .field = field}; }

}  // namespace

std::uint16_t crc16(std::string_view bytes) noexcept {
  std::uint16_t crc = 0;
  for (const char c : bytes) {
    crc ^= static_cast<std::uint8_t>(c);
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1u) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001u) : crc >> 1;
  }
  return crc;
}

std::string frame_command(std::string_view name, std::string_view arguments) {
  std::string command(name);
  command += ':';
  command += arguments;
  return command + hex(crc16(command), 4) + '\r';
}

std::string frame_reply(std::string_view body) { return std::string(body) + hex(crc16(body), 4) + '\r'; }

Result<std::string> check_reply(std::string_view framed) {
  if (framed.size() < 4) return bad("reply shorter than its CRC", "reply");
  const std::string_view body = framed.substr(0, framed.size() - 4);
  std::uint32_t crc = 0;
  if (!parse_hex(framed.substr(framed.size() - 4), crc)) return bad("reply CRC is not 4 hex digits", "reply");
  if (crc != crc16(body)) return bad("reply CRC mismatch", "reply");
  return std::string(body);
}

ToolState state_from_bits(bool missing, bool disabled, std::uint32_t port_status) noexcept {
  if (disabled) return ToolState::disabled;
  if (missing) return ToolState::missing;
  if (port_status & kPortOutOfVolume) return ToolState::out_of_volume;
  if (port_status & kPortPartlyOutOfVolume) return ToolState::partly_out_of_volume;
  return ToolState::ok;
}

std::string encode_bx(const TrackingReply& reply) {
  std::string body;
  body += static_cast<char>(reply.handles.size());
  for (const HandleRecord& record : reply.handles) {
    body += static_cast<char>(record.handle);
    if (record.state == ToolState::disabled) {
      body += static_cast<char>(kBxDisabled);
      continue;
    }
    body += static_cast<char>(has_pose(record.state) ? kBxValid : kBxMissing);
    if (has_pose(record.state)) {
      for (double q : record.orientation_wxyz) put_f32(body, q);
      for (double t : record.position_mm) put_f32(body, t);
      put_f32(body, record.error_mm);
    }
    put_u32(body, record.port_status);
    put_u32(body, record.frame_number);
  }
  put_u16(body, reply.system_status);
  std::string header;
  put_u16(header, kBxStart);
  put_u16(header, static_cast<std::uint16_t>(body.size()));
  put_u16(header, crc16(header));
  std::string out = header + body;
  put_u16(out, crc16(body));
  return out;
}

std::optional<std::size_t> bx_reply_size(std::string_view header) noexcept {
  Reader reader(header);
  std::uint16_t start = 0, length = 0, crc = 0;
  if (!reader.u16(start) || !reader.u16(length) || !reader.u16(crc)) return std::nullopt;
  if (start != kBxStart || crc != crc16(header.substr(0, 4))) return std::nullopt;
  return std::size_t{6} + length + 2;
}

Result<TrackingReply> decode_bx(std::string_view bytes) {
  const auto size = bx_reply_size(bytes);
  if (!size) return bad("BX header: wrong start sequence or header CRC", "BX header");
  if (*size != bytes.size()) return bad("BX reply length does not match its header", "BX length");
  const std::string_view body = bytes.substr(6, bytes.size() - 8);
  Reader crc_reader(bytes.substr(bytes.size() - 2));
  std::uint16_t body_crc = 0;
  crc_reader.u16(body_crc);
  if (body_crc != crc16(body)) return bad("BX body CRC mismatch", "BX body");
  Reader reader(body);
  TrackingReply reply;
  std::uint8_t count = 0;
  if (!reader.u8(count)) return bad("BX body too short", "BX handle count");
  for (std::uint8_t i = 0; i < count; ++i) {
    HandleRecord record;
    std::uint8_t status = 0;
    if (!reader.u8(record.handle) || !reader.u8(status)) return bad("BX body too short", "BX handle");
    if (status != kBxValid && status != kBxMissing && status != kBxDisabled)
      return bad("unknown handle status", "BX handle");
    if (status == kBxDisabled) {
      record.state = ToolState::disabled;
      reply.handles.push_back(record);
      continue;
    }
    if (status == kBxValid) {
      for (double& q : record.orientation_wxyz) {
        if (!reader.f32(q)) return bad("BX transform truncated or not finite", "BX transform");
      }
      for (double& t : record.position_mm) {
        if (!reader.f32(t)) return bad("BX transform truncated or not finite", "BX transform");
      }
      if (!reader.f32(record.error_mm)) return bad("BX transform truncated or not finite", "BX transform");
    }
    if (!reader.u32(record.port_status) || !reader.u32(record.frame_number))
      return bad("BX body too short", "BX port status");
    record.state = state_from_bits(status == kBxMissing, false, record.port_status);
    reply.handles.push_back(record);
  }
  if (!reader.u16(reply.system_status) || !reader.done()) return bad("BX body length mismatch", "BX system status");
  return reply;
}

std::string encode_tx(const TrackingReply& reply) {
  std::string body = hex(static_cast<std::uint32_t>(reply.handles.size()), 2);
  for (const HandleRecord& record : reply.handles) {
    body += hex(record.handle, 2);
    if (record.state == ToolState::disabled) {
      body += "DISABLED\n";
      continue;
    }
    if (has_pose(record.state)) {
      for (double q : record.orientation_wxyz) put_signed(body, q, 5, 1e4);
      for (double t : record.position_mm) put_signed(body, t, 6, 1e2);
      put_signed(body, record.error_mm, 5, 1e4);
    } else {
      body += "MISSING";
    }
    body += hex(record.port_status, 8) + hex(record.frame_number, 8) + "\n";
  }
  return body + hex(reply.system_status, 4);
}

Result<TrackingReply> decode_tx(std::string_view body) {
  Reader reader(body);
  std::string_view field;
  std::uint32_t count = 0;
  if (!reader.text(2, field) || !parse_hex(field, count))
    return bad("TX handle count is not 2 hex digits", "TX handle count");
  TrackingReply reply;
  for (std::uint32_t i = 0; i < count; ++i) {
    HandleRecord record;
    std::uint32_t handle = 0;
    if (!reader.text(2, field) || !parse_hex(field, handle)) return bad("TX handle is not 2 hex digits", "TX handle");
    record.handle = static_cast<std::uint8_t>(handle);
    if (reader.starts_with("DISABLED\n")) {
      reader.skip(9);
      record.state = ToolState::disabled;
      reply.handles.push_back(record);
      continue;
    }
    const bool missing = reader.starts_with("MISSING");
    if (missing) {
      reader.skip(7);
    } else {
      for (double& q : record.orientation_wxyz) {
        if (!parse_signed(reader, 5, 1e-4, q)) return bad("TX quaternion field malformed", "TX transform");
      }
      for (double& t : record.position_mm) {
        if (!parse_signed(reader, 6, 1e-2, t)) return bad("TX position field malformed", "TX transform");
      }
      if (!parse_signed(reader, 5, 1e-4, record.error_mm)) return bad("TX error field malformed", "TX transform");
    }
    if (!reader.text(8, field) || !parse_hex(field, record.port_status))
      return bad("TX port status malformed", "TX port status");
    if (!reader.text(8, field) || !parse_hex(field, record.frame_number))
      return bad("TX frame number malformed", "TX frame");
    if (!reader.text(1, field) || field != "\n") return bad("TX handle record not ended by LF", "TX handle");
    record.state = state_from_bits(missing, false, record.port_status);
    reply.handles.push_back(record);
  }
  std::uint32_t system_status = 0;
  if (!reader.text(4, field) || !parse_hex(field, system_status) || !reader.done()) {
    return bad("TX system status malformed or trailing bytes", "TX system status");
  }
  reply.system_status = static_cast<std::uint16_t>(system_status);
  return reply;
}

std::string encode_phsr(const std::vector<PortHandle>& handles) {
  std::string body = hex(static_cast<std::uint32_t>(handles.size()), 2);
  for (const PortHandle& handle : handles) body += hex(handle.handle, 2) + hex(handle.status, 3);
  return body;
}

Result<std::vector<PortHandle>> decode_phsr(std::string_view body) {
  Reader reader(body);
  std::string_view field;
  std::uint32_t count = 0;
  if (!reader.text(2, field) || !parse_hex(field, count)) return bad("PHSR count is not 2 hex digits", "PHSR");
  std::vector<PortHandle> handles;
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint32_t handle = 0, status = 0;
    if (!reader.text(2, field) || !parse_hex(field, handle)) return bad("PHSR handle malformed", "PHSR handle");
    if (!reader.text(3, field) || !parse_hex(field, status)) return bad("PHSR status malformed", "PHSR status");
    handles.push_back({static_cast<std::uint8_t>(handle), static_cast<std::uint16_t>(status)});
  }
  if (!reader.done()) return bad("PHSR reply has trailing bytes", "PHSR");
  return handles;
}

namespace {

/// COMM's rate codes: the character at position k is the code of kCommBauds[k].
constexpr std::string_view kCommCodes = "012345A6";
constexpr int kCommBauds[] = {9600, 14400, 19200, 38400, 57600, 115200, 230400, 921600};
constexpr std::string_view kCommFraming = "0000";  // 8 data bits, no parity, 1 stop bit, no handshake

bool hex_value(char c, int& value) {
  if (c >= '0' && c <= '9')
    value = c - '0';
  else if (c >= 'A' && c <= 'F')
    value = c - 'A' + 10;
  else if (c >= 'a' && c <= 'f')
    value = c - 'a' + 10;
  else
    return false;
  return true;
}

}  // namespace

std::optional<std::string> comm_arguments(int baud) {
  if (std::find(std::begin(kSerialBauds), std::end(kSerialBauds), baud) == std::end(kSerialBauds)) return std::nullopt;
  for (std::size_t k = 0; k < kCommCodes.size(); ++k)
    if (kCommBauds[k] == baud) return std::string(1, kCommCodes[k]) + std::string(kCommFraming);
  return std::nullopt;
}

std::optional<int> comm_baud(std::string_view arguments) {
  if (arguments.size() != 1 + kCommFraming.size() || arguments.substr(1) != kCommFraming) return std::nullopt;
  const std::size_t k = kCommCodes.find(arguments[0]);
  if (k == std::string_view::npos) return std::nullopt;
  return kCommBauds[k];
}

std::string encode_pvwr(const RomWrite& write) {
  char head[8];
  std::snprintf(head, sizeof head, "%02X%04zX", write.handle, write.address);
  std::string out = head;
  for (std::size_t i = 0; i < kRomChunkBytes; ++i) {
    char byte[4];
    std::snprintf(byte, sizeof byte, "%02X", i < write.bytes.size() ? static_cast<unsigned char>(write.bytes[i]) : 0u);
    out += byte;
  }
  return out;
}

Result<RomWrite> decode_pvwr(std::string_view arguments) {
  if (arguments.size() != 6 + 2 * kRomChunkBytes)
    return Error{.message = "PVWR takes a handle, an address and 64 bytes in hex", .field = "PVWR"};
  int digits[6 + 2 * kRomChunkBytes];
  for (std::size_t i = 0; i < arguments.size(); ++i)
    if (!hex_value(arguments[i], digits[i]))
      return Error{.message = "PVWR: not a hex digit at " + std::to_string(i), .field = "PVWR"};
  RomWrite write;
  write.handle = static_cast<std::uint8_t>(16 * digits[0] + digits[1]);
  write.address = static_cast<std::size_t>(((digits[2] * 16 + digits[3]) * 16 + digits[4]) * 16 + digits[5]);
  if (write.address % kRomChunkBytes != 0 || write.address + kRomChunkBytes > kRomBytes)
    return Error{
        .message = "PVWR: address " + std::to_string(write.address) + " is not a chunk of the 1024-byte definition",
        .field = "PVWR"};
  for (std::size_t i = 0; i < kRomChunkBytes; ++i)
    write.bytes += static_cast<char>(16 * digits[6 + 2 * i] + digits[7 + 2 * i]);
  return write;
}

}  // namespace nav::trackers::ndi
