#include "nav/dds/recording_file.hpp"

#include <zlib.h>

#include <array>
#include <cstring>

namespace nav::dds {
namespace {

constexpr char kFileMagic[8] = {'N', 'A', 'V', 'R', 'E', 'C', '1', '\n'};
constexpr char kIndexMagic[8] = {'N', 'A', 'V', 'I', 'D', 'X', '1', '\n'};
constexpr std::uint32_t kRecordMagic = 0x4345524EU;  // "NREC" in little-endian bytes
constexpr std::size_t kRecordHeaderBytes = 32;
constexpr std::size_t kFooterBytes = 24;

/// The fixed-size head of a record.
struct RecordHeader {
  std::uint32_t magic = kRecordMagic;
  std::uint8_t topic = 0;
  std::uint32_t payload_bytes = 0;
  std::int64_t source_time_ns = 0;
  std::int64_t receive_time_ns = 0;
  std::uint32_t payload_crc = 0;
};

template <typename T>
void put(std::uint8_t* at, T value) {
  std::memcpy(at, &value, sizeof(T));  // the file is little-endian, like every target here
}
template <typename T>
T get(const std::uint8_t* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

std::array<std::uint8_t, kRecordHeaderBytes> encode_header(const RecordHeader& header) {
  std::array<std::uint8_t, kRecordHeaderBytes> bytes{};
  put(bytes.data(), header.magic);
  bytes[4] = header.topic;
  put(bytes.data() + 8, header.payload_bytes);
  put(bytes.data() + 12, header.source_time_ns);
  put(bytes.data() + 20, header.receive_time_ns);
  put(bytes.data() + 28, header.payload_crc);
  return bytes;
}

RecordHeader decode_header(const std::uint8_t* bytes) {
  RecordHeader header;
  header.magic = get<std::uint32_t>(bytes);
  header.topic = bytes[4];
  header.payload_bytes = get<std::uint32_t>(bytes + 8);
  header.source_time_ns = get<std::int64_t>(bytes + 12);
  header.receive_time_ns = get<std::int64_t>(bytes + 20);
  header.payload_crc = get<std::uint32_t>(bytes + 28);
  return header;
}

std::uint32_t crc_of(const std::vector<std::uint8_t>& bytes) {
  return static_cast<std::uint32_t>(crc32(0L, bytes.data(), static_cast<uInt>(bytes.size())));
}

bool read_at(std::FILE* file, std::uint64_t offset, void* into, std::size_t bytes) {
  return fseeko(file, static_cast<off_t>(offset), SEEK_SET) == 0 && std::fread(into, 1, bytes, file) == bytes;
}

Error damage_at(const std::string& path, std::uint64_t offset, const std::string& what) {
  return Error{.message = what + " at byte offset " + std::to_string(offset), .file = path};
}

}  // namespace

Result<std::unique_ptr<RecordingWriter>> RecordingWriter::create(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return Error{.message = "cannot create the recording", .file = path};
  std::unique_ptr<RecordingWriter> writer(new RecordingWriter(file, path));
  if (std::fwrite(kFileMagic, 1, sizeof(kFileMagic), file) != sizeof(kFileMagic)) {
    return Error{.message = "cannot write the recording header", .file = path};
  }
  writer->end_offset_ = sizeof(kFileMagic);
  return writer;
}

RecordingWriter::~RecordingWriter() { close(); }

Status RecordingWriter::append(Topic topic, TimeNs source_time_ns, TimeNs receive_time_ns,
                               const std::vector<std::uint8_t>& payload) {
  if (file_ == nullptr) return Error{.message = "recording already closed", .file = path_};
  RecordHeader header;
  header.topic = static_cast<std::uint8_t>(topic);
  header.payload_bytes = static_cast<std::uint32_t>(payload.size());
  header.source_time_ns = source_time_ns;
  header.receive_time_ns = receive_time_ns;
  header.payload_crc = crc_of(payload);
  const auto head = encode_header(header);
  if (std::fwrite(head.data(), 1, head.size(), file_) != head.size() ||
      std::fwrite(payload.data(), 1, payload.size(), file_) != payload.size()) {
    return Error{.message = "cannot write a record (disk full?)", .file = path_};
  }
  offsets_.push_back(end_offset_);
  end_offset_ += head.size() + payload.size();
  return Done{};
}

Status RecordingWriter::close() {
  if (file_ == nullptr) return Done{};
  std::vector<std::uint8_t> index(offsets_.size() * 8 + kFooterBytes);
  for (std::size_t i = 0; i < offsets_.size(); ++i) put(index.data() + 8 * i, offsets_[i]);
  std::uint8_t* footer = index.data() + offsets_.size() * 8;
  put(footer, end_offset_);
  put(footer + 8, static_cast<std::uint64_t>(offsets_.size()));
  std::memcpy(footer + 16, kIndexMagic, sizeof(kIndexMagic));
  const bool written = std::fwrite(index.data(), 1, index.size(), file_) == index.size();
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!written || !closed) return Error{.message = "cannot write the recording index", .file = path_};
  return Done{};
}

Result<std::unique_ptr<RecordingReader>> RecordingReader::open(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return Error{.message = "cannot open the recording", .file = path};
  std::unique_ptr<RecordingReader> reader(new RecordingReader(file, path));
  char magic[sizeof(kFileMagic)] = {};
  if (!read_at(file, 0, magic, sizeof(magic)) || std::memcmp(magic, kFileMagic, sizeof(magic)) != 0) {
    return Error{.message = "not a navigation recording (bad file header)", .file = path};
  }
  const off_t end = fseeko(file, 0, SEEK_END) == 0 ? ftello(file) : -1;
  if (end < 0) return Error{.message = "cannot read the recording's size", .file = path};
  reader->file_size_ = static_cast<std::uint64_t>(end);
  if (!reader->load_index(reader->file_size_)) reader->scan(reader->file_size_);
  return reader;
}

RecordingReader::~RecordingReader() { std::fclose(file_); }

bool RecordingReader::load_index(std::uint64_t file_size) {
  if (file_size < sizeof(kFileMagic) + kFooterBytes) return false;
  std::uint8_t footer[kFooterBytes];
  if (!read_at(file_, file_size - kFooterBytes, footer, kFooterBytes)) return false;
  if (std::memcmp(footer + 16, kIndexMagic, sizeof(kIndexMagic)) != 0) return false;
  const auto index_offset = get<std::uint64_t>(footer);
  const auto count = get<std::uint64_t>(footer + 8);
  if (count > (file_size - kFooterBytes) / 8) return false;  // checked first: count * 8 must not wrap
  if (index_offset < sizeof(kFileMagic) || index_offset != file_size - kFooterBytes - count * 8) return false;
  std::vector<std::uint8_t> index(count * 8);
  if (!read_at(file_, index_offset, index.data(), index.size())) return false;
  offsets_.resize(count);
  for (std::size_t i = 0; i < count; ++i) offsets_[i] = get<std::uint64_t>(index.data() + 8 * i);
  indexed_ = true;
  return true;
}

void RecordingReader::scan(std::uint64_t file_size) {
  std::uint64_t offset = sizeof(kFileMagic);
  while (offset < file_size) {
    std::uint8_t head[kRecordHeaderBytes];
    if (offset + kRecordHeaderBytes > file_size || !read_at(file_, offset, head, kRecordHeaderBytes)) {
      damage_ = damage_at(path_, offset, "truncated record header");
      return;
    }
    const RecordHeader header = decode_header(head);
    if (header.magic != kRecordMagic || header.topic >= kTopicCount) {
      damage_ = damage_at(path_, offset, "no record starts here (bad record magic or topic)");
      return;
    }
    if (offset + kRecordHeaderBytes + header.payload_bytes > file_size) {
      damage_ = damage_at(path_, offset, "truncated record payload");
      return;
    }
    offsets_.push_back(offset);
    offset += kRecordHeaderBytes + header.payload_bytes;
  }
  damage_ = Error{.message = "no index at the end (the recorder did not close the file); " +
                             std::to_string(offsets_.size()) + " records found by scanning",
                  .file = path_};
}

Result<RecordedSample> RecordingReader::read(std::size_t index) {
  const std::uint64_t offset = offsets_.at(index);
  std::uint8_t head[kRecordHeaderBytes];
  if (!read_at(file_, offset, head, kRecordHeaderBytes)) return damage_at(path_, offset, "truncated record header");
  const RecordHeader header = decode_header(head);
  if (header.magic != kRecordMagic || header.topic >= kTopicCount) {
    return damage_at(path_, offset, "no record starts here (bad record magic or topic)");
  }
  if (header.payload_bytes > file_size_ - offset - kRecordHeaderBytes) {  // before allocating it
    return damage_at(path_, offset, "truncated record payload");
  }
  RecordedSample sample;
  sample.topic = static_cast<Topic>(header.topic);
  sample.source_time_ns = header.source_time_ns;
  sample.receive_time_ns = header.receive_time_ns;
  sample.offset = offset;
  sample.payload.resize(header.payload_bytes);
  if (!read_at(file_, offset + kRecordHeaderBytes, sample.payload.data(), sample.payload.size())) {
    return damage_at(path_, offset, "truncated record payload");
  }
  if (crc_of(sample.payload) != header.payload_crc) return damage_at(path_, offset, "record checksum mismatch");
  return sample;
}

}  // namespace nav::dds
