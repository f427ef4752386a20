#include "mtcal/kinematics/tool_point_coordinates.hpp"

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

ToolPointCoordinates::ToolPointCoordinates(const Machine& machine)
    : solver_(machine), tool_length_(machine.tool.length), slot_(3, machine.axes.size()) {
  for (std::size_t k = 0; k < machine.axes.size(); ++k) {
    const Axis& ax = machine.axes[k];
    if (ax.kind != AxisKind::Linear) continue;
    const char c = ax.letter;
    if (c < 'X' || c > 'Z')
      throw ModelError(fmt::format("topology {}: linear axis {} is not X, Y or Z; tool-point coordinates name the "
                                   "tool point's x y z by the letters X Y Z",
                                   machine.topology.chain, c));
    slot_[static_cast<std::size_t>(c - 'X')] = k;
  }
  for (std::size_t i = 0; i < 3; ++i)
    if (slot_[i] == machine.axes.size())
      throw ModelError(fmt::format("topology {} has no linear axis {}: tool-point coordinates need X, Y and Z",
                                   machine.topology.chain, "XYZ"[i]));
}

std::vector<double> ToolPointCoordinates::world(std::span<const double> q) const {
  const CommandedPose p = solver_.nominal_forward(q, tool_length_);
  std::vector<double> out(q.begin(), q.end());  // rotary slots keep their values
  for (std::size_t i = 0; i < 3; ++i) out[slot_[i]] = p.point[static_cast<Eigen::Index>(i)];
  return out;
}

std::vector<double> ToolPointCoordinates::axes(std::span<const double> world) const {
  CommandedPose p;
  for (std::size_t i = 0; i < 3; ++i) p.point[static_cast<Eigen::Index>(i)] = world[slot_[i]];
  for (std::size_t k : solver_.rotary_axes()) p.rotary.push_back(world[k]);
  return solver_.nominal_inverse(p, tool_length_);
}

}  // namespace mtcal
