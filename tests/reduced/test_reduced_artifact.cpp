// The reduced-basis artifact: a bit-exact round trip of every field, a basis of another mesh
// refused, and every single-byte corruption and every truncation of a small artifact refused
// with an error that names the file (never a crash, never a wrong basis).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <random>

#include "nav/reduced/reduced_artifact.hpp"
#include "support/test_data.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

/// A basis of `mesh` with every field filled from a seeded generator (the artifact does not
/// care how a basis was computed, only that every bit comes back).
ReducedBasis synthetic_basis(const TetMesh& mesh, int r, ReducedForceKind kind) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal;
  ReducedBasis b;
  b.mesh_fingerprint = mesh_fingerprint(mesh);
  b.node_count = static_cast<std::int32_t>(mesh.nodes_m.size());
  b.basis_size = r;
  b.source = ReducedBasisSource::modal_derivatives;
  b.force_kind = kind;
  const std::size_t rows = 3 * mesh.nodes_m.size();
  for (std::size_t i = 0; i < rows * static_cast<std::size_t>(r); ++i) b.basis.push_back(normal(rng));
  for (int i = 0; i < r; ++i) b.column_values.push_back(std::abs(normal(rng)) * 1e3);
  for (std::size_t i = 0; i < rows * 3; ++i) b.diaphragm_lift.push_back(normal(rng));
  for (int i = 0; i < 3; ++i) {
    b.sample_tets.push_back(static_cast<std::int32_t>(rng() % mesh.tets.size()));
    b.sample_weights.push_back(std::abs(normal(rng)));
  }
  if (kind == ReducedForceKind::stvk_cubic_polynomial)
    for (int i = 0; i < 7; ++i) b.polynomial_coefficients.push_back(normal(rng));
  for (int i = 0; i < r; ++i) b.training_q_bound.push_back(std::abs(normal(rng)));
  b.training_residual_bound = 0.0123;
  for (std::size_t i = 0; i < 2 * rows; ++i) b.error_calibration.missing_compliance_m_per_n.push_back(normal(rng));
  b.error_calibration.gain = 1.25;
  b.error_calibration.correlation = 0.875;
  b.error_calibration.lowest_ratio = 0.39;
  b.error_calibration.highest_ratio = 2.98;
  b.error_calibration.held_out_loads = 10;
  return b;
}

void expect_bit_equal(const std::vector<double>& a, const std::vector<double>& b) {
  ASSERT_EQ(a.size(), b.size());
  if (!a.empty()) {
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
  }
}

void expect_identical(const ReducedBasis& a, const ReducedBasis& b) {
  EXPECT_EQ(a.mesh_fingerprint, b.mesh_fingerprint);
  EXPECT_EQ(a.node_count, b.node_count);
  EXPECT_EQ(a.basis_size, b.basis_size);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.force_kind, b.force_kind);
  expect_bit_equal(a.basis, b.basis);
  expect_bit_equal(a.column_values, b.column_values);
  expect_bit_equal(a.diaphragm_lift, b.diaphragm_lift);
  EXPECT_EQ(a.sample_tets, b.sample_tets);
  expect_bit_equal(a.sample_weights, b.sample_weights);
  expect_bit_equal(a.polynomial_coefficients, b.polynomial_coefficients);
  expect_bit_equal(a.training_q_bound, b.training_q_bound);
  EXPECT_EQ(std::memcmp(&a.training_residual_bound, &b.training_residual_bound, sizeof(double)), 0);
  const ReducedErrorCalibration &x = a.error_calibration, &y = b.error_calibration;
  expect_bit_equal(x.missing_compliance_m_per_n, y.missing_compliance_m_per_n);
  expect_bit_equal({x.gain, x.correlation, x.lowest_ratio, x.highest_ratio},
                   {y.gain, y.correlation, y.lowest_ratio, y.highest_ratio});
  EXPECT_EQ(x.held_out_loads, y.held_out_loads);
}

TEST(ReducedArtifact, FileRoundTripIsBitExact) {
  const TetMesh mesh = testing::box_mesh({0.02, 0.02, 0.04}, 0.01);
  for (const ReducedForceKind kind :
       {ReducedForceKind::corotational_cubature, ReducedForceKind::stvk_cubic_polynomial}) {
    const ReducedBasis basis = synthetic_basis(mesh, 4, kind);
    const std::string path = testing::temporary_path("reduced_round_trip.navrb");
    ASSERT_TRUE(save_reduced_basis(path, basis).ok());
    const auto loaded = load_reduced_basis(path, &mesh);
    ASSERT_TRUE(loaded.ok()) << loaded.error().describe();
    expect_identical(basis, loaded.value());
    // Encoding is deterministic: the same basis gives the same bytes.
    EXPECT_EQ(encode_reduced_basis(basis), encode_reduced_basis(loaded.value()));
  }
}

TEST(ReducedArtifact, LayoutIsLittleEndianWithMagicAndVersion) {
  const TetMesh mesh = testing::box_mesh({0.01, 0.01, 0.01}, 0.01);
  const std::vector<std::uint8_t> bytes = encode_reduced_basis(synthetic_basis(mesh, 2, ReducedForceKind::linear));
  ASSERT_GT(bytes.size(), 56u);
  EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 8), std::string("NAVRBAS\n"));
  EXPECT_EQ(bytes[8], kReducedArtifactVersion);
  EXPECT_EQ(bytes[9] | bytes[10] | bytes[11], 0);
  std::uint64_t size = 0;
  for (int i = 0; i < 8; ++i) size |= static_cast<std::uint64_t>(bytes[16 + static_cast<std::size_t>(i)]) << (8 * i);
  EXPECT_EQ(size, bytes.size());
}

