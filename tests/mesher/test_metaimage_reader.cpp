// MetaImage label volumes: a good file in both layouts, and a corpus of broken files whose
// errors must name the file, the header line and the field.
#include <gtest/gtest.h>

#include <string>

#include "nav/mesher/metaimage_reader.hpp"
#include "support/test_data.hpp"

namespace nav {
namespace {

std::string corpus(const std::string& name) { return testing::test_data_path("mesher/" + name); }

void expect_ball(const LabelVolume& volume) {
  // 9 x 8 x 7 voxels, spacing (1, 1.25, 1.5) mm, offset (-4, -5, -3.5) mm; a ball of radius 3
  // voxels around voxel (4, 4, 3), label 1 (123 voxels).
  EXPECT_EQ(volume.size, (std::array<std::int32_t, 3>{9, 8, 7}));
  EXPECT_DOUBLE_EQ(volume.spacing_m[1], 0.00125);
  EXPECT_DOUBLE_EQ(volume.origin_m[2], -0.0035);
  ASSERT_EQ(volume.labels.size(), 9u * 8u * 7u);
  EXPECT_EQ(volume.at(4, 4, 3), 1);
  EXPECT_EQ(volume.at(0, 0, 0), 0);
  EXPECT_EQ(volume.at(4, 4, 6), 1);
  EXPECT_EQ(volume.at(4, 4, 7), 0);  // outside the grid
  std::size_t tissue = 0;
  for (const auto label : volume.labels) tissue += label;
  EXPECT_EQ(tissue, 123u);
}

TEST(MetaImageReader, ReadsLocalData) {
  const auto volume = read_metaimage_labels(corpus("ball.mha"));
  ASSERT_TRUE(volume.ok()) << volume.error().describe();
  expect_ball(volume.value());
}

TEST(MetaImageReader, ReadsSeparateRawFile) {
  const auto volume = read_metaimage_labels(corpus("ball.mhd"));
  ASSERT_TRUE(volume.ok()) << volume.error().describe();
  expect_ball(volume.value());
}

TEST(MetaImageReader, ScalesByTheGivenUnit) {
  const auto volume = read_metaimage_labels(corpus("ball.mha"), LengthUnit::centimetre);
  ASSERT_TRUE(volume.ok());
  EXPECT_DOUBLE_EQ(volume.value().spacing_m[2], 0.015);
}

struct BrokenFile {
  const char* name;
  int line;
  const char* field;
  const char* words;  ///< part of the message
};

class BrokenMetaImage : public ::testing::TestWithParam<BrokenFile> {};

TEST_P(BrokenMetaImage, NamesFileLineAndField) {
  const BrokenFile& broken = GetParam();
  const auto volume = read_metaimage_labels(corpus(broken.name));
  ASSERT_FALSE(volume.ok());
  const Error& error = volume.error();
  EXPECT_EQ(error.file, corpus(broken.name));
  EXPECT_EQ(error.line, broken.line) << error.describe();
  EXPECT_EQ(error.field, broken.field) << error.describe();
  EXPECT_NE(error.message.find(broken.words), std::string::npos) << error.describe();
}

INSTANTIATE_TEST_SUITE_P(Corpus, BrokenMetaImage,
                         ::testing::Values(BrokenFile{"truncated.mha", 11, "ElementDataFile", "truncated voxel data"},
                                           BrokenFile{"extra_bytes.mha", 11, "ElementDataFile", "unexpected bytes"},
                                           BrokenFile{"wrong_dims.mha", 2, "NDims", "only 3-D"},
                                           BrokenFile{"short_dimsize.mha", 9, "DimSize", "expected 3 values"},
                                           BrokenFile{"bad_dimsize.mha", 9, "DimSize", "positive integer, found '-8'"},
                                           BrokenFile{"bad_type.mha", 10, "ElementType", "MET_FLOAT"},
                                           BrokenFile{"bad_spacing.mha", 8, "ElementSpacing", "found 'x'"},
                                           BrokenFile{"compressed.mha", 5, "CompressedData", "compressed"},
                                           BrokenFile{"rotated.mha", 6, "TransformMatrix", "axis-aligned"},
                                           BrokenFile{"no_data_file.mha", 10, "ElementDataFile", "missing"},
                                           BrokenFile{"missing_raw.mhd", 11, "ElementDataFile",
                                                      "cannot open data file"},
                                           BrokenFile{"no_equals.mha", 4, "NDims 3", "Key = Value"},
                                           BrokenFile{"no_element_type.mha", 10, "ElementType", "missing"}),
                         [](const ::testing::TestParamInfo<BrokenFile>& info) {
                           std::string name = info.param.name;
                           for (char& c : name)
                             if (c == '.') c = '_';
                           return name;
                         });

TEST(MetaImageReader, MissingFileIsAnError) {
  const auto volume = read_metaimage_labels(corpus("does_not_exist.mha"));
  ASSERT_FALSE(volume.ok());
  EXPECT_NE(volume.error().describe().find("does_not_exist.mha"), std::string::npos);
}

}  // namespace
}  // namespace nav
