#pragma once
// The NDI combined API (Polaris, Aurora) on the wire: CRC-16, command framing, and the
// replies: text replies ("OKAY", "ERRORnn", PHSR lists), TX text tracking replies and BX
// binary tracking replies. Pure functions shared by the host driver and the simulated device;
// decoding never trusts the input (it is fuzzed).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/trackers/tracker_sample.hpp"

namespace nav::trackers::ndi {

/// CRC-16 of the combined API (polynomial 0x8005 reflected, i.e. 0xA001; initial value 0).
std::uint16_t crc16(std::string_view bytes) noexcept;

/// "NAME:args" followed by its CRC as 4 upper-case hex digits and CR: the framing with CRC.
std::string frame_command(std::string_view name, std::string_view arguments);
/// A text reply: `body`, its CRC (4 hex digits) and CR.
std::string frame_reply(std::string_view body);
/// The body of a framed text reply (without CR) after checking its CRC, or an error.
Result<std::string> check_reply(std::string_view framed_without_cr);

/// Port status bits of the combined API (the ones the station uses).
inline constexpr std::uint32_t kPortOccupied = 0x0001;
inline constexpr std::uint32_t kPortInitialized = 0x0010;
inline constexpr std::uint32_t kPortEnabled = 0x0020;
inline constexpr std::uint32_t kPortOutOfVolume = 0x0040;
inline constexpr std::uint32_t kPortPartlyOutOfVolume = 0x0080;

/// One port handle's record in a BX or TX reply (transforms, option 0x0001).
struct HandleRecord {
  std::uint8_t handle = 0;
  ToolState state = ToolState::missing;
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  std::array<double, 3> position_mm{};
  double error_mm = 0.0;
  std::uint32_t port_status = 0;
  std::uint32_t frame_number = 0;
};

/// A decoded tracking reply.
struct TrackingReply {
  std::vector<HandleRecord> handles;
  std::uint16_t system_status = 0;
};

/// The tool state a handle record's status and port status bits say.
ToolState state_from_bits(bool missing, bool disabled, std::uint32_t port_status) noexcept;

/// The BX reply (start 0xA5C4, length, header CRC, body, body CRC) of `reply`.
std::string encode_bx(const TrackingReply& reply);
/// Decodes a whole BX reply; errors say which part is wrong (start, CRCs, lengths).
Result<TrackingReply> decode_bx(std::string_view bytes);
/// The bytes of the BX reply starting at `bytes` (6 header bytes needed), or nullopt.
std::optional<std::size_t> bx_reply_size(std::string_view header) noexcept;

/// The TX text reply body (without CRC) of `reply`: fixed-width signed decimals.
std::string encode_tx(const TrackingReply& reply);
/// Decodes a TX reply body (CRC already checked).
Result<TrackingReply> decode_tx(std::string_view body);

/// A PHSR reply: handles and their 3-hex-digit status.
struct PortHandle {
  std::uint8_t handle = 0;
  std::uint16_t status = 0;
};
std::string encode_phsr(const std::vector<PortHandle>& handles);
Result<std::vector<PortHandle>> decode_phsr(std::string_view body);

/// The serial rates COMM can ask for that a Linux host can also set (the device's own 14400
/// and 1228739 have no termios speed).
inline constexpr int kSerialBauds[] = {9600, 19200, 38400, 57600, 115200, 230400, 921600};
/// The serial rate of a device after power-on or a serial break.
inline constexpr int kResetBaud = 9600;
/// COMM's arguments for `baud` at 8N1 without handshake ("50000" for 115200), or nothing for
/// a rate not in kSerialBauds.
std::optional<std::string> comm_arguments(int baud);
/// The rate COMM's arguments ask for, or nothing (another framing or handshake, a bad code).
std::optional<int> comm_baud(std::string_view arguments);

/// A passive tool's definition (its .rom file) is written in chunks of 64 bytes into 1024.
inline constexpr std::size_t kRomBytes = 1024;
inline constexpr std::size_t kRomChunkBytes = 64;
/// PHRQ's arguments asking for a port handle for a passive (wireless) tool.
inline constexpr std::string_view kPassiveToolRequest = "*********1****";
/// One PVWR: a port handle, a start address and 64 bytes of the tool's definition.
struct RomWrite {
  std::uint8_t handle = 0;
  std::size_t address = 0;
  std::string bytes;
};
/// PVWR's arguments: "hh" handle, "aaaa" address, 128 hex digits (the chunk, zero-padded).
std::string encode_pvwr(const RomWrite& write);
/// Decodes PVWR's arguments; an address past the definition or a chunk of another size fails.
Result<RomWrite> decode_pvwr(std::string_view arguments);

}  // namespace nav::trackers::ndi
