// FANUC files for a compensation: a listing of the pitch error compensation parameters and values to key in.
#pragma once

#include "mtcal/compensation/fanuc.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// fanuc-pitch.txt: ';' comments; "PARAMETER <no> <value per axis>" for 3620-3625 (axis columns
// in controlled-axis order, named in a comment); "PITCH <point no> <value>" per compensation point,
// a comment giving its section and axis. README.txt: how to enter them and what to check.
TargetOutput fanuc_output(const FanucCompensation& c);

}  // namespace mtcal
