// The G-code reader: modes, words, arcs in every plane and form, and every malformed input with its line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kPi;

constexpr double gcode_kTol = 1e-12;

GcodeProgram gcode_parse(const std::string& text, const std::string& axes = "XYZABC") {
  GcodeOptions o;
  o.axes = axes;
  return parse_gcode(text, "t.nc", o);
}

void expect_position(const GcodePosition& p, std::initializer_list<double> xyzabc) {
  std::size_t i = 0;
  for (double v : xyzabc) {
    EXPECT_NEAR(p[i], v, gcode_kTol) << "axis " << kGcodeAxes[i];
    ++i;
  }
}

}  // namespace

TEST(Gcode, StraightMovesFeedAndNumbers) {
  const auto p = gcode_parse("G0 X10 Y20 Z5\nN7 G1 X15 F200\nX-.5 Y1. Z+2\n");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].motion, GcodeMotion::Rapid);
  expect_position(p.moves[0].start, {0, 0, 0, 0, 0, 0});
  expect_position(p.moves[0].end, {10, 20, 5, 0, 0, 0});
  EXPECT_EQ(p.moves[0].line, 1);
  EXPECT_EQ(p.moves[0].n, -1);
  EXPECT_EQ(p.moves[0].feed, 0.0);
  EXPECT_EQ(p.moves[1].motion, GcodeMotion::Linear);
  EXPECT_EQ(p.moves[1].n, 7);
  EXPECT_EQ(p.moves[1].feed, 200.0);
  expect_position(p.moves[1].start, {10, 20, 5, 0, 0, 0});
  expect_position(p.moves[1].end, {15, 20, 5, 0, 0, 0});
  // Modal G1 and F carry over; ".5", "1." and "+2" are numbers.
  EXPECT_EQ(p.moves[2].motion, GcodeMotion::Linear);
  EXPECT_EQ(p.moves[2].feed, 200.0);
  EXPECT_EQ(p.moves[2].line, 3);
  expect_position(p.moves[2].end, {-0.5, 1, 2, 0, 0, 0});
  EXPECT_EQ(p.counts.blocks, 3u);
  EXPECT_EQ(p.counts.moves, 3u);
  EXPECT_NEAR(path_length(p.moves[1]), 5.0, gcode_kTol);
}

TEST(Gcode, CommentsLowercaseSpacesPercentAndIgnoredWords) {
  const std::string text =
      "%\r\n"
      "(header comment)\r\n"
      "\r\n"
      "n10 g1 x 1.5 (inline) y-.5 z +2 f 100 ; to the end ( not a comment\r\n"
      "N20 S8000 M3 T1 G40 G49 G80 G94\r\n"
      "   ; only a comment\r\n"
      "N30 G0 a 90\r\n"
      "%\r\n"
      "\r\n";
  const auto p = gcode_parse(text);
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.moves[0].n, 10);
  EXPECT_EQ(p.moves[0].line, 4);
  expect_position(p.moves[0].end, {1.5, -0.5, 2, 0, 0, 0});
  EXPECT_EQ(p.moves[0].feed, 100.0);
  EXPECT_EQ(p.moves[1].line, 7);
  EXPECT_EQ(p.moves[1].motion, GcodeMotion::Rapid);
  expect_position(p.moves[1].end, {1.5, -0.5, 2, 90, 0, 0});
  // S M T and the four no-op G codes: 7 words that move nothing.
  EXPECT_EQ(p.counts.ignored_words, 7u);
  EXPECT_EQ(p.counts.blocks, 3u);
  EXPECT_EQ(p.counts.lines, 9u);
}

TEST(Gcode, IncrementalAndAbsoluteModes) {
  const auto p = gcode_parse("G0 X1 Y2 Z3 A10\nG91 G1 X10 Y5\nX-3 A15 C-20\nG90 X1\nB7\n");
  ASSERT_EQ(p.moves.size(), 5u);
  expect_position(p.moves[1].end, {11, 7, 3, 10, 0, 0});
  expect_position(p.moves[2].end, {8, 7, 3, 25, 0, -20});
  expect_position(p.moves[3].end, {1, 7, 3, 25, 0, -20});
  expect_position(p.moves[4].end, {1, 7, 3, 25, 7, -20});
}

