// Tool-path simulation: where the points fall, how rotary axes and directions follow, and that
// the errors are the model's at those configurations.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "mtcal/evaluation/toolpath.hpp"
#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kDeg;
using mtcal::testing::kPi;

GcodeProgram program(const Machine& m, const std::string& text) {
  GcodeOptions o;
  o.axes.clear();
  for (const auto& ax : m.axes) o.axes += ax.letter;
  return parse_gcode(text, "p.nc", o);
}

// Joint value of axis letter at point i (internal units).
double joint(const Machine& m, const ToolpathChunk& c, std::size_t i, char letter) {
  return c.q[i * m.axes.size() + *m.axis_index(letter)];
}

}  // namespace

TEST(Toolpath, StraightLineStepsAndEndPoints) {
  const Machine m = ::mtcal::testing::nominal_machine("wfXYZt");
  ToolpathOptions o;
  o.step = 3;
  // 10 mm at most 3 mm apart: 4 equal parts of 2.5 mm, the end point last, no start point.
  auto c = interpolate_toolpath(m, program(m, "G1 X10 F100\n"), o);
  ASSERT_EQ(c.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(joint(m, c, i, 'X'), 2.5 * static_cast<double>(i + 1), 1e-12);
    EXPECT_NEAR(c.s[i], 2.5 * static_cast<double>(i + 1), 1e-12);
    EXPECT_EQ(c.line[i], 1);
    EXPECT_EQ(c.motion[i], GcodeMotion::Linear);
  }
  EXPECT_EQ(joint(m, c, 3, 'X'), 10.0);
  // Exactly 4 steps of 2.5 mm stay 4 parts; the next block continues s; a zero-length block adds
  // nothing.
  o.step = 2.5;
  c = interpolate_toolpath(m, program(m, "G1 X10 F100\nN5 G0 X10\nN6 Y3 Z4\n"), o);
  ASSERT_EQ(c.size(), 6u);
  EXPECT_EQ(c.n[3], -1);
  // Line 3: 5 mm from (10, 0, 0) to (10, 3, 4) in 2 parts, 2.5 mm each.
  EXPECT_NEAR(c.s[4], 12.5, 1e-12);
  EXPECT_NEAR(c.s[5], 15, 1e-12);
  EXPECT_NEAR(joint(m, c, 4, 'Y'), 1.5, 1e-12);
  EXPECT_NEAR(joint(m, c, 4, 'Z'), 2, 1e-12);
  EXPECT_EQ(c.line[5], 3);
  EXPECT_EQ(c.n[5], 6);
  EXPECT_EQ(c.motion[5], GcodeMotion::Rapid);
}

TEST(Toolpath, ArcPointsLieOnTheCircleEvenlySpaced) {
  const Machine m = ::mtcal::testing::nominal_machine("wfXYZt");
  ToolpathOptions o;
  o.step = 1;
  const auto c = interpolate_toolpath(m, program(m, "G0 X10 Y0 Z-5\nG3 X0 Y10 I-10 J0\n"), o);
  // The rapid from (0, 0, 0) is sqrt(125) = 11.18 mm: 12 parts. The quarter circle of radius 10
  // is 15.71 mm: 16 parts of pi/32 rad.
  ASSERT_EQ(c.size(), 12u + 16u);
  for (std::size_t i = 0; i < 16; ++i) {
    const double x = joint(m, c, 12 + i, 'X'), y = joint(m, c, 12 + i, 'Y');
    EXPECT_NEAR(std::hypot(x, y), 10, 1e-12);
    EXPECT_NEAR(std::atan2(y, x), kPi / 32 * static_cast<double>(i + 1), 1e-12);
    EXPECT_EQ(joint(m, c, 12 + i, 'Z'), -5.0);
    EXPECT_NEAR(c.s[12 + i], std::sqrt(125.0) + 10 * kPi / 32 * static_cast<double>(i + 1), 1e-11);
  }
  EXPECT_EQ(joint(m, c, 27, 'X'), 0.0);
  EXPECT_EQ(joint(m, c, 27, 'Y'), 10.0);
}

TEST(Toolpath, HelixInYZSplitsByArcLength) {
  const Machine m = ::mtcal::testing::nominal_machine("wfXYZt");
  ToolpathOptions o;
  o.step = 2;
  o.skip_rapids = true;
  // G19 full turn of radius 5 about (Y, Z) = (0, 0), rising 10 mm along X:
  // length sqrt((10 pi)^2 + 10^2) = 32.97 mm: 17 parts.
  const auto c = interpolate_toolpath(m, program(m, "G0 Y5\nG19 G3 X10 J-5 F100\n"), o);
  ASSERT_EQ(c.size(), 17u);
  const double length = std::hypot(10 * kPi, 10);
  for (std::size_t i = 0; i < 17; ++i) {
    const double t = static_cast<double>(i + 1) / 17;
    EXPECT_NEAR(joint(m, c, i, 'X'), 10 * t, 1e-12);
    EXPECT_NEAR(joint(m, c, i, 'Y'), 5 * std::cos(2 * kPi * t), 1e-12);
    EXPECT_NEAR(joint(m, c, i, 'Z'), 5 * std::sin(2 * kPi * t), 1e-12);
    EXPECT_NEAR(c.s[i], length * t, 1e-11);  // the skipped rapid is left out of s
  }
}

