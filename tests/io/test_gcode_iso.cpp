// mtcal's G-code reader in the ISO dialect: canned cycles expanded (hand-computed from the LinuxCNC G-code reference's
// motion lists, the same lists its interpreter rs274 prints), work offsets, tool lengths, G28/G30, inches, O numbers,
// the M/S/T words kept, warnings and refusals; the tool table and parameter file readers; the expanded writer.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/gcode/rewrite.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

constexpr double gcode_iso_kTol = 1e-12;

GcodeProgram gcode_iso_parse(const std::string& text, GcodeSetup setup = {}, const std::string& axes = "XYZABC") {
  GcodeOptions o;
  o.axes = axes;
  o.setup = std::move(setup);
  return parse_gcode(text, "t.nc", o);
}

// One expected move: rapid or feed, to X Y Z.
struct Step {
  char kind;  // 'r' rapid, 'f' feed
  double x, y, z;
};

void expect_steps(const GcodeProgram& p, std::size_t first, const std::vector<Step>& steps) {
  ASSERT_GE(p.moves.size(), first + steps.size());
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const GcodeMove& m = p.moves[first + k];
    SCOPED_TRACE(::testing::Message() << "move " << first + k << " (line " << m.line << ")");
    EXPECT_EQ(m.motion, steps[k].kind == 'r' ? GcodeMotion::Rapid : GcodeMotion::Linear);
    EXPECT_NEAR(m.end[0], steps[k].x, 1e-9);
    EXPECT_NEAR(m.end[1], steps[k].y, 1e-9);
    EXPECT_NEAR(m.end[2], steps[k].z, 1e-9);
    if (first + k > 0) {
      EXPECT_EQ(m.start, p.moves[first + k - 1].end);  // moves chain
    }
  }
}

template <class E>
std::string gcode_iso_error_of(const std::string& text, GcodeSetup setup = {}) {
  try {
    gcode_iso_parse(text, std::move(setup));
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "no error";
}

}  // namespace

// G81 from Z10 to holes at (1,2) and (5,2): R2, bottom -3. G99 goes back to R between holes;
// G98 to the level the series of cycles began at (10). LinuxCNC G-code reference, G81 and G98/G99.
TEST(GcodeIso, G81WithG99ThenG98) {
  const auto p = gcode_iso_parse("G21 G90 F100\nG0 X0 Y0 Z10\nG99 G81 X1 Y2 Z-3 R2\nX5\nG98 X1\nG80\nM2\n");
  expect_steps(p, 0,
               {{'r', 0, 0, 10},
                {'r', 1, 2, 10},  // over the hole at the present level
                {'r', 1, 2, 2},   // R
                {'f', 1, 2, -3},  // drill
                {'r', 1, 2, 2},   // G99: back to R
                {'r', 5, 2, 2},   // next hole at R
                {'f', 5, 2, -3},
                {'r', 5, 2, 2},
                {'r', 1, 2, 2},
                {'f', 1, 2, -3},
                {'r', 1, 2, 10}});  // G98: the level before the series
  EXPECT_EQ(p.moves.size(), 11u);
  EXPECT_EQ(p.counts.cycles, 3u);
  EXPECT_EQ(p.counts.expanded_blocks, 3u);
  EXPECT_EQ(p.moves[3].line, 3);
  EXPECT_EQ(p.moves[3].part, 2);
  EXPECT_EQ(p.moves[3].feed, 100.0);
}

// Below R at the start: first up to R (LinuxCNC: "if the current Z is below R, Z moves to R"),
// and G98 then returns to R, not to the lower start level.
TEST(GcodeIso, CycleStartingBelowR) {
  const auto p = gcode_iso_parse("G0 X0 Y0 Z1\nG98 G81 X1 Y2 Z-3 R2 F50\nG80\n");
  expect_steps(p, 1, {{'r', 0, 0, 2}, {'r', 1, 2, 2}, {'f', 1, 2, -3}, {'r', 1, 2, 2}});
  EXPECT_EQ(p.moves.size(), 5u);
}

