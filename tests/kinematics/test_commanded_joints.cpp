// The inverse with errors (CommandedJointSolver) on the four example machines: the model evaluated
// at the joints it returns puts the actual tool point on the commanded one; forward() is its inverse.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/kinematics/commanded_joints.hpp"
#include "mtcal/util/errors.hpp"
#include "synthetic.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::example;

const char* kExamples[] = {"vmc-3axis.yaml", "hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"};

Vec3 axis_unit(const Machine& m) {
  Vec3 a = Vec3::Zero();
  a[m.tool.tool_axis] = 1.0;
  return a;
}

// Commanded poses: the nominal forward of random joints inside the travel (so the pose is reachable).
std::vector<CommandedPose> random_poses(const CommandedJointSolver& s, std::size_t count, std::uint64_t seed,
                                        double tool_length) {
  const Machine& m = s.model().machine();
  const auto q = mtcal::testing::random_configurations(m, count, seed);
  const std::size_t n = m.axes.size();
  std::vector<CommandedPose> out;
  for (std::size_t r = 0; r < count; ++r) out.push_back(s.nominal_forward({q.data() + r * n, n}, tool_length));
  return out;
}

}  // namespace

TEST(CommandedJoints, ActualToolPointOnTheCommandedOneForEveryExample) {
  for (const char* f : kExamples) {
    const Machine m = example(f);
    const CommandedJointSolver s(m);
    for (double tool : {0.0, m.tool.length, 75.0}) {
      int max_iterations = 0;
      double before = 0.0;
      for (const auto& pose : random_poses(s, 200, 7, tool)) {
        const auto r = s.inverse(pose, tool);
        ASSERT_TRUE(r.converged) << f << " residual " << r.point_residual << " after " << r.iterations;
        max_iterations = std::max(max_iterations, r.iterations);
        // Independent of the solver's own residual: the model's actual pose at the joints.
        const Affine T = s.actual_pose(r.q, tool);
        EXPECT_LE((T.t - pose.point).norm(), 1e-9) << f;
        // The uncorrected joints (nominal inverse) miss the point by the model's error.
        const Affine T0 = s.actual_pose(s.nominal_inverse(pose, tool), tool);
        before = std::max(before, (T0.t - pose.point).norm());
      }
      EXPECT_LE(max_iterations, 5) << f;
      EXPECT_GT(before, 1e-3) << f << ": the example's errors must be visible before correction";
    }
  }
}

TEST(CommandedJoints, ToolLengthMovesThePointAlongTheActualSpindleAxis) {
  // Independent reference: a machine file with the other tool length, evaluated by ErrorModel.
  for (const char* f : kExamples) {
    Machine m = example(f);
    const CommandedJointSolver s(m);
    Machine m2 = m;
    m2.tool.length = 42.5;
    const ErrorModel model2(m2);
    const auto q = mtcal::testing::random_configurations(m, 20, 3);
    const std::size_t n = m.axes.size();
    for (std::size_t r = 0; r < 20; ++r) {
      std::span<const double> qr(q.data() + r * n, n);
      EXPECT_LE((s.actual_pose(qr, 42.5).t - model2.actual_pose(qr).t).norm(), 1e-12) << f;
      EXPECT_LE((s.nominal_pose(qr, 42.5).t - model2.nominal_pose(qr).t).norm(), 1e-12) << f;
    }
  }
}

TEST(CommandedJoints, ForwardIsTheInverseOfInverse) {
  for (const char* f : kExamples) {
    const Machine m = example(f);
    const CommandedJointSolver s(m);
    for (const auto& pose : random_poses(s, 100, 11, m.tool.length)) {
      const auto r = s.inverse(pose, m.tool.length);
      ASSERT_TRUE(r.converged) << f;
      const auto fw = s.forward(r.q, m.tool.length);
      ASSERT_TRUE(fw.converged) << f;
      EXPECT_LE((fw.pose.point - pose.point).norm(), 1e-9) << f;
      for (std::size_t j = 0; j < pose.rotary.size(); ++j) EXPECT_NEAR(fw.pose.rotary[j], pose.rotary[j], 1e-11) << f;
    }
  }
}

