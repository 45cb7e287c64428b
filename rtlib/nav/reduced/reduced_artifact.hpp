#pragma once
// The versioned binary file of a ReducedBasis (written by navtool reduce, read when a station
// builds its reduced liver). Little-endian throughout:
//   header   magic "NAVRBAS\n" (8 bytes), format version (u32), section count (u32), file size
//            in bytes (u64), mesh fingerprint (u64), node count (i32), r (i32), source (u32),
//            force kind (u32), training residual bound (f64): 56 bytes;
//   sections one per array field of ReducedBasis, in a fixed order (version 2 adds the error
//            calibration's missing compliance and its five numbers): id (u32), element kind
//            (u32: 1 f64, 2 i32), element count (u64), the elements, then the FNV-1a checksum
//            (u64) of the section's id, kind, count and elements;
//   trailer  the FNV-1a checksum (u64) of every byte before it.
// Init-time code: it allocates and returns errors that name the file and what is wrong.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"

namespace nav {

/// The format version this code writes and the only one it reads.
inline constexpr std::uint32_t kReducedArtifactVersion = 2;

/// The artifact bytes of `basis`.
std::vector<std::uint8_t> encode_reduced_basis(const ReducedBasis& basis);

/// The basis in `bytes` (named `source_name` in errors). With `expected_mesh`, a basis of
/// another mesh (different fingerprint or node count, a sampled tetrahedron out of range) is
/// refused. Errors: not an artifact (magic), an unsupported version, truncated at byte N,
/// a section checksum mismatch, a whole-file checksum mismatch, inconsistent dimensions,
/// non-finite values, "belongs to another mesh".
Result<ReducedBasis> decode_reduced_basis(std::span<const std::uint8_t> bytes, const std::string& source_name,
                                          const TetMesh* expected_mesh);

/// Writes the artifact of `basis` to `path`; an Error names the file when it cannot be written.
Status save_reduced_basis(const std::string& path, const ReducedBasis& basis);

/// Reads the artifact at `path` (see decode_reduced_basis; `expected_mesh` may be null).
Result<ReducedBasis> load_reduced_basis(const std::string& path, const TetMesh* expected_mesh);

}  // namespace nav
