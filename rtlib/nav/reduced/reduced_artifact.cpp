#include "nav/reduced/reduced_artifact.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <type_traits>

#include "nav/core/finite.hpp"
#include "nav/core/fnv_hash.hpp"

namespace nav {
namespace {

constexpr char kMagic[8] = {'N', 'A', 'V', 'R', 'B', 'A', 'S', '\n'};
constexpr std::size_t kHeaderBytes = 56;
constexpr std::uint32_t kF64 = 1;
constexpr std::uint32_t kI32 = 2;

/// The sections, in file order.
enum SectionId : std::uint32_t {
  basis_section = 1,
  column_values_section,
  diaphragm_lift_section,
  sample_tets_section,
  sample_weights_section,
  polynomial_section,
  q_bound_section,
  missing_compliance_section,
  error_calibration_section,
};
constexpr std::uint32_t kSectionCount = 9;

const char* section_name(std::uint32_t id) {
  switch (id) {
    case basis_section:
      return "basis";
    case column_values_section:
      return "column_values";
    case diaphragm_lift_section:
      return "diaphragm_lift";
    case sample_tets_section:
      return "sample_tets";
    case sample_weights_section:
      return "sample_weights";
    case polynomial_section:
      return "polynomial_coefficients";
    case q_bound_section:
      return "training_q_bound";
    case missing_compliance_section:
      return "error_calibration.missing_compliance_m_per_n";
    case error_calibration_section:
      return "error_calibration";
    default:
      return "unknown";
  }
}

/// The error calibration's numbers, in file order.
constexpr std::size_t kCalibrationValues = 5;

std::vector<double> calibration_values(const ReducedErrorCalibration& c) {
  return {c.gain, c.correlation, c.lowest_ratio, c.highest_ratio, static_cast<double>(c.held_out_loads)};
}

void read_calibration(const std::vector<double>& values, ReducedErrorCalibration& c) {
  c.gain = values[0];
  c.correlation = values[1];
  c.lowest_ratio = values[2];
  c.highest_ratio = values[3];
  c.held_out_loads = std::isfinite(values[4]) ? static_cast<int>(std::clamp(values[4], 0.0, 1e9)) : -1;
}

/// The checksum of a section or of the whole file.
std::uint64_t checksum(std::span<const std::uint8_t> bytes) {
  return fnv1a(kFnvOffsetBasis, bytes.data(), bytes.size());
}

// ---- writing ----

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void put_f64(std::vector<std::uint8_t>& out, double v) { put_u64(out, std::bit_cast<std::uint64_t>(v)); }
void put_i32(std::vector<std::uint8_t>& out, std::int32_t v) { put_u32(out, std::bit_cast<std::uint32_t>(v)); }

void put_section(std::vector<std::uint8_t>& out, std::uint32_t id, std::span<const double> values) {
  const std::size_t start = out.size();
  put_u32(out, id);
  put_u32(out, kF64);
  put_u64(out, values.size());
  for (const double v : values) put_f64(out, v);
  put_u64(out, checksum(std::span(out).subspan(start)));
}

void put_section(std::vector<std::uint8_t>& out, std::uint32_t id, std::span<const std::int32_t> values) {
  const std::size_t start = out.size();
  put_u32(out, id);
  put_u32(out, kI32);
  put_u64(out, values.size());
  for (const std::int32_t v : values) put_i32(out, v);
  put_u64(out, checksum(std::span(out).subspan(start)));
}

// ---- reading ----

/// A bounds-checked little-endian reader over the artifact's bytes.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  std::size_t position() const { return position_; }
  std::size_t remaining() const { return bytes_.size() - position_; }

  /// An Error when fewer than `count` bytes are left for `what`.
  std::optional<Error> need(std::size_t count, const std::string& what) const {
    if (count <= remaining()) return std::nullopt;
    return fail(what, "truncated at byte " + std::to_string(bytes_.size()) + " (needs " + std::to_string(count) +
                          " bytes from byte " + std::to_string(position_) + ")");
  }
  Error fail(const std::string& field, const std::string& message) const {
    return Error{.message = message, .file = name_, .field = field};
  }

  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(bytes_[position_++]) << (8 * i);
    return v;
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(bytes_[position_++]) << (8 * i);
    return v;
  }
  std::int32_t i32() { return std::bit_cast<std::int32_t>(u32()); }
  double f64() { return std::bit_cast<double>(u64()); }

