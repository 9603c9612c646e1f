// F-tables (io/FTable.hpp): rows, the optional rotation columns, comments, and a DeckError at
// file:line:column for each kind of bad table.
#include "spall/core/Error.hpp"
#include "spall/io/FTable.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace {

std::string write(const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("spall_ftable_" + std::to_string(::getpid()) + ".ftable");
  std::ofstream(path) << text;
  return path.string();
}

// The position of the DeckError a table raises ("line:column"), or "none".
std::string errorAt(const std::string& text) {
  try {
    spall::io::readFTable(write(text));
  } catch (const spall::DeckError& e) {
    return std::to_string(e.where().line) + ":" + std::to_string(e.where().column);
  }
  return "none";
}

} // namespace

TEST(FTable, ReadsRowsCommentsAndRotation) {
  const auto t = spall::io::readFTable(write("# a comment\n"
                                             "0 1 0 0 0 1 0 0 0 1  0 0 0 2   # trailing\n"
                                             "\n"
                                             "2.5 1.1 0.2 0 0 1 0 0 0 0.9  90 0 0 1\n"));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_TRUE(t.rotation);
  EXPECT_EQ(t.rows[1].t, 2.5);
  EXPECT_EQ(t.rows[1].F(0, 1), 0.2);
  EXPECT_EQ(t.rows[1].F(2, 2), 0.9);
  EXPECT_EQ(t.rows[1].line, 4);
  EXPECT_EQ(t.rows[0].axis, spall::Vec<3>(0.0, 0.0, 1.0)); // normalised
  EXPECT_EQ(t.rows[1].thetaDeg, 90.0);
}

TEST(FTable, BadTablesNameTheirPosition) {
  const std::string I = " 1 0 0 0 1 0 0 0 1";
  EXPECT_EQ(errorAt("0" + I + "\n1 1 0 0 0 1 0 0 0\n"), "2:1");           // 9 numbers
  EXPECT_EQ(errorAt("0" + I + "\n1" + I + " 0 0 0 1\n"), "2:1");          // widths differ
  EXPECT_EQ(errorAt("0" + I + "\n1 1 0 0 0 1 0 0 0 nan\n"), "2:19");      // not finite
  EXPECT_EQ(errorAt("0" + I + "\n0" + I + "\n"), "2:1");                  // time not increasing
  EXPECT_EQ(errorAt("0" + I + "\n1 -1 0 0 0 1 0 0 0 1\n"), "2:3");        // det F < 0
  EXPECT_EQ(errorAt("0" + I + " 0 0 0 0\n1" + I + " 0 0 0 1\n"), "1:23"); // zero axis
  EXPECT_EQ(errorAt("0" + I + "\n"), "1:0");                              // one row
  EXPECT_EQ(errorAt("0" + I + "\n1" + I + "\n"), "none");
}