TEST(Gcode, InchAndMillimetreUnits) {
  // 1 in = 25.4 mm; feeds in in/min become mm/min; A B C stay degrees; I J K and R scale too.
  const auto p = gcode_parse("G20 G1 X1 Y0.5 A30 F10\nG21 X2\nG20 G91 Y1\nG90 G0 X0 Y0\nG2 X1 Y0 I0.5\nG3 X0 Y0 R0.5\n");
  ASSERT_EQ(p.moves.size(), 6u);
  expect_position(p.moves[0].end, {25.4, 12.7, 0, 30, 0, 0});
  EXPECT_NEAR(p.moves[0].feed, 254.0, gcode_kTol);
  expect_position(p.moves[1].end, {2, 12.7, 0, 30, 0, 0});
  EXPECT_NEAR(p.moves[1].feed, 254.0, gcode_kTol);  // modal F was converted when it was read
  expect_position(p.moves[2].end, {2, 38.1, 0, 30, 0, 0});
  // Semicircles of 0.5 in = 12.7 mm radius about (12.7, 0), by I and by R.
  EXPECT_NEAR(p.moves[4].centre[0], 12.7, gcode_kTol);
  EXPECT_NEAR(p.moves[4].centre[1], 0, gcode_kTol);
  EXPECT_NEAR(p.moves[4].sweep, -kPi, gcode_kTol);
  expect_position(p.moves[4].end, {25.4, 0, 0, 30, 0, 0});
  EXPECT_NEAR(p.moves[5].centre[0], 12.7, gcode_kTol);
  EXPECT_NEAR(p.moves[5].centre[1], 0, gcode_kTol);
  EXPECT_NEAR(p.moves[5].sweep, kPi, gcode_kTol);
  EXPECT_NEAR(path_length(p.moves[5]), 12.7 * kPi, 1e-11);
}

TEST(Gcode, ArcsInXYWithCentreOffsets) {
  const auto p = gcode_parse("G0 X10 Y0 Z0\nG3 X0 Y10 I-10 J0\nG0 X10 Y0\nG2 X0 Y10 I-10\n");
  ASSERT_EQ(p.moves.size(), 4u);
  const auto& ccw = p.moves[1];
  EXPECT_EQ(ccw.motion, GcodeMotion::ArcCCW);
  EXPECT_EQ(ccw.plane, GcodePlane::XY);
  EXPECT_NEAR(ccw.centre[0], 0, gcode_kTol);
  EXPECT_NEAR(ccw.centre[1], 0, gcode_kTol);
  EXPECT_NEAR(ccw.sweep, kPi / 2, gcode_kTol);
  EXPECT_NEAR(path_length(ccw), 10 * kPi / 2, 1e-11);
  // Half way: 45 deg on the circle of radius 10.
  expect_position(position_at(ccw, 0.5), {10 / std::sqrt(2.0), 10 / std::sqrt(2.0), 0, 0, 0, 0});
  // Clockwise to the same end: the long way round, 270 deg.
  EXPECT_NEAR(p.moves[3].sweep, -3 * kPi / 2, gcode_kTol);
  expect_position(position_at(p.moves[3], 1.0 / 3.0), {0, -10, 0, 0, 0, 0});
}

TEST(Gcode, ArcsWithRadius) {
  // From (0, 0) to (10, 10) with |R| = 10: the centre is (0, 10) for the short G3 arc (left
  // of the chord) and (10, 0) for the long one (R < 0).
  const auto p = gcode_parse(
      "G0 X0 Y0\nG3 X10 Y10 R10\nG0 X0 Y0\nG3 X10 Y10 R-10\nG0 X0 Y0\nG2 X10 Y10 R10\n"
      "G0 X0 Y0\nG2 X10 Y0 R5\n");
  ASSERT_EQ(p.moves.size(), 8u);
  EXPECT_NEAR(p.moves[1].centre[0], 0, 1e-12);
  EXPECT_NEAR(p.moves[1].centre[1], 10, 1e-12);
  EXPECT_NEAR(p.moves[1].sweep, kPi / 2, 1e-12);
  EXPECT_NEAR(p.moves[3].centre[0], 10, 1e-12);
  EXPECT_NEAR(p.moves[3].centre[1], 0, 1e-12);
  EXPECT_NEAR(p.moves[3].sweep, 3 * kPi / 2, 1e-12);
  // G2 with R > 0: the centre is right of the chord, (10, 0).
  EXPECT_NEAR(p.moves[5].centre[0], 10, 1e-12);
  EXPECT_NEAR(p.moves[5].centre[1], 0, 1e-12);
  EXPECT_NEAR(p.moves[5].sweep, -kPi / 2, 1e-12);
  // Semicircle: R is half the chord, the centre the chord's midpoint.
  EXPECT_NEAR(p.moves[7].centre[0], 5, 1e-12);
  EXPECT_NEAR(p.moves[7].centre[1], 0, 1e-12);
  EXPECT_NEAR(p.moves[7].sweep, -kPi, 1e-12);
  // Clockwise from (0, 0) round (5, 0): through (5, 5).
  expect_position(position_at(p.moves[7], 0.5), {5, 5, 0, 0, 0, 0});
  // R short of half the chord by less than the tolerance: a semicircle all the same.
  const auto q = gcode_parse("G0 X0 Y0\nG2 X10 Y0 R4.999\n");
  EXPECT_NEAR(q.moves[1].centre[0], 5, 1e-12);
  EXPECT_NEAR(std::abs(q.moves[1].sweep), kPi, 1e-12);
}

