// The shared tokenizer of the text mesh formats: tokens across and within lines, numbers,
// line numbers of what was read and of the end, and the first error kept.
#include <gtest/gtest.h>

#include "nav/mesh/text_lines.hpp"

namespace {

using nav::TextScanner;
using nav::Within;

TEST(ParseNumbers, WholeTokenMustBeAFiniteNumber) {
  EXPECT_EQ(nav::parse_double("1.5e-3"), 1.5e-3);
  EXPECT_EQ(nav::parse_double("+2"), 2.0);
  EXPECT_EQ(nav::parse_double("-0.25"), -0.25);
  EXPECT_FALSE(nav::parse_double("1.5x"));
  EXPECT_FALSE(nav::parse_double(""));
  EXPECT_FALSE(nav::parse_double("+-1"));
  EXPECT_FALSE(nav::parse_double("nan"));
  EXPECT_FALSE(nav::parse_double("inf"));
  EXPECT_FALSE(nav::parse_double("1e999"));
  EXPECT_EQ(nav::parse_int("-42"), -42);
  EXPECT_EQ(nav::parse_int("+7"), 7);
  EXPECT_FALSE(nav::parse_int("4.0"));
  EXPECT_FALSE(nav::parse_int("99999999999999999999"));
}

TEST(TextScanner, ReadsTokensAcrossLinesAndCountsThem) {
  TextScanner scanner("a.txt", "  1 2.5\n\n  three\r\n");
  std::int64_t one = 0;
  double two = 0.0;
  std::string_view three;
  ASSERT_TRUE(scanner.read(one, "f"));
  ASSERT_TRUE(scanner.read(two, "f"));
  ASSERT_TRUE(scanner.read(three, "f"));
  EXPECT_EQ(one, 1);
  EXPECT_EQ(two, 2.5);
  EXPECT_EQ(three, "three");
  EXPECT_EQ(scanner.line(), 3);
  EXPECT_TRUE(scanner.at_end());
  EXPECT_EQ(scanner.line(), 3);  // the end is reported on the last line with something on it
}

TEST(TextScanner, ReadWithinALineStopsAtItsEnd) {
  TextScanner scanner("a.txt", "v 1 2\nv 3 4 5\n");
  std::string_view token;
  double value = 0.0;
  ASSERT_TRUE(scanner.read(token, "v", Within::line));
  ASSERT_TRUE(scanner.read(value, "v", Within::line));
  ASSERT_TRUE(scanner.read(value, "v", Within::line));
  EXPECT_FALSE(scanner.read(value, "v", Within::line));
  EXPECT_EQ(scanner.error().describe(), "a.txt:1: v: missing value at end of line");
}

TEST(TextScanner, EndLineRefusesLeftoversAndMovesOn) {
  TextScanner scanner("a.txt", "1 2\n3\n");
  std::int64_t value = 0;
  ASSERT_TRUE(scanner.read(value, "n", Within::line));
  EXPECT_FALSE(scanner.end_line("n"));
  EXPECT_EQ(scanner.error().describe(), "a.txt:1: n: unexpected extra value '2'");
  TextScanner ok("a.txt", "1  \n3\n");
  ASSERT_TRUE(ok.read(value, "n"));
  ASSERT_TRUE(ok.end_line("n"));
  EXPECT_EQ(ok.line(), 2);
  ASSERT_TRUE(ok.read(value, "n"));
  EXPECT_EQ(value, 3);
}

TEST(TextScanner, FirstErrorIsKept) {
  TextScanner scanner("a.txt", "x\ny\n");
  double value = 0.0;
  EXPECT_FALSE(scanner.read(value, "first"));
  EXPECT_FALSE(scanner.read(value, "second"));
  EXPECT_EQ(scanner.error().describe(), "a.txt:1: first: 'x' is not a finite number");
}

TEST(TextScanner, ErrorAtTheEndNamesTheLastLineWithContent) {
  TextScanner scanner("a.txt", "1\n2\n\n  \n");
  std::int64_t value = 0;
  ASSERT_TRUE(scanner.read(value, "n"));
  ASSERT_TRUE(scanner.read(value, "n"));
  EXPECT_FALSE(scanner.read(value, "n"));
  EXPECT_EQ(scanner.error().describe(), "a.txt:2: n: unexpected end of file");
}

TEST(TextScanner, EmptyTextFailsOnLineOne) {
  TextScanner scanner("empty.txt", "");
  std::string_view token;
  EXPECT_TRUE(scanner.at_end());
  EXPECT_FALSE(scanner.read(token, "f"));
  EXPECT_EQ(scanner.error().line, 1);
}

TEST(TextScanner, RangeExpectAndPeek) {
  TextScanner scanner("a.txt", "5 $End\n");
  std::int64_t value = 0;
  EXPECT_EQ(scanner.peek(), "5");
  EXPECT_FALSE(scanner.read_in_range(value, 0, 4, "count"));
  EXPECT_EQ(scanner.error().message, "5 is out of range [0, 4]");
  TextScanner words("a.txt", "$Nodes $End");
  EXPECT_TRUE(words.expect("$Nodes", "s"));
  EXPECT_FALSE(words.expect("$EndNodes", "s"));
  EXPECT_EQ(words.error().message, "expected '$EndNodes', found '$End'");
}

TEST(TextScanner, TakeUntilCountsTheLinesItPasses) {
  TextScanner scanner("a.xml", "<a>\n1\n2</a>", 10);
  ASSERT_TRUE(scanner.take_until('>'));
  scanner.advance(1);
  const auto inside = scanner.take_until('<');
  ASSERT_TRUE(inside);
  EXPECT_EQ(*inside, "\n1\n2");
  EXPECT_EQ(scanner.line(), 12);
  EXPECT_FALSE(scanner.take_until('#'));
  EXPECT_EQ(scanner.remaining(), 0u);
}

TEST(LineOfToken, FindsTheLineOfTheNthTokenOrTheLastOne) {
  const std::string_view text = "\n  1 2\n3\n\n4 5\n";
  EXPECT_EQ(nav::line_of_token(text, 7, 0), 8);
  EXPECT_EQ(nav::line_of_token(text, 7, 2), 9);
  EXPECT_EQ(nav::line_of_token(text, 7, 4), 11);
  EXPECT_EQ(nav::line_of_token(text, 7, 99), 11);
}

TEST(ReadTextFile, MissingFileAndFolderAreErrorsNamingThePath) {
  EXPECT_EQ(nav::read_text_file("/nonexistent/x.msh").error().describe(),
            "/nonexistent/x.msh: cannot open file: no such file");
  EXPECT_EQ(nav::read_text_file("/").error().describe(), "/: cannot open file: not a regular file");
}

}  // namespace