TEST(Toolpath, RotaryAxesFollowProgressAndRotaryOnlyBlocksSplitByAngle) {
  const Machine m = ::mtcal::testing::nominal_machine("wCBXfYZt");
  ToolpathOptions o;
  o.step = 1;
  o.angle_step = 0.5;
  // Line 1: 10 mm with B 0 -> 4 deg: 10 parts (the angle needs 8). Line 2: C 0 -> 90 deg alone:
  // 180 parts of 0.5 deg, s unchanged. Line 3: 1 mm with C 90 -> 93 deg: the angle needs 6 parts.
  const auto c = interpolate_toolpath(m, program(m, "G1 X10 B4 F100\nC90\nX11 C93\n"), o);
  ASSERT_EQ(c.size(), 10u + 180u + 6u);
  for (std::size_t i = 0; i < 10; ++i) EXPECT_NEAR(joint(m, c, i, 'B'), 0.4 * static_cast<double>(i + 1) * kDeg, 1e-15);
  for (std::size_t i = 0; i < 180; ++i) {
    EXPECT_NEAR(joint(m, c, 10 + i, 'C'), 0.5 * static_cast<double>(i + 1) * kDeg, 1e-15);
    EXPECT_EQ(joint(m, c, 10 + i, 'X'), 10.0);
    EXPECT_EQ(c.s[10 + i], 10.0);
  }
  EXPECT_NEAR(joint(m, c, 190, 'X'), 10 + 1.0 / 6, 1e-12);
  EXPECT_NEAR(joint(m, c, 190, 'C'), 90.5 * kDeg, 1e-15);
  EXPECT_NEAR(c.s.back(), 11, 1e-12);
}

TEST(Toolpath, DirectionsOfMotion) {
  const Machine m = ::mtcal::testing::nominal_machine("wfXYZt");
  ToolpathOptions o;
  o.step = 10;
  // X up, X down, then Y alone: X keeps the side it came from (-1); Y had not moved before: 0.
  const auto c = interpolate_toolpath(m, program(m, "G1 X10 F100\nX5\nY-3\n"), o);
  ASSERT_EQ(c.size(), 3u);
  auto dir = [&](std::size_t i, std::size_t k) { return c.dir[i * 3 + k]; };
  EXPECT_EQ(dir(0, 0), 1);
  EXPECT_EQ(dir(0, 1), 0);
  EXPECT_EQ(dir(1, 0), -1);
  EXPECT_EQ(dir(1, 1), 0);
  EXPECT_EQ(dir(2, 0), -1);
  EXPECT_EQ(dir(2, 1), -1);
  // Full circle G3 from (10, 0) about (0, 0) in 4 parts (62.8 mm, step 15.8): at (0, 10) X
  // arrived moving -x, Y +y; at (-10, 0) X -x, Y -y; at (0, -10) X +x, Y -y; at (10, 0) Y +y.
  o.step = 15.8;
  const auto a = interpolate_toolpath(m, program(m, "G0 X10\nG3 I-10\n"), o);
  ASSERT_EQ(a.size(), 1u + 4u);
  auto adir = [&](std::size_t i, std::size_t k) { return a.dir[i * 3 + k]; };
  EXPECT_EQ(adir(1, 0), -1);
  EXPECT_EQ(adir(1, 1), 1);
  EXPECT_EQ(adir(2, 0), -1);
  EXPECT_EQ(adir(2, 1), -1);
  EXPECT_EQ(adir(3, 0), 1);
  EXPECT_EQ(adir(3, 1), -1);
  EXPECT_EQ(adir(4, 0), 1);
  EXPECT_EQ(adir(4, 1), 1);
  o.directions = false;
  EXPECT_TRUE(interpolate_toolpath(m, program(m, "G1 X10\n"), o).dir.empty());
}

TEST(Toolpath, OriginOffsetAndAxesNotInTheProgram) {
  const Machine m = ::mtcal::testing::nominal_machine("wCBXfYZt");
  ToolpathOptions o;
  o.step = 5;
  o.origin = {100, -20, -300, 0, 30, 45};
  const auto c = interpolate_toolpath(m, program(m, "G1 X10 F100\n"), o);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(joint(m, c, 0, 'X'), 105, 1e-12);
  EXPECT_NEAR(joint(m, c, 1, 'X'), 110, 1e-12);
  EXPECT_NEAR(joint(m, c, 1, 'Y'), -20, 1e-12);
  EXPECT_NEAR(joint(m, c, 1, 'Z'), -300, 1e-12);
  EXPECT_NEAR(joint(m, c, 1, 'B'), 30 * kDeg, 1e-15);
  EXPECT_NEAR(joint(m, c, 1, 'C'), 45 * kDeg, 1e-15);
}