TEST(Gcode, ArcsInZXAndYZPlanes) {
  // G18: positive turn about +Y takes +X to -Z, so G3 from X10 Z0 to X0 Z10 is 270 deg and G2 90.
  const auto p = gcode_parse("G0 X10 Y0 Z0\nG18 G3 X0 Z10 I-10 K0\nG0 X10 Z0\nG2 X0 Z10 I-10\n");
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_EQ(p.moves[1].plane, GcodePlane::ZX);
  EXPECT_NEAR(p.moves[1].sweep, 3 * kPi / 2, gcode_kTol);
  expect_position(position_at(p.moves[1], 1.0 / 3.0), {0, 0, -10, 0, 0, 0});
  EXPECT_NEAR(p.moves[3].sweep, -kPi / 2, gcode_kTol);
  expect_position(position_at(p.moves[3], 0.5), {10 / std::sqrt(2.0), 0, 10 / std::sqrt(2.0), 0, 0, 0});
  // G19: positive turn about +X takes +Y to +Z, so G3 from Y10 Z0 to Y0 Z10 is 90 deg.
  const auto q = gcode_parse("G0 X0 Y10 Z0\nG19 G3 Y0 Z10 J-10\nG0 Y10 Z0\nG19 G2 Y0 Z10 R10\n");
  ASSERT_EQ(q.moves.size(), 4u);
  EXPECT_EQ(q.moves[1].plane, GcodePlane::YZ);
  EXPECT_NEAR(q.moves[1].sweep, kPi / 2, gcode_kTol);
  expect_position(position_at(q.moves[1], 0.5), {0, 10 / std::sqrt(2.0), 10 / std::sqrt(2.0), 0, 0, 0});
  // The short clockwise arc of radius 10 from (Y, Z) = (10, 0) to (0, 10) turns about (10, 10).
  EXPECT_NEAR(q.moves[3].centre[1], 10, 1e-12);
  EXPECT_NEAR(q.moves[3].centre[2], 10, 1e-12);
  EXPECT_NEAR(q.moves[3].sweep, -kPi / 2, 1e-12);
}

TEST(Gcode, FullCirclesAndHelices) {
  const auto p = gcode_parse("G0 X10 Y0 Z0\nG2 X10 Y0 I-5\nG3 I-5 J0\nG3 X10 Y0 Z-6 I-10 J0 A90\n");
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_NEAR(p.moves[1].sweep, -2 * kPi, gcode_kTol);
  EXPECT_NEAR(p.moves[1].centre[0], 5, gcode_kTol);
  EXPECT_NEAR(path_length(p.moves[1]), 2 * kPi * 5, 1e-11);
  // No axis word: a full circle from where the tool is.
  EXPECT_NEAR(p.moves[2].sweep, 2 * kPi, gcode_kTol);
  expect_position(p.moves[2].end, {10, 0, 0, 0, 0, 0});
  // Helix: one turn of radius 10 down 6 mm; length sqrt((2 pi 10)^2 + 6^2); A turns with it.
  const auto& h = p.moves[3];
  EXPECT_NEAR(h.sweep, 2 * kPi, gcode_kTol);
  EXPECT_NEAR(path_length(h), std::sqrt(std::pow(2 * kPi * 10, 2) + 36), 1e-11);
  expect_position(position_at(h, 0.25), {0, 10, -1.5, 22.5, 0, 0});
  expect_position(position_at(h, 0.5), {-10, 0, -3, 45, 0, 0});
  // A helix in G18 rises along Y.
  const auto q = gcode_parse("G0 X10 Y0 Z0\nG18 G2 X0 Z10 Y4 I-10\n");
  expect_position(position_at(q.moves[1], 0.5), {10 / std::sqrt(2.0), 2, 10 / std::sqrt(2.0), 0, 0, 0});
  EXPECT_NEAR(path_length(q.moves[1]), std::hypot(10 * kPi / 2, 4), 1e-11);
}

TEST(Gcode, ArcEndRadiusTolerance) {
  // 0.001 mm off the circle is inside 0.002 mm; 0.1 mm is not, and the message names both radii.
  EXPECT_NO_THROW(gcode_parse("G0 X10\nG3 X0 Y10.001 I-10\n"));
  try {
    gcode_parse("G0 X10\nG3 X0 Y10.1 I-10\n");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(e.where().line, 2);
    EXPECT_NE(m.find("start radius 10 mm"), std::string::npos) << m;
    EXPECT_NE(m.find("end radius 10.1 mm"), std::string::npos) << m;
    EXPECT_NE(m.find("column 13"), std::string::npos) << m;
  }
  // Relative tolerance: at r = 100 m, 1e-4 r = 10 mm.
  EXPECT_NO_THROW(gcode_parse("G0 X100000\nG3 X0 Y100005 I-100000\n"));
}

