#include "mtcal/io/compensation/linuxcnc_kins.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <variant>

#include <fmt/format.h>

namespace mtcal {

std::string linuxcnc_c_number(double v) { return fmt::format("{:.17g}", v); }

std::string linuxcnc_c_comment(const std::string& s) {
  std::string out = s;
  for (std::size_t p; (p = out.find("*/")) != std::string::npos;) out.replace(p, 2, "* /");
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return out;
}

namespace {

// The machine-independent C (chain evaluation, inverse, forward).
constexpr const char* kCore =
#include "linuxcnc_kins_core.inc"
    ;

std::string list(const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + linuxcnc_c_number(v[i]);
  return s;
}

// Data of one motion function: {kind, n, ncos, x, v} (see struct mtk_fn).
std::string function_data(const MotionFunction& f, const std::string& id, std::string& arrays) {
  return std::visit(
      [&](const auto& form) -> std::string {
        using F = std::decay_t<decltype(form)>;
        if (f.is_zero()) return "{0, 0, 0, 0, 0}";
        if constexpr (std::is_same_v<F, Polynomial>) {
          arrays += fmt::format("static const double {}_v[4] = {{{}}};\n", id,
                                list({form.coefficients.begin(), form.coefficients.end()}));
          return fmt::format("{{1, 4, 0, 0, {}_v}}", id);
        } else if constexpr (std::is_same_v<F, Table>) {
          arrays += fmt::format("static const double {}_x[{}] = {{{}}};\n", id, form.positions.size(), list(form.positions));
          arrays += fmt::format("static const double {}_v[{}] = {{{}}};\n", id, form.forward.size(), list(form.forward));
          return fmt::format("{{2, {}, 0, {}_x, {}_v}}", form.positions.size(), id, id);
        } else {
          std::vector<double> v{form.constant};
          v.insert(v.end(), form.cos_terms.begin(), form.cos_terms.end());
          v.insert(v.end(), form.sin_terms.begin(), form.sin_terms.end());
          arrays += fmt::format("static const double {}_v[{}] = {{{}}};\n", id, v.size(), list(v));
          return fmt::format("{{3, {}, {}, 0, {}_v}}", form.sin_terms.size(), form.cos_terms.size(), id);
        }
      },
      f.form());
}

std::string affine_data(const Affine& a) {
  std::vector<double> R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.push_back(a.R(i, j));
  return fmt::format("{{{}}}, {{{}}}", list(R), list({a.t.x(), a.t.y(), a.t.z()}));
}

std::string unit_name(const KinsAxis& a) { return a.rotary ? "deg" : "mm"; }
double to_joint_units(const KinsAxis& a, double v) { return a.rotary ? v * 180.0 / std::numbers::pi : v; }
// The world letter G43's offset comes on: the machine axis the tool points along at rotary zero.
char tool_axis_letter(const LinuxcncKins& k) { return "xyz"[std::clamp(k.tool_axis, 0, 2)]; }

}  // namespace

std::string linuxcnc_kins_model_source(const LinuxcncKins& k, bool model_only) {
  const std::size_t n = k.axes.size();
  std::vector<int> linear, rotary, rotary_world;
  std::string rotary_letters;
  for (const char c : k.coordinates)
    if (c == 'A' || c == 'B' || c == 'C') rotary_letters += c;
  for (std::size_t i = 0; i < n; ++i) {
    if (k.axes[i].rotary) {
      rotary.push_back(static_cast<int>(i));
      rotary_world.push_back(static_cast<int>(rotary_letters.find(k.axes[i].letter)));
    } else {
      linear.push_back(static_cast<int>(i));
    }
  }
  const std::size_t nr = rotary.size();
  auto ints = [](const std::vector<int>& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return v.empty() ? std::string("0") : s;
  };
  std::string s = model_only ? "#define MTK_MODEL_ONLY /* the actual chain only: no solver, no nominal-chain data */\n" : "";
  s += fmt::format("#define MTK_N {}\n#define MTK_NR {}\n#define MTK_NOPS {}\n#define MTK_MAX_ITER {}\n", n, nr,
                   k.chain.size(), k.solver.max_iterations);
  s += fmt::format("#define MTK_TOL_POINT {} /* mm */\n#define MTK_TOL_ORIENT {}\n#define MTK_DAMPING2 {} /* rad^2 */\n",
                   linuxcnc_c_number(k.solver.point_tolerance), linuxcnc_c_number(k.solver.orientation_tolerance),
                   linuxcnc_c_number(k.solver.orientation_damping * k.solver.orientation_damping));
  s += fmt::format("#define MTK_TOOL_AXIS {}\n#define MTK_TOOL_LENGTH {} /* mm, the machine file's */\n\n", k.tool_axis,
                   linuxcnc_c_number(k.tool_length));
  std::vector<int> joint, is_rotary, dir_axis;
  std::vector<double> dir_sign, zero;
  std::string points;
  for (const auto& a : k.axes) {
    joint.push_back(a.joint);
    is_rotary.push_back(a.rotary ? 1 : 0);
    dir_axis.push_back(a.direction_axis);
    dir_sign.push_back(a.direction_sign);
    zero.push_back(a.zero_position);
    const Vec3 p = a.rotary ? a.point : Vec3::Zero();
    points += fmt::format("{}{{{}}}", points.empty() ? "" : ", ", list({p.x(), p.y(), p.z()}));
  }
  std::string letters;
  for (const auto& a : k.axes) letters += a.letter;
  s += fmt::format("/* Axes in chain order (workpiece to tool): {} */\n", letters);
  s += fmt::format("static const int mtk_joint[MTK_N] = {{{}}};\n", ints(joint));
  s += fmt::format("static const int mtk_is_rotary[MTK_N] = {{{}}};\n", ints(is_rotary));
  s += fmt::format("static const int mtk_dir_axis[MTK_N] = {{{}}};\n", ints(dir_axis));
  s += fmt::format("static const double mtk_dir_sign[MTK_N] = {{{}}};\n", list(dir_sign));
  s += fmt::format("static const double mtk_zero[MTK_N] = {{{}}}; /* zero positions (mm, rad) */\n", list(zero));
  if (!model_only) {  // the nominal chain and the solver's index lists
    s += fmt::format("static const double mtk_point[MTK_N][3] = {{{}}}; /* rotary axis lines */\n", points);
    s += fmt::format("static const int mtk_linear[3] = {{{}}};\n", ints(linear));
    s += fmt::format("static const int mtk_rot[MTK_NR + 1] = {{{}}};\n", ints(rotary));
    s += fmt::format("static const int mtk_rot_world[MTK_NR + 1] = {{{}}}; /* index among the rotary letters {} */\n",
                     ints(rotary_world), rotary_letters.empty() ? "(none)" : rotary_letters);
    s += fmt::format("static const double mtk_w_origin[3] = {{{}}};\n",
                     list({k.workpiece_origin.x(), k.workpiece_origin.y(), k.workpiece_origin.z()}));
    s += fmt::format("static const double mtk_spindle[3] = {{{}}};\n\n",
                     list({k.spindle_point.x(), k.spindle_point.y(), k.spindle_point.z()}));
  }
  // Motion errors at direction 0, internal units (mm, rad; argument mm or rad).
  s += "/* Motion errors (dir 0) per axis: EX EY EZ (mm) EA EB EC (rad) of the axis position (mm, rad).\n"
       "   kind 1 polynomial v[0..3]; 2 table x[n], v[n], held ends; 3 Fourier v[0] + ncos cos + n sin terms. */\n"
       "struct mtk_fn {\n    int kind, n, ncos;\n    const double *x, *v;\n};\n";
  std::string arrays, table = "static const struct mtk_fn mtk_motion[MTK_N][6] = {\n";
  for (std::size_t i = 0; i < n; ++i) {
    table += "    {";
    for (int c = 0; c < 6; ++c)
      table += (c ? ", " : "") +
               function_data(k.axes[i].motion[static_cast<std::size_t>(c)], fmt::format("mtk_f{}{}", i, c), arrays);
    table += i + 1 < n ? "},\n" : "}\n";
  }
  s += arrays + table + "};\n\n";
  s += "/* The actual chain, workpiece to spindle gauge point: 0 constant, 1 joint, 2 motion errors of an axis. */\n"
       "struct mtk_op {\n    int kind, axis;\n    double R[9], t[3];\n};\n"
       "static const struct mtk_op mtk_chain[MTK_NOPS] = {\n";
  for (std::size_t i = 0; i < k.chain.size(); ++i) {
    const auto& f = k.chain[i];
    const int kind = f.kind == KinsFactor::Kind::Constant ? 0 : f.kind == KinsFactor::Kind::Joint ? 1 : 2;
    s += fmt::format("    {{{}, {}, {}}}{}\n", kind, f.axis,
                     f.kind == KinsFactor::Kind::Constant ? affine_data(f.value) : "{0}, {0}",
                     i + 1 < k.chain.size() ? "," : "");
  }
  s += "};\n";
  s += kCore;
  return s;
}

std::string linuxcnc_kins_source(const LinuxcncKins& k) {
  std::string rotary_letters;
  for (const char c : k.coordinates)
    if (c == 'A' || c == 'B' || c == 'C') rotary_letters += c;
  std::string s = fmt::format(
      "/* LinuxCNC kinematics module {0}, written by mtcal compensate --format linuxcnc-kins.\n"
      " * Machine: {1} (topology {2}); joints {3} (joint n is the n-th letter, mm and deg).\n"
      " * kinematicsInverse returns the joints at which the machine's error model puts the ACTUAL tool point on\n"
      " * the commanded one (error e = actual - nominal, ISO 230-1; the joints carry the correction -e), and\n"
      " * turns the rotary axes so that the actual tool direction is the commanded one as far as they can\n"
      " * (damped least squares); kinematicsForward is its exact inverse. World coordinates: the tool point in\n"
      " * the workpiece frame and the rotary coordinates (tool-centre-point convention of LinuxCNC's trt kins).\n"
      " * Tool length as LinuxCNC's trt kins take it: with G43 the world {5} LinuxCNC passes includes the tool length\n"
      " * offset; the pin tool-offset (motion.tooloffset.{6}) is subtracted from it, and the tip lies tool-length +\n"
      " * tool-offset from the spindle gauge point along the ACTUAL tool axis (mtk_inverse_offset below).\n"
      " * Real time: no allocation, no file access, at most {4} steps; a non-finite or unconverged result is an\n"
      " * error (motion stops) and never a position. Coefficients are generated into this file: nothing is read\n"
      " * at load time, so the module and the model it was checked against cannot drift apart.\n"
      " * Build: halcompile --install {0}.c (Debian package linuxcnc-uspace-dev). docs/compensation-linuxcnc-kins.md\n"
      " * Without LinuxCNC (-DMTCAL_KINS_STANDALONE): mtk_inverse(), mtk_forward() and their _offset forms as plain C\n"
      " * for tests.\n"
      " */\n"
      "#ifdef MTCAL_KINS_STANDALONE\n#include <math.h>\n#else\n"
      "#include \"rtapi.h\"\n#include \"rtapi_app.h\"\n#include \"rtapi_math.h\"\n#include \"hal.h\"\n"
      "#include \"kinematics.h\"\n#endif\n\n",
      k.module_name, linuxcnc_c_comment(k.machine_name), linuxcnc_c_comment(k.topology), k.coordinates, k.solver.max_iterations,
      static_cast<char>(std::toupper(tool_axis_letter(k))), tool_axis_letter(k));
  s += linuxcnc_kins_model_source(k, false);
  // LinuxCNC glue (kinematics.h of LinuxCNC 2.9; modelled on src/emc/kinematics/maxkins.c and trtfuncs.c).
  std::string world_in, world_out;
  for (std::size_t j = 0; j < rotary_letters.size(); ++j) {
    const char l = static_cast<char>(std::tolower(rotary_letters[j]));
    world_in += fmt::format("    w[{}] = pos->{};\n", 3 + j, l);
    world_out += fmt::format("    pos->{} = w[{}];\n", l, 3 + j);
  }
  // The refused pose on LinuxCNC's log: "X=... Y=... Z=... A=... C=..." (mm, deg) with six decimals
  // written from integers (a kernel-space RTAPI prints no floating point).
  std::string pose_format, pose_args;
  const std::string world_letters = "XYZ" + rotary_letters;
  for (std::size_t j = 0; j < world_letters.size(); ++j) {
    pose_format += fmt::format("{}{}=%s%ld.%06ld", j ? " " : "", world_letters[j]);
    pose_args += fmt::format(", mtk_sign(w[{0}]), mtk_whole(w[{0}]), mtk_micro(w[{0}])", j);
  }
  s += fmt::format(
      "\n#ifndef MTCAL_KINS_STANDALONE\n"
      "/* ---- LinuxCNC interface (kinematics.h) ---- */\n"
      "struct mtk_hal_data {{\n"
      "    hal_float_t *tool_length; /* in: mm from the spindle gauge point that the tool offset does not hold */\n"
      "    hal_float_t *tool_offset; /* in: G43's tool length offset, motion.tooloffset.{3} */\n"
      "    hal_s32_t *iterations;    /* out: steps of the last inverse */\n"
      "    hal_float_t *residual;    /* out: mm, tool point residual of the last inverse */\n"
      "    hal_u32_t *failures;      /* out: inverses refused (non-finite or unconverged) */\n"
      "}};\n"
      "static struct mtk_hal_data *mtk_hal;\n"
      "static int mtk_reported; /* the failure since the last inverse that succeeded is on the log */\n\n"
      "/* A value as sign, whole part and millionths, for messages (values beyond 1e9 or non-finite: 999999999). */\n"
      "static const char *mtk_sign(double v)\n{{\n    return v < 0.0 ? \"-\" : \"\";\n}}\n"
      "static long mtk_whole(double v)\n{{\n    double a = fabs(v);\n"
      "    if (!(a < 1e9)) return 999999999L;\n"
      "    return (long)a + ((a - (double)(long)a) * 1e6 + 0.5 >= 1e6 ? 1L : 0L);\n}}\n"
      "static long mtk_micro(double v)\n{{\n    double a = fabs(v);\n    long u;\n"
      "    if (!(a < 1e9)) return 0L;\n"
      "    u = (long)((a - (double)(long)a) * 1e6 + 0.5);\n"
      "    return u >= 1000000L ? u - 1000000L : u;\n}}\n\n"
      "int kinematicsForward(const double *joints, EmcPose *pos, const KINEMATICS_FORWARD_FLAGS *fflags,\n"
      "                      KINEMATICS_INVERSE_FLAGS *iflags)\n"
      "{{\n"
      "    double w[3 + MTK_NR];\n"
      "    (void)fflags;\n    (void)iflags;\n"
      "    if (mtk_forward_offset(joints, *(mtk_hal->tool_length), *(mtk_hal->tool_offset), w) != 0) return -1;\n"
      "    pos->tran.x = w[0];\n    pos->tran.y = w[1];\n    pos->tran.z = w[2];\n"
      "    pos->a = pos->b = pos->c = 0.0;\n    pos->u = pos->v = pos->w = 0.0;\n"
      "{1}"
      "    return 0;\n"
      "}}\n\n"
      "int kinematicsInverse(const EmcPose *pos, double *joints, const KINEMATICS_INVERSE_FLAGS *iflags,\n"
      "                      KINEMATICS_FORWARD_FLAGS *fflags)\n"
      "{{\n"
      "    double w[3 + MTK_NR], q[MTK_N], residual;\n"
      "    int iterations, k;\n"
      "    (void)iflags;\n    (void)fflags;\n"
      "    w[0] = pos->tran.x;\n    w[1] = pos->tran.y;\n    w[2] = pos->tran.z;\n"
      "{2}"
      "    k = mtk_inverse_offset(w, *(mtk_hal->tool_length), *(mtk_hal->tool_offset), q, &iterations, &residual);\n"
      "    *(mtk_hal->iterations) = iterations;\n"
      "    *(mtk_hal->residual) = residual;\n"
      "    if (k != 0) {{\n        *(mtk_hal->failures) += 1;\n"
      "        /* LinuxCNC stops the motion and says \"kinematicsInverse failed\"; the module says where, once. */\n"
      "        if (!mtk_reported)\n"
      "            rtapi_print_msg(RTAPI_MSG_ERR, \"{0}: no joints for the commanded pose {4} (mm, deg): %s after %d \"\n"
      "                            \"steps (cap %d), tool point residual %s%ld.%06ld mm\\n\"{5},\n"
      "                            k == -2 ? \"the inverse did not converge\" : k == -3 ? \"a singular step\" : \"a non-finite value\",\n"
      "                            iterations, MTK_MAX_ITER, mtk_sign(residual), mtk_whole(residual), mtk_micro(residual));\n"
      "        mtk_reported = 1;\n"
      "        return -1;\n    }}\n"
      "    mtk_reported = 0;\n"
      "    for (k = 0; k < MTK_N; ++k) joints[k] = q[k];\n"
      "    return 0;\n"
      "}}\n\n"
      "KINEMATICS_TYPE kinematicsType(void)\n{{\n    return KINEMATICS_BOTH;\n}}\n\n"
      "KINS_NOT_SWITCHABLE\n"
      "EXPORT_SYMBOL(kinematicsType);\nEXPORT_SYMBOL(kinematicsForward);\nEXPORT_SYMBOL(kinematicsInverse);\n"
      "MODULE_LICENSE(\"GPL\");\n\n"
      "static int mtk_comp_id;\n\n"
      "int rtapi_app_main(void)\n"
      "{{\n"
      "    int r = 0;\n"
      "    mtk_comp_id = hal_init(\"{0}\");\n"
      "    if (mtk_comp_id < 0) return mtk_comp_id;\n"
      "    mtk_hal = hal_malloc(sizeof(struct mtk_hal_data));\n"
      "    if (!mtk_hal) {{\n        hal_exit(mtk_comp_id);\n        return -1;\n    }}\n"
      "    r += hal_pin_float_newf(HAL_IN, &(mtk_hal->tool_length), mtk_comp_id, \"{0}.tool-length\");\n"
      "    r += hal_pin_float_newf(HAL_IN, &(mtk_hal->tool_offset), mtk_comp_id, \"{0}.tool-offset\");\n"
      "    r += hal_pin_s32_newf(HAL_OUT, &(mtk_hal->iterations), mtk_comp_id, \"{0}.iterations\");\n"
      "    r += hal_pin_float_newf(HAL_OUT, &(mtk_hal->residual), mtk_comp_id, \"{0}.residual\");\n"
      "    r += hal_pin_u32_newf(HAL_OUT, &(mtk_hal->failures), mtk_comp_id, \"{0}.failures\");\n"
      "    if (r != 0) {{\n        hal_exit(mtk_comp_id);\n        return -1;\n    }}\n"
      "    *(mtk_hal->tool_length) = 0.0; /* G49: the gauge point; G43 brings the tool's length (tool-offset) */\n"
      "    *(mtk_hal->tool_offset) = 0.0;\n"
      "    *(mtk_hal->iterations) = 0;\n    *(mtk_hal->residual) = 0.0;\n    *(mtk_hal->failures) = 0;\n"
      "    hal_ready(mtk_comp_id);\n"
      "    return 0;\n"
      "}}\n\n"
      "void rtapi_app_exit(void)\n{{\n    hal_exit(mtk_comp_id);\n}}\n"
      "#endif\n",
      k.module_name, world_out, world_in, tool_axis_letter(k), pose_format, pose_args);
  return s;
}

TargetOutput linuxcnc_kins_output(const LinuxcncKins& k) {
  TargetOutput out;
  out.summary = k.summary;
  out.files.push_back({k.module_name + ".c", linuxcnc_kins_source(k)});
  out.files.push_back(
      {"build.sh",
       fmt::format("#!/bin/sh\n"
                   "# Builds and installs the kinematics module {0} (written by mtcal compensate --format "
                   "linuxcnc-kins).\n"
                   "# Needs Debian's linuxcnc-uspace-dev (halcompile, kinematics.h, Makefile.modinc); root to install.\n"
                   "set -e\n"
                   "command -v halcompile >/dev/null 2>&1 || {{ echo \"halcompile not found: install Debian's "
                   "linuxcnc-uspace-dev\" >&2; exit 1; }}\n"
                   "[ -f /usr/include/linuxcnc/kinematics.h ] || {{ echo \"/usr/include/linuxcnc/kinematics.h not "
                   "found: install Debian's linuxcnc-uspace-dev\" >&2; exit 1; }}\n"
                   "cd \"$(dirname \"$0\")\"\n"
                   "halcompile --install {0}.c\n",
                   k.module_name)});
  // INI snippet: kinematics, joints with their limits, COMP_FILE of the direction-dependent terms.
  std::string coords;
  for (const char l : k.coordinates) coords += std::string(coords.empty() ? "" : " ") + l;
  std::string ini = fmt::format(
      "# Written by mtcal compensate --format linuxcnc-kins for {}: merge into the machine's INI file.\n"
      "# The kinematics module {} applies the whole error model (docs/compensation-linuxcnc-kins.md);\n"
      "# direction-dependent terms (reversal, forward/backward tables) cannot live in kinematics and are in the\n"
      "# COMP_FILE type 1 tables below (corrections -e added to the motor command).\n"
      "# Tool length: G43 works as with LinuxCNC's trt-kins; linuxcnc-kins.hal nets motion.tooloffset.{} to\n"
      "# {}.tool-offset, and the module puts the tool tip on the programmed point along the actual tool axis.\n"
      "# Pre-check: {} configurations of the commanded travel, at most {} steps, tool point residual up to {:.3g} mm.\n"
      "# Largest correction per joint (the margin the joint limits need beyond the commanded travel):\n",
      linuxcnc_c_comment(k.machine_name), k.module_name, tool_axis_letter(k), k.module_name, k.checked, k.max_iterations,
      k.max_point_residual);
  for (std::size_t j = 0; j < k.coordinates.size(); ++j) {
    const auto& a = *std::find_if(k.axes.begin(), k.axes.end(), [&](const KinsAxis& x) { return x.joint == static_cast<int>(j); });
    ini += fmt::format("#   joint {} ({}): {:.6f} {}\n", j, a.letter, k.largest_correction[j], unit_name(a));
  }
  ini += "# Commanded travel (the pre-check's range; keep the programs inside it):\n";
  for (const auto& c : k.summary.commanded)
    ini += fmt::format("#   {} {:.6f} to {:.6f} {} ({})\n", c.axis, c.lo, c.hi, c.unit, c.given ? "given" : c.why);
  ini += fmt::format("\n[KINS]\nKINEMATICS = {}\nJOINTS = {}\n\n[TRAJ]\nCOORDINATES = {}\nLINEAR_UNITS = mm\n"
                     "ANGULAR_UNITS = degree\n\n[HAL]\nHALFILE = linuxcnc-kins.hal\n",
                     k.module_name, k.coordinates.size(), coords);
  for (std::size_t j = 0; j < k.coordinates.size(); ++j) {
    const auto& a = *std::find_if(k.axes.begin(), k.axes.end(), [&](const KinsAxis& x) { return x.joint == static_cast<int>(j); });
    ini += fmt::format("\n[JOINT_{}]\nTYPE = {}\nMIN_LIMIT = {:.6f}\nMAX_LIMIT = {:.6f}\n", j,
                       a.rotary ? "ANGULAR" : "LINEAR", to_joint_units(a, a.min), to_joint_units(a, a.max));
    for (const auto& t : k.reversal_tables)
      if (t.joint == static_cast<int>(j))
        ini += fmt::format("COMP_FILE = joint{}-reversal.comp\nCOMP_FILE_TYPE = 1\n", j);
  }
  out.files.push_back({"linuxcnc-kins.ini", std::move(ini)});
  out.files.push_back(
      {"linuxcnc-kins.hal",
       fmt::format("# Written by mtcal compensate --format linuxcnc-kins. [KINS]KINEMATICS loads {0} (loadrt in the\n"
                   "# main HAL file); load this file after the one that loads motmod.\n"
                   "#\n"
                   "# Tool length, as LinuxCNC's own trt-kins and 5axiskins take it (their sim configurations net\n"
                   "# motion.tooloffset.z to the kinematics): with G43 LinuxCNC adds the tool table's length to the world\n"
                   "# {2} it passes the kinematics; the module subtracts {0}.tool-offset from it, so the programmed point is\n"
                   "# the tool tip, and puts that tip tool-length + tool-offset from the spindle gauge point along the\n"
                   "# ACTUAL tool axis (the model's: table-table, head-head and 3-axis alike). G49 (offset 0) controls\n"
                   "# the gauge point. The tool table's lengths are taken from the model's spindle gauge point\n"
                   "# (tool.spindle_point of the machine file); tool-length is what lies between that point and the one\n"
                   "# the tool table measures from (0 when they agree). Only the {2} component of the tool offset is a\n"
                   "# length along the tool; keep a tool's other offsets 0 (as trt-kins do, they would shift the point).\n"
                   "# Change tools (G43, G49) with the rotary axes at 0: elsewhere the new length along the tilted tool\n"
                   "# moves the joints at once, as with trt-kins. The machine file's tool length ({1:g} mm) is the one\n"
                   "# the pre-check used. If motion.tooloffset.{3} is already on a signal, add {0}.tool-offset to it.\n"
                   "net mtcal-kins-tool-offset motion.tooloffset.{3} => {0}.tool-offset\n"
                   "setp {0}.tool-length 0\n"
                   "# Without G43 (all programs with G49): leave tool-offset unconnected and set the length per tool:\n"
                   "#   setp {0}.tool-length {1:.9f}\n"
                   "# Diagnostics: {0}.iterations, {0}.residual (mm), {0}.failures (refused inverses).\n",
                   k.module_name, k.tool_length, static_cast<char>(std::toupper(tool_axis_letter(k))),
                   tool_axis_letter(k))});
  for (const auto& t : k.reversal_tables) {
    std::string text;
    for (std::size_t i = 0; i < t.nominal.size(); ++i)
      text += fmt::format("{:.9f} {:.9f} {:.9f}\n", t.nominal[i], t.forward[i], t.reverse[i]);
    out.files.push_back({fmt::format("joint{}-reversal.comp", t.joint), std::move(text)});
  }
  out.files.push_back(
      {"README.txt",
       fmt::format("LinuxCNC kinematics module for {}, written by mtcal compensate --format linuxcnc-kins.\n\n"
                   "  {}.c               the module (C; the machine's coefficients are in it)\n"
                   "  build.sh           halcompile --install {}.c (needs Debian's linuxcnc-uspace-dev)\n"
                   "  linuxcnc-kins.ini  [KINS], [TRAJ], [JOINT_n] lines; the largest correction per joint\n"
                   "  linuxcnc-kins.hal  the tool-offset pin on motion.tooloffset (G43), tool-length\n"
                   "  joint*-reversal.comp  direction-dependent terms, COMP_FILE type 1 (corrections)\n\n"
                   "What it holds, what it does not, and how to check it on the machine:\n"
                   "docs/compensation-linuxcnc-kins.md in mtcal.\n",
                   linuxcnc_c_comment(k.machine_name), k.module_name, k.module_name)});
  return out;
}

}  // namespace mtcal
