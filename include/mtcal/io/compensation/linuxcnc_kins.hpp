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
//   int mtk_inverse_offset(const double world[], double tool_length, double tool_offset, double joints[], int* iterations, double* residual)
//   int mtk_forward_offset(const double joints[], double tool_length, double tool_offset, double world[])
// (world: x y z mm and the rotary coordinates in deg in the order of `coordinates`' rotary letters;
// joints in LinuxCNC joint order, mm and deg; return 0 on success) for tests and benchmarks. The
// _offset forms are what kinematicsInverse/Forward call: LinuxCNC's G43 convention (trt-kins), the
// tool tip at world - tool_offset along the tool axis letter, the tool tool_length + tool_offset long
// along the actual tool axis.
std::string linuxcnc_kins_source(const LinuxcncKins& k);

// The machine part of that source, shared with the simulated probe (io/compensation/linuxcnc_probe.hpp):
// the #defines, the generated data (axes, motion functions, the actual chain) and the chain
// evaluation mtk_actual(q, L, p, a). model_only: only what mtk_actual needs (MTK_MODEL_ONLY: no
// solver, no nominal-chain data). Plain C99 with <math.h> or LinuxCNC's rtapi_math.h included before it.
std::string linuxcnc_kins_model_source(const LinuxcncKins& k, bool model_only);

// Text for the generated C (the module's and the simulated probe's): a double written to read back
// bit for bit ("%.17g"), and a name made safe inside a /* */ comment ("*/" broken, control and
// non-ASCII characters as '?').
std::string linuxcnc_c_number(double v);
std::string linuxcnc_c_comment(const std::string& s);

// Every file of --format linuxcnc-kins: <module>.c, build.sh, linuxcnc-kins.ini, linuxcnc-kins.hal,
// joint<N>-reversal.comp per joint with direction-dependent terms, README.txt.
TargetOutput linuxcnc_kins_output(const LinuxcncKins& k);

}  // namespace mtcal
