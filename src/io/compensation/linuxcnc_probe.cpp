#include "mtcal/io/compensation/linuxcnc_probe.hpp"

#include <cmath>

#include <fmt/format.h>

#include "mtcal/io/compensation/linuxcnc_kins.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

void check(const LinuxcncProbeOptions& o) {
  const std::string where = "simulated probe";
  if (o.spheres.empty() || o.spheres.size() > kLinuxcncProbeMaxSpheres)
    throw InputError({where, 0, "spheres"}, fmt::format("expected 1 to {} spheres, found {}", kLinuxcncProbeMaxSpheres,
                                                        o.spheres.size()));
  for (std::size_t i = 0; i < o.spheres.size(); ++i) {
    const auto& s = o.spheres[i];
    if (!s.centre.allFinite() || s.centre.cwiseAbs().maxCoeff() > 1e6)
      throw InputError({where, 0, fmt::format("sphere {}", i + 1)},
                       "expected a finite centre within +-1e6 mm, found a non-finite or huge coordinate");
    if (!(s.diameter > 0) || !std::isfinite(s.diameter) || s.diameter > 1e4)
      throw InputError({where, 0, fmt::format("sphere {} diameter", i + 1)},
                       fmt::format("expected a diameter > 0 and <= 1e4 mm, found {:g}", s.diameter));
  }
  if (!(o.stylus_diameter >= 0) || !std::isfinite(o.stylus_diameter) || o.stylus_diameter > 1e3)
    throw InputError({where, 0, "stylus diameter"},
                     fmt::format("expected a diameter >= 0 and <= 1e3 mm, found {:g}", o.stylus_diameter));
  if (o.component_name != "mtcal_probe")  // the HAL names below are written for this one
    throw InputError({where, 0, "component name"}, "expected mtcal_probe, found '" + printable(o.component_name) + "'");
}

}  // namespace