// G83 peck drilling, Q2 from R2 to -3: pecks to 0, -2, -3; after each peck out to R, then back
// down to 0.254 mm above the last bottom. G73: back off 0.254 mm only.
TEST(GcodeIso, G83AndG73Pecks) {
  const auto p = gcode_iso_parse("G21 F100\nG0 X0 Y0 Z10\nG98 G83 X1 Y2 Z-3 R2 Q2\nG73 X4\nG80\n");
  expect_steps(p, 1,
               {{'r', 1, 2, 10},
                {'r', 1, 2, 2},
                {'f', 1, 2, 0},
                {'r', 1, 2, 2},
                {'r', 1, 2, 0.254},
                {'f', 1, 2, -2},
                {'r', 1, 2, 2},
                {'r', 1, 2, -1.746},
                {'f', 1, 2, -3},
                {'r', 1, 2, 10},
                // G73 (same series: R, depth and Q kept): over (4,2), down to R, chip breaking.
                {'r', 4, 2, 10},
                {'r', 4, 2, 2},
                {'f', 4, 2, 0},
                {'r', 4, 2, 0.254},
                {'f', 4, 2, -2},
                {'r', 4, 2, -1.746},
                {'f', 4, 2, -3},
                {'r', 4, 2, 10}});
  EXPECT_EQ(p.moves.size(), 19u);
}

// G91 with L3: X10 steps repeated, R-8 from the level 10 (R at 2), Z-5 from R (bottom -3).
TEST(GcodeIso, IncrementalCycleWithRepeats) {
  const auto p = gcode_iso_parse("G0 X0 Y0 Z10\nG91 G98 G81 X10 Z-5 R-8 L3 F100\nG90 G80\n");
  expect_steps(p, 1,
               {{'r', 10, 0, 10},
                {'r', 10, 0, 2},
                {'f', 10, 0, -3},
                {'r', 10, 0, 10},
                {'r', 20, 0, 10},
                {'r', 20, 0, 2},
                {'f', 20, 0, -3},
                {'r', 20, 0, 10},
                {'r', 30, 0, 10},
                {'r', 30, 0, 2},
                {'f', 30, 0, -3},
                {'r', 30, 0, 10}});
  EXPECT_EQ(p.counts.cycles, 3u);
}

// The retracts of the other cycles (LinuxCNC G-code reference): G82 dwell then rapid, G84 feed
// out to the clearance, G85 feed to R then rapid, G86 rapid, G89 feed out.
TEST(GcodeIso, CycleRetracts) {
  const std::string start = "G0 X0 Y0 Z10\nG98 ";
  EXPECT_EQ(gcode_iso_parse(start + "G82 X1 Y2 Z-3 R2 P1.5 F100\n").moves.back().motion, GcodeMotion::Rapid);
  const auto g84 = gcode_iso_parse(start + "G84 X1 Y2 Z-3 R2 F100\n");
  expect_steps(g84, 1, {{'r', 1, 2, 10}, {'r', 1, 2, 2}, {'f', 1, 2, -3}, {'f', 1, 2, 10}});
  const auto g85 = gcode_iso_parse(start + "G85 X1 Y2 Z-3 R2 F100\n");
  expect_steps(g85, 3, {{'f', 1, 2, -3}, {'f', 1, 2, 2}, {'r', 1, 2, 10}});
  const auto g86 = gcode_iso_parse(start + "G86 X1 Y2 Z-3 R2 P1 F100\n");
  expect_steps(g86, 3, {{'f', 1, 2, -3}, {'r', 1, 2, 10}});
  const auto g89 = gcode_iso_parse(start + "G89 X1 Y2 Z-3 R2 P2 F100\n");
  expect_steps(g89, 3, {{'f', 1, 2, -3}, {'f', 1, 2, 10}});
  // G88: the operator retracts by hand; the path stays at the bottom, with a warning.
  const auto g88 = gcode_iso_parse(start + "G88 X1 Y2 Z-3 R2 P1 F100\n");
  EXPECT_EQ(g88.moves.size(), 4u);
  EXPECT_NEAR(g88.moves.back().end[2], -3, gcode_iso_kTol);
  ASSERT_EQ(g88.warnings.size(), 1u);
  EXPECT_NE(g88.warnings[0].find("by hand"), std::string::npos) << g88.warnings[0];
}

