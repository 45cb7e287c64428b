#pragma once
// The recording file: every sample of every topic with its source and receive times, as
// CDR bytes, followed by an index. Layout (little-endian):
//   "NAVREC1\n"
//   records: u32 magic "NREC" | u8 topic | 3 x u8 0 | u32 payload bytes | i64 source time ns
//            | i64 receive time ns | u32 CRC-32 of the payload | payload
//   index (clean close only): u64 offset of each record | u64 index offset | u64 record count
//            | "NAVIDX1\n"
// A file without a valid index (the recorder died) is scanned record by record; damage is
// reported with its byte offset and the intact records before it (and, with an index,
// after it) still play.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/topics.hpp"

namespace nav::dds {

/// One recorded sample: topic, times, CDR bytes, and where its record starts in the file.
struct RecordedSample {
  Topic topic = Topic::tool_pose;
  TimeNs source_time_ns = 0;
  TimeNs receive_time_ns = 0;
  std::vector<std::uint8_t> payload;
  std::uint64_t offset = 0;
};

/// Appends records to a new recording; close() writes the index.
class RecordingWriter {
 public:
  /// Creates (or truncates) `path` and writes the file header.
  static Result<std::unique_ptr<RecordingWriter>> create(const std::string& path);
  ~RecordingWriter();
  RecordingWriter(const RecordingWriter&) = delete;
  RecordingWriter& operator=(const RecordingWriter&) = delete;

  Status append(Topic topic, TimeNs source_time_ns, TimeNs receive_time_ns, const std::vector<std::uint8_t>& payload);
  /// Writes the index and closes the file (also done, errors ignored, by the destructor).
  Status close();
  std::uint64_t record_count() const noexcept { return offsets_.size(); }

 private:
  RecordingWriter(std::FILE* file, std::string path) : file_(file), path_(std::move(path)) {}
  std::FILE* file_;
  std::string path_;
  std::uint64_t end_offset_ = 0;
  std::vector<std::uint64_t> offsets_;
};

/// Reads a recording, with or without its index.
class RecordingReader {
 public:
  /// Opens `path` and locates its records (from the index, else by a scan that stops at
  /// the first damaged record). Errors only when the file cannot be read or is no recording.
  static Result<std::unique_ptr<RecordingReader>> open(const std::string& path);
  ~RecordingReader();
  RecordingReader(const RecordingReader&) = delete;
  RecordingReader& operator=(const RecordingReader&) = delete;

  /// Records located (all of them with an index; those before the damage without).
  std::size_t record_count() const noexcept { return offsets_.size(); }
  /// True when the file ended with a valid index.
  bool indexed() const noexcept { return indexed_; }
  /// Damage found while locating the records (e.g. a truncated record), with its offset.
  const std::optional<Error>& damage() const noexcept { return damage_; }
  /// The i-th record, or an Error naming its offset (bad magic, short read, CRC mismatch).
  Result<RecordedSample> read(std::size_t index);

 private:
  RecordingReader(std::FILE* file, std::string path) : file_(file), path_(std::move(path)) {}
  bool load_index(std::uint64_t file_size);
  void scan(std::uint64_t file_size);
  std::FILE* file_;
  std::string path_;
  std::uint64_t file_size_ = 0;
  std::vector<std::uint64_t> offsets_;
  bool indexed_ = false;
  std::optional<Error> damage_;
};

}  // namespace nav::dds
