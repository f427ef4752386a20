// The CSV reader: header, comments, byte order mark, and every bad input with file, line, column.
#include <gtest/gtest.h>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

TEST(Csv, ReadsHeaderRowsCommentsAndLineNumbers) {
  const CsvTable t = parse_csv("\xEF\xBB\xBF# a comment\nX, Y ,dirX\r\n\n1,2,-1\r\n# skip\n3.5,-4e2,+1\n", "t.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"X", "Y", "dirX"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[1], (std::vector<double>{3.5, -400, 1}));
  EXPECT_EQ(t.lines, (std::vector<int>{4, 6}));
  EXPECT_EQ(t.column("Y"), 1);
  EXPECT_EQ(t.column("Z"), -1);
}

TEST(Csv, RejectsBadInputWithLocation) {
  struct CsvCase {
    const char* text;
    int line;
    const char* field;
    const char* message;
  };
  const CsvCase cases[] = {
      {"", 0, "", "no header"},
      {"# only a comment\n", 0, "", "no header"},
      {"X,,Y\n", 1, "", "empty column name"},
      {"X,X\n", 1, "X", "duplicated column"},
      {"X,Y\n1\n", 2, "", "expected 2 values"},
      {"X,Y\n1,2,3\n", 2, "", "expected 2 values"},
      {"X,Y\n1,abc\n", 2, "Y", "finite number"},
      {"X,Y\n1,nan\n", 2, "Y", "finite number"},
      {"X,Y\n1,\n", 2, "Y", "finite number"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      parse_csv(c.text, "bad.csv");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "bad.csv");
      EXPECT_EQ(e.where().line, c.line) << e.what();
      EXPECT_EQ(e.where().field, c.field) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(read_csv("/nonexistent/file.csv"), InputError);
}
