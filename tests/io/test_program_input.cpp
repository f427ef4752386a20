// A program opened with its setup (io/gcode/program_input.hpp): the setup's files and the work offsets given axis by
// axis over them, G28/G30, the interpreter chosen or refused. What `toolpath`, `compensate --gcode` and Python's
// toolpath / correct_gcode share.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "mtcal/io/gcode/program_input.hpp"
#include "mtcal/util/errors.hpp"
#include "temp_dir.hpp"

using namespace mtcal;

namespace {

std::string program_input_file(const mtcal::testing::TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = (dir.path / name).string();
  std::ofstream(path) << text;
  return path;
}

}  // namespace

TEST(ProgramInput, WorkSystemNames) {
  EXPECT_EQ(work_system_index("G54"), 0);
  EXPECT_EQ(work_system_index("G59"), 5);
  EXPECT_EQ(work_system_index("G59.3"), 8);
  EXPECT_FALSE(work_system_index("G60"));
  EXPECT_FALSE(work_system_index("g54"));
  EXPECT_EQ(parse_gcode_interpreter("rs274"), GcodeInterpreter::Rs274);
  try {
    parse_gcode_interpreter("fanuc", "--interpreter");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "--interpreter");
    EXPECT_NE(std::string(e.what()).find("expected auto, mtcal or rs274, found 'fanuc'"), std::string::npos);
  }
}

TEST(ProgramInput, WorkOffsetsGivenOverTheParameterFileAxisByAxis) {
  mtcal::testing::TempDir dir("mtcal-program-input");
  GcodeSetupInputs in;
  // LinuxCNC's numbers: G54 at 5221-5226, G55 at 5241..., G28 at 5161..., in inches here.
  in.parameters = program_input_file(dir, "p.var", "5161 1\n5163 -2\n5221 -6\n5222 -4\n5223 -18\n5241 1\n");
  in.parameter_scale = 25.4;
  WorkOffsetEntry g54;
  g54.system = 0;
  g54.values[2] = -450.0;  // Z only: X and Y stay the file's
  WorkOffsetEntry g56;
  g56.system = 2;
  g56.values[0] = 10.0;
  in.work_offsets = {g54, g56};
  const GcodeSetup s = make_gcode_setup(in);
  EXPECT_DOUBLE_EQ(s.work_offsets[0][0], -6 * 25.4);
  EXPECT_DOUBLE_EQ(s.work_offsets[0][1], -4 * 25.4);
  EXPECT_DOUBLE_EQ(s.work_offsets[0][2], -450.0);
  EXPECT_DOUBLE_EQ(s.work_offsets[1][0], 25.4);  // G55 from the file alone
  EXPECT_DOUBLE_EQ(s.work_offsets[2][0], 10.0);
  EXPECT_DOUBLE_EQ(s.work_offsets[2][1], 0.0);
  EXPECT_DOUBLE_EQ(s.g28[0], 25.4);
  EXPECT_DOUBLE_EQ(s.g28[2], -2 * 25.4);
  EXPECT_FALSE(s.has_tool_table);
  // G28 given: the whole position is the one given (axes not named 0), as --g28 "Z=-50".
  in.g28 = GcodePosition{0, 0, -50, 0, 0, 0};
  EXPECT_DOUBLE_EQ(make_gcode_setup(in).g28[0], 0.0);
  EXPECT_DOUBLE_EQ(make_gcode_setup(in).g28[2], -50.0);
  in.work_offsets = {WorkOffsetEntry{9, {}}};
  EXPECT_THROW(make_gcode_setup(in), InputError);
}

TEST(ProgramInput, ToolLengthsAndOffsetsReachTheMoves) {
  mtcal::testing::TempDir dir("mtcal-program-input");
  GcodeSetupInputs in;
  in.tool_table = program_input_file(dir, "t.tbl", "T1 P1 Z2.0 D0.25\n");
  in.tool_scale = 25.4;
  WorkOffsetEntry g54;
  g54.values = {100.0, -50.0, -300.0, std::nullopt, std::nullopt, std::nullopt};
  in.work_offsets = {g54};
  const std::string path = program_input_file(dir, "p.nc", "G21 G90 G54\nT1 M6\nG43 H1 G0 X1 Y2 Z3\nM30\n");
  const GcodeProgram p = read_gcode_program(path, "XYZ", in);
  ASSERT_EQ(p.moves.size(), 1u);
  EXPECT_EQ(p.interpreter, "mtcal");
  EXPECT_DOUBLE_EQ(p.moves[0].end[0], 101.0);
  EXPECT_DOUBLE_EQ(p.moves[0].end[1], -48.0);
  EXPECT_DOUBLE_EQ(p.moves[0].end[2], -300.0 + 3.0 + 2.0 * 25.4);  // work offset + programmed + tool length
}

TEST(ProgramInput, TheInterpreterChosenOrRefused) {
  mtcal::testing::TempDir dir("mtcal-program-input");
  const std::string plain = program_input_file(dir, "plain.nc", "G21 G90\nG1 X1 F100\nM30\n");
  const std::string needs = program_input_file(dir, "needs.ngc", "#1 = 5\nG21 G90 G1 X#1 F100\nM30\n");
  GcodeInputOptions o;
  o.rs274.executable = (dir.path / "no-such-rs274").string();
  // Not named: mtcal's reader reads a program it can; an interpreter named must exist all the same.
  EXPECT_EQ(open_gcode(plain, "XYZ", {}, o).interpreter, "mtcal");
  o.rs274_named = true;
  try {
    open_gcode(plain, "XYZ", {}, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "rs274");
    EXPECT_NE(std::string(e.what()).find("is not a program that can be run"), std::string::npos) << e.what();
  }
  // A program only LinuxCNC's interpreter reads, which is not there: the first such word and what to install.
  o.rs274_named = false;
  try {
    open_gcode(needs, "XYZ", {}, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, needs);
    EXPECT_EQ(e.where().line, 1);
    EXPECT_NE(std::string(e.what()).find("linuxcnc-uspace"), std::string::npos) << e.what();
  }
  // mtcal's reader asked for: its own refusal, located in the program.
  o.interpreter = GcodeInterpreter::Mtcal;
  EXPECT_THROW(read_gcode_program(needs, "XYZ", {}, o), GcodeNeedsInterpreter);
}
