// The tool point a controller reached: commanded world poses and the joints it commanded, evaluated on a (true) machine.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/kinematics/commanded_joints.hpp"

namespace mtcal {

// One commanded pose (LinuxCNC's world coordinates: tool point in the workpiece frame and the
// rotary coordinates, kinematics/commanded_joints.hpp) and the joints the controller computed for
// it (chain order, internal units), with where it was read.
struct ReachedPose {
  CommandedPose commanded;
  std::vector<double> q;
  int line = 0;
};

struct PoseCheckOptions {
  // The tool length the controller used (its tool offset), mm; nullopt: the machine file's.
  std::optional<double> tool_length;
};

// Per pose: the actual tool point of the machine at the reached joints minus the commanded point
// (mm, workpiece frame), and the angle between the actual tool direction and the commanded one
// (the nominal direction at the commanded rotary coordinates; rad).
struct PoseDeviation {
  Vec3 error = Vec3::Zero();
  double direction_error = 0.0;
};

struct PoseCheck {
  std::vector<PoseDeviation> poses;
  double tool_length = 0.0;
  double max_error = 0.0;  // largest |e|, mm
  std::size_t max_index = 0;
  double rms_error = 0.0;  // sqrt(mean |e|^2), mm
  double max_direction_error = 0.0;
  // Fletcher's volumetric accuracy of the errors e (largest |e_i - e_j|): with the module what a
  // part made over these poses would see, the same figure as `mtcal volumetric` of e = actual -
  // nominal before a compensation.
  VolumetricAccuracy va;
};

// Evaluates every pose on machine (the truth, when the loop is rehearsed): the commanded point
// and direction need the machine's nominal topology as the controller sees it (three linear
// axes, at most two rotary: CommandedJointSolver). Throws ModelError for another topology,
// InputError (naming source and the pose's line) for a pose whose joint or rotary count does not
// match, and Error for a non-finite result.
PoseCheck check_reached_poses(const Machine& machine, std::span<const ReachedPose> poses,
                              const PoseCheckOptions& options = {}, const std::string& source = "reached poses");

}  // namespace mtcal
