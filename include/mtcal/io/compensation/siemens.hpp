// Siemens SINUMERIK files for a compensation: the %_N_AX_EEC_INI program of the axis tables and the %_N_NC_CEC_INI
// program of the sag/angularity tables.
#pragma once

#include "mtcal/compensation/siemens.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// AX_EEC.INI: "%_N_AX_EEC_INI", "CHANDATA(1)", per table $AA_ENC_COMP[0,i,AXn]=value (mm, the
// error), $AA_ENC_COMP_STEP/_MIN/_MAX[0,AXn], $AA_ENC_COMP_IS_MODULO[0,AXn]=0, and "M17".
// NC_CEC.INI (when there are CEC tables): "%_N_NC_CEC_INI", "CHANDATA(1)", per table t
// $AN_CEC[t,i]=value (mm, the correction), $AN_CEC_INPUT_AXIS[t]=(AXn), $AN_CEC_OUTPUT_AXIS[t]=(AXm),
// $AN_CEC_STEP/_MIN/_MAX[t], $AN_CEC_DIRECTION[t]=0, $AN_CEC_MULT_BY_TABLE[t]=0,
// $AN_CEC_IS_MODULO[t]=0, and "M17" (the layout of K3 03/2013 4.4.3's example).
TargetOutput siemens_output(const SiemensCompensation& c);

}  // namespace mtcal
