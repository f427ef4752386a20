// Inverse kinematics with errors: the joint commands that put the actual tool point on a commanded one.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// World coordinates in LinuxCNC's tool-centre-point convention (src/emc/kinematics/trtfuncs.c,
// 5axiskins.c): the tool point in the workpiece frame (mm) and the rotary coordinates, which are
// the nominal rotary joint values whose nominal tool direction is the commanded one (rad here;
// LinuxCNC passes degrees).
struct CommandedPose {
  Vec3 point = Vec3::Zero();
  std::vector<double> rotary;  // one per rotary axis, in the machine's chain order
};

struct CommandedJointOptions {
  // Fixed cap of quasi-Newton steps: the steps contract by about the size of the errors' slopes
  // (1e-4 rad, 1e-5 mm/mm), so 3-4 steps reach 1e-12 mm on the example machines.
  int max_iterations = 12;
  double point_tolerance = 1e-11;        // mm, |actual - commanded tool point|
  double orientation_tolerance = 1e-13;  // rad, |stationarity residual| of the orientation equation
  // Weight of the rotary correction in the orientation equation (rad, Tikhonov / Levenberg):
  // the rotary joints minimise |a_actual - a_commanded|^2 + damping^2 |q_rot - rotary|^2 to first
  // order. Keeps the correction bounded (at most |tool direction error| / (2 damping)) where the
  // tool axis is parallel to the first rotary axis, and leaves a share damping^2 / (s^2 + damping^2)
  // of the direction error where that axis turns the tool direction with gain s.
  double orientation_damping = 0.02;
};

struct CommandedJointResult {
  std::vector<double> q;  // joint values in chain order, internal units (mm, rad)
  bool converged = false;
  int iterations = 0;                  // steps taken
  double point_residual = 0.0;         // mm
  double orientation_residual = 0.0;   // stationarity residual of the orientation equation
  double direction_error = 0.0;        // rad, angle between actual and commanded tool direction
};

// The machine's nominal topology with its errors, ready to solve for commanded joints: exactly
// three linear axes whose directions span space and at most two rotary axes (LinuxCNC's
// XYZ + two of ABC). The tool length is a call argument (LinuxCNC's tool offset), replacing the
// machine file's. Directions of motion are not used: the model at dir = 0 (reversal terms and the
// mean of forward and backward tables; docs/compensation-linuxcnc-kins.md).
class CommandedJointSolver {
 public:
  // Throws ModelError naming the topology when it is not representable (see above).
  explicit CommandedJointSolver(const Machine& machine, CommandedJointOptions options = {});

  // Why a machine cannot be solved for, or nullopt when it can.
  static std::optional<std::string> unsupported(const Machine& machine);

  const ErrorModel& model() const { return model_; }
  const CommandedJointOptions& options() const { return options_; }
  std::size_t rotary_count() const { return rotary_.size(); }
  const std::vector<std::size_t>& linear_axes() const { return linear_; }
  const std::vector<std::size_t>& rotary_axes() const { return rotary_; }

  // Nominal inverse of the topology: rotary joints = rotary coordinates, linear joints from the
  // tool point (affine in the linear joints at fixed rotary joints: one 3x3 solve).
  std::vector<double> nominal_inverse(const CommandedPose& pose, double tool_length) const;
  // Nominal forward: the nominal tool point and the rotary joints.
  CommandedPose nominal_forward(std::span<const double> q, double tool_length) const;

  // The joints whose actual tool point (the full model at dir = 0) is the commanded point, and
  // whose actual tool direction is the commanded one as far as the rotary axes can turn it.
  CommandedJointResult inverse(const CommandedPose& pose, double tool_length) const;
  // Its inverse: actual tool point, and the rotary coordinates that inverse() maps to q.
  // converged/iterations/orientation_residual describe the rotary solve.
  struct ForwardResult {
    CommandedPose pose;
    bool converged = false;
    int iterations = 0;
    double orientation_residual = 0.0;
  };
  ForwardResult forward(std::span<const double> q, double tool_length) const;

  // Actual tool point and tool direction (unit, along the spindle axis from the tool point) at q.
  Affine actual_pose(std::span<const double> q, double tool_length) const;
  Affine nominal_pose(std::span<const double> q, double tool_length) const;

 private:
  struct Nominal;  // nominal pose and its joint Jacobian at a configuration
  Nominal nominal_at(std::span<const double> q, double tool_length) const;
  Vec3 nominal_direction(std::span<const double> q_template, std::span<const double> rotary) const;

  ErrorModel model_;
  CommandedJointOptions options_;
  std::vector<std::size_t> linear_, rotary_;
};

// The actual chain of a machine (workpiece to spindle gauge point, tool length apart) as a
// module evaluates it: consecutive constant factors multiplied out, joints and motion-error
// transforms in between. T = prod(steps) * Trans(-l a); a Joint step is
// joint_motion(q + zero_position), a Motion step error_transform(motion errors at q, dir).
struct ChainStep {
  enum class Kind { Constant, Joint, Motion };
  Kind kind = Kind::Constant;
  Affine value;                // Constant
  int axis = -1;               // Joint, Motion: chain index
  double zero_position = 0.0;  // Joint: added to the joint value (internal units)
};
std::vector<ChainStep> actual_chain_steps(const Machine& machine);

}  // namespace mtcal
