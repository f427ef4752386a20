// Strict number parsing shared by the machine file, CSV and command-line readers.
#include <gtest/gtest.h>

#include "mtcal/util/parse.hpp"

using mtcal::parse_number;

TEST(ParseNumber, AcceptsDecimalNumbers) {
  EXPECT_EQ(parse_number("12"), 12.0);
  EXPECT_EQ(parse_number("-0.5"), -0.5);
  EXPECT_EQ(parse_number("+3e-6"), 3e-6);
  EXPECT_EQ(parse_number(".5"), 0.5);
  EXPECT_EQ(parse_number("1E3"), 1000.0);
}

TEST(ParseNumber, RejectsEverythingElse) {
  for (const char* s :
       {"", "+", "-", "+-3", "++3", "0x10", " 1", "1 ", "1,5", "1e", "abc", "inf", "nan", "-inf", "1e400", "5um"})
    EXPECT_FALSE(parse_number(s)) << "'" << s << "'";
}
