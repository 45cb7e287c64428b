#pragma once
// One entry point per kind of mesh file, choosing the reader by the file's extension.
#include <string>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// What a file holds, judged by its extension (case-insensitive).
enum class MeshFileKind {
  tetrahedra,  ///< .msh, .vtk, .vtu
  surface,     ///< .obj
  unknown
};

/// The kind of mesh file `path` names.
MeshFileKind mesh_file_kind(const std::string& path);

/// Loads a tetrahedral mesh from a .msh (Gmsh 2.2 / 4.1), .vtk (legacy) or .vtu file
/// (extension case-insensitive) whose coordinates are in `unit`.
Result<TetMesh> load_tet_mesh(const std::string& path, LengthUnit unit);

/// Loads a triangulated surface from an .obj file whose coordinates are in `unit`.
Result<TriSurface> load_surface(const std::string& path, LengthUnit unit);

}  // namespace nav
