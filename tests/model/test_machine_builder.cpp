// MachineBuilder and validate(): a machine built in code equals the machine file's, and every
// inconsistency is refused naming the item (in code) or the file, line and key (in the reader).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/model/machine_builder.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

constexpr double um = 1e-3, urad = 1e-6, per_m = 1e-3;  // to mm, rad; 1/m to 1/mm

Polynomial poly(double unit, std::array<double, 4> per_m_coefficients, double reversal = 0) {
  Polynomial p;
  for (std::size_t i = 0; i < 4; ++i) p.coefficients[i] = per_m_coefficients[i] * unit * std::pow(per_m, double(i));
  p.reversal = reversal * unit;
  return p;
}

// examples/machines/vmc-3axis.yaml, item by item.
Machine vmc_in_code() {
  MachineBuilder b;
  b.name("VMC 800 (example 3-axis vertical mill)").topology("wXYfZt");
  b.axis_travel('X', -400, 400).axis_travel('Y', -250, 250).axis_travel('Z', -500, 0);
  b.axis_point('Z', Vec3(0, 0, -250)).axis_kind('Z', AxisKind::Linear).axis_direction('Z', 2, +1);
  b.tool_length(100).tool_spindle_point(Vec3::Zero()).tool_axis(2).workpiece_origin(Vec3(0, 0, -450));
  b.motion("EXX", MotionFunction(poly(um, {0.5, 8.0, -12.0, 4.0}, 1.0)));
  b.motion("EYX", MotionFunction(poly(um, {0, 0, 15.0, 0})));
  b.motion("EZX", MotionFunction(poly(um, {0, 0, -20.0, 6.0})));
  b.motion("EAX", MotionFunction(poly(urad, {0, 6.0, 0, 0})));
  b.motion("EBX", MotionFunction(poly(urad, {0, -10.0, 18.0, 0})));
  b.motion("ECX", MotionFunction(poly(urad, {0, 7.5, 0, 0})));
  Table t;
  t.positions = {-250, -125, 0, 125, 250};
  for (double v : {-2.1, -0.9, 0.0, 1.4, 3.0}) t.forward.push_back(v * um);
  for (double v : {-1.5, -0.3, 0.6, 2.0, 3.5}) t.backward.push_back(v * um);
  b.motion("EYY", MotionFunction(t));
  b.motion("EXY", MotionFunction(poly(um, {0, 0, 24.0, 0})));
  b.motion("EZY", MotionFunction(poly(um, {0, 4.0, -16.0, 0})));
  b.motion("EAY", MotionFunction(poly(urad, {0, 12.0, -8.0, 0})));
  b.motion("EBY", MotionFunction(poly(urad, {0, -5.0, 0, 0})));
  b.motion("ECY", MotionFunction(poly(urad, {0, 9.0, 0, -30.0})));
  // Coefficients by parameter name too: EZZ = 12 um/m q + 5 um/m^2 q^2, reversal 0.8 um.
  b.parameter("EZZ.1", 12.0 * um * per_m).parameter("EZZ.2", 5.0 * um * per_m * per_m, "mm/mm^2");
  b.parameter("EZZ.b", 0.8, "um");
  b.motion("EXZ", MotionFunction(poly(um, {0, 0, 18.0, 0})));
  b.motion("EYZ", MotionFunction(poly(um, {0, 0, -14.0, 0})));
  b.motion("EAZ", MotionFunction(poly(urad, {0, 8.0, 0, 0})));
  b.motion("EBZ", MotionFunction(poly(urad, {0, -6.0, 10.0, 0})));
  b.motion("ECZ", MotionFunction(poly(urad, {0, 4.0, 0, 0})));
  b.parameter("EC0Y", 15, "um/m").error_value("EA0Z", -12 * urad).parameter("EB0Z", 20, "urad");
  return b.build();
}

// The ModelError message of f, or "" if none.
template <class F>
std::string model_error(F&& f) {
  try {
    f();
  } catch (const ModelError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no ModelError";
  return "";
}

MachineBuilder five_axis() {
  MachineBuilder b;
  b.topology("wCBXfYZt");
  return b;
}

}  // namespace

