// LinuxCNC compensation from a machine model: per-joint screw tables (COMP_FILE) and the rotary axis lines of trt
// kinematics.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One joint's table in LinuxCNC's joint coordinates (mm or deg), as COMP_FILE holds it: nominal
// strictly increasing, and per row the controller's columns (src/emc/motion/usrmotintf.cc,
// usrmotLoadComp(): type 0 columns are the positions actually reached, nominal + e, and the
// controller adds nominal - column; type 1 columns are added to the motor command as they are,
// i.e. corrections -e). "forward" is the column used while the joint moves in + (control.c,
// compute_screw_comp()).
struct LinuxcncJointTable {
  char axis = 'X';
  int joint = 0;
  std::vector<double> nominal, forward, reverse;
};

// A HAL pin of the kinematics module and its value (mm).
struct LinuxcncPin {
  std::string name;  // "xyzac-trt-kins.x-rot-point"
  double value = 0.0;
};

struct LinuxcncCompensation {
  int comp_file_type = 1;
  std::string coordinates;  // "XYZ", "XYZAC": joint n is the n-th letter (trivkins order)
  std::string kinematics;   // "trivkins", "xyzac-trt-kins", "xyzbc-trt-kins"
  std::vector<LinuxcncJointTable> tables;
  std::vector<LinuxcncPin> pins;
  CompensationSummary summary;
};

// The most lines a COMP_FILE may have (EMCMOT_COMP_SIZE, src/emc/motion/motion.h).
constexpr std::size_t kLinuxcncMaxCompLines = 256;

// The tables (linear joints: the tool point's error along the axis when it alone moves, every other
// axis at the reference; correction c = -e), the trt-kins pins where the rotary axes are a C table
// on an A or B table (their line positions, ISO 230-7 EX0C EY0C and EY0A EZ0A or EX0B EZ0B, go to the
// pins and out of the tables), what neither holds, and the residual by LinuxCNC's own rule.
// Throws InputError for options out of range, and when nothing is left to compensate.
LinuxcncCompensation compensate_linuxcnc(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
