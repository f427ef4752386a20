// Reading LinuxCNC's canonical calls (the print format of src/emc/sai/saicanon.cc, as rs274 -g prints them) and the
// numbered copy of a program that gives moves their lines; bad input of every kind. The interpreter itself is run by
// the linuxcnc ctest label (tests/linuxcnc/); here only where installed, to show that runs at once keep their own
// tool tables.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <unistd.h>

#include "mtcal/io/gcode/rs274.hpp"
#include "mtcal/io/system/process.hpp"
#include "mtcal/util/errors.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kPi;

std::string rs274_error_of(const std::string& calls, const std::string& axes = "XYZABC") {
  GcodeOptions o;
  o.axes = axes;
  try {
    parse_canon(calls, "p.ngc", o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

// Lines as rs274 -g printed them for a program (copied from its output: units, offsets, arcs).
TEST(Rs274, CanonicalCallsToMoves) {
  const std::string calls =
      "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n"
      "    2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "    3 N..... SET_G92_OFFSET(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "    4 N..... SET_XY_ROTATION(0.0000)\n"
      "    5 N2     STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n"
      "    6 N3     SET_FEED_RATE(100.0000)\n"
      "    7 N3     STRAIGHT_FEED(10.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n"
      "    8 N4     ARC_FEED(20.0000, 2.0000, 15.0000, 2.0000, -1, 3.0000, 0.0000, 0.0000, 0.0000)\n"
      "    9 N5     SET_G5X_OFFSET(2, 100.0000, 50.0000, 10.0000, 0.0000, 0.0000, 0.0000)\n"
      "   10 N6     USE_TOOL_LENGTH_OFFSET(0.0000 0.0000 12.9794, 0.0000 0.0000 0.0000, 0.0000 0.0000 0.0000)\n"
      "   11 N6     CHANGE_TOOL(1)\n"
      "   12 N7     STRAIGHT_TRAVERSE(1.0000, 1.0000, 1.0000, 0.0000, 0.0000, 0.0000)\n"
      "   13 N8     USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"
      "   14 N9     SELECT_PLANE(CANON_PLANE_XZ)\n"
      "   15 N9     STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "   16 N9     ARC_FEED(0.0000, -1.0000, 0.0000, 0.0000, 2, 0.0000, 0.0000, 0.0000, 0.0000)\n"
      "   16 N10    COMMENT(\"interpreter: a comment, (with parentheses)\")\n"
      "   17 N..... PROGRAM_END()\n";
  const auto p = parse_canon(calls, "p.ngc");
  EXPECT_EQ(p.interpreter, "rs274");
  ASSERT_EQ(p.moves.size(), 6u);
  EXPECT_EQ(p.moves[0].motion, GcodeMotion::Rapid);
  EXPECT_EQ(p.moves[0].line, 2);
  EXPECT_EQ(p.moves[0].end, (GcodePosition{1, 2, 3, 0, 0, 0}));
  EXPECT_EQ(p.moves[1].feed, 100.0);
  // ARC_FEED rotation -1: clockwise, half a turn about (15, 2) from (10, 2) to (20, 2).
  EXPECT_EQ(p.moves[2].motion, GcodeMotion::ArcCW);
  EXPECT_NEAR(p.moves[2].sweep, -kPi, 1e-12);
  EXPECT_NEAR(p.moves[2].centre[0], 15, 1e-12);
  // Machine frame: program + G5X offset + tool length.
  EXPECT_EQ(p.moves[3].line, 7);
  EXPECT_NEAR(p.moves[3].end[0], 101, 1e-9);
  EXPECT_NEAR(p.moves[3].end[1], 51, 1e-9);
  EXPECT_NEAR(p.moves[3].end[2], 1 + 10 + 12.9794, 1e-9);
  EXPECT_EQ(p.moves[3].tool, 1);
  // Inches from call 13 on (the offsets were read in mm and stay so): X1 in is 25.4 mm + 100.
  EXPECT_NEAR(p.moves[4].end[0], 125.4, 1e-9);
  // XZ plane: first Z, second X; rotation 2: counter-clockwise, one full turn more than the half
  // turn from X +1 in to X -1 in about the program's zero.
  const GcodeMove& a = p.moves[5];
  EXPECT_EQ(a.plane, GcodePlane::ZX);
  EXPECT_EQ(a.motion, GcodeMotion::ArcCCW);
  EXPECT_NEAR(a.end[0], -25.4 + 100, 1e-9);
  EXPECT_NEAR(a.end[2], 0 + 10 + 12.9794, 1e-9);
  EXPECT_NEAR(a.centre[0], 100, 1e-9);
  EXPECT_NEAR(a.centre[2], 10 + 12.9794, 1e-9);
  EXPECT_NEAR(a.sweep, 3 * kPi, 1e-12);
  EXPECT_EQ(p.counts.tool_changes, 1u);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(Rs274, ZeroRadiusHelixIsAStraightFeed) {
  const auto p =
      parse_canon("1 N27 ARC_FEED(0.0000, 0.0000, 0.0000, 0.0000, 1, -0.5000, 0.0000, 0.0000, 0.0000)\n", "p.ngc");
  ASSERT_EQ(p.moves.size(), 1u);
  EXPECT_EQ(p.moves[0].motion, GcodeMotion::Linear);
  EXPECT_EQ(p.moves[0].end[2], -0.5);
}

TEST(Rs274, RefusalsAndBadInput) {
  EXPECT_NE(rs274_error_of("   29 N35    STRAIGHT_PROBE(0.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)\n")
                .find("p.ngc:35: (call 1 of LinuxCNC's interpreter) STRAIGHT_PROBE: probing"),
            std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 START_SPEED_FEED_SYNC(0.050000,0)\n").find("synchronised with the spindle"),
            std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 NURBS_FEED(3, ...)\n").find("spline"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 SET_XY_ROTATION(30.0000)\n").find("rotated"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 STRAIGHT_FEED(1.0000, 2.0000)\n").find("with 2 arguments (expected 6 or 9)"),
            std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 STRAIGHT_FEED(1.0000, x, 0, 0, 0, 0)\n").find("argument 2 of STRAIGHT_FEED, found 'x'"),
            std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 STRAIGHT_FEED(0, 0, 0, 0, 0, 0, 1, 0, 0)\n").find("U, V or W"), std::string::npos);
  EXPECT_NE(
      rs274_error_of("1 N1 STRAIGHT_FEED(0, 0, 0, 0, 5, 0)\n", "XYZ").find("moves B, an axis this machine does not have"),
      std::string::npos);
  EXPECT_NE(rs274_error_of("STRAIGHT_FEED(0, 0, 0, 0, 0, 0)\n").find("expected a call's number"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 STRAIGHT_FEED(0, 0, 0, 0, 0, 0\n").find("NAME(arguments)"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 Nx STRAIGHT_FEED(0, 0, 0, 0, 0, 0)\n").find("after 'N'"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 USE_LENGTH_UNITS(CANON_UNITS_FURLONG)\n").find("CANON_UNITS_MM"), std::string::npos);
  EXPECT_NE(rs274_error_of("1 N1 ARC_FEED(1, 0, 0, 0, 0, 0, 0, 0, 0)\n").find("rotation 0"), std::string::npos);
  EXPECT_NE(
      rs274_error_of("1 N1 STRAIGHT_FEED(1, 0, 0, 0, 0, 0)\n2 N2 ARC_FEED(5, 0, 0, 0, 1, 0, 0, 0, 0)\n").find("end radius"),
      std::string::npos);
  // An unknown call that moves nothing: a warning naming it, not silence.
  const auto p = parse_canon("1 N4 SOMETHING_NEW(1)\n", "p.ngc");
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0], "p.ngc:4: canonical call SOMETHING_NEW is not known to mtcal and is skipped");
}

// Every line gets N<line> (an own N number replaced), after blanks and '/'; '%' lines kept.
TEST(Rs274, NumberedProgram) {
  EXPECT_EQ(number_gcode_lines("%\nG0 X1\n  /N0010 G1 X2\n\n(comment)\nn 5 o100 sub\n%"),
            "%\nN2 G0 X1\n  /N3  G1 X2\nN4 \nN5 (comment)\nN6  o100 sub\n%");
}

// LinuxCNC 2.9 keeps the loaded tool table in $HOME/.tool.mmap, shared by every interpreter of the user: a program
// interpreted while another run loads a table with tool 1 found that tool although its own table was empty
// (rough_edges_cli failed so in CI beside gcode_linuxcnc_examples). Reproduced here: another interpreter, with the
// test's HOME, loads tool 1 again and again while mtcal's run interprets a long program that ends in T1 M6.
TEST(Rs274, RunsAtOnceKeepTheirOwnToolTables) {
  const std::string exe = find_rs274();
  if (exe.empty()) GTEST_SKIP() << "LinuxCNC's rs274 is not installed (linuxcnc-uspace)";
  const auto sh = find_program({"sh"});
  ASSERT_TRUE(sh);
  const auto dir = std::filesystem::temp_directory_path() / fmt::format("mtcal-rs274-tools-{}", ::getpid());
  std::filesystem::create_directories(dir);
  const std::string home = std::getenv("HOME") != nullptr ? std::getenv("HOME") : dir.string();
  {
    std::ofstream(dir / "t1.tbl") << "T1 P1 Z1.5 D0.25\n";
    std::ofstream(dir / "other.ngc") << "G20\nM2\n";
    std::ofstream program(dir / "long.ngc");
    program << "G21 G90\n";
    for (int i = 0; i < 30000; ++i) program << "G1 X" << i % 100 << " F100\n";
    program << "T1 M6\nM2\n";
  }
  std::atomic<bool> done{false};
  int other_runs = 0;
  std::thread other([&] {
    while (!done) {
      run_program({*sh, "-c", "HOME=\"$0\" exec \"$1\" -g -t \"$2\" \"$3\"", home, exe, (dir / "t1.tbl").string(),
                   (dir / "other.ngc").string()},
                  20);
      ++other_runs;
    }
  });
  std::string error = "no error";
  try {
    run_rs274((dir / "long.ngc").string(), GcodeSetup{});
  } catch (const InputError& e) {
    error = e.what();
  }
  done = true;
  other.join();
  std::filesystem::remove_all(dir);
  EXPECT_GT(other_runs, 0);
  EXPECT_NE(error.find("Requested tool 1 not found in the tool table"), std::string::npos) << error;
}
