// Every loader on every good small file cut at every byte, with every line deleted and with
// every byte overwritten, and on the files of real writers cut at every line: no crash, no
// hang, and each failure is an Error naming the file and a line that exists. Formats that end
// with a closing marker (.msh, .vtu) must refuse every cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

#include "nav/mesh/msh_reader.hpp"
#include "nav/mesh/obj_reader.hpp"
#include "nav/mesh/text_lines.hpp"
#include "nav/mesh/vtk_reader.hpp"
#include "nav/mesh/vtu_reader.hpp"
#include "support/test_data.hpp"

namespace {

using nav::LengthUnit;

/// Parses `text` as the format of `name`; returns the Error, or nullopt if it loaded.
std::optional<nav::Error> parse_as(const std::string& name, std::string_view text) {
  auto error_of = [](const auto& result) { return result.ok() ? std::nullopt : std::optional(result.error()); };
  if (name.ends_with(".msh")) return error_of(nav::parse_msh_tet_mesh(text, name, LengthUnit::metre));
  if (name.ends_with(".vtk")) return error_of(nav::parse_vtk_tet_mesh(text, name, LengthUnit::metre));
  if (name.ends_with(".vtu")) return error_of(nav::parse_vtu_tet_mesh(text, name, LengthUnit::metre));
  return error_of(nav::parse_obj_surface(text, name, LengthUnit::metre));
}

int line_count(std::string_view text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1; }

/// Checks one mangled text; returns true if it loaded.
bool check_mangled(const std::string& name, std::string_view text, const std::string& how) {
  const auto error = parse_as(name, text);
  if (!error) return true;
  EXPECT_EQ(error->file, name) << how;
  EXPECT_GE(error->line, 1) << how << ": " << error->describe();
  EXPECT_LE(error->line, line_count(text)) << how << ": " << error->describe();
  EXPECT_FALSE(error->message.empty()) << how;
  return false;
}

/// Reads tests/data/mesh/`name`.
std::string read_test_file(const char* name) {
  auto text = nav::read_text_file(nav::testing::test_data_path(std::string("mesh/") + name));
  EXPECT_TRUE(text.ok());
  return text.ok() ? text.value() : std::string();
}

std::string test_name(const ::testing::TestParamInfo<const char*>& info) {
  std::string name = info.param;
  std::replace(name.begin(), name.end(), '.', '_');
  return name;
}

class GoodFile : public ::testing::TestWithParam<const char*> {
 protected:
  std::string name() const { return GetParam(); }
  std::string text() const { return read_test_file(GetParam()); }
};

TEST_P(GoodFile, LoadsIntact) { EXPECT_FALSE(parse_as(name(), text())); }

TEST_P(GoodFile, EveryTruncationFailsCleanly) {
  const std::string full = text();
  const bool has_end_marker = name().ends_with(".msh") || name().ends_with(".vtu");
  const std::size_t last_content = full.find_last_not_of(" \t\r\n");
  for (std::size_t length = 0; length < full.size(); ++length) {
    const bool loaded =
        check_mangled(name(), std::string_view(full).substr(0, length), "cut at " + std::to_string(length));
    if (has_end_marker && length <= last_content) {
      EXPECT_FALSE(loaded) << "cut at " << length << " loaded";
    }
  }
}

TEST_P(GoodFile, EveryDeletedLineFailsCleanly) {
  const std::string full = text();
  for (std::size_t start = 0; start < full.size();) {
    const std::size_t end = std::min(full.find('\n', start), full.size() - 1) + 1;
    check_mangled(name(), full.substr(0, start) + full.substr(end),
                  "line at byte " + std::to_string(start) + " deleted");
    start = end;
  }
}

TEST_P(GoodFile, EveryOverwrittenByteFailsCleanly) {
  const std::string full = text();
  for (const char replacement : {'x', '-', '9', '\n', '<', '$', '\0'}) {
    for (std::size_t at = 0; at < full.size(); ++at) {
      std::string mangled = full;
      mangled[at] = replacement;
      check_mangled(name(), mangled, "byte " + std::to_string(at) + " overwritten");
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Mesh, GoodFile,
                         ::testing::Values("cube_v22.msh", "cube_v41.msh", "cube.vtk", "cube_v51.vtk", "cube.vtu",
                                           "cube.obj"),
                         test_name);

using RealWriterFile = GoodFile;

TEST_P(RealWriterFile, EveryLineTruncationFailsCleanly) {
  const std::string full = text();
  for (std::size_t end = full.find('\n'); end != std::string::npos; end = full.find('\n', end + 1)) {
    check_mangled(name(), std::string_view(full).substr(0, end), "cut at " + std::to_string(end));
  }
}

INSTANTIATE_TEST_SUITE_P(Mesh, RealWriterFile,
                         ::testing::Values("gmsh_ball_v22.msh", "gmsh_ball_v41.msh", "gmsh_ball.vtk", "gmsh_ball.vtu"),
                         test_name);

}  // namespace
