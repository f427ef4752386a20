// A simulated touch probe for LinuxCNC: a HAL component, generated as C, that trips when the stylus tip of a "truth" machine model touches a sphere.
#pragma once

#include <string>
#include <vector>

#include "mtcal/compensation/linuxcnc_kins.hpp"
#include "mtcal/io/compensation/output.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// One reference sphere as the simulated probe sees it: its true centre in the workpiece frame of
// the truth machine (mm) and its diameter (mm).
struct SimulatedSphere {
  Vec3 centre = Vec3::Zero();
  double diameter = 0.0;
};

struct LinuxcncProbeOptions {
  std::string component_name = "mtcal_probe";  // HAL prefix, the .c file name
  std::vector<SimulatedSphere> spheres;          // 1 to kLinuxcncProbeMaxSpheres
  double stylus_diameter = 0.0;                  // the tip ball, mm
};

inline constexpr std::size_t kLinuxcncProbeMaxSpheres = 16;

// The component's C source (C99, a HAL realtime module built with halcompile --install). It holds
// the truth machine's actual chain (linuxcnc_kins_model_source: the same generated data and chain
// evaluation as the kinematics module of --format linuxcnc-kins) and, each servo period, computes
// the stylus tip centre from the joint pins and sets `<name>.out` while the tip is on or inside a
// sphere grown by the stylus radius. Compiled with -DMTCAL_PROBE_STANDALONE it is plain C:
//   int mtp_gap(const double joints[], double tool_length, double* gap, int* sphere, double tip[3])
// (joints in LinuxCNC joint order, mm and deg; gap in mm, < 0 inside; return 0, or -1 for a
// non-finite input or result). Throws InputError for no sphere, too many, or a non-positive or
// non-finite diameter or centre.
std::string linuxcnc_probe_source(const LinuxcncKins& truth, const LinuxcncProbeOptions& o);

// Every file: <name>.c, build.sh (halcompile --install), linuxcnc-probe.hal (loadrt, addf before
// the motion controller, the joint and probe nets), README.txt.
std::vector<TargetFile> linuxcnc_probe_files(const LinuxcncKins& truth, const LinuxcncProbeOptions& o);

// The files of `mtcal linuxcnc-probe`: linuxcnc_probe_files of the truth machine's chain
// (linuxcnc_kins_model named by the component), to be written with write_target_output. Throws as
// linuxcnc_kins_model and linuxcnc_probe_source do.
TargetOutput linuxcnc_probe_output(const Machine& truth, const LinuxcncProbeOptions& o);

// {"machine", "component", "spheres" (their count), "out", "files": [name ...]}: the summary
// `mtcal linuxcnc-probe --json` prints (out: the directory written).
Json linuxcnc_probe_json(const Machine& truth, const LinuxcncProbeOptions& o, const TargetOutput& out,
                         const std::string& dir);

}  // namespace mtcal