TEST(MachineBuilder, MachineInCodeEqualsMachineFile) {
  const Machine file = load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/vmc-3axis.yaml");
  const Machine code = vmc_in_code();
  ASSERT_EQ(code.parameter_count(), file.parameter_count());
  const auto pf = file.parameters(), pc = code.parameters();
  for (std::size_t i = 0; i < pf.size(); ++i) {
    EXPECT_EQ(pc[i].name, pf[i].name);
    EXPECT_NEAR(pc[i].value, pf[i].value, 1e-15 + 1e-12 * std::abs(pf[i].value)) << pf[i].name;
  }
  const ErrorModel mf(file), mc(code);
  for (const auto& q : {std::array<double, 3>{0, 0, 0}, {-350, 120, -40}, {300, -200, -480}, {17, 249, -250}}) {
    for (int di : {-1, 0, 1}) {
      const auto d = static_cast<std::int8_t>(di);
      const std::array<std::int8_t, 3> dir{d, d, d};
      const auto ef = mf.evaluate(q, dir), ec = mc.evaluate(q, dir);
      EXPECT_LT((ef.translation - ec.translation).norm(), 1e-12) << q[0] << " " << q[1] << " " << q[2];
      EXPECT_LT((ef.rotation - ec.rotation).norm(), 1e-15);
    }
  }
  EXPECT_NO_THROW(validate(file));
}

TEST(MachineBuilder, TopologyWithUnknownLetter) {
  const auto msg = model_error([] { MachineBuilder().topology("wXQfZt"); });
  EXPECT_NE(msg.find("topology 'wXQfZt': unknown character 'Q'"), std::string::npos) << msg;
}

TEST(MachineBuilder, TopologyWithTwoFrames) {
  const auto msg = model_error([] { MachineBuilder().topology("wXfYfZt"); });
  EXPECT_NE(msg.find("more than one 'f'"), std::string::npos) << msg;
}

TEST(MachineBuilder, TopologyWithRepeatedAxis) {
  const auto msg = model_error([] { MachineBuilder().topology("wXXfZt"); });
  EXPECT_NE(msg.find("axis 'X' appears twice"), std::string::npos) << msg;
}

TEST(MachineBuilder, TopologyWithoutWorkpieceOrTool) {
  const auto msg = model_error([] { MachineBuilder().topology("XfZt"); });
  EXPECT_NE(msg.find("must start with 'w' and end with 't'"), std::string::npos) << msg;
}

TEST(MachineBuilder, NoTopology) {
  EXPECT_NE(model_error([] { MachineBuilder().build(); }).find("topology"), std::string::npos);
  EXPECT_NE(model_error([] { MachineBuilder().axis_travel('X', 0, 1); }).find("axis 'X': no topology"),
            std::string::npos);
}

TEST(MachineBuilder, AxisNotInTopology) {
  const auto msg = model_error([] { five_axis().axis_travel('A', 0, 1); });
  EXPECT_EQ(msg, "axis 'A': axis 'A' is not in topology wCBXfYZt");
}

TEST(MachineBuilder, RotaryLetterWithLinearKind) {
  const auto msg = model_error([] { five_axis().axis_kind('B', AxisKind::Linear); });
  EXPECT_EQ(msg, "axis 'B': kind linear, but B is a rotary axis (A, B, C are rotary)");
}

TEST(MachineBuilder, LinearLetterWithRotaryKind) {
  const auto msg = model_error([] { five_axis().axis_kind('Y', AxisKind::Rotary); });
  EXPECT_EQ(msg, "axis 'Y': kind rotary, but Y is a linear axis (X, Y, Z are linear)");
}

TEST(MachineBuilder, DirectionAcrossTheLetter) {
  const auto msg = model_error([] { five_axis().axis_direction('C', 0, 1); });
  EXPECT_EQ(msg, "axis 'C': axis C turns about machine z: its direction is '+z' or '-z'");
  EXPECT_NE(model_error([] { five_axis().axis_direction('X', 0, 0.5); }).find("axis 'X': direction sign 0.5"),
            std::string::npos);
}

TEST(MachineBuilder, TravelMinNotBelowMax) {
  EXPECT_EQ(model_error([] { five_axis().axis_travel('X', 5, 5); }),
            "axis 'X' travel: expected [min, max] with min < max");
  EXPECT_NE(model_error([] {
              five_axis().axis_travel('X', 0, std::numeric_limits<double>::infinity());
            }).find("axis 'X' travel"),
            std::string::npos);
}

