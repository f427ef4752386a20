// LinuxCNC kinematics module files: the C source with the machine's coefficients, its build line, INI/HAL snippets, COMP_FILE tables.
#pragma once

#include <string>

#include "mtcal/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/output.hpp"

namespace mtcal {

// The module's C source (C99; LinuxCNC 2.9's kinematics.h API). Compiled with
// -DMTCAL_KINS_STANDALONE it is plain C with no LinuxCNC header: the functions
//   int mtk_inverse(const double world[], double tool_length, double joints[], int* iterations, double* residual)
//   int mtk_forward(const double joints[], double tool_length, double world[])
// (world: x y z mm and the rotary coordinates in deg in the order of `coordinates`' rotary letters;
// joints in LinuxCNC joint order, mm and deg; return 0 on success) for tests and benchmarks.
std::string linuxcnc_kins_source(const LinuxcncKins& k);

// Every file of --format linuxcnc-kins: <module>.c, build.sh, linuxcnc-kins.ini, linuxcnc-kins.hal,
// joint<N>-reversal.comp per joint with direction-dependent terms, README.txt.
TargetOutput linuxcnc_kins_output(const LinuxcncKins& k);

}  // namespace mtcal
