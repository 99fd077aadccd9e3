// The CCD benchmark's query files (scenes/ccd_query_file.hpp): rows of rational coordinates, eight
// per query, read exactly; every malformed row named by its line.
#include <gtest/gtest.h>

#include <string>

#include "scenes/ccd_query_file.hpp"
#include "tumble/error.hpp"

namespace tumble {
namespace {

std::string repeated_rows(int count, const std::string& row) {
  std::string text;
  for (int i = 0; i < count; ++i)
    text += row + "\n";
  return text;
}

std::string ccd_file_error(const std::string& text) {
  try {
    read_ccd_query_text(text, "q.csv");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CcdQueryFile, ReadsRationalCoordinatesExactly) {
  // 3/4, -1/8, 5/1 on every row; the truth 1.
  const std::vector<CcdQuery> q = read_ccd_query_text(repeated_rows(16, "3,4,-1,8,5,1,1"), "q.csv");
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[1].end[3], Vec3(0.75, -0.125, 5));
  EXPECT_TRUE(q[0].truth);
}

TEST(CcdQueryFile, NamesTheLineOfEachMistake) {
  EXPECT_NE(ccd_file_error(repeated_rows(7, "1,1,1,1,1,1,0") + "1,0,1,1,1,1,0\n")
                .find("q.csv:8: field x_den"),
            std::string::npos);
  EXPECT_NE(ccd_file_error("1,1,1,1,1,1\n").find("q.csv:1: expected 7"), std::string::npos);
  EXPECT_NE(ccd_file_error("1,1,1,1,1,1,2\n").find("q.csv:1: field truth"), std::string::npos);
  EXPECT_NE(ccd_file_error(repeated_rows(3, "1,1,1,1,1,1,0")).find("ends inside a query"),
            std::string::npos);
  // Each number is finite, but their quotient is not.
  EXPECT_NE(ccd_file_error("1e300,1e-300,1,1,1,1,0\n").find("q.csv:1: the coordinates overflow"),
            std::string::npos);
}

}  // namespace
}  // namespace tumble
