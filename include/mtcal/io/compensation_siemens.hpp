// Siemens SINUMERIK files for a compensation: the %_N_AX_EEC_INI program of the axis tables.
#pragma once

#include "mtcal/compensation/siemens.hpp"
#include "mtcal/io/compensation_output.hpp"

namespace mtcal {

// AX_EEC.INI: "%_N_AX_EEC_INI", "CHANDATA(1)", per table $AA_ENC_COMP[0,i,AXn]=value (mm, the
// error), $AA_ENC_COMP_STEP/_MIN/_MAX[0,AXn], $AA_ENC_COMP_IS_MODULO[0,AXn]=0, and "M17".
TargetOutput siemens_output(const SiemensCompensation& c);

}  // namespace mtcal