TEST(ReducedArtifact, AnotherMeshIsRefused) {
  const TetMesh mesh = testing::box_mesh({0.02, 0.02, 0.04}, 0.01);
  TetMesh moved = mesh;
  moved.nodes_m[3][1] += 1e-6;  // same counts, one node moved by a micrometre
  const std::string path = testing::temporary_path("reduced_other_mesh.navrb");
  ASSERT_TRUE(save_reduced_basis(path, synthetic_basis(mesh, 3, ReducedForceKind::linear)).ok());
  const auto loaded = load_reduced_basis(path, &moved);
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().describe().find("belongs to another mesh"), std::string::npos) << loaded.error().describe();
  EXPECT_NE(loaded.error().describe().find(path), std::string::npos);
  EXPECT_TRUE(load_reduced_basis(path, nullptr).ok());  // without a mesh to check against
}

TEST(ReducedArtifact, ErrorsNameFileAndCause) {
  const TetMesh mesh = testing::box_mesh({0.01, 0.01, 0.01}, 0.01);
  const std::vector<std::uint8_t> good = encode_reduced_basis(synthetic_basis(mesh, 2, ReducedForceKind::linear));
  const auto message = [&](std::vector<std::uint8_t> bytes) {
    const auto decoded = decode_reduced_basis(bytes, "basis.navrb", &mesh);
    return decoded.ok() ? std::string("ok") : decoded.error().describe();
  };
  std::vector<std::uint8_t> text(good);
  text[0] = 'X';
  EXPECT_NE(message(text).find("not a reduced-basis artifact"), std::string::npos);
  std::vector<std::uint8_t> version(good);
  version[8] = 9;
  EXPECT_NE(message(version).find("unsupported format version 9"), std::string::npos);
  const std::vector<std::uint8_t> cut(good.begin(), good.begin() + 100);
  EXPECT_NE(message(cut).find("truncated at byte 100"), std::string::npos) << message(cut);
  std::vector<std::uint8_t> payload(good);
  payload[56 + 16 + 5] ^= 0x10;  // inside the first basis value
  EXPECT_NE(message(payload).find("section basis checksum mismatch"), std::string::npos) << message(payload);
  std::vector<std::uint8_t> header(good);
  header[52] ^= 0x01;  // training residual bound: covered by the whole-file checksum only
  EXPECT_NE(message(header).find("whole-file checksum mismatch"), std::string::npos) << message(header);
  EXPECT_NE(message(header).find("basis.navrb"), std::string::npos);
  EXPECT_NE(
      load_reduced_basis(testing::temporary_path("no_such.navrb"), nullptr).error().describe().find("no_such.navrb"),
      std::string::npos);
}

TEST(ReducedArtifact, InconsistentDimensionsAreRefused) {
  const TetMesh mesh = testing::box_mesh({0.01, 0.01, 0.01}, 0.01);
  ReducedBasis basis = synthetic_basis(mesh, 2, ReducedForceKind::linear);
  basis.column_values.pop_back();
  const auto decoded = decode_reduced_basis(encode_reduced_basis(basis), "dims.navrb", &mesh);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().describe().find("inconsistent dimensions"), std::string::npos)
      << decoded.error().describe();
  EXPECT_EQ(decoded.error().field, "column_values");
  basis = synthetic_basis(mesh, 2, ReducedForceKind::linear);
  basis.error_calibration.missing_compliance_m_per_n.pop_back();  // not 6 per node
  const auto calibration = decode_reduced_basis(encode_reduced_basis(basis), "dims.navrb", &mesh);
  ASSERT_FALSE(calibration.ok());
  EXPECT_EQ(calibration.error().field, "error_calibration.missing_compliance_m_per_n");
  basis = synthetic_basis(mesh, 2, ReducedForceKind::linear);
  basis.error_calibration.gain = -1.0;
  const auto gain = decode_reduced_basis(encode_reduced_basis(basis), "gain.navrb", &mesh);
  ASSERT_FALSE(gain.ok());
  EXPECT_EQ(gain.error().field, "error_calibration");
}

TEST(ReducedArtifact, EveryByteFlipAndEveryTruncationIsAnError) {
  const TetMesh mesh = testing::box_mesh({0.01, 0.01, 0.01}, 0.01);
  const ReducedBasis basis = synthetic_basis(mesh, 2, ReducedForceKind::corotational_cubature);
  const std::vector<std::uint8_t> good = encode_reduced_basis(basis);
  ASSERT_TRUE(decode_reduced_basis(good, "good", &mesh).ok());
  for (std::size_t i = 0; i < good.size(); ++i) {
    for (const std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0x80}, std::uint8_t{0xff}}) {
      std::vector<std::uint8_t> bad(good);
      bad[i] ^= mask;
      const auto decoded = decode_reduced_basis(bad, "flipped", &mesh);
      ASSERT_FALSE(decoded.ok()) << "byte " << i << " mask " << int(mask);
      EXPECT_EQ(decoded.error().file, "flipped");
      EXPECT_FALSE(decoded.error().message.empty());
    }
  }
  for (std::size_t length = 0; length < good.size(); ++length) {
    const std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length));
    const auto decoded = decode_reduced_basis(cut, "cut", &mesh);
    ASSERT_FALSE(decoded.ok()) << "length " << length;
    if (length >= 8) {
      EXPECT_NE(decoded.error().message.find("truncated at byte " + std::to_string(length)), std::string::npos)
          << decoded.error().message;
    }
  }
  std::vector<std::uint8_t> longer(good);
  longer.push_back(0);
  EXPECT_FALSE(decode_reduced_basis(longer, "longer", &mesh).ok());
}

}  // namespace
}  // namespace nav