TEST(CommandedJoints, RotaryAxesCorrectTheToolDirectionAwayFromTheSingularity) {
  // With no damping, wherever the rotary axes turn the tool direction both ways (not at the pole
  // where the tool axis is along the first rotary axis) the actual direction equals the commanded one.
  for (const char* f : {"hu40t-wCBXfYZt.yaml", "rrttt-table-table.yaml", "head-head-5axis.yaml"}) {
    const Machine m = example(f);
    CommandedJointOptions o;
    o.orientation_damping = 0.0;
    const CommandedJointSolver s(m, o);
    const CommandedJointSolver damped(m);
    const Vec3 a = axis_unit(m);
    int checked = 0;
    for (const auto& pose : random_poses(s, 200, 5, m.tool.length)) {
      std::vector<double> q = s.nominal_inverse(pose, m.tool.length);
      const Vec3 target = s.nominal_pose(q, m.tool.length).R * a;
      const auto r = s.inverse(pose, m.tool.length);
      if (!r.converged) continue;  // near the pole the undamped equations are ill-conditioned
      const Vec3 actual = s.actual_pose(r.q, m.tool.length).R * a;
      const double before = std::atan2(target.cross(s.actual_pose(q, m.tool.length).R * a).norm(),
                                        target.dot(s.actual_pose(q, m.tool.length).R * a));
      const double after = std::atan2(target.cross(actual).norm(), target.dot(actual));
      if (before < 1e-6) continue;
      EXPECT_LE(after, 1e-12) << f << " before " << before;
      // The damped solve (the module's default) removes most of it as well, and keeps the point.
      const auto rd = damped.inverse(pose, m.tool.length);
      ASSERT_TRUE(rd.converged) << f;
      EXPECT_LE(rd.direction_error, before) << f;
      ++checked;
    }
    EXPECT_GT(checked, 100) << f;
  }
}

TEST(CommandedJoints, DampingBoundsTheRotaryCorrectionAtThePole) {
  // Head-head at A = 0: the tool axis is along C, which cannot tilt the tool; the C correction
  // stays below |direction error| / (2 damping) and the tool point is still exact.
  const Machine m = example("head-head-5axis.yaml");
  const CommandedJointSolver s(m);
  const std::size_t c = *m.axis_index('C'), a = *m.axis_index('A');
  for (double C : {-1.0, 0.0, 0.7, 2.5}) {
    std::vector<double> q(m.axes.size(), 0.0);
    q[c] = C;
    q[a] = 0.0;
    q[*m.axis_index('X')] = 100.0;
    const CommandedPose pose = s.nominal_forward(q, m.tool.length);
    const auto r = s.inverse(pose, m.tool.length);
    ASSERT_TRUE(r.converged);
    EXPECT_LE((s.actual_pose(r.q, m.tool.length).t - pose.point).norm(), 1e-9);
    EXPECT_LE(std::abs(r.q[c] - C), 1e-4 / (2 * s.options().orientation_damping));
  }
}

TEST(CommandedJoints, ErrorFreeMachineGivesTheNominalInverse) {
  for (const char* f : kExamples) {
    Machine m = example(f);
    m.clear_errors();
    const CommandedJointSolver s(m);
    for (const auto& pose : random_poses(s, 20, 9, 10.0)) {
      const auto r = s.inverse(pose, 10.0);
      EXPECT_TRUE(r.converged);
      EXPECT_LE(r.iterations, 1);
      const auto q0 = s.nominal_inverse(pose, 10.0);
      for (std::size_t k = 0; k < q0.size(); ++k) EXPECT_NEAR(r.q[k], q0[k], 1e-9) << f;
    }
  }
}

TEST(CommandedJoints, RefusesTopologiesItCannotRepresent) {
  Machine m = example("rrttt-table-table.yaml");
  // Two linear axes only.
  Machine two = example("vmc-3axis.yaml");
  EXPECT_FALSE(CommandedJointSolver::unsupported(two).has_value());
  two.axes.pop_back();
  two.topology.axes.pop_back();
  ASSERT_TRUE(CommandedJointSolver::unsupported(two).has_value());
  EXPECT_NE(CommandedJointSolver::unsupported(two)->find("exactly three"), std::string::npos);
  EXPECT_THROW(CommandedJointSolver{two}, ModelError);
  // Three rotary axes.
  Machine three = m;
  Axis extra = m.axes[0];
  extra.letter = 'A';
  three.axes.insert(three.axes.begin(), extra);
  ASSERT_TRUE(CommandedJointSolver::unsupported(three).has_value());
  EXPECT_NE(CommandedJointSolver::unsupported(three)->find("3 rotary axes"), std::string::npos);
  // Bad options.
  CommandedJointOptions o;
  o.max_iterations = 0;
  EXPECT_THROW((CommandedJointSolver{m, o}), ModelError);
  o = {};
  o.orientation_damping = std::nan("");
  EXPECT_THROW((CommandedJointSolver{m, o}), ModelError);
}

TEST(CommandedJoints, NonFiniteTargetIsNotConverged) {
  const Machine m = example("head-head-5axis.yaml");
  const CommandedJointSolver s(m);
  CommandedPose p = s.nominal_forward(std::vector<double>(m.axes.size(), 0.0), m.tool.length);
  p.point.x() = std::nan("");
  EXPECT_FALSE(s.inverse(p, m.tool.length).converged);
  p = s.nominal_forward(std::vector<double>(m.axes.size(), 0.0), m.tool.length);
  EXPECT_FALSE(s.inverse(p, std::numeric_limits<double>::infinity()).converged);
  p.rotary.pop_back();
  EXPECT_THROW(s.inverse(p, m.tool.length), ModelError);
}
