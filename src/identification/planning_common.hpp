// Internal: small helpers the planning units share (candidates, design, probing program).
#pragma once

#include <cstddef>
#include <vector>

#include "mtcal/identification/planning.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal::planning_detail {

inline std::vector<std::size_t> rotary_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Rotary) out.push_back(i);
  return out;
}
inline std::vector<std::size_t> linear_axes(const Machine& m) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < m.axes.size(); ++i)
    if (m.axes[i].kind == AxisKind::Linear) out.push_back(i);
  return out;
}

inline Machine nominal_of(const Machine& m) {
  Machine n = m;
  n.clear_errors();
  return n;
}

// Unit vector from the probe's tip to the spindle in the workpiece frame: the tool points along
// -(tool axis) of the tool frame (model/machine.hpp, ToolSetup).
inline Vec3 tool_axis(const ErrorModel& nominal, const ProbingRecord& r) {
  return nominal.nominal_pose(r.q).R.col(nominal.machine().tool.tool_axis).normalized();
}

}  // namespace mtcal::planning_detail
