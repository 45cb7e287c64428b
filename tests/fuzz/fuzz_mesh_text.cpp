// libFuzzer target for one text mesh parser, chosen when compiling by NAV_FUZZ_PARSE
// (nav::parse_msh_tet_mesh, parse_vtk_tet_mesh, parse_vtu_tet_mesh or parse_obj_surface):
// the input is parsed as a file's text, and what loads is validated as `navtool mesh info`
// does, so that the checks run on whatever a parser lets through.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

#include "nav/mesh/msh_reader.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesh/vtk_reader.hpp"
#include "nav/mesh/vtu_reader.hpp"

namespace {

/// The checks `navtool mesh info` runs on a loaded mesh or surface.
template <typename Loaded>
void validate(const Loaded& loaded) {
  if constexpr (std::is_same_v<Loaded, nav::TetMesh>) {
    nav::validate_tet_mesh(loaded);
    nav::extract_boundary(loaded);
  } else {
    nav::validate_surface(loaded);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto loaded = NAV_FUZZ_PARSE(text, "fuzz-input", nav::LengthUnit::millimetre);
  if (loaded.ok()) validate(loaded.value());
  return 0;
}