TEST(Toolpath, ErrorsAreTheModelsAtThePoints) {
  const Machine m = load_machine(MTCAL_EXAMPLES_DIR "/vmc-3axis.yaml");
  const ErrorModel model(m);
  const GcodeProgram p = program(m,
                                 "G0 X10 Y0 Z5\nG1 Z-2 F300\nX70\nG3 X80 Y10 R10\nG2 X90 Y20 Z-4 I10\n"
                                 "G18 G2 X100 Z-14 I10\nG17 G91 G1 X-30 Y-5\n");
  ToolpathOptions o;
  o.step = 0.7;
  o.origin = {-40, -25, -400, 0, 0, 0};
  o.chunk = 37;  // many chunks, blocks split across them
  ToolpathChunk all;
  std::size_t chunks = 0;
  const auto sum = simulate_toolpath(model, p, o, [&](const ToolpathChunk& c) {
    ++chunks;
    EXPECT_LE(c.size(), 37u);
    all.q.insert(all.q.end(), c.q.begin(), c.q.end());
    all.dir.insert(all.dir.end(), c.dir.begin(), c.dir.end());
    all.error.insert(all.error.end(), c.error.begin(), c.error.end());
    all.line.insert(all.line.end(), c.line.begin(), c.line.end());
    all.s.insert(all.s.end(), c.s.begin(), c.s.end());
  });
  // The same points as in one piece.
  const ToolpathChunk ref = interpolate_toolpath(m, p, o);
  ASSERT_EQ(all.size(), ref.size());
  EXPECT_EQ(all.q, ref.q);
  EXPECT_EQ(all.dir, ref.dir);
  EXPECT_EQ(sum.points, ref.size());
  EXPECT_EQ(chunks, (ref.size() + 36) / 37);  // full chunks, whatever the block boundaries
  EXPECT_EQ(sum.blocks, 7u);
  EXPECT_NEAR(sum.path_length, ref.s.back(), 1e-9);

  double best = -1;
  int best_line = 0;
  std::array<std::array<double, 2>, 6> range;
  for (auto& r : range) r = {1e300, -1e300};
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto e = model.evaluate(std::span<const double>(all.q).subspan(i * 3, 3),
                                  std::span<const std::int8_t>(all.dir).subspan(i * 3, 3));
    const double v[6] = {e.translation.x(), e.translation.y(), e.translation.z(),
                         e.rotation.x(),    e.rotation.y(),    e.rotation.z()};
    for (std::size_t k = 0; k < 6; ++k) {
      EXPECT_NEAR(all.error[i * 6 + k], v[k], k < 3 ? 1e-12 : 1e-15);
      range[k] = {std::min(range[k][0], v[k]), std::max(range[k][1], v[k])};
    }
    if (e.translation.norm() > best) best = e.translation.norm(), best_line = all.line[i];
  }
  EXPECT_NEAR(sum.max_error, best, 1e-12);
  EXPECT_EQ(sum.max_line, best_line);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_NEAR(sum.range[k][0], range[k][0], 1e-12);
    EXPECT_NEAR(sum.range[k][1], range[k][1], 1e-12);
  }
  // The directions reach the model: X runs forward on line 3 and backward on line 7.
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (all.line[i] == 3) {
      EXPECT_EQ(all.dir[i * 3], 1);
    }
    if (all.line[i] == 7) {
      EXPECT_EQ(all.dir[i * 3], -1);
    }
  }
}

TEST(Toolpath, TravelCheckNamesTheBlock) {
  const Machine m = load_machine(MTCAL_EXAMPLES_DIR "/vmc-3axis.yaml");  // X travel [-400, 400]
  const ErrorModel model(m);
  // The arc bulges beyond X = 400 although both its ends are inside.
  const GcodeProgram p = program(m, "G0 X390 Y-20 Z-100\nG3 X390 Y20 R20\n");
  try {
    simulate_toolpath(model, p, ToolpathOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(e.where().file, "p.nc:2") << msg;
    EXPECT_NE(msg.find("outside the travel"), std::string::npos) << msg;
  }
  ToolpathOptions o;
  o.travel_check = false;
  EXPECT_GT(simulate_toolpath(model, p, o).points, 0u);
}

TEST(Toolpath, SkippedRapidsAndBadSteps) {
  const Machine m = ::mtcal::testing::nominal_machine("wfXYZt");
  ToolpathOptions o;
  o.step = 1;
  o.skip_rapids = true;
  const auto c = interpolate_toolpath(m, program(m, "G0 X100\nG1 X95\n"), o);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_NEAR(c.s.back(), 5, 1e-12);
  EXPECT_EQ(c.dir[0], -1);
  EXPECT_NEAR(c.q[0], 99, 1e-12);
  for (double bad : {0.0, -1.0, std::nan("")}) {
    o.step = bad;
    EXPECT_THROW(ToolpathInterpolator(m, o), InputError);
  }
  o.step = 1;
  o.angle_step = 0;
  EXPECT_THROW(ToolpathInterpolator(m, o), InputError);
  // A step far too fine for the path is refused, not attempted.
  o.angle_step = 0.5;
  o.step = 1e-9;
  EXPECT_THROW(interpolate_toolpath(m, program(m, "G1 X100\n"), o), InputError);
}
