// navtool mesh info: loads a tetrahedral mesh (.msh, .vtk, .vtu) or a surface (.obj) and prints
// its counts, volume, element quality and topology, as a table or as one JSON object.
#include <charconv>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/mesh/validation.hpp"

namespace navtool {
namespace {

/// One reported figure: its key, its value as JSON and as text for the table.
struct Item {
  std::string key;
  std::string json;
  std::string text;
};

/// The command line of mesh info.
struct InfoArgs {
  std::string file;
  std::string unit_name = "m";
  nav::LengthUnit unit = nav::LengthUnit::metre;
  bool json = false;
};

/// `text` as a JSON string literal.
std::string json_string(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      quoted += '\\';
      quoted += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\u%04x", static_cast<unsigned>(c));
      quoted += escape;
    } else {
      quoted += c;
    }
  }
  return quoted + "\"";
}

/// A real number: shortest round-trip form in JSON, 6 significant digits in the table.
Item number(std::string key, double value) {
  char json[32];
  const auto end = std::to_chars(json, json + sizeof(json), value).ptr;
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return {std::move(key), std::string(json, end), text};
}

/// A count.
Item count(std::string key, std::size_t value) {
  return {std::move(key), std::to_string(value), std::to_string(value)};
}

/// A yes/no figure.
Item flag(std::string key, bool value) { return {std::move(key), value ? "true" : "false", value ? "yes" : "no"}; }

/// A string.
Item text(std::string key, const std::string& value) { return {std::move(key), json_string(value), value}; }

/// Parses FILE [--unit mm|cm|m] [--json]; nullopt (after a message on stderr) if malformed.
std::optional<InfoArgs> parse_args(const std::vector<std::string>& args) {
  InfoArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--json") {
      parsed.json = true;
    } else if (args[i] == "--unit" && i + 1 < args.size()) {
      const auto unit = nav::parse_length_unit(args[++i]);
      if (!unit) {
        std::fprintf(stderr, "navtool mesh info: unknown unit '%s' (mm, cm or m)\n", args[i].c_str());
        return std::nullopt;
      }
      parsed.unit = *unit;
      parsed.unit_name = args[i];
    } else if (parsed.file.empty() && !args[i].starts_with("--")) {
      parsed.file = args[i];
    } else {
      std::fprintf(stderr, "navtool mesh info: unexpected argument '%s'\n", args[i].c_str());
      return std::nullopt;
    }
  }
  if (parsed.file.empty()) {
    std::fputs("usage: navtool mesh info FILE [--unit mm|cm|m] [--json]\n", stderr);
    return std::nullopt;
  }
  return parsed;
}

std::vector<Item> tet_mesh_items(const nav::TetMesh& mesh) {
  const nav::TetMeshReport report = nav::validate_tet_mesh(mesh);
  const nav::SurfaceReport boundary = nav::validate_surface(nav::extract_boundary(mesh).surface);
  return {count("nodes", report.nodes),
          count("tetrahedra", report.tetrahedra),
          number("volume_m3", report.volume_m3),
          count("inverted", report.inverted),
          count("degenerate", report.degenerate),
          number("degenerate_below_radius_ratio", report.degenerate_radius_ratio),
          number("min_quality", report.min_quality),
          number("mean_quality", report.mean_quality),
          number("min_dihedral_deg", report.min_dihedral_deg),
          count("unreferenced_nodes", report.unreferenced_nodes),
          count("out_of_range_indices", report.out_of_range_indices),
          count("boundary_triangles", boundary.triangles),
          flag("boundary_closed", boundary.closed),
          flag("boundary_oriented", boundary.consistently_oriented)};
}

std::vector<Item> surface_items(const nav::TriSurface& surface) {
  const nav::SurfaceReport report = nav::validate_surface(surface);
  return {count("vertices", report.vertices),
          count("triangles", report.triangles),
          flag("closed", report.closed),
          flag("consistently_oriented", report.consistently_oriented),
          count("boundary_edges", report.boundary_edges),
          count("non_manifold_edges", report.non_manifold_edges),
          count("out_of_range_indices", report.out_of_range_indices),
          number("volume_m3", report.enclosed_volume_m3)};
}

void print_json(const std::vector<Item>& items) {
  std::string text = "{";
  for (std::size_t i = 0; i < items.size(); ++i) {
    text += (i == 0 ? "" : ", ") + json_string(items[i].key) + ": " + items[i].json;
  }
  std::printf("%s}\n", text.c_str());
}

void print_table(const std::vector<Item>& items) {
  for (const Item& item : items) std::printf("%-30s %s\n", item.key.c_str(), item.text.c_str());
}

}  // namespace

int mesh_info(const std::vector<std::string>& args) {
  const auto parsed = parse_args(args);
  if (!parsed) return exit_bad_input;
  std::vector<Item> items{text("file", parsed->file), text("unit", parsed->unit_name)};
  std::vector<Item> figures;
  if (nav::mesh_file_kind(parsed->file) == nav::MeshFileKind::surface) {
    const auto surface = nav::load_surface(parsed->file, parsed->unit);
    if (!surface) {
      std::fprintf(stderr, "%s\n", surface.error().describe().c_str());
      return exit_bad_input;
    }
    figures = surface_items(surface.value());
  } else {
    const auto mesh = nav::load_tet_mesh(parsed->file, parsed->unit);
    if (!mesh) {
      std::fprintf(stderr, "%s\n", mesh.error().describe().c_str());
      return exit_bad_input;
    }
    figures = tet_mesh_items(mesh.value());
  }
  items.insert(items.end(), figures.begin(), figures.end());
  if (parsed->json) {
    print_json(items);
  } else {
    print_table(items);
  }
  return exit_ok;
}

}  // namespace navtool