// G18: the drilling axis is Y, the hole's position X and Z.
TEST(GcodeIso, CycleInG18DrillsAlongY) {
  const auto p = gcode_iso_parse("G18 G0 X0 Y10 Z0\nG99 G81 X5 Z7 Y-4 R1 F80\n");
  expect_steps(p, 1, {{'r', 5, 10, 7}, {'r', 5, 1, 7}, {'f', 5, -4, 7}, {'r', 5, 1, 7}});
}

TEST(GcodeIso, CycleErrors) {
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG81 X1 Y1 Z-3\n").find("without R"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG81 X1 Y1 R2\n").find("without Z"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG83 X1 Z-3 R2\n").find("peck Q > 0"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG81 X1 Z5 R2\n").find("lies above R"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG81 X1 Z-3 R2 A5\n").find("rotary axis word 'A'"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG87 X1 Z-3 R2\n").find("G87"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG81 X1 Z-3 R2 L1.5\n").find("repeats"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG91 G81 X1 Z-3 R2 L10001\n").find("repeats from 0 to 10000"),
            std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G0 Z10\nG83 X1 Z-300 R2 Q0.01\n").find("more than 10000 pecks"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G80 X1\n").find("G80"), std::string::npos);
  // Each bound alone (10000 repeats, 10000 pecks a hole) let one block expand into 10^8 pecks,
  // gigabytes of moves (fuzz_gcode, out of memory): the pecks of a block are bounded in all, and
  // the message points at L.
  const std::string many = gcode_iso_error_of<InputError>("G0 Z10\nG91 G73 X1 Z-2000 R2 Q0.25 L20\n");
  EXPECT_NE(many.find("column 28: G73: L 20 holes of 8000 pecks each give more than 100000 pecks in one block"),
            std::string::npos)
      << many;
}

