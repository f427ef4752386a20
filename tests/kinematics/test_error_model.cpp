// The exact error model against hand calculations of single ISO 230 errors, zero machines,
// batched vs scalar evaluation and rigid relocation of the workpiece frame.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kDeg;

// 3-axis wXYfZt, tool length 100 mm along -z, everything else at the origin.
Machine mill() {
  return parse_machine(R"(mtcal_machine: 1
name: hand
topology: wXYfZt
axes: {X: {}, Y: {}, Z: {}}
tool: {length: 100}
)",
                       "mill");
}

// Rotary table C (point (50, 20, 0)) carrying the workpiece, X Y Z moving the tool.
Machine rotary_table() {
  return parse_machine(R"(mtcal_machine: 1
name: table
topology: wCfXYZt
axes: {C: {point: [50, 20, 0]}, X: {}, Y: {}, Z: {}}
)",
                       "table");
}

VolumetricError eval(const Machine& m, std::vector<double> q, std::vector<std::int8_t> dir = {}) {
  return ErrorModel(m).evaluate(q, dir);
}

void expect_near(const Vec3& a, const Vec3& b, double tol, const char* what) {
  EXPECT_LE((a - b).norm(), tol) << what << ": got " << a.transpose() << " expected " << b.transpose();
}

// Errors are differences of tool positions hundreds of mm from the origin: rounding leaves about
// 1e-13 mm, so hand calculations are compared to 1e-12 mm and 1e-15 rad.
const std::vector<std::string> kTopologies = {"wXYfZt",   "wfXYZt",   "wYXfZt",   "wXfYZt",  "wCBXfYZt",
                                              "wCAYXfZt", "wXfYZCAt", "wfXYZBCt", "wBfXYZCt"};

}  // namespace

TEST(ErrorModel, ZeroMachineHasZeroErrorEverywhere) {
  for (const auto& topo : kTopologies) {
    SCOPED_TRACE(topo);
    Machine m = mtcal::testing::nominal_machine(topo);
    const auto q = mtcal::testing::random_configurations(m, 200, 1);
    std::vector<double> out(200 * 6, 1.0);
    ErrorModel model(m);
    model.evaluate_batch(q, {}, out);
    for (double v : out) EXPECT_EQ(v, 0.0);
    const auto e = model.evaluate(std::span(q).first(m.axes.size()));
    EXPECT_EQ(e.translation.norm(), 0.0);
    EXPECT_EQ(e.rotation.norm(), 0.0);
  }
}

TEST(ErrorModel, NominalPoseOfMillIsTheCommandedPoint) {
  const Machine m = mill();
  const Affine p = ErrorModel(m).nominal_pose(std::vector<double>{300, 200, -400});
  expect_near(p.t, Vec3(300, 200, -500), 1e-12, "tool point");
  EXPECT_LE((p.R - Mat3::Identity()).norm(), 0.0);
}

TEST(ErrorModel, LinearAxisMotionErrorsMatchIsoDefinitions) {
  const std::vector<double> q{300, 200, -400};
  // Positioning error of X: the tool is further along +x by EXX (relative sense).
  Machine m = mill();
  m.set_parameter("EXX.0", 0.005);
  expect_near(eval(m, q).translation, Vec3(0.005, 0, 0), 1e-12, "EXX");
  // Straightness of X in Y, quadratic: dy = c x^2.
  m = mill();
  m.set_parameter("EYX.2", 1e-8);
  expect_near(eval(m, q).translation, Vec3(0, 9e-4, 0), 1e-12, "EYX");
  // Yaw of X (about z) acts on the tool point seen from the X carriage: (0, 200, -500).
  const double eps = 2e-5;
  m = mill();
  m.set_parameter("ECX.0", eps);
  auto e = eval(m, q);
  expect_near(e.translation, Vec3(-200 * std::sin(eps), 200 * (std::cos(eps) - 1), 0), 1e-12, "ECX");
  expect_near(e.rotation, Vec3(0, 0, eps), 1e-15, "ECX rotation");
  // Roll of Y (about x) acts on (0, 0, -500): Abbe offset of Z position plus tool length.
  const double a = 3e-5;
  m = mill();
  m.set_parameter("EAY.0", a);
  expect_near(eval(m, q).translation, Vec3(0, 500 * std::sin(a), 500 * (1 - std::cos(a))), 1e-12, "EAY");
  // Reference point of X moved to y = 100: the yaw acts on (0, 100, -500).
  m = mill();
  m.axes[0].point = Vec3(0, 100, 0);
  m.set_parameter("ECX.0", eps);
  expect_near(eval(m, q).translation, Vec3(-100 * std::sin(eps), 100 * (std::cos(eps) - 1), 0), 1e-12,
              "ECX with reference point");
}