 private:
  std::span<const std::uint8_t> bytes_;
  const std::string& name_;
  std::size_t position_ = 0;
};

/// Reads section `id` of element kind `kind` into `out` (a vector of double or int32).
template <typename T>
std::optional<Error> read_section(Reader& in, std::span<const std::uint8_t> bytes, std::uint32_t id,
                                  std::vector<T>& out) {
  constexpr std::uint32_t kind = std::is_same_v<T, double> ? kF64 : kI32;
  constexpr std::size_t element_bytes = sizeof(T);
  const std::string name = section_name(id);
  const std::size_t start = in.position();
  if (auto e = in.need(16, name + " section header")) return e;
  const std::uint32_t read_id = in.u32();
  const std::uint32_t read_kind = in.u32();
  const std::uint64_t count = in.u64();
  if (read_id != id)
    return in.fail(name, "expected section " + std::to_string(id) + " (" + name + ") at byte " + std::to_string(start) +
                             ", found id " + std::to_string(read_id));
  if (read_kind != kind)
    return in.fail(name, "element kind " + std::to_string(read_kind) + ", expected " + std::to_string(kind));
  if (count > (in.remaining() / element_bytes)) {
    return in.fail(name, "truncated at byte " + std::to_string(bytes.size()) + " (section declares " +
                             std::to_string(count) + " elements from byte " + std::to_string(in.position()) + ")");
  }
  out.resize(static_cast<std::size_t>(count));
  for (T& v : out) {
    if constexpr (kind == kF64) {
      v = in.f64();
    } else {
      v = in.i32();
    }
  }
  const std::uint64_t computed = checksum(bytes.subspan(start, in.position() - start));
  if (auto e = in.need(8, name + " checksum")) return e;
  if (in.u64() != computed) return in.fail(name, "section " + name + " checksum mismatch");
  return std::nullopt;
}

/// Dimensions and values that every basis must satisfy, whatever its mesh.
std::optional<Error> check_consistency(const ReducedBasis& b, const Reader& in) {
  if (b.node_count <= 0)
    return in.fail("node_count", "inconsistent dimensions: node count " + std::to_string(b.node_count));
  if (b.basis_size <= 0) return in.fail("basis_size", "inconsistent dimensions: r " + std::to_string(b.basis_size));
  if (static_cast<std::uint32_t>(b.source) > static_cast<std::uint32_t>(ReducedBasisSource::pod))
    return in.fail("source", "unknown basis source " + std::to_string(static_cast<std::uint32_t>(b.source)));
  if (static_cast<std::uint32_t>(b.force_kind) > static_cast<std::uint32_t>(ReducedForceKind::stvk_cubic_polynomial))
    return in.fail("force_kind", "unknown force kind " + std::to_string(static_cast<std::uint32_t>(b.force_kind)));
  const std::uint64_t rows = 3ull * static_cast<std::uint64_t>(b.node_count);
  const std::uint64_t r = static_cast<std::uint64_t>(b.basis_size);
  const auto dimension_error = [&](const char* field, std::size_t found, const std::string& expected) {
    return in.fail(field, "inconsistent dimensions: " + std::to_string(found) + " values, expected " + expected);
  };
  if (b.basis.size() != rows * r)
    return dimension_error("basis", b.basis.size(), "3 n r = " + std::to_string(rows * r));
  if (b.column_values.size() != r)
    return dimension_error("column_values", b.column_values.size(), "r = " + std::to_string(r));
  if (!b.diaphragm_lift.empty() && b.diaphragm_lift.size() != rows * 3)
    return dimension_error("diaphragm_lift", b.diaphragm_lift.size(), "0 or 9 n = " + std::to_string(rows * 3));
  if (b.sample_weights.size() != b.sample_tets.size())
    return dimension_error("sample_weights", b.sample_weights.size(), "one per sampled tetrahedron");
  if (!b.training_q_bound.empty() && b.training_q_bound.size() != r)
    return dimension_error("training_q_bound", b.training_q_bound.size(), "0 or r = " + std::to_string(r));
  if (!b.polynomial_coefficients.empty() && b.force_kind != ReducedForceKind::stvk_cubic_polynomial)
    return in.fail("polynomial_coefficients", "inconsistent dimensions: coefficients for a force kind that has none");
  for (const std::int32_t t : b.sample_tets)
    if (t < 0) return in.fail("sample_tets", "negative tetrahedron index " + std::to_string(t));
  for (const double w : b.sample_weights)
    if (!(w >= 0.0) || !std::isfinite(w)) return in.fail("sample_weights", "weight not finite and non-negative");
  const std::pair<const char*, const std::vector<double>*> arrays[] = {
      {"basis", &b.basis},
      {"column_values", &b.column_values},
      {"diaphragm_lift", &b.diaphragm_lift},
      {"polynomial_coefficients", &b.polynomial_coefficients},
      {"training_q_bound", &b.training_q_bound}};
  for (const auto& [field, values] : arrays)
    if (!all_finite(*values)) return in.fail(field, "non-finite value");
  if (!std::isfinite(b.training_residual_bound)) return in.fail("training_residual_bound", "non-finite value");
  const ReducedErrorCalibration& c = b.error_calibration;
  if (!c.missing_compliance_m_per_n.empty() && c.missing_compliance_m_per_n.size() != 2 * rows)
    return dimension_error("error_calibration.missing_compliance_m_per_n", c.missing_compliance_m_per_n.size(),
                           "0 or 6 n = " + std::to_string(2 * rows));
  if (!all_finite(c.missing_compliance_m_per_n))
    return in.fail("error_calibration.missing_compliance_m_per_n", "non-finite value");
  if (!all_finite(calibration_values(c)) || c.gain < 0.0 || c.held_out_loads < 0)
    return in.fail("error_calibration", "gain or load count not finite and non-negative");
  return std::nullopt;
}

