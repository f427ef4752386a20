// LinuxCNC's files for a compensation: COMP_FILE tables, the INI snippet that loads them, the trt-kins HAL pins.
#pragma once

#include "mtcal/compensation/linuxcnc.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// <axis>.comp per table (lines "nominal forward reverse", nine decimals, no header, comment or
// blank line: usrmotLoadComp() stops silently at the first line that is not three numbers),
// linuxcnc.ini ([JOINT_n] COMP_FILE / COMP_FILE_TYPE, [KINS], [TRAJ] COORDINATES, [HAL] HALFILE)
// and, with trt kinematics, linuxcnc-kins.hal (setp lines).
TargetOutput linuxcnc_output(const LinuxcncCompensation& c);

}  // namespace mtcal