TEST(ErrorModel, SquarenessErrorsTiltTheDirectionOfMotion) {
  const std::vector<double> q{300, 200, -400};
  const double g = 1.5e-5, b = 2e-5;
  Machine m = mill();
  m.set_parameter("EC0Y", g);  // Y tilted about +z towards -x
  auto e = eval(m, q);
  expect_near(e.translation, Vec3(-200 * std::sin(g), 200 * (std::cos(g) - 1), 0), 1e-12, "EC0Y");
  EXPECT_EQ(e.rotation.norm(), 0.0);  // an axis line's orientation does not tilt the carriage
  m = mill();
  m.set_parameter("EB0Z", b);
  expect_near(eval(m, q).translation, Vec3(-400 * std::sin(b), 0, -400 * (std::cos(b) - 1)), 1e-12, "EB0Z");
  m = mill();
  m.set_parameter("EY0Y", 0.002);  // zero position of Y
  expect_near(eval(m, q).translation, Vec3(0, 0.002, 0), 1e-12, "EY0Y");
}

TEST(ErrorModel, ReversalAndTablesFollowTheDirectionOfMotion) {
  const std::vector<double> q{300, 125, -400};
  Machine m = mill();
  m.set_parameter("EXX.b", 0.002);
  EXPECT_NEAR(eval(m, q, {1, 0, 0}).translation.x(), 0.002, 1e-12);
  EXPECT_NEAR(eval(m, q, {-1, 0, 0}).translation.x(), -0.002, 1e-12);
  EXPECT_NEAR(eval(m, q, {0, 0, 0}).translation.x(), 0.0, 1e-12);
  Table t;
  t.positions = {-250, 0, 250};
  t.forward = {-2e-3, 0, 4e-3};
  t.backward = {-1e-3, 1e-3, 5e-3};
  m = mill();
  m.axes[1].motion[1] = MotionFunction(t);  // EYY
  EXPECT_NEAR(eval(m, q, {0, 1, 0}).translation.y(), 2e-3, 1e-12);
  EXPECT_NEAR(eval(m, q, {0, -1, 0}).translation.y(), 3e-3, 1e-12);
  EXPECT_NEAR(eval(m, q, {0, 0, 0}).translation.y(), 2.5e-3, 1e-12);
  // Beyond the table the end value holds.
  EXPECT_NEAR(eval(m, {0, 400, 0}, {0, 1, 0}).translation.y(), 4e-3, 1e-12);
}

TEST(ErrorModel, MountingErrors) {
  const std::vector<double> q{300, 200, -400};
  Machine m = mill();
  m.set_parameter("EXt", 0.003);
  expect_near(eval(m, q).translation, Vec3(0.003, 0, 0), 1e-12, "EXt");
  const double a = 1e-4;
  m = mill();
  m.set_parameter("EAt", a);  // tilt of the tool about x at the spindle gauge point
  auto e = eval(m, q);
  expect_near(e.translation, Vec3(0, 100 * std::sin(a), 100 * (1 - std::cos(a))), 1e-12, "EAt");
  expect_near(e.rotation, Vec3(a, 0, 0), 1e-15, "EAt rotation");
  m = mill();
  m.set_parameter("EXw", 0.004);  // workpiece displaced +x: tool relative to it -x
  expect_near(eval(m, q).translation, Vec3(-0.004, 0, 0), 1e-12, "EXw");
  const double g = 5e-5;
  m = mill();
  m.set_parameter("ECw", g);
  e = eval(m, q);
  expect_near(e.translation,
              Vec3(300 * (std::cos(g) - 1) + 200 * std::sin(g), -300 * std::sin(g) + 200 * (std::cos(g) - 1), 0), 1e-12,
              "ECw");
  expect_near(e.rotation, Vec3(0, 0, -g), 1e-15, "ECw rotation");
}

