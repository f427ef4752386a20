// LinuxCNC kinematics module from a machine model: what the generated module holds, checked on a grid before writing.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/compensation/linuxcnc.hpp"
#include "mtcal/kinematics/commanded_joints.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One factor of the actual chain (src/kinematics/chain.cpp, build_chain) as the module evaluates
// it: consecutive constant factors (location and mounting errors, offsets) multiplied out.
struct KinsFactor {
  enum class Kind { Constant, Joint, Motion };
  Kind kind = Kind::Constant;
  Affine value;   // Constant
  int axis = -1;  // Joint, Motion: chain index
};

// One axis as the module sees it (chain order).
struct KinsAxis {
  char letter = 'X';
  int joint = 0;  // LinuxCNC joint number (trivkins order of the coordinate letters)
  bool rotary = false;
  int direction_axis = 0;
  double direction_sign = 1.0;
  double zero_position = 0.0;  // internal units, added to the joint in the actual chain
  Vec3 point = Vec3::Zero();   // rotary: nominal axis line point (machine coordinates at zero)
  // Motion errors at direction 0 (reversal terms out, tables the mean of both runs).
  std::array<MotionFunction, 6> motion;
  double min = 0.0, max = 0.0;  // joint limits, internal units (the travel)
};

struct LinuxcncKinsOptions {
  std::string module_name = "mtcal_kins";  // [KINS]KINEMATICS, HAL prefix, the .c file name
  CommandedJointOptions solver;
  std::size_t check_points = 5;  // pre-check grid values per axis (ends included)
};

struct LinuxcncKins {
  std::string module_name;
  std::string machine_name;
  std::string topology;
  std::string coordinates;  // "XYZAC": LinuxCNC joint j is the j-th letter
  std::vector<KinsAxis> axes;
  std::vector<KinsFactor> chain;  // actual chain, workpiece to the spindle, tool length apart
  Vec3 workpiece_origin = Vec3::Zero();
  Vec3 spindle_point = Vec3::Zero();
  int tool_axis = 2;
  double tool_length = 0.0;  // the machine file's: the tool-length pin's initial value
  CommandedJointOptions solver;

  // Direction-dependent terms of each axis along/about itself (type-1 COMP_FILE tables,
  // corrections added to the motor command; LinuxcncJointTable's convention).
  std::vector<LinuxcncJointTable> reversal_tables;
  // Pre-check over the grid: largest |corrected - nominal joint| per LinuxCNC joint (mm, deg).
  std::vector<double> largest_correction;
  std::size_t checked = 0;
  int max_iterations = 0;
  double max_point_residual = 0.0;  // mm
  CompensationSummary summary;
};

// The chain the module evaluates (axes, factors, frames) at direction of motion 0, without the
// checks, tables and solver of compensate_linuxcnc_kins: also what the simulated probe of
// io/compensation/linuxcnc_probe.hpp evaluates as its "truth" (an axis without a travel gets 0, 0).
LinuxcncKins linuxcnc_kins_model(const Machine& m, const std::string& module_name);

// Builds what the module holds and checks it: throws InputError when the topology is not one
// the module represents (why), when the inverse does not converge at a grid configuration (the
// configuration), or when a corrected joint leaves its travel (joint, value, limit).
LinuxcncKins compensate_linuxcnc_kins(const Machine& m, const CompensationOptions& o,
                                      const LinuxcncKinsOptions& k = {});

}  // namespace mtcal
