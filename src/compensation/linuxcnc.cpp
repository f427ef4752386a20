#include "mtcal/compensation/linuxcnc.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

constexpr std::size_t kDefaultPoints = 51;
constexpr const char* kLinuxcncTarget = "linuxcnc";

// The ISO 230-7 positions of a rotary axis line across it (the two that are not along the axis).
std::array<Component, 2> line_positions(char axis) {
  switch (axis) {
    case 'A': return {Component::Y, Component::Z};
    case 'B': return {Component::X, Component::Z};
    default: return {Component::X, Component::Y};
  }
}

// xyzac-trt-kins / xyzbc-trt-kins (src/emc/kinematics/trtfuncs.c): a C table riding on an A or B
// table, both between the workpiece and the frame. Returns the module name or "".
std::string trt_kinematics(const Machine& m, std::string& tilt) {
  std::vector<char> table;
  for (std::size_t i = 0; i < m.topology.frame_index; ++i)
    if (m.axes[i].kind == AxisKind::Rotary) table.push_back(m.axes[i].letter);
  std::size_t rotary = 0;
  for (const auto& ax : m.axes) rotary += ax.kind == AxisKind::Rotary ? 1 : 0;
  if (table.size() != 2 || rotary != 2 || table[0] != 'C' || (table[1] != 'A' && table[1] != 'B')) return "";
  tilt = std::string(1, table[1]);
  return table[1] == 'A' ? "xyzac-trt-kins" : "xyzbc-trt-kins";
}

// The tool point with every axis at zero (machine coordinates): LinuxCNC's joint origin.
Vec3 tool_point_at_zero(const Machine& m) {
  Vec3 t = m.tool.spindle_point;
  t[m.tool.tool_axis] -= m.tool.length;  // the tool points along -(tool axis) (ToolSetup)
  return t;
}

}  // namespace