TEST(ErrorModel, RotaryAxisLocationErrorsMatchIso230_7) {
  const Vec3 c(50, 20, 0), P(120, -40, 75);
  for (double C : {0.0, 30.0, 90.0, 180.0, -135.0}) {
    SCOPED_TRACE(C);
    const std::vector<double> q{C * kDeg, P.x(), P.y(), P.z()};
    const Mat3 R = Eigen::AngleAxisd(C * kDeg, Vec3::UnitZ()).toRotationMatrix();
    // Position error of the C axis line in x: (I - R) e.
    Machine m = rotary_table();
    m.set_parameter("EX0C", 0.003);
    expect_near(eval(m, q).translation, (Mat3::Identity() - R) * Vec3(0.003, 0, 0), 1e-12, "EX0C");
    // Orientation error about x: rotation about the tilted line through c.
    const double al = 4e-5;
    m = rotary_table();
    m.set_parameter("EA0C", al);
    const Mat3 Rx = Eigen::AngleAxisd(al, Vec3::UnitX()).toRotationMatrix();
    const Mat3 Rt = Rx * R * Rx.transpose();
    auto e = eval(m, q);
    expect_near(e.translation, (Rt - R) * (P - c), 1e-13, "EA0C");
    const Eigen::AngleAxisd aa(Rt * R.transpose());
    expect_near(e.rotation, aa.angle() * aa.axis(), 1e-12, "EA0C rotation");
    // Radial motion error EXC: the axis point moves along the fixed machine x direction.
    m = rotary_table();
    m.set_parameter("EXC.0", 0.002);
    expect_near(eval(m, q).translation, R * Vec3(0.002, 0, 0), 1e-12, "EXC");
    // Angular positioning error: rotation by C + eps about the nominal line.
    const double eps = 3e-5;
    m = rotary_table();
    m.set_parameter("ECC.0", eps);
    const Mat3 Re = Eigen::AngleAxisd(C * kDeg + eps, Vec3::UnitZ()).toRotationMatrix();
    e = eval(m, q);
    expect_near(e.translation, (Re - R) * (P - c), 1e-13, "ECC");
    expect_near(e.rotation, Vec3(0, 0, eps), 1e-12, "ECC rotation");
    // The zero position EC0C and a constant ECC are the same error (ISO 230-7).
    Machine z = rotary_table();
    z.set_parameter("EC0C", eps);
    const auto ez = eval(z, q);
    expect_near(ez.translation, e.translation, 1e-12, "EC0C = ECC.0");
    expect_near(ez.rotation, e.rotation, 1e-15, "EC0C = ECC.0");
  }
}

TEST(ErrorModel, RotaryMotionErrorsAreInTheAxisBaseFrame) {
  // A head C axis (carries the tool): its radial error EXC is along the ram's x whatever C is,
  // as a fixed indicator on the ram would see it; the tool tip is at the axis point here.
  const Machine head = parse_machine(R"(mtcal_machine: 1
name: head
topology: wfXYZCt
axes: {X: {}, Y: {}, Z: {}, C: {point: [0, 0, 0]}}
)",
                                     "head");
  for (double C : {0.0, 90.0, 200.0}) {
    Machine m = head;
    m.set_parameter("EXC.0", 0.002);
    expect_near(eval(m, {10, 20, 30, C * kDeg}).translation, Vec3(0.002, 0, 0), 1e-12, "head EXC");
    // Tilt EAC of the head about the ram's x, with the tool 100 mm below the axis point.
    m = head;
    m.tool.length = 100;
    m.set_parameter("EAC.0", 5e-5);
    expect_near(eval(m, {10, 20, 30, C * kDeg}).translation, Vec3(0, 100 * std::sin(5e-5), 100 * (1 - std::cos(5e-5))),
                1e-12, "head EAC");
  }
}

