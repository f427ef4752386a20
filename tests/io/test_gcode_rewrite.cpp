// G-code rewriter: what is kept of a line, what changes, units and distance modes, pieces as lines;
// checked against values written here by hand and by reading the result back with the reader.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/rewrite.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

GcodeOptions xyz() {
  GcodeOptions o;
  o.axes = "XYZ";
  return o;
}

// One piece per move, ending at the given positions.
std::vector<CorrectedMove> single(const GcodeProgram& p, const std::vector<GcodePosition>& ends) {
  std::vector<CorrectedMove> out;
  for (std::size_t i = 0; i < p.moves.size(); ++i) {
    CorrectedMove m;
    m.line = p.moves[i].line;
    m.motion = p.moves[i].motion;
    CorrectedPiece c;
    c.motion = p.moves[i].motion;
    c.end = ends[i];
    c.centre = p.moves[i].centre;
    c.sweep = p.moves[i].sweep;
    m.pieces.push_back(c);
    out.push_back(m);
  }
  return out;
}

}  // namespace

TEST(GcodeRewrite, KeepsEverythingButTheChangedCoordinates) {
  const std::string text =
      "%\r\n(header)\r\nN10 G90 G21 G1 X10.0  Y5 F300 (move)\r\nN20 x20 ; lower case\r\nM30\r\n%\r\n";
  const auto p = parse_gcode(text, "a.nc", xyz());
  ASSERT_EQ(p.moves.size(), 2u);
  auto moves = single(p, {GcodePosition{10.0012345, 5, 0.002, 0, 0, 0}, GcodePosition{20, 5, 0.002, 0, 0, 0}});
  GcodeRewriteSummary s;
  const std::string out = rewrite_gcode(text, "a.nc", xyz(), moves, {}, &s);
  // X gets 6 decimals (rounded), Y keeps its text, Z is added after the last axis word; the
  // second line needs no word (Z holds 0.002 already, X is 20 as written).
  EXPECT_EQ(
      out, "%\r\n(header)\r\nN10 G90 G21 G1 X10.001235  Y5 Z0.002 F300 (move)\r\nN20 x20 ; lower case\r\nM30\r\n%\r\n");
  EXPECT_EQ(s.lines_in, 6u);
  EXPECT_EQ(s.lines_changed, 1u);
  EXPECT_EQ(s.lines_added, 0u);
}

TEST(GcodeRewrite, InchesAndIncrementsAreWrittenInTheLinesOwnMode) {
  // G20: 25.4 mm per inch; G91: increments from the position written before.
  const std::string text = "G20 G90 G1 X1 F10\nG91 X1\nX1\n";
  const auto p = parse_gcode(text, "b.nc", xyz());
  // Ends (mm): 25.4 + 0.00254, 50.8 - 0.00127, 76.2 (uncorrected).
  auto moves = single(p, {GcodePosition{25.40254, 0, 0, 0, 0, 0}, GcodePosition{50.79873, 0, 0, 0, 0, 0},
                          GcodePosition{76.2, 0, 0, 0, 0, 0}});
  const std::string out = rewrite_gcode(text, "b.nc", xyz(), moves);
  // Inch values get 7 decimals: 1.0001 in; the increment 50.79873 - 25.40254 = 25.39619 mm =
  // 0.99985 in; then 76.2 - 50.79873 = 25.40127 mm = 1.00005 in.
  EXPECT_EQ(out, "G20 G90 G1 X1.0001 F10\nG91 X0.99985\nX1.00005\n");
  const auto back = parse_gcode(out, "b2.nc", xyz());
  for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(back.moves[i].end[0], moves[i].pieces[0].end[0], 1e-9);
}

TEST(GcodeRewrite, PiecesBecomeLinesAndArcWordsFollowTheFirstPiece) {
  const std::string text = "G17 G1 X10 Y0 F100\nN5 G3 X0 Y10 I-10 J0 (quarter)\nX-10 Y0 R10\n";
  const auto p = parse_gcode(text, "c.nc", xyz());
  ASSERT_EQ(p.moves.size(), 3u);
  std::vector<CorrectedMove> moves = single(p, {p.moves[0].end, p.moves[1].end, p.moves[2].end});
  // Move 2: a reversal move, then the arc in two halves (centre moved by 0.001 in X).
  CorrectedMove& m = moves[1];
  m.pieces.clear();
  CorrectedPiece t;
  t.motion = GcodeMotion::Linear;
  t.end = {10.002, 0, 0, 0, 0, 0};
  t.transition = true;
  m.pieces.push_back(t);
  const double h = std::sqrt(0.5) * 10;
  CorrectedPiece a;
  a.motion = GcodeMotion::ArcCCW;
  a.centre = {0.002, 0, 0};
  a.end = {0.002 + h, h, 0, 0, 0, 0};
  a.sweep = std::numbers::pi / 4;
  CorrectedPiece b = a;
  b.end = {0.002, 10.0, 0, 0, 0, 0};
  m.pieces.push_back(a);
  m.pieces.push_back(b);
  GcodeRewriteSummary s;
  const std::string out = rewrite_gcode(text, "c.nc", xyz(), moves, {}, &s);
  // Line 2 carries the straight reversal move (G3 -> G1, I J gone); the halves follow with their
  // centre offsets from their written starts. Line 3 relies on G3 being modal, which the last
  // added line leaves in effect: nothing is added.
  EXPECT_EQ(out,
            "G17 G1 X10 Y0 F100\n"
            "N5 G1 X10.002 Y0.0 (quarter)\n"
            "G3 X7.073068 Y7.071068 I-10.0 J0.0\n"
            "G3 X0.002 Y10.0 I-7.071068 J-7.071068\n"
            "X-10 Y0 R10\n");
  EXPECT_EQ(s.lines_added, 2u);
  const auto back = parse_gcode(out, "c2.nc", xyz());
  ASSERT_EQ(back.moves.size(), 5u);
  EXPECT_NEAR(back.moves[2].centre[0], 0.002, 1e-6);
  EXPECT_NEAR(back.moves[3].centre[0], 0.002, 1e-6);
  EXPECT_NEAR(back.moves[3].sweep, std::numbers::pi / 4, 1e-6);
}

TEST(GcodeRewrite, BadInput) {
  const std::string text = "G1 X1 F1\n";
  const auto p = parse_gcode(text, "d.nc", xyz());
  const auto moves = single(p, {p.moves[0].end});
  GcodeRewriteOptions ro;
  ro.decimals = 13;
  EXPECT_THROW(rewrite_gcode(text, "d.nc", xyz(), moves, ro), InputError);
  EXPECT_THROW(rewrite_gcode(text + "G1 X2\n", "d.nc", xyz(), moves), Error);   // a move left uncorrected
  EXPECT_THROW(rewrite_gcode("G1 X1 #3\n", "d.nc", xyz(), moves), InputError);  // the reader's own errors
}
