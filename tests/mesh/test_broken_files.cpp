// The broken-file corpus of tests/data/mesh/broken/: every file is refused with an Error whose
// describe() names the file, the line of the fault and what is wrong; the table below is the
// specification, and every file of the corpus must appear in it.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "nav/mesh/load_mesh.hpp"
#include "support/test_data.hpp"

namespace {

/// One broken file, the line its Error must name and a text its describe() must contain.
struct BrokenFile {
  const char* name;
  int line;
  const char* expected;
};

const BrokenFile kCorpus[] = {
    {"empty.msh", 1, "$MeshFormat: unexpected end of file"},
    {"msh_unsupported_version.msh", 2, "unsupported version '3.0'"},
    {"msh_binary.msh", 2, "binary .msh files are not supported"},
    {"msh_no_mesh_format.msh", 1, "expected '$MeshFormat'"},
    {"msh22_truncated_in_nodes.msh", 15, "$Nodes: unexpected end of file"},
    {"msh22_garbled_coordinate.msh", 16, "'0.0.5' is not a finite number"},
    {"msh22_node_count_too_high.msh", 19, "found '$EndNodes' after 8 of 9 records"},
    {"msh22_node_count_too_low.msh", 18, "expected '$EndNodes', found '999'"},
    {"msh22_negative_node_count.msh", 10, "-8 is out of range"},
    {"msh22_unknown_node_tag.msh", 27, "node tag 1000 is not in $Nodes"},
    {"msh22_duplicate_node_tag.msh", 13, "duplicate node tag 101"},
    {"msh22_tet_with_five_nodes.msh", 28, "unexpected extra value '8'"},
    {"msh22_tet_with_three_nodes.msh", 29, "$Elements: missing value at end of line"},
    {"msh22_missing_elements.msh", 19, "missing $Elements section"},
    {"msh22_truncated_mid_element.msh", 30, "$Elements: unexpected end of file"},
    {"msh22_missing_end_elements.msh", 30, "$Elements: unexpected end of file"},
    {"msh22_unterminated_section.msh", 30, "before $EndPhysicalNames"},
    {"msh22_elements_before_nodes.msh", 9, "$Elements comes before $Nodes"},
    {"msh22_section_without_dollar.msh", 9, "expected a section name ($...), found 'Nodes'"},
    {"msh22_too_many_tags.msh", 25, "99 is out of range [0, 64]"},
    {"msh41_node_count_mismatch.msh", 30, "blocks hold 8 records, the header declares 9"},
    {"msh41_bad_parametric_flag.msh", 15, "2 is out of range [0, 1]"},
    {"msh41_truncated_in_entities.msh", 7, "$Entities: unexpected end of file"},
    {"msh41_block_ends_early.msh", 19, "found '$EndNodes' after 3 of 7 records"},
    {"msh41_unknown_node_tag.msh", 42, "node tag 55 is not in $Nodes"},
    {"msh41_element_count_too_low.msh", 38, "a block of 5 records, but the header leaves room for 4"},
    {"msh41_element_count_too_high.msh", 44, "blocks hold 8 records, the header declares 9"},
    {"msh41_garbled_coordinate.msh", 24, "'O' is not a finite number"},
    {"msh41_truncated_in_elements.msh", 40, "$Elements: unexpected end of file"},
    {"vtk_bad_header.vtk", 1, "the first line is not '# vtk DataFile Version x.y'"},
    {"vtk_binary.vtk", 3, "format: 'BINARY' is not supported"},
    {"vtk_structured_points.vtk", 4, "'STRUCTURED_POINTS' is not supported"},
    {"vtk_truncated_in_points.vtk", 10, "POINTS: unexpected end of file"},
    {"vtk_garbled_cell_index.vtk", 19, "CELLS: 'seven' is not an integer"},
    {"vtk_cell_index_out_of_range.vtk", 20, "point index 8 is out of range (8 points)"},
    {"vtk_too_few_cell_types.vtk", 30, "7 cell types for 8 cells"},
    {"vtk_cells_size_too_large.vtk", 23, "CELLS: found 'CELL_TYPES' after 36 of 37 values"},
    {"vtk_cells_size_too_small.vtk", 21, "claims 4 points, more than the data left"},
    {"vtk_missing_cell_types.vtk", 21, "missing CELL_TYPES section"},
    {"vtk_tet_with_three_points.vtk", 26, "cell 2 of type 10 has 3 points, not 4"},
    {"vtk_points_without_values.vtk", 9, "POINTS: found 'POINTS' after 0 of 24 values"},
    {"vtk_unexpected_keyword.vtk", 23, "unexpected keyword 'CELL_TYPE'"},
    {"vtk_truncated_in_cells.vtk", 17, "CELLS: unexpected end of file"},
    {"vtk_truncated_in_cell_types.vtk", 26, "CELL_TYPES: unexpected end of file"},
    {"vtk51_offset_beyond_connectivity.vtk", 19, "offset 21 is beyond the 20 connectivity values"},
    {"vtk51_offsets_not_from_zero.vtk", 19, "offsets must start with 0"},
    {"vtu_appended.vtu", 29, "format=\"appended\" DataArrays are not supported"},
    {"vtu_binary_points.vtu", 17, "format=\"binary\" DataArrays are not supported"},
    {"vtu_compressed.vtu", 17, "Points: format=\"binary\" DataArrays are not supported"},
    {"vtu_truncated_in_connectivity.vtu", 33, "connectivity: unexpected end of file inside the DataArray"},
    {"vtu_truncated_in_points.vtu", 21, "Points: unexpected end of file inside the DataArray"},
    {"vtu_truncated_after_cells.vtu", 43, "unexpected end of file before </VTKFile>"},
    {"vtu_truncated_in_tag.vtu", 40, "unexpected end of file inside a tag"},
    {"vtu_garbled_point.vtu", 20, "Points: 'l' is not a finite number"},
    {"vtu_connectivity_out_of_range.vtu", 32, "point index 60 is out of range (8 points)"},
    {"vtu_wrong_number_of_points.vtu", 25, "24 values, but the Piece declares 27"},
    {"vtu_offsets_short_of_connectivity.vtu", 38, "the offsets cover 22 of the 23 connectivity values"},
    {"vtu_offsets_decreasing.vtu", 38, "offset 10 is below the previous one"},
    {"vtu_bad_cell_count.vtu", 5, "missing or invalid NumberOfCells"},
    {"vtu_missing_types.vtu", 43, "missing types DataArray"},
    {"vtu_too_few_types.vtu", 41, "5 cell types for 6 cells"},
    {"vtu_polydata.vtu", 3, "type 'PolyData' is not supported"},
    {"vtu_not_vtk.vtu", 4, "not a VTK XML file"},
    {"vtu_unquoted_attribute.vtu", 37, "attribute 'format' has no quoted value"},
    {"vtu_two_pieces.vtu", 6, "more than one Piece"},
    {"obj_index_out_of_range.obj", 27, "vertex index 9 is out of range (8 vertices defined so far)"},
    {"obj_negative_index_out_of_range.obj", 23, "vertex index -9 is out of range"},
    {"obj_zero_index.obj", 26, "vertex index 0 is out of range"},
    {"obj_garbled_vertex.obj", 7, "v: '1.0e' is not a finite number"},
    {"obj_vertex_missing_z.obj", 12, "v: missing value at end of line"},
    {"obj_face_with_two_vertices.obj", 24, "a face needs at least 3 vertices, found 2"},
    {"obj_garbled_face_index.obj", 22, "'x//2' is not a vertex index"},
    {"obj_no_faces.obj", 18, "f: no faces found"},
    {"obj_truncated_in_vertex.obj", 7, "v: unexpected end of file"},
};

/// Loads a file of the corpus with the loader its extension calls for.
nav::Error load_error(const std::string& path) {
  if (path.ends_with(".obj")) {
    const auto surface = nav::load_surface(path, nav::LengthUnit::metre);
    return surface.ok() ? nav::Error{.message = "loaded without error"} : surface.error();
  }
  const auto mesh = nav::load_tet_mesh(path, nav::LengthUnit::metre);
  return mesh.ok() ? nav::Error{.message = "loaded without error"} : mesh.error();
}

class BrokenFileCorpus : public ::testing::TestWithParam<BrokenFile> {};

TEST_P(BrokenFileCorpus, ErrorNamesFileLineAndFault) {
  const BrokenFile& broken = GetParam();
  const std::string path = nav::testing::test_data_path(std::string("mesh/broken/") + broken.name);
  const nav::Error error = load_error(path);
  const std::string text = error.describe();
  EXPECT_EQ(error.file, path) << text;
  EXPECT_EQ(error.line, broken.line) << text;
  EXPECT_NE(text.find(path + ":" + std::to_string(broken.line) + ": "), std::string::npos) << text;
  EXPECT_NE(text.find(broken.expected), std::string::npos) << text << "\n  expected to contain: " << broken.expected;
}

INSTANTIATE_TEST_SUITE_P(Mesh, BrokenFileCorpus, ::testing::ValuesIn(kCorpus),
                         [](const ::testing::TestParamInfo<BrokenFile>& info) {
                           std::string name = info.param.name;
                           for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return name;
                         });

TEST(BrokenFiles, EveryFileOfTheCorpusHasAnExpectation) {
  std::set<std::string> listed;
  for (const BrokenFile& broken : kCorpus) listed.insert(broken.name);
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(nav::testing::test_data_path("mesh/broken"))) {
    EXPECT_TRUE(listed.count(entry.path().filename().string())) << entry.path() << " has no expectation";
    ++files;
  }
  EXPECT_EQ(files, listed.size());
}

TEST(BrokenFiles, NonexistentFileIsNamedWithoutALine) {
  const std::string path = nav::testing::test_data_path("mesh/broken/does_not_exist.vtu");
  const nav::Error error = load_error(path);
  EXPECT_EQ(error.describe(), path + ": cannot open file: no such file");
}

TEST(BrokenFiles, FolderInsteadOfAFileIsRefused) {
  std::filesystem::create_directories(nav::testing::temporary_path("folder.msh"));
  const nav::Error error = load_error(nav::testing::temporary_path("folder.msh"));
  EXPECT_NE(error.describe().find("not a regular file"), std::string::npos) << error.describe();
}

}  // namespace
