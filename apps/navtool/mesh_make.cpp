// navtool mesh make: tetrahedralises the embedded default liver, a closed surface (.obj) or a
// label volume (.mha/.mhd) with the library's mesher, prints the figures of the result and
// writes it as a .vtu (with the element regions and radius ratios as cell data).
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesh/vtu_writer.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/mesher/label_volume_domain.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/mesher/metaimage_reader.hpp"
#include "nav/mesher/surface_domain.hpp"

namespace navtool {
namespace {

constexpr const char* kUsage =
    "usage: navtool mesh make (--liver | --surface FILE.obj [--unit mm|cm|m] | --labels FILE.mha [--unit mm|cm|m])"
    " --size H_M --out FILE.vtu\n";

/// What to mesh.
enum class Source { none, liver, surface, labels };

/// The command line of mesh make.
struct MakeArgs {
  Source source = Source::none;
  std::string input;
  std::optional<nav::LengthUnit> unit;  ///< default: m for surfaces, mm for label volumes
  double size_m = 0.0;
  std::string out;
};

/// A made mesh and what to say about it beyond its own figures.
struct Made {
  nav::TetMesh mesh;
  std::string notes;
};

/// Prints "navtool mesh make: <message>" and the usage on stderr; returns exit_bad_input.
int bad_input(const std::string& message) {
  std::fprintf(stderr, "navtool mesh make: %s\n%s", message.c_str(), kUsage);
  return exit_bad_input;
}

/// Parses the arguments into `parsed`; an error message if they are malformed.
std::optional<std::string> parse_args(const std::vector<std::string>& args, MakeArgs& parsed) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--liver" || ((arg == "--surface" || arg == "--labels") && has_value)) {
      if (parsed.source != Source::none) return "give one of --liver, --surface and --labels";
      parsed.source = arg == "--liver" ? Source::liver : (arg == "--surface" ? Source::surface : Source::labels);
      if (parsed.source != Source::liver) parsed.input = args[++i];
    } else if (arg == "--unit" && has_value) {
      parsed.unit = nav::parse_length_unit(args[++i]);
      if (!parsed.unit) return "--unit: unknown unit '" + args[i] + "' (mm, cm or m)";
    } else if (arg == "--size" && has_value) {
      const std::string& text = args[++i];
      const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), parsed.size_m);
      if (error != std::errc() || end != text.data() + text.size() || !(parsed.size_m > 0.0) ||
          !std::isfinite(parsed.size_m)) {
        return "--size: expected a positive element size in metres, got '" + text + "'";
      }
    } else if (arg == "--out" && has_value) {
      parsed.out = args[++i];
    } else {
      return "unexpected argument '" + arg + "'";
    }
  }
  if (parsed.source == Source::none) return "give one of --liver, --surface FILE and --labels FILE";
  if (parsed.source == Source::liver && parsed.unit) return "--unit applies to --surface and --labels only";
  if (parsed.size_m == 0.0) return "--size H_M is required";
  if (parsed.out.empty() || !parsed.out.ends_with(".vtu")) return "--out FILE.vtu is required";
  return std::nullopt;
}

/// Meshes `domain`, or gives the mesher's Error.
nav::Result<Made> mesh_domain(const nav::MeshingDomain& domain, double size_m) {
  auto made = nav::make_tet_mesh(domain, {.element_size_m = size_m, .fitting = {}});
  if (!made.ok()) return made.error();
  Made result{std::move(made.value().mesh), ""};
  result.notes =
      "boundary nodes off the boundary: " + std::to_string(made.value().report.fitting.unsnapped_nodes.size()) +
      " of " + std::to_string(made.value().report.boundary_nodes) + "\n";
  return result;
}

/// The mesh of the source the arguments name, or the Error that prevented it.
nav::Result<Made> make(const MakeArgs& args) {
  if (args.source == Source::liver) {
    try {
      nav::EmbeddedLiver liver = nav::make_embedded_liver(args.size_m);
      std::size_t tumour_tets = 0;
      for (const std::int32_t region : liver.mesh.tet_regions)
        tumour_tets += region == static_cast<std::int32_t>(nav::TissueRegion::tumour) ? 1 : 0;
      return Made{std::move(liver.mesh), "tumour tetrahedra: " + std::to_string(tumour_tets) + "\nattachment nodes: " +
                                             std::to_string(liver.attachment_nodes.size()) + "\n"};
    } catch (const std::invalid_argument& error) {
      return nav::Error{.message = error.what(), .field = "--size"};
    }
  }
  if (args.source == Source::surface) {
    const auto surface = nav::load_surface(args.input, args.unit.value_or(nav::LengthUnit::metre));
    if (!surface.ok()) return surface.error();
    return mesh_domain(nav::SurfaceDomain(surface.value()), args.size_m);
  }
  const auto volume = nav::read_metaimage_labels(args.input, args.unit.value_or(nav::LengthUnit::millimetre));
  if (!volume.ok()) return volume.error();
  return mesh_domain(nav::LabelVolumeDomain(volume.value()), args.size_m);
}

/// The radius ratio of every element, as a cell field.
nav::VtuField radius_ratios(const nav::TetMesh& mesh) {
  nav::VtuField field{"radius_ratio", 1, {}};
  for (const auto& t : mesh.tets) {
    field.values.push_back(
        nav::tet_radius_ratio(mesh.nodes_m[t[0]], mesh.nodes_m[t[1]], mesh.nodes_m[t[2]], mesh.nodes_m[t[3]]));
  }
  return field;
}

}  // namespace

int mesh_make(const std::vector<std::string>& args) {
  MakeArgs parsed;
  if (const auto problem = parse_args(args, parsed)) return bad_input(*problem);

  const auto start = std::chrono::steady_clock::now();
  const auto made = make(parsed);
  const double elapsed_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!made.ok()) {
    std::fprintf(stderr, "navtool mesh make: %s\n", made.error().describe().c_str());
    return exit_bad_input;
  }
  const nav::TetMesh& mesh = made.value().mesh;
  const nav::TetMeshReport report = nav::validate_tet_mesh(mesh);
  std::printf(
      "tetrahedra: %zu\nnodes: %zu\nvolume: %.6g m^3 (%.4g L)\ninverted: %zu\n"
      "min radius ratio: %.3f\nmin dihedral angle: %.1f deg\n%stime: %.0f ms\n",
      report.tetrahedra, report.nodes, report.volume_m3, report.volume_m3 * 1e3, report.inverted, report.min_quality,
      report.min_dihedral_deg, made.value().notes.c_str(), elapsed_ms);

  const nav::Status written = nav::write_vtu(parsed.out, mesh, {}, {radius_ratios(mesh)});
  if (!written.ok()) {
    std::fprintf(stderr, "navtool mesh make: %s\n", written.error().describe().c_str());
    return exit_failure;
  }
  std::printf("written: %s\n", parsed.out.c_str());
  return exit_ok;
}

}  // namespace navtool