// G54-G59.3 from the setup, G10 L2, G53, and G43 H from a tool table: moves in the frame of the
// setup (program + work offset + tool length).
TEST(GcodeIso, WorkOffsetsAndToolLength) {
  GcodeSetup setup;
  setup.work_offsets[1] = {100, 50, -200, 0, 0, 0};  // G55
  setup.work_offsets[8] = {1, 2, 3, 0, 0, 0};        // G59.3
  setup.tools = parse_tool_table("T1 P1 Z50.5 D6 ;end mill\nT2 P2 Z-10\n", "tools.tbl");
  setup.has_tool_table = true;
  const auto p = gcode_iso_parse(
      "G0 X1 Y1 Z1\n"        // G54 (all 0)
      "G55 X1 Y1 Z1\n"       // 100 + 1, 50 + 1, -200 + 1
      "T1 M6\nG43 H1 Z1\n"   // Z: -200 + 50.5 + 1
      "G59.3 X0 Y0\n"        // 1, 2; Z keeps its machine position
      "G43 H2 Z0\n"          // 3 - 10
      "G49 Z0\n"             // 3
      "G10 L2 P9 X10\nX0\n"  // G59.3's X is now 10
      "G53 G0 X-5 Y-6\n"     // machine frame, no offsets
      "G54 G1 X0 Y0 F100\n",
      setup);
  ASSERT_EQ(p.moves.size(), 9u);
  expect_steps(p, 0,
               {{'r', 1, 1, 1},
                {'r', 101, 51, -199},
                {'r', 101, 51, -148.5},
                {'r', 1, 2, -148.5},
                {'r', 1, 2, -7},
                {'r', 1, 2, 3},
                {'r', 10, 2, 3},
                {'r', -5, -6, 3},
                {'f', 0, 0, 3}});
  EXPECT_EQ(p.moves[2].tool, 1);
  EXPECT_EQ(p.counts.tool_changes, 1u);
  EXPECT_EQ(p.counts.offset_blocks, 7u);  // every move but the first and the G53 and G54 ones
  EXPECT_NE(gcode_iso_error_of<InputError>("G43 H3 Z0\n", setup).find("tool 3, which the tool table has not"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G43 H3 Z0\n").find("expected a tool table"), std::string::npos);
}

// G28/G30: by way of the point the axis words give (in the work coordinates), then the named axes
// to the stored position; no axis words: all axes. G28.1 stores the present position.
TEST(GcodeIso, G28AndG30) {
  GcodeSetup setup;
  setup.g28 = {-10, -20, 0, 0, 0, 0};
  setup.g30 = {5, 5, 5, 0, 0, 0};
  const auto p = gcode_iso_parse("G0 X1 Y2 Z3\nG91 G28 Z2\nG90 G28\nG0 X7 Y7 Z7\nG30.1\nG0 X0\nG30 X1\n", setup);
  expect_steps(p, 1,
               {{'r', 1, 2, 5},      // G91: Z2 is a step, the intermediate point
                {'r', 1, 2, 0},      // Z only to the stored 0
                {'r', -10, -20, 0},  // all axes
                {'r', 7, 7, 7},
                {'r', 0, 7, 7},
                {'r', 1, 7, 7},    // intermediate X1
                {'r', 7, 7, 7}});  // X to the position G30.1 stored (7)
  EXPECT_EQ(p.moves.size(), 8u);
}

// G20: lengths in inches, 25.4 mm each (cycle R, depth and Q too); A B C stay degrees.
TEST(GcodeIso, InchesInMovesAndCycles) {
  const auto p = gcode_iso_parse("G20 G0 X1 Y0 Z1 A10\nG99 G83 X2 Z-0.5 R0.1 Q0.4 F10\n");
  EXPECT_NEAR(p.moves[0].end[0], 25.4, gcode_iso_kTol);
  EXPECT_NEAR(p.moves[0].end[3], 10, gcode_iso_kTol);
  expect_steps(p, 1,
               {{'r', 50.8, 0, 25.4},
                {'r', 50.8, 0, 2.54},
                {'f', 50.8, 0, 2.54 - 10.16},
                {'r', 50.8, 0, 2.54},
                {'r', 50.8, 0, 2.54 - 10.16 + 0.254},
                {'f', 50.8, 0, -12.7},
                {'r', 50.8, 0, 2.54}});
  EXPECT_NEAR(p.moves[1].feed, 254, gcode_iso_kTol);
}

// O numbers (ISO 6983-1 program numbers) and ':' open a program; M S T kept and counted.
TEST(GcodeIso, ProgramNumbersAndWordsKept) {
  const auto p = gcode_iso_parse(":100\nO1234 (part)\nN5 T3 M6\nS1200 M3 M8\nG1 X1 F100\nM30\n");
  ASSERT_EQ(p.moves.size(), 1u);
  EXPECT_EQ(p.moves[0].tool, 3);
  EXPECT_EQ(p.moves[0].spindle, 1200);
  EXPECT_EQ(p.counts.m_words, 4u);
  EXPECT_EQ(p.counts.s_words, 1u);
  EXPECT_EQ(p.counts.t_words, 1u);
  EXPECT_EQ(p.counts.tool_changes, 1u);
  EXPECT_TRUE(p.warnings.empty());
  EXPECT_NE(gcode_iso_error_of<InputError>("G1 X1 O5\n").find("must open its line"), std::string::npos);
}

// What is read but not simulated: a warning naming file, line, column and word, never silence.
TEST(GcodeIso, WarningsNameFileLineAndWord) {
  const auto p = gcode_iso_parse("G64 P0.01\nG1 X1 E5 F100\nG17.1\nG93\n/G1 X9\nG1 X2 L3\nM2\nG1 X50\nG1 X60\n");
  ASSERT_EQ(p.warnings.size(), 7u);
  EXPECT_EQ(p.counts.warnings, 7u);
  EXPECT_EQ(p.warnings[0],
            "t.nc:1: column 5: 'G64 P0.01' (path blending tolerance) is not simulated: the programmed "
            "path is evaluated");
  EXPECT_NE(p.warnings[1].find("t.nc:2: column 7: 'E5'"), std::string::npos) << p.warnings[1];
  EXPECT_NE(p.warnings[2].find("t.nc:3: column 1: G17.1 is not known"), std::string::npos) << p.warnings[2];
  EXPECT_NE(p.warnings[3].find("t.nc:4: column 1: G93"), std::string::npos) << p.warnings[3];
  EXPECT_NE(p.warnings[4].find("t.nc:5: column 1: '/' block delete"), std::string::npos) << p.warnings[4];
  EXPECT_NE(p.warnings[5].find("t.nc:6: column 7: 'L3' has no meaning"), std::string::npos) << p.warnings[5];
  EXPECT_NE(p.warnings[6].find("t.nc:8: column 1: 'G' after the program's end (M2/M30 at line 7)"), std::string::npos)
      << p.warnings[6];
  ASSERT_EQ(p.moves.size(), 2u);  // the lines after M2 are not run
  EXPECT_NEAR(p.moves.back().end[0], 2, gcode_iso_kTol);
}

// Programs only LinuxCNC's interpreter reads, and lathe programs: typed errors naming line and column.
TEST(GcodeIso, NeedsInterpreterOrLathe) {
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("G0 X1\n#1 = 5\n").find("t.nc:2: column 1: '#' parameter"),
            std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("G0 X[1+2]\n").find("column 5: 'X' computed by a '[' expression"),
            std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("G0 X#1\n").find("computed by a '#' parameter"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("o100 sub\n").find("O-word 'sub'"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("O<probe> call\n").find("named O-word"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("G41 D3\n").find("cutter radius compensation"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeNeedsInterpreter>("G92 X0\n").find("coordinate system offset"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<GcodeLatheProgram>("G18 G7\n").find("column 5: G7 (diameter or radius mode): a lathe program"),
            std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G38.2 Z-5 F10\n").find("probing"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("M98 P100\n").find("M98"), std::string::npos);
  EXPECT_NE(gcode_iso_error_of<InputError>("G1 U5\n").find("axis word 'U'"), std::string::npos);
  EXPECT_FALSE(gcode_needs_interpreter("G0 X1\nG1 Y2\n", "t.nc"));
  const auto need = gcode_needs_interpreter("G0 X1\n#<depth> = 2\n", "t.nc");
  ASSERT_TRUE(need);
  EXPECT_EQ(need->where().line, 2);
}

TEST(GcodeIso, LatheScanOfAnyProgram) {
  EXPECT_NO_THROW(refuse_lathe_program("G17 G0 X1 (G7 in a comment) ; G96\nG70.5\n", "t.ngc"));
  try {
    refuse_lathe_program("o100 sub\n  G96 S200 (css)\n", "t.ngc");
    FAIL() << "no error";
  } catch (const GcodeLatheProgram& e) {
    EXPECT_NE(std::string(e.what()).find("t.ngc:2: column 3: G96 (constant surface speed)"), std::string::npos)
        << e.what();
  }
}

// The LinuxCNC tool table format (LinuxCNC documentation, "Tool Table Format").
TEST(GcodeIso, ToolTable) {
  const auto t =
      parse_tool_table("T1 P1 D0.125 Z+0.511 ;1/8 end mill\n\n; comment only\nT99999 P123 Z+0.1\n", "tool.tbl", 25.4);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t.at(1).offset[2], 0.511 * 25.4, gcode_iso_kTol);
  EXPECT_NEAR(t.at(1).diameter, 0.125 * 25.4, gcode_iso_kTol);
  EXPECT_NEAR(t.at(99999).offset[2], 2.54, gcode_iso_kTol);
  auto bad = [](const std::string& text) {
    try {
      parse_tool_table(text, "tool.tbl");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(bad("T1 P1 Zabc\n").find("tool.tbl:1: column 7: expected a number after 'Z', found 'abc'"),
            std::string::npos);
  EXPECT_NE(bad("P1 Z5\n").find("tool.tbl:1: expected the tool's number"), std::string::npos);
  EXPECT_NE(bad("T1 Z1\nT1 Z2\n").find("tool.tbl:2: tool 1 listed twice (first at line 1)"), std::string::npos);
  EXPECT_NE(bad("T1 K5\n").find("expected a tool table word"), std::string::npos);
  EXPECT_NE(bad("T-1 Z5\n").find("whole tool number"), std::string::npos);
}

// A LinuxCNC parameter file: G28 (5161-), G30 (5181-), system in effect (5220), offsets (5221-, 20 apart).
TEST(GcodeIso, ParameterFile) {
  GcodeSetup s;
  parse_parameter_file("5161 1.0\n5163\t-2\n5181 3\n5220 2.000000\n5221 10\n5242 20\n5383 7\n5400 99\n", "p.var", s);
  EXPECT_EQ(s.g28, (GcodePosition{1, 0, -2, 0, 0, 0}));
  EXPECT_EQ(s.g30[0], 3);
  EXPECT_EQ(s.work_system, 1);
  EXPECT_EQ(s.work_offsets[0][0], 10);
  EXPECT_EQ(s.work_offsets[1][1], 20);
  EXPECT_EQ(s.work_offsets[8][2], 7);
  auto bad = [](const std::string& text) {
    GcodeSetup t;
    try {
      parse_parameter_file(text, "p.var", t);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(bad("5221\n").find("p.var:1: expected a parameter's number and value"), std::string::npos);
  EXPECT_NE(bad("5221 x\n").find("p.var:1:"), std::string::npos);
  EXPECT_NE(bad("\n5220 12\n").find("p.var:2: parameter 5220"), std::string::npos);
  EXPECT_NE(bad("1.5 3\n").find("expected a parameter's number"), std::string::npos);
}

// The expanded writer, read back by the reader: the same moves (positions, arcs, feeds), whatever
// the original's offsets, cycles and units.
TEST(GcodeIso, ExpandedProgramReadsBackAsTheSameMoves) {
  GcodeSetup setup;
  setup.work_offsets[1] = {100, 50, -200, 0, 0, 0};
  const auto p = gcode_iso_parse(
      "G20 G55 G0 X0 Y0 Z1\nG99 G83 X1 Y1 Z-0.5 R0.1 Q0.2 F10\nG80\nG18 G2 X1.5 Z0.1 I0.25 K-0.5\nG17 G3 X1 Y1 R0.5\n",
      setup);
  std::vector<CorrectedMove> moves;
  for (const auto& m : p.moves) {
    CorrectedMove c;
    c.line = m.line;
    c.motion = m.motion;
    CorrectedPiece piece;
    piece.motion = m.motion;
    piece.end = m.end;
    piece.centre = m.centre;
    piece.sweep = m.sweep;
    c.pieces.push_back(piece);
    moves.push_back(c);
  }
  const std::string text = write_expanded_gcode(moves, p, "XYZ", "test", {10});
  GcodeOptions o;
  o.axes = "XYZ";
  o.start = p.moves.front().start;
  const auto back = parse_gcode(text, "expanded.nc", o);
  ASSERT_EQ(back.moves.size(), p.moves.size()) << text;
  for (std::size_t k = 0; k < p.moves.size(); ++k) {
    SCOPED_TRACE(::testing::Message() << "move " << k);
    EXPECT_EQ(back.moves[k].motion, p.moves[k].motion);
    for (std::size_t s = 0; s < 3; ++s) EXPECT_NEAR(back.moves[k].end[s], p.moves[k].end[s], 1e-9);
    EXPECT_NEAR(back.moves[k].sweep, p.moves[k].sweep, 1e-9);
    if (p.moves[k].motion != GcodeMotion::Rapid) {
      EXPECT_NEAR(back.moves[k].feed, p.moves[k].feed, 1e-3);
    }
  }
  EXPECT_EQ(back.counts.offset_blocks, 0u);
  EXPECT_EQ(back.counts.expanded_blocks, 0u);
}
