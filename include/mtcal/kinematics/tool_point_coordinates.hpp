// Axis values <-> the world of a tool-centre-point kinematics (LinuxCNC trt-kins, mtcal's linuxcnc-kins module), nominal chain.
#pragma once

#include <span>
#include <vector>

#include "mtcal/kinematics/commanded_joints.hpp"

namespace mtcal {

// A program for a controller that runs tool-centre-point kinematics (docs/compensation-linuxcnc-kins.md,
// "What it applies"; LinuxCNC src/emc/kinematics/trtfuncs.c) is written in its world coordinates: x y z
// the tool point in the workpiece frame, the rotary coordinates the rotary joint values. Here a world
// position is held like axis values, in chain order: the slot of the linear axis lettered X holds x,
// Y holds y, Z holds z (mm), a rotary axis's slot its value (rad) — so a G-code writer or a log reader
// that maps letters to axes handles both. The nominal chain only (no errors): what the kinematics of
// the nominal machine (mtcal compensate of an error-free machine file) computes.
class ToolPointCoordinates {
 public:
  // Throws ModelError where the topology has no such world (CommandedJointSolver::unsupported) or
  // its linear axes are not lettered X, Y and Z.
  explicit ToolPointCoordinates(const Machine& machine);

  // World position of the nominal tool point (the machine file's tool length) at axis values q.
  std::vector<double> world(std::span<const double> q) const;
  // Axis values whose nominal tool point is the world position (rotary axes as given; the linear
  // ones by one 3x3 solve, exact: the nominal tool point is affine in them).
  std::vector<double> axes(std::span<const double> world) const;

 private:
  CommandedJointSolver solver_;
  double tool_length_ = 0.0;
  std::vector<std::size_t> slot_;  // slot_[i]: chain index of the linear axis lettered "XYZ"[i]
};

}  // namespace mtcal