TEST(MachineBuilder, PointNotFinite) {
  const auto msg = model_error([] { five_axis().axis_point('B', Vec3(0, std::nan(""), 0)); });
  EXPECT_EQ(msg, "axis 'B' point: expected finite coordinates");
}

TEST(MachineBuilder, NegativeToolLength) {
  EXPECT_EQ(model_error([] { five_axis().tool_length(-1); }), "tool length: expected a tool length >= 0");
  EXPECT_NE(model_error([] { five_axis().tool_axis(3); }).find("tool axis: 3 is not a machine axis"),
            std::string::npos);
}

TEST(MachineBuilder, UnknownErrorName) {
  const auto msg = model_error([] { five_axis().error_value("EQQ", 1); });
  EXPECT_NE(msg.find("error 'EQQ': unknown error name 'EQQ'"), std::string::npos) << msg;
}

TEST(MachineBuilder, ErrorOfAnAxisNotInTheTopology) {
  const auto msg = model_error([] { five_axis().motion("EXA", MotionFunction(Polynomial{})); });
  EXPECT_NE(msg.find("error 'EXA': error 'EXA' names axis 'A', which is not in topology wCBXfYZt"), std::string::npos)
      << msg;
}

TEST(MachineBuilder, LocationErrorTheAxisDoesNotHave) {
  const auto msg = model_error([] { five_axis().error_value("EY0X", 1e-3); });
  EXPECT_NE(msg.find("'EY0X' is not a location error of axis X"), std::string::npos) << msg;
}

TEST(MachineBuilder, MotionFunctionForALocationError) {
  const auto msg = model_error([] { five_axis().motion("EC0Y", MotionFunction(Polynomial{})); });
  EXPECT_NE(msg.find("error 'EC0Y': is a location or mounting error"), std::string::npos) << msg;
  EXPECT_NE(model_error([] { five_axis().error_value("EXX", 1); }).find("error 'EXX': is a motion error"),
            std::string::npos);
}

TEST(MachineBuilder, TableOutOfOrder) {
  Table t{{0, 10, 5}, {0, 0, 0}, {}};
  const auto msg = model_error([&] { five_axis().motion("EYX", MotionFunction(t)); });
  EXPECT_NE(msg.find("error 'EYX': positions must increase strictly"), std::string::npos) << msg;
  Table u{{0, 10}, {0}, {}};
  EXPECT_NE(model_error([&] { five_axis().motion("EYX", MotionFunction(u)); }).find("expected 2 forward values"),
            std::string::npos);
}

TEST(MachineBuilder, FourierOnALinearAxis) {
  const auto msg = model_error([] { five_axis().motion("EXY", MotionFunction(Fourier{})); });
  EXPECT_EQ(msg, "error 'EXY': a Fourier series is for rotary axes; this axis is linear");
  EXPECT_NO_THROW(five_axis().motion("EXC", MotionFunction(Fourier{0, {1e-3}, {}, 0})));
}

TEST(MachineBuilder, ValueNotFinite) {
  const double nan = std::nan("");
  EXPECT_NE(model_error([&] { five_axis().error_value("EXt", nan); }).find("error 'EXt': nan is not a finite value"),
            std::string::npos);
  EXPECT_NE(model_error([&] {
              five_axis().motion("EXX", MotionFunction(Polynomial{{0, nan, 0, 0}, 0}));
            }).find("error 'EXX': coefficient '1' is nan"),
            std::string::npos);
}

TEST(MachineBuilder, UnknownParameterSaysWhatIsValid) {
  const auto msg = model_error([] { five_axis().parameter("EXX.7", 1); });
  EXPECT_NE(msg.find("unknown parameter 'EXX.7'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected a parameter of topology wCBXfYZt"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("--"), std::string::npos) << msg;
}

TEST(MachineBuilder, ParameterUnitOfTheWrongDimension) {
  const auto msg = model_error([] { five_axis().parameter("EC0Y", 1, "um"); });
  EXPECT_NE(msg.find("parameter 'EC0Y': unit 'um' does not fit; its unit is rad"), std::string::npos) << msg;
  EXPECT_NE(model_error([] { five_axis().parameter("EXX.1", 1, "um"); }).find("its unit is mm/mm"), std::string::npos);
  MachineBuilder b = five_axis();
  b.parameter("EC0Y", 12, "um/m").parameter("EXX.1", 2e-6, "mm/mm").parameter("EX0C", 3, "um");
  const Machine m = b.build();
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EC0Y")), 12e-6);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EXX.1")), 2e-6);
  EXPECT_DOUBLE_EQ(m.parameter(*m.parameter_index("EX0C")), 3e-3);
}

