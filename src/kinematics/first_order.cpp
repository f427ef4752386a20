#include "mtcal/kinematics/first_order.hpp"

#include <Eigen/Geometry>

#include "mtcal/util/errors.hpp"

namespace mtcal {

VolumetricError first_order_error(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir) {
  const std::size_t n = m.axes.size();
  for (const auto& ax : m.axes)
    if (ax.kind != AxisKind::Linear)
      throw ModelError("the first-order sum model is for machines with linear axes only; " + m.topology.chain +
                       " has rotary axis " + std::string(1, ax.letter));
  if (q.size() != n) throw ModelError("expected " + std::to_string(n) + " joint values");
  auto split = [](const std::array<double, 6>& e, Vec3& d, Vec3& eps) {
    d = Vec3(e[0], e[1], e[2]);
    eps = Vec3(e[3], e[4], e[5]);
  };
  Vec3 a = Vec3::Zero();
  a[m.tool.tool_axis] = 1.0;
  const Vec3 tool_at_zero = m.tool.spindle_point - m.tool.length * a;

  Vec3 p = tool_at_zero - m.workpiece.origin;
  for (std::size_t k = 0; k < n; ++k) p += q[k] * m.axes[k].direction();

  VolumetricError e;
  Vec3 d, eps;
  split(m.workpiece_mounting, d, eps);
  e.translation = -d - eps.cross(p);
  e.rotation = -eps;
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    const Vec3 u = ax.direction();
    Vec3 pk = tool_at_zero;
    for (std::size_t j = k + 1; j < n; ++j) pk += q[j] * m.axes[j].direction();
    const Vec3 o(ax.location[3], ax.location[4], ax.location[5]);
    const double z = ax.location[ax.direction_axis];
    const int dk = dir.empty() ? 0 : dir[k];
    std::array<double, 6> me{};
    for (int c = 0; c < 6; ++c) me[c] = ax.motion[c].value(q[k], dk);
    split(me, d, eps);
    e.translation += z * Vec3::Unit(ax.direction_axis) + q[k] * o.cross(u) + d + eps.cross(pk - ax.point);
    e.rotation += eps;
  }
  split(m.tool_mounting, d, eps);
  e.translation += d - m.tool.length * eps.cross(a);
  e.rotation += eps;
  return e;
}

}  // namespace mtcal