std::string hex(std::uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof(text), "%016llx", static_cast<unsigned long long>(v));
  return text;
}

}  // namespace

std::vector<std::uint8_t> encode_reduced_basis(const ReducedBasis& basis) {
  std::vector<std::uint8_t> out(std::begin(kMagic), std::end(kMagic));
  put_u32(out, kReducedArtifactVersion);
  put_u32(out, kSectionCount);
  put_u64(out, 0);  // file size, patched below
  put_u64(out, basis.mesh_fingerprint);
  put_i32(out, basis.node_count);
  put_i32(out, basis.basis_size);
  put_u32(out, static_cast<std::uint32_t>(basis.source));
  put_u32(out, static_cast<std::uint32_t>(basis.force_kind));
  put_f64(out, basis.training_residual_bound);
  put_section(out, basis_section, std::span<const double>(basis.basis));
  put_section(out, column_values_section, std::span<const double>(basis.column_values));
  put_section(out, diaphragm_lift_section, std::span<const double>(basis.diaphragm_lift));
  put_section(out, sample_tets_section, std::span<const std::int32_t>(basis.sample_tets));
  put_section(out, sample_weights_section, std::span<const double>(basis.sample_weights));
  put_section(out, polynomial_section, std::span<const double>(basis.polynomial_coefficients));
  put_section(out, q_bound_section, std::span<const double>(basis.training_q_bound));
  put_section(out, missing_compliance_section,
              std::span<const double>(basis.error_calibration.missing_compliance_m_per_n));
  put_section(out, error_calibration_section, std::span<const double>(calibration_values(basis.error_calibration)));
  const std::uint64_t size = out.size() + 8;
  for (int i = 0; i < 8; ++i) out[16 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(size >> (8 * i));
  put_u64(out, checksum(out));
  return out;
}

Result<ReducedBasis> decode_reduced_basis(std::span<const std::uint8_t> bytes, const std::string& source_name,
                                          const TetMesh* expected_mesh) {
  Reader in(bytes, source_name);
  const std::size_t magic_bytes = std::min(bytes.size(), sizeof(kMagic));
  if (bytes.empty() || std::memcmp(bytes.data(), kMagic, magic_bytes) != 0)
    return in.fail("magic", "not a reduced-basis artifact (bad magic)");
  if (auto e = in.need(kHeaderBytes, "header")) return *e;
  in.u64();  // magic, checked above
  const std::uint32_t version = in.u32();
  if (version != kReducedArtifactVersion)
    return in.fail("version", "unsupported format version " + std::to_string(version) + " (this build reads " +
                                  std::to_string(kReducedArtifactVersion) + ")");
  const std::uint32_t sections = in.u32();
  if (sections != kSectionCount)
    return in.fail("section_count", std::to_string(sections) + " sections, expected " + std::to_string(kSectionCount));
  const std::uint64_t declared_size = in.u64();
  if (declared_size > bytes.size())
    return in.fail("file_size",
                   "truncated at byte " + std::to_string(bytes.size()) + " of " + std::to_string(declared_size));
  if (declared_size < bytes.size())
    return in.fail("file_size", std::to_string(bytes.size() - declared_size) +
                                    " bytes after the declared end at byte " + std::to_string(declared_size));
  ReducedBasis basis;
  basis.mesh_fingerprint = in.u64();
  basis.node_count = in.i32();
  basis.basis_size = in.i32();
  basis.source = static_cast<ReducedBasisSource>(in.u32());
  basis.force_kind = static_cast<ReducedForceKind>(in.u32());
  basis.training_residual_bound = in.f64();
  if (auto e = read_section(in, bytes, basis_section, basis.basis)) return *e;
  if (auto e = read_section(in, bytes, column_values_section, basis.column_values)) return *e;
  if (auto e = read_section(in, bytes, diaphragm_lift_section, basis.diaphragm_lift)) return *e;
  if (auto e = read_section(in, bytes, sample_tets_section, basis.sample_tets)) return *e;
  if (auto e = read_section(in, bytes, sample_weights_section, basis.sample_weights)) return *e;
  if (auto e = read_section(in, bytes, polynomial_section, basis.polynomial_coefficients)) return *e;
  if (auto e = read_section(in, bytes, q_bound_section, basis.training_q_bound)) return *e;
  if (auto e = read_section(in, bytes, missing_compliance_section, basis.error_calibration.missing_compliance_m_per_n))
    return *e;
  std::vector<double> calibration;
  if (auto e = read_section(in, bytes, error_calibration_section, calibration)) return *e;
  if (calibration.size() != kCalibrationValues)
    return in.fail("error_calibration", "inconsistent dimensions: " + std::to_string(calibration.size()) +
                                            " values, expected " + std::to_string(kCalibrationValues));
  read_calibration(calibration, basis.error_calibration);
  if (auto e = in.need(8, "file checksum")) return *e;
  const std::uint64_t computed = checksum(bytes.subspan(0, in.position()));
  if (in.u64() != computed) return in.fail("file_checksum", "whole-file checksum mismatch");
  if (in.remaining() != 0) return in.fail("file_size", "bytes after the trailer");
  if (auto e = check_consistency(basis, in)) return *e;
  if (expected_mesh) {
    const std::uint64_t fingerprint = mesh_fingerprint(*expected_mesh);
    if (fingerprint != basis.mesh_fingerprint ||
        static_cast<std::size_t>(basis.node_count) != expected_mesh->nodes_m.size())
      return in.fail("mesh_fingerprint", "belongs to another mesh (artifact fingerprint " +
                                             hex(basis.mesh_fingerprint) + ", " + std::to_string(basis.node_count) +
                                             " nodes; this mesh " + hex(fingerprint) + ", " +
                                             std::to_string(expected_mesh->nodes_m.size()) + " nodes)");
    for (const std::int32_t t : basis.sample_tets)
      if (static_cast<std::size_t>(t) >= expected_mesh->tets.size())
        return in.fail("sample_tets", "tetrahedron " + std::to_string(t) + " out of range for this mesh");
  }
  return basis;
}

Status save_reduced_basis(const std::string& path, const ReducedBasis& basis) {
  const std::vector<std::uint8_t> bytes = encode_reduced_basis(basis);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Error{.message = "cannot open for writing", .file = path};
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) return Error{.message = "cannot write " + std::to_string(bytes.size()) + " bytes", .file = path};
  return Done{};
}

Result<ReducedBasis> load_reduced_basis(const std::string& path, const TetMesh* expected_mesh) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open", .file = path};
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) return Error{.message = "cannot read", .file = path};
  return decode_reduced_basis(bytes, path, expected_mesh);
}

}  // namespace nav
