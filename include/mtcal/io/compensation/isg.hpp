// Beckhoff/ISG TF5280 files for a compensation: one ISG CSV file of position errors and component-error blocks.
#pragma once

#include "mtcal/compensation/isg.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// volcomp.csv in the ISG CSV format (TF5280 manual, "ISG CSV format"): '//' comments, a header
// naming arguments and parameters, rows of values, '#' between blocks: first the position errors
// (one row), then per axis "X EXX EYX ..." with one row per position.
TargetOutput isg_output(const IsgCompensation& c);

}  // namespace mtcal