TEST(Gcode, MachineAxesOnly) {
  EXPECT_NO_THROW(gcode_parse("G1 X1 Y2 Z3\n", "XYZ"));
  EXPECT_NO_THROW(gcode_parse("G1 X1 B2 C3\n", "CBXYZ"));
}

TEST(Gcode, MalformedLinesNameLineAndColumn) {
  struct GcodeCase {
    std::string text;
    int line;
    int column;
    const char* message;
    std::string axes = "XYZABC";
  };
  const GcodeCase cases[] = {
      {"G1 X1\nG5 X2\n", 2, 1, "G5 spline"},
      {"G1 X1 & Y2\n", 1, 7, "found '&'"},
      {"G0 G1 X1\n", 1, 4, "two motion codes"},
      {"G17 G18\n", 1, 5, "two plane codes"},
      {"G20 G21\n", 1, 5, "two unit codes"},
      {"G90 G91\n", 1, 5, "two distance mode codes"},
      {"G1 X1 X2\n", 1, 7, "'X' given twice"},
      {"G1 X1 F1 F2\n", 1, 10, "'F' given twice"},
      {"G1 X1 I2\n", 1, 7, "I, J, K and R go with G2 or G3"},
      {"R5\n", 1, 1, "I, J, K and R go with G2 or G3"},
      {"G0 X1\nG2 X2 Y1 I1 R1\n", 2, 13, "R and I/J/K in one block"},
      {"G0 X1\nG2 X2 Y1\n", 2, 1, "with no centre"},
      {"G0 X10\nG2 X0 Y10 K1\n", 2, 11, "'K' is no centre offset in the G17 plane"},
      {"G0 X10\nG18 G2 X0 Z10 J1\n", 2, 15, "'J' is no centre offset in the G18 plane"},
      {"G0 X10\nG2 X0 Y10 R4\n", 2, 11, "R 4 mm is shorter than half the chord"},
      {"G0 X1\nG2 X1 R5\n", 2, 7, "R arc whose end is its start"},
      {"G0 X1\nG2 I0 J0\n", 2, 4, "centre is its start point"},
      {"G1 X\n", 1, 4, "expected a number after 'X', found the end of the block"},
      {"G1 X ; no number\n", 1, 4, "expected a number after 'X', found the end of the block"},
      {"G1 Xabc\n", 1, 4, "found 'abc'"},
      {"G1 Xnan\n", 1, 4, "found 'nan'"},
      {"G1 X-inf\n", 1, 4, "found '-inf'"},
      {"G1 X+-1\n", 1, 4, "found '+-1'"},
      {"G1 X1e5\n", 1, 4, "no exponent"},
      {"G1 X" + std::string(400, '9') + "\n", 1, 4, "expected a finite number"},
      {"G1 X1 (comment\n", 1, 7, "unterminated comment"},
      {"G1 X1 B5\n", 1, 7, "axis word 'B' for an axis this machine does not have (its axes: XYZ)", "XYZ"},
      {"\n\nX5\n", 3, 1, "no motion mode"},
      {"G1 X1 %\n", 1, 7, "'%' must be alone"},
      {"% x\n", 1, 3, "expected nothing after '%'"},
      {"%\nG1 X1\n%\nG1 X2\n", 4, 1, "after the closing '%'"},
      {"N-5 G1 X1\n", 1, 1, "whole block number"},
      {"N1.5\n", 1, 1, "whole block number"},
      {"G1 X1 F-1\n", 1, 7, "feed >= 0"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text.substr(0, 40));
    try {
      gcode_parse(c.text, c.axes);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_EQ(e.where().file, "t.nc");
      EXPECT_EQ(e.where().line, c.line) << m;
      const std::string where = "t.nc:" + std::to_string(c.line) + ": column " + std::to_string(c.column) + ": ";
      EXPECT_EQ(m.rfind(where, 0), 0u) << m << "\nexpected it to start with " << where;
      EXPECT_NE(m.find(c.message), std::string::npos) << m;
    }
  }
}

TEST(Gcode, StreamingReaderMatchesWholeProgram) {
  const std::string text = "G0 X1\nG1 Y2 F100\nM3\nG2 X3 Y0 R2\n";
  GcodeReader r(text, "s.nc");
  GcodeMove m;
  int count = 0;
  while (r.next(m)) ++count;
  EXPECT_EQ(count, 3);
  EXPECT_EQ(r.counts().moves, 3u);
  EXPECT_EQ(r.counts().ignored_words, 1u);
  EXPECT_EQ(gcode_parse(text).moves.size(), 3u);
  EXPECT_THROW(read_gcode("/nonexistent/p.nc"), InputError);
}
