// Etalon exchange format (vendor variant) for a compensation: the ISG control's model parameters, one block each.
#pragma once

#include <string>

#include "mtcal/compensation/isg.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// The text of an Etalon exchange file (TF5280 manual, "Etalon Exchange Format"): '//' comments,
// a block per parameter headed by its name in square brackets, "VALUE = v" for a position error
// ([C0B]), "Gridpoints = {" rows "argument value" "}" for a component error ([EXY]). Numbers are
// written in their shortest form that reads back as the same double (fmt's "{}").
std::string etalon_text(const IsgCompensation& c);

// volcomp.etalon and README.txt (how the control is told to read it).
TargetOutput etalon_output(const IsgCompensation& c);

}  // namespace mtcal
