// Reached-pose files: commanded world poses and the joints a controller computed for them (pose-check, campaign).
#pragma once

#include <string>
#include <vector>

#include "mtcal/evaluation/pose_check.hpp"

namespace mtcal {

// A CSV file (docs/campaign.md, "Reached poses") with, per row, the commanded world pose in
// columns X, Y, Z and the machine's rotary letters (tool point in mm in the workpiece frame,
// rotary coordinates in deg: LinuxCNC's world coordinates) and the joints reached in columns
// qX, qY, qZ, q<rotary> (mm, deg); an optional column `pose` (a number naming the pose) is
// read and ignored. Every column must be present, no other may be. '#' lines are comments.
// Throws InputError naming file, line and column; the machine must have three linear axes and
// at most two rotary ones (the controller's world coordinates).
std::vector<ReachedPose> read_reached_poses(const Machine& m, const std::string& path);
std::vector<ReachedPose> parse_reached_poses(const Machine& m, const std::string& text, const std::string& source);

}  // namespace mtcal