// A machine assembled by hand: each record that disagrees with the topology is named.
TEST(Validate, HandMadeMachines) {
  const Machine good = five_axis().build();
  EXPECT_NO_THROW(validate(good));
  {
    Machine m = good;
    m.axes[*m.axis_index('B')].kind = AxisKind::Linear;
    EXPECT_EQ(model_error([&] { validate(m); }), "axis 'B': kind linear, but B is a rotary axis (A, B, C are rotary)");
  }
  {
    Machine m = good;
    std::swap(m.axes[0], m.axes[1]);
    EXPECT_NE(model_error([&] {
                validate(m);
              }).find("axis 'B': at position 1 of the axes, where topology wCBXfYZt has C"),
              std::string::npos);
  }
  {
    Machine m = good;
    m.axes.pop_back();
    EXPECT_NE(model_error([&] { validate(m); }).find("axes: 4 given, but topology wCBXfYZt has 5"), std::string::npos);
  }
  {
    Machine m = good;
    m.axes[*m.axis_index('Y')].moves_workpiece = true;
    EXPECT_NE(model_error([&] { validate(m); }).find("axis 'Y': moves_workpiece is true"), std::string::npos);
  }
  {
    Machine m = good;
    m.axes[*m.axis_index('X')].location[1] = 1e-3;  // EY0X: not a location error of a linear X
    EXPECT_NE(model_error([&] { validate(m); }).find("error 'EY0X': 0.001, but it is not a location error of axis X"),
              std::string::npos);
  }
  {
    Machine m = good;
    m.topology.frame_index = 1;
    EXPECT_NE(model_error([&] { validate(m); }).find("topology 'wCBXfYZt'"), std::string::npos);
  }
  {
    Machine m = good;
    m.tool.length = -5;
    EXPECT_EQ(model_error([&] { validate(m); }), "tool length: expected a tool length >= 0");
  }
}

// The reader builds through MachineBuilder and keeps file, line and key in its messages.
TEST(MachineBuilder, ReaderKeepsFileAndLine) {
  const std::string head = "mtcal_machine: 1\ntopology: wCBXfYZt\naxes:\n  X: {}\n  Y: {}\n  Z: {}\n";
  auto bad = [&](const std::string& rest) -> InputError {
    try {
      parse_machine(head + rest, "m.yaml");
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError for " << rest;
    return InputError({}, "");
  };
  {
    const auto e = bad("  B: {}\n  C: {direction: +x}\n");
    EXPECT_EQ(e.where().file, "m.yaml");
    EXPECT_EQ(e.where().line, 8);
    EXPECT_EQ(e.where().field, "axes.C.direction");
    EXPECT_STREQ(e.what(),
                 "m.yaml:8: field 'axes.C.direction': axis C turns about machine z: its direction is '+z' or '-z'");
  }
  {
    const auto e = bad("  B: {travel: [10, -10]}\n  C: {}\n");
    EXPECT_EQ(e.where().line, 7);
    EXPECT_EQ(e.where().field, "axes.B.travel");
  }
  {
    const auto e = bad("  B: {}\n  C: {}\ntool: {length: -3}\n");
    EXPECT_EQ(e.where().line, 9);
    EXPECT_EQ(e.where().field, "tool.length");
  }
  {
    const auto e = bad("  B: {}\n  C: {}\nerrors:\n  EY0X: 3 um\n");
    EXPECT_EQ(e.where().line, 10);
    EXPECT_EQ(e.where().field, "errors.EY0X");
    EXPECT_NE(std::string(e.what()).find("not a location error of axis X"), std::string::npos);
  }
  {
    const auto e =
        bad("  B: {}\n  C: {}\nerrors:\n  EYY: {unit: um, table: {positions: [0, 1], forward: [0, 1]}}\n  EZY: {unit: "
            "um, polynomial: [.nan]}\n");
    EXPECT_EQ(e.where().line, 11);
  }
}