LinuxcncCompensation compensate_linuxcnc(const Machine& m, const CompensationOptions& o) {
  if (o.comp_file_type != 0 && o.comp_file_type != 1)
    throw InputError({kLinuxcncTarget, 0, "COMP_FILE_TYPE"},
                     fmt::format("expected COMP_FILE_TYPE 0 or 1, found {}", o.comp_file_type));
  LinuxcncCompensation out;
  out.comp_file_type = o.comp_file_type;
  for (const char c : std::string("XYZABC"))
    if (m.axis_index(c)) out.coordinates += c;
  const auto sampling = resolve_sampling(m, o, kDefaultPoints, kLinuxcncMaxCompLines, kLinuxcncTarget);

  // What the kinematics module holds: the rotary axis lines' positions (trt pins).
  std::string tilt;
  out.kinematics = trt_kinematics(m, tilt);
  std::vector<ErrorName> held_locations;
  Machine rest = m;  // the model less what the pins hold: what the joint tables see
  if (!out.kinematics.empty()) {
    const Vec3 t0 = tool_point_at_zero(m);
    Vec3 line[2];
    const char letters[2] = {'C', tilt[0]};
    for (int k = 0; k < 2; ++k) {
      const Axis& ax = m.axis(letters[k]);
      line[k] = ax.point;
      for (const Component c : line_positions(letters[k])) {
        line[k][index_of(c)] += ax.location[static_cast<std::size_t>(index_of(c))];
        held_locations.push_back(ErrorName{ErrorKind::Location, c, letters[k]});
        rest.set_parameter(held_locations.back().str(), 0.0);
      }
      line[k] -= t0;  // LinuxCNC's joints are zero where mtcal's are: positions relative to the tool point there
    }
    // trtfuncs.c: the C line through (x-rot-point, y-rot-point); the tilting line offset from it by
    // y-offset (A) or x-offset (B), at height z-offset.
    const std::string k = out.kinematics + ".";
    out.pins.push_back({k + "x-rot-point", line[0].x()});
    out.pins.push_back({k + "y-rot-point", line[0].y()});
    out.pins.push_back({k + "z-rot-point", 0.0});
    if (tilt == "A") {
      out.pins.push_back({k + "y-offset", line[1].y() - line[0].y()});
    } else {
      out.pins.push_back({k + "x-offset", line[1].x() - line[0].x()});
    }
    out.pins.push_back({k + "z-offset", line[1].z()});
  } else {
    out.kinematics = "trivkins";
    for (const auto& ax : m.axes)
      if (ax.kind == AxisKind::Rotary) {
        out.kinematics.clear();  // the configuration's own 5-axis kinematics, not written here
        out.summary.warnings.push_back(fmt::format(
            "rotary axes of {} are not a C table on an A or B table: no trt kinematics pins are written and "
            "the rotary axes' location errors are not compensated",
            m.topology.chain));
        break;
      }
  }

  // Joint tables of the linear axes: the tool point's error along the axis when it alone moves.
  const ErrorModel model(rest);
  for (const PositioningTable& t : positioning_tables(model, sampling, o.reference, kLinuxcncTarget)) {
    LinuxcncJointTable table;
    table.axis = t.axis;
    table.joint = static_cast<int>(out.coordinates.find(t.axis));
    table.nominal = t.position;
    for (std::size_t i = 0; i < t.position.size(); ++i) {
      // usrmotLoadComp(): type 0 holds the position reached (nominal + e), type 1 the correction -e.
      table.forward.push_back(o.comp_file_type == 0 ? t.position[i] + t.forward[i] : -t.forward[i]);
      table.reverse.push_back(o.comp_file_type == 0 ? t.position[i] + t.reverse[i] : -t.reverse[i]);
    }
    out.tables.push_back(std::move(table));
  }
  if (out.tables.empty() && out.pins.empty())
    throw InputError({m.source, 0, ""},
                     "nothing to compensate for LinuxCNC: the model has no error along a linear axis and no rotary "
                     "axis line position a trt kinematics holds");

  // Residual by LinuxCNC's rule (control.c, compute_screw_comp(): linear interpolation, ends held,
  // the forward column while the joint moves +): the pins hold their errors exactly, the tables the rest.
  // usrmotLoadComp() turns the columns into trims at the nodes (type 0: nominal - column); those
  // are what compute_screw_comp() interpolates.
  std::vector<ControllerTable> applied;
  for (const auto& t : out.tables) {
    const std::size_t a = *m.axis_index(t.axis);
    ControllerTable trim{.input = a, .output = a, .position = t.nominal, .forward = t.forward, .reverse = t.reverse};
    if (out.comp_file_type == 0)
      for (auto* col : {&trim.forward, &trim.reverse})
        for (std::size_t i = 0; i < col->size(); ++i) (*col)[i] = t.nominal[i] - (*col)[i];
    applied.push_back(std::move(trim));
  }
  out.summary.residual = residual_before_after(ErrorModel(m), model, residual_grid(m, sampling, o.residual_points),
                                               table_rule(std::move(applied), m.axes.size()), o.threads);
  out.summary.target = kLinuxcncTarget;
  out.summary.quantity = o.comp_file_type == 0 ? TableQuantity::ActualPosition : TableQuantity::Correction;
  out.summary.sign_source =
      "LinuxCNC 2.9 src/emc/motion/usrmotintf.cc usrmotLoadComp(): COMP_FILE_TYPE 0 columns are the positions "
      "reached and nominal - column is added to the command, type 1 columns are added as they are; "
      "src/emc/motion/control.c compute_screw_comp(): linear interpolation, ends held, forward column while moving +";
  // What neither the tables nor the pins hold: every error other than a linear axis's positioning
  // error along its own direction and the pins' line positions.
  const auto coarse = residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5));
  out.summary.not_compensated = errors_not_held(
      m, coarse,
      [&](const ErrorName& n) {
        if (std::find(held_locations.begin(), held_locations.end(), n) != held_locations.end()) return true;
        if (n.kind != ErrorKind::Motion) return false;
        const auto i = m.axis_index(n.body);
        return i && m.axes[*i].kind == AxisKind::Linear && index_of(n.component) == m.axes[*i].direction_axis;
      },
      o.threads);
  if (!out.summary.not_compensated.empty())
    out.summary.warnings.push_back(
        "per-joint tables hold each linear axis's error along itself only; the errors listed as not compensated "
        "remain (largest effect each over the residual grid)");
  return out;
}

}  // namespace mtcal