std::string linuxcnc_probe_source(const LinuxcncKins& truth, const LinuxcncProbeOptions& o) {
  check(o);
  const std::string& name = o.component_name;
  std::string s = fmt::format(
      "/* HAL component {0}: a simulated touch probe, written by mtcal linuxcnc-probe.\n"
      " * Truth machine: {1} (topology {2}); joints {3} (LinuxCNC joint n is the n-th letter, mm and deg).\n"
      " * Each servo period {0}.update computes the stylus tip centre from the joint pins through the truth\n"
      " * machine's ACTUAL chain (its whole error model at direction of motion 0: the same generated data and\n"
      " * chain evaluation as the kinematics module of mtcal compensate --format linuxcnc-kins) and sets\n"
      " * {0}.out while the tip centre is on or inside a sphere grown by the stylus radius (the tip ball touches\n"
      " * the sphere). Connect {0}.out to motion.probe-input; run {0}.update before motion-controller.\n"
      " * A non-finite joint or result sets {0}.fault and holds {0}.out on (a probing move stops).\n"
      " * Real time: no allocation, no file access, a fixed loop over {4} sphere(s).\n"
      " * Build: halcompile --install {0}.c (Debian package linuxcnc-uspace-dev). docs/planning.md\n"
      " * Without LinuxCNC (-DMTCAL_PROBE_STANDALONE): mtp_gap() as plain C for tests.\n"
      " */\n"
      "#ifdef MTCAL_PROBE_STANDALONE\n#include <math.h>\n#else\n"
      "#include \"rtapi.h\"\n#include \"rtapi_app.h\"\n#include \"rtapi_math.h\"\n#include \"hal.h\"\n#endif\n\n",
      name, linuxcnc_c_comment(truth.machine_name), linuxcnc_c_comment(truth.topology), truth.coordinates, o.spheres.size());
  s += linuxcnc_kins_model_source(truth, true);
  std::string centres, radii;
  for (const auto& sp : o.spheres) {
    centres += fmt::format("{}{{{}, {}, {}}}", centres.empty() ? "" : ", ", linuxcnc_c_number(sp.centre.x()), linuxcnc_c_number(sp.centre.y()),
                           linuxcnc_c_number(sp.centre.z()));
    radii += fmt::format("{}{}", radii.empty() ? "" : ", ", linuxcnc_c_number((sp.diameter + o.stylus_diameter) / 2));
  }
  s += fmt::format(
      "\n/* ---- The probe ---- */\n"
      "#define MTP_NS {0}\n"
      "/* Sphere centres in the truth machine's workpiece frame (mm), and the tip centre's distance at\n"
      "   contact: (sphere diameter + stylus diameter) / 2, stylus diameter {3} mm. */\n"
      "static const double mtp_centre[MTP_NS][3] = {{{1}}};\n"
      "static const double mtp_contact[MTP_NS] = {{{2}}};\n\n"
      "/* The gap (mm) between the stylus tip ball and the nearest sphere (< 0: overlapping), that sphere\n"
      "   (0-based) and the tip centre (workpiece frame), at LinuxCNC joints (mm, deg) and tool length L\n"
      "   (mm from the spindle gauge point to the tip centre). Returns -1 for a non-finite input or result. */\n"
      "static int mtp_gap(const double joints[], double L, double *gap, int *sphere, double tip[3])\n"
      "{{\n"
      "    double q[MTK_N], a[3], best = 0.0;\n"
      "    int k, i;\n"
      "    for (k = 0; k < MTK_N; ++k) {{\n"
      "        const double v = joints[mtk_joint[k]];\n"
      "        if (!(v == v) || fabs(v) > 1e9) return -1;\n"
      "        q[k] = mtk_is_rotary[k] ? v * (mtk_pi / 180.0) : v;\n"
      "    }}\n"
      "    if (!(L == L) || fabs(L) > 1e6) return -1;\n"
      "    mtk_actual(q, L, tip, a);\n"
      "    for (i = 0; i < 3; ++i)\n"
      "        if (!(tip[i] == tip[i]) || fabs(tip[i]) > 1e30) return -1;\n"
      "    *sphere = -1;\n"
      "    for (k = 0; k < MTP_NS; ++k) {{\n"
      "        const double dx = tip[0] - mtp_centre[k][0], dy = tip[1] - mtp_centre[k][1], dz = tip[2] - mtp_centre[k][2];\n"
      "        const double g = sqrt(dx * dx + dy * dy + dz * dz) - mtp_contact[k];\n"
      "        if (*sphere < 0 || g < best) {{\n"
      "            best = g;\n"
      "            *sphere = k;\n"
      "        }}\n"
      "    }}\n"
      "    *gap = best;\n"
      "    return 0;\n"
      "}}\n",
      o.spheres.size(), centres, radii, linuxcnc_c_number(o.stylus_diameter));
  std::string pins, reads;
  for (std::size_t j = 0; j < truth.coordinates.size(); ++j)
    pins += fmt::format("    r += hal_pin_float_newf(HAL_IN, &(mtp_hal->joint[{0}]), mtp_comp_id, \"{1}.joint-{0}\");\n", j,
                        name);
  s += fmt::format(
      "\n#ifndef MTCAL_PROBE_STANDALONE\n"
      "/* ---- HAL (modelled on LinuxCNC's src/hal/components: hal_init, hal_malloc, pins, hal_export_funct) ---- */\n"
      "struct mtp_hal_data {{\n"
      "    hal_float_t *joint[MTK_N];  /* in: joint positions, LinuxCNC joint order (mm, deg) */\n"
      "    hal_float_t *tool_length;   /* in: mm from the spindle gauge point to the tip centre */\n"
      "    hal_bit_t *out;             /* out: the probe is tripped (to motion.probe-input) */\n"
      "    hal_bit_t *fault;           /* out: a non-finite joint or result (out is held on) */\n"
      "    hal_float_t *gap;           /* out: mm between tip ball and the nearest sphere, < 0 overlapping */\n"
      "    hal_s32_t *sphere;          /* out: that sphere, 0-based */\n"
      "    hal_float_t *tip[3];        /* out: tip centre, truth workpiece frame (mm) */\n"
      "}};\n"
      "static struct mtp_hal_data *mtp_hal;\n"
      "static int mtp_comp_id;\n\n"
      "static void mtp_update(void *arg, long period)\n"
      "{{\n"
      "    double j[MTK_N], tip[3] = {{0.0, 0.0, 0.0}}, gap = 0.0;\n"
      "    int k, sphere = -1;\n"
      "    (void)arg;\n    (void)period;\n"
      "    for (k = 0; k < MTK_N; ++k) j[k] = *(mtp_hal->joint[k]);\n"
      "    if (mtp_gap(j, *(mtp_hal->tool_length), &gap, &sphere, tip) != 0) {{\n"
      "        *(mtp_hal->fault) = 1;\n"
      "        *(mtp_hal->out) = 1;\n"
      "        return;\n"
      "    }}\n"
      "    *(mtp_hal->fault) = 0;\n"
      "    *(mtp_hal->out) = gap <= 0.0;\n"
      "    *(mtp_hal->gap) = gap;\n"
      "    *(mtp_hal->sphere) = sphere;\n"
      "    for (k = 0; k < 3; ++k) *(mtp_hal->tip[k]) = tip[k];\n"
      "}}\n\n"
      "MODULE_LICENSE(\"GPL\");\n\n"
      "int rtapi_app_main(void)\n"
      "{{\n"
      "    int r = 0, k;\n"
      "    mtp_comp_id = hal_init(\"{0}\");\n"
      "    if (mtp_comp_id < 0) return mtp_comp_id;\n"
      "    mtp_hal = hal_malloc(sizeof(struct mtp_hal_data));\n"
      "    if (!mtp_hal) {{\n        hal_exit(mtp_comp_id);\n        return -1;\n    }}\n"
      "{1}"
      "    r += hal_pin_float_newf(HAL_IN, &(mtp_hal->tool_length), mtp_comp_id, \"{0}.tool-length\");\n"
      "    r += hal_pin_bit_newf(HAL_OUT, &(mtp_hal->out), mtp_comp_id, \"{0}.out\");\n"
      "    r += hal_pin_bit_newf(HAL_OUT, &(mtp_hal->fault), mtp_comp_id, \"{0}.fault\");\n"
      "    r += hal_pin_float_newf(HAL_OUT, &(mtp_hal->gap), mtp_comp_id, \"{0}.gap\");\n"
      "    r += hal_pin_s32_newf(HAL_OUT, &(mtp_hal->sphere), mtp_comp_id, \"{0}.sphere\");\n"
      "    r += hal_pin_float_newf(HAL_OUT, &(mtp_hal->tip[0]), mtp_comp_id, \"{0}.tip-x\");\n"
      "    r += hal_pin_float_newf(HAL_OUT, &(mtp_hal->tip[1]), mtp_comp_id, \"{0}.tip-y\");\n"
      "    r += hal_pin_float_newf(HAL_OUT, &(mtp_hal->tip[2]), mtp_comp_id, \"{0}.tip-z\");\n"
      "    if (r == 0) r = hal_export_funct(\"{0}.update\", mtp_update, 0, 1, 0, mtp_comp_id);\n"
      "    if (r != 0) {{\n        hal_exit(mtp_comp_id);\n        return -1;\n    }}\n"
      "    for (k = 0; k < MTK_N; ++k) *(mtp_hal->joint[k]) = 0.0;\n"
      "    *(mtp_hal->tool_length) = MTK_TOOL_LENGTH;\n"
      "    *(mtp_hal->out) = 0;\n    *(mtp_hal->fault) = 0;\n    *(mtp_hal->gap) = 0.0;\n    *(mtp_hal->sphere) = -1;\n"
      "    for (k = 0; k < 3; ++k) *(mtp_hal->tip[k]) = 0.0;\n"
      "    hal_ready(mtp_comp_id);\n"
      "    return 0;\n"
      "}}\n\n"
      "void rtapi_app_exit(void)\n{{\n    hal_exit(mtp_comp_id);\n}}\n"
      "#endif\n",
      name, pins);
  return s;
}

