#include "nav/mesh/load_mesh.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "nav/mesh/msh_reader.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "nav/mesh/vtk_reader.hpp"
#include "nav/mesh/vtu_reader.hpp"

namespace nav {
namespace {

/// The extension of `path` in lower case, with its dot (".vtu").
std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

MeshFileKind mesh_file_kind(const std::string& path) {
  const std::string extension = lower_extension(path);
  if (extension == ".msh" || extension == ".vtk" || extension == ".vtu") return MeshFileKind::tetrahedra;
  if (extension == ".obj") return MeshFileKind::surface;
  return MeshFileKind::unknown;
}

Result<TetMesh> load_tet_mesh(const std::string& path, LengthUnit unit) {
  const std::string extension = lower_extension(path);
  if (extension == ".msh") return load_msh_tet_mesh(path, unit);
  if (extension == ".vtk") return load_vtk_tet_mesh(path, unit);
  if (extension == ".vtu") return load_vtu_tet_mesh(path, unit);
  return Error{.message = "unknown tetrahedral mesh extension '" + extension + "' (.msh, .vtk and .vtu are read)",
               .file = path};
}

Result<TriSurface> load_surface(const std::string& path, LengthUnit unit) {
  const std::string extension = lower_extension(path);
  if (extension == ".obj") return load_obj_surface(path, unit);
  return Error{.message = "unknown surface extension '" + extension + "' (.obj is read)", .file = path};
}

}  // namespace nav
