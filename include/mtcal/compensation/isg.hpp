// Beckhoff/ISG TF5280 volumetric compensation from a machine model: the ISO 230-1 parameters the control's own machine
// model evaluates.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "mtcal/compensation/compensation.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// The component (motion) errors of one axis sampled along it, as an ISG CSV block "X EXX EYX ..."
// holds them: arguments in mm or deg, values in mm or rad (TF5280 manual, "Units of measure").
struct IsgComponentTable {
  char axis = 'X';
  std::vector<std::string> names;           // "EXX", "EYX", ... (the axis's non-zero motion errors)
  std::vector<double> position;             // mm or deg
  std::vector<std::vector<double>> values;  // values[name][position]: the mean of both directions
};

struct IsgCompensation {
  std::vector<std::pair<std::string, double>> position_errors;  // "C0Y", "X0C" ...: mtcal's name without 'E'
  std::vector<IsgComponentTable> tables;
  CompensationSummary summary;
};

// The model's errors as the control's parametric model takes them (ISO 230-1/-7, ISO/TR 16907):
// position errors of the axes as constants, motion errors as tables along their axis. The control
// corrects the tool position, not its orientation; reversal terms and tool/workpiece set-up errors
// are not held (listed). Needs linear axes X, Y, Z and at most three rotary axes.
IsgCompensation compensate_isg(const Machine& m, const CompensationOptions& o);

// The same parameters for the Etalon exchange format (vendor variant), the second parameter file
// format the TF5280 reads (manual, "Etalon Exchange Format"): the control's model and residual
// are those of compensate_isg; only the summary's target and sign source differ.
IsgCompensation compensate_etalon(const Machine& m, const CompensationOptions& o);

}  // namespace mtcal