std::vector<TargetFile> linuxcnc_probe_files(const LinuxcncKins& truth, const LinuxcncProbeOptions& o) {
  std::vector<TargetFile> files;
  files.push_back({o.component_name + ".c", linuxcnc_probe_source(truth, o)});
  files.push_back(
      {"build.sh",
       fmt::format("#!/bin/sh\n"
                   "# Builds and installs the simulated-probe HAL component {0} (written by mtcal linuxcnc-probe).\n"
                   "# Needs Debian's linuxcnc-uspace-dev (halcompile, hal.h, Makefile.modinc); root to install.\n"
                   "set -e\n"
                   "command -v halcompile >/dev/null 2>&1 || {{ echo \"halcompile not found: install Debian's "
                   "linuxcnc-uspace-dev\" >&2; exit 1; }}\n"
                   "[ -f /usr/include/linuxcnc/hal.h ] || {{ echo \"/usr/include/linuxcnc/hal.h not found: install "
                   "Debian's linuxcnc-uspace-dev\" >&2; exit 1; }}\n"
                   "cd \"$(dirname \"$0\")\"\n"
                   "halcompile --install {0}.c\n",
                   o.component_name)});
  std::string joints;
  for (std::size_t j = 0; j < truth.coordinates.size(); ++j)
    joints += fmt::format("#   net <signal of joint.{0}.motor-pos-fb> => {1}.joint-{0}    ({2})\n", j, o.component_name,
                          truth.coordinates[j]);
  files.push_back(
      {"linuxcnc-probe.hal",
       fmt::format("# Written by mtcal linuxcnc-probe: the simulated probe {0} of a truth machine ({1}).\n"
                   "# Its update runs first in the servo thread, before motion-controller, so that the motion\n"
                   "# controller sees the trip in the cycle whose joint feedback caused it.\n"
                   "loadrt {0}\n"
                   "addf {0}.update servo-thread 1\n"
                   "net mtcal-probe-trip {0}.out => motion.probe-input\n"
                   "setp {0}.tool-length {2:.9f}\n"
                   "# The joints: add {0}.joint-N to the signal that feeds joint.N.motor-pos-fb (the physical\n"
                   "# joint position; in a sim configuration the loop-back of joint.N.motor-pos-cmd):\n"
                   "{3}",
                   o.component_name, linuxcnc_c_comment(truth.machine_name), truth.tool_length, joints)});
  files.push_back(
      {"README.txt",
       fmt::format("Simulated touch probe for LinuxCNC, written by mtcal linuxcnc-probe.\n"
                   "Truth machine: {}.\n\n"
                   "  {}.c           the HAL component (C; the truth model and the spheres are in it)\n"
                   "  build.sh              halcompile --install (needs Debian's linuxcnc-uspace-dev)\n"
                   "  linuxcnc-probe.hal    loadrt, addf, the probe net; the joint nets to complete\n\n"
                   "docs/planning.md in mtcal: the LinuxCNC run, the trip's quantisation by the servo period.\n",
                   linuxcnc_c_comment(truth.machine_name), o.component_name)});
  return files;
}

TargetOutput linuxcnc_probe_output(const Machine& truth, const LinuxcncProbeOptions& o) {
  TargetOutput out;
  out.files = linuxcnc_probe_files(linuxcnc_kins_model(truth, o.component_name), o);
  return out;
}

Json linuxcnc_probe_json(const Machine& truth, const LinuxcncProbeOptions& o, const TargetOutput& out,
                         const std::string& dir) {
  Json j;
  j["machine"] = truth.name;
  j["component"] = o.component_name;
  j["spheres"] = o.spheres.size();
  j["out"] = dir;
  for (const auto& f : out.files) j["files"].push_back(f.name);
  return j;
}

}  // namespace mtcal