TEST(ErrorModel, ReversedAxesKeepTheSenseOfEveryError) {
  // A positive error moves the tool along + machine axis whatever the axis's direction:
  // the zero position of a reversed axis equals a constant positioning error, as for others.
  for (const char* topo : {"wCfXYZt", "wXfYZCt"}) {
    SCOPED_TRACE(topo);
    const Machine rev = mtcal::testing::nominal_machine(topo, true);
    const std::vector<double> q = std::string(topo) == "wCfXYZt" ? std::vector<double>{0.7, 100, -50, 30}
                                                                 : std::vector<double>{100, -50, 30, 0.7};
    Machine a = rev, b = rev;
    a.set_parameter("EC0C", 3e-5);
    b.set_parameter("ECC.0", 3e-5);
    const auto ea = eval(a, q), eb = eval(b, q);
    expect_near(ea.translation, eb.translation, 1e-12, "EC0C = ECC.0");
    expect_near(ea.rotation, Vec3(0, 0, 3e-5), 1e-15, "EC0C turns the tool about +z");
    a = rev;
    b = rev;
    a.set_parameter("EX0X", 2e-3);
    b.set_parameter("EXX.0", 2e-3);
    expect_near(eval(a, q).translation, eval(b, q).translation, 1e-12, "EX0X = EXX.0");
    if (std::string(topo) == "wXfYZCt")  // no rotary axis between workpiece and X
      expect_near(eval(a, q).translation, Vec3(2e-3, 0, 0), 1e-12, "EX0X along +x");
  }
  // The nominal motion of a reversed linear axis runs along -x.
  const Machine rev = mtcal::testing::nominal_machine("wfXYZt", true);
  const Machine fwd = mtcal::testing::nominal_machine("wfXYZt", false);
  const std::vector<double> q{10, 20, 30};
  expect_near(ErrorModel(rev).nominal_pose(q).t - ErrorModel(fwd).nominal_pose(q).t, Vec3(-20, -40, -60), 1e-12,
              "reversed nominal motion");
}

TEST(ErrorModel, BatchedAgreesWithScalarForEveryExampleAndTopology) {
  std::vector<Machine> machines;
  for (const char* f : {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"})
    machines.push_back(load_machine(std::string(MTCAL_EXAMPLES_DIR) + "/" + f));
  for (const auto& topo : kTopologies) {
    Machine m = mtcal::testing::nominal_machine(topo);
    mtcal::testing::randomize_errors(m, 11, 1.0);
    machines.push_back(m);
    Machine rev = mtcal::testing::nominal_machine(topo, true);
    mtcal::testing::randomize_errors(rev, 13, 1.0);
    machines.push_back(rev);
    Machine big = m;  // large errors: exercises the exact (non-series) rotation vector path
    mtcal::testing::randomize_errors(big, 12, 3000.0);
    machines.push_back(big);
  }
  for (const auto& m : machines) {
    SCOPED_TRACE(m.name);
    std::vector<std::int8_t> dir;
    const std::size_t N = 203;  // not a multiple of the block size
    auto q = mtcal::testing::random_configurations(m, N, 5, &dir);
    const std::size_t n = m.axes.size();
    const ErrorModel model(m);
    std::vector<double> out(N * 6);
    model.evaluate_batch(q, dir, out, BatchOptions{1});
    for (std::size_t r = 0; r < N; ++r) {
      const auto e = model.evaluate(std::span(q).subspan(r * n, n), std::span(dir).subspan(r * n, n));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[r * 6 + c], e.translation[c], 1e-12) << r;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[r * 6 + 3 + c], e.rotation[c], 1e-14) << r;
    }
  }
}

TEST(ErrorModel, LargeRotaryAnglesKeepPrecisionInTheBatchedKernel) {
  // Continuous rotary axes turn many times: the kernel's own sin/cos must reduce the argument
  // as well as the C library does. Location and mounting errors only, so that no polynomial is
  // evaluated far outside its travel.
  for (const char* topo : {"wCBXfYZt", "wXfYZCAt"}) {
    SCOPED_TRACE(topo);
    Machine m = mtcal::testing::nominal_machine(topo);
    mtcal::testing::randomize_errors(m, 40);
    for (auto& ax : m.axes)
      for (auto& f : ax.motion) f = MotionFunction(Polynomial{});
    const ErrorModel model(m);
    for (double angle : {-9999.25, -1234.5678, 100.0, 1234.5678, 31415.9}) {
      std::vector<double> q = {angle, -0.7 * angle, 10.0, 20.0, 30.0};
      if (std::string(topo) == "wXfYZCAt") q = {10.0, 20.0, 30.0, angle, 0.5};
      std::vector<double> out(6);
      model.evaluate_batch(q, {}, out);
      const auto e = model.evaluate(q);
      // 1e-12 relative rounding of q + zero position at these angles, on arms of ~500 mm.
      const double tol = 1e-10 * std::max(1.0, std::abs(angle) / 100.0);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[c], e.translation[c], tol) << angle;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(out[3 + c], e.rotation[c], tol * 1e-2) << angle;
    }
  }
}

TEST(ErrorModel, ThreadsGiveIdenticalResults) {
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, 3);
  std::vector<std::int8_t> dir;
  const auto q = mtcal::testing::random_configurations(m, 20000, 9, &dir);
  const ErrorModel model(m);
  std::vector<double> a(20000 * 6), b(20000 * 6);
  model.evaluate_batch(q, dir, a, BatchOptions{1});
  model.evaluate_batch(q, dir, b, BatchOptions{4});
  EXPECT_EQ(a, b);
}

TEST(ErrorModel, RigidRelocationOfTheWorkpieceFrameLeavesErrorsUnchanged) {
  for (const auto& topo : kTopologies) {
    SCOPED_TRACE(topo);
    Machine m = mtcal::testing::nominal_machine(topo);
    mtcal::testing::randomize_errors(m, 21);
    // A workpiece mounting rotation turns about the workpiece origin, so it is part of where the
    // frame is; every machine error must be independent of that choice.
    for (const char* r : {"EAw", "EBw", "ECw"}) m.set_parameter(r, 0.0);
    Machine moved = m;
    moved.workpiece.origin += Vec3(123.4, -56.7, 89.0);
    const auto q = mtcal::testing::random_configurations(m, 30, 4);
    const std::size_t n = m.axes.size();
    for (std::size_t r = 0; r < 30; ++r) {
      std::span<const double> qr(q.data() + r * n, n);
      const auto a = ErrorModel(m).evaluate(qr), b = ErrorModel(moved).evaluate(qr);
      expect_near(a.translation, b.translation, 1e-12, "translation");
      expect_near(a.rotation, b.rotation, 1e-16, "rotation");
      // The nominal tool point moves by exactly the relocation.
      const Vec3 d = ErrorModel(m).nominal_pose(qr).t - ErrorModel(moved).nominal_pose(qr).t;
      expect_near(d, Vec3(123.4, -56.7, 89.0), 1e-9, "nominal point");
    }
  }
}

TEST(ErrorModel, ToolLengthMattersOnlyThroughRotations) {
  Machine m = mtcal::testing::nominal_machine("wCBXfYZt");
  mtcal::testing::randomize_errors(m, 8);
  const auto q = mtcal::testing::random_configurations(m, 20, 2);
  for (std::size_t r = 0; r < 20; ++r) {
    std::span<const double> qr(q.data() + r * 5, 5);
    Machine longer = m;
    longer.tool.length += 50.0;
    const auto a = ErrorModel(m).evaluate(qr), b = ErrorModel(longer).evaluate(qr);
    // Same orientation error; the tool point difference is the orientation error acting on the
    // extra 50 mm of tool: (R_a - R_n)(-50 a) expressed in the workpiece frame.
    expect_near(a.rotation, b.rotation, 1e-16, "rotation");
    const Affine pa = ErrorModel(m).actual_pose(qr), pn = ErrorModel(m).nominal_pose(qr);
    const Vec3 extra = (pa.R - pn.R) * Vec3(0, 0, -50.0);
    expect_near(b.translation - a.translation, extra, 1e-12, "translation");
  }
}

TEST(ErrorModel, RejectsWrongNumberOfJointValues) {
  const ErrorModel model(mill());
  EXPECT_THROW(model.evaluate(std::vector<double>{1, 2}), ModelError);
  std::vector<double> out(6);
  EXPECT_THROW(model.evaluate_batch(std::vector<double>{1, 2, 3, 4}, {}, out), ModelError);
  EXPECT_THROW(model.evaluate_batch(std::vector<double>{1, 2, 3}, {}, std::span<double>(out).first(5)), ModelError);
}
