#include "chain.hpp"

#include <cassert>

namespace mtcal::detail {

int zero_position_component(const Axis& ax) {
  return ax.kind == AxisKind::Linear ? ax.direction_axis : 3 + ax.direction_axis;
}

double zero_position(const Axis& ax) {
  // The location error is along/about +machine axis like every error; the joint runs in the
  // axis's command sense, which a reversed axis (direction -x ...) turns the other way.
  return ax.direction_sign * ax.location[zero_position_component(ax)];
}

Error6 location_without_zero(const Axis& ax) {
  Error6 e{};
  for (int c = 0; c < 6; ++c) e[c] = ax.location[c];
  e[zero_position_component(ax)] = 0.0;
  return e;
}

Affine joint_motion(const Axis& ax, double s) {
  if (ax.kind == AxisKind::Linear) return Affine::translation(ax.direction() * s);
  return {axis_rotation(ax.direction_axis, ax.direction_sign * s), Vec3::Zero()};
}

AffineDerivative joint_motion_derivative(const Axis& ax, double s) {
  AffineDerivative d;
  if (ax.kind == AxisKind::Linear) {
    d.v = ax.direction();
    return d;
  }
  // d/ds Rot(u, sign s) = sign * hat(e_axis) * Rot.
  Mat3 h = Mat3::Zero();
  const int a = ax.direction_axis, i = (a + 1) % 3, j = (a + 2) % 3;
  h(j, i) = 1.0;
  h(i, j) = -1.0;
  d.D = ax.direction_sign * h * axis_rotation(a, ax.direction_sign * s);
  return d;
}

namespace {
Factor constant(const Affine& a) { return {Factor::Kind::Const, a, -1, false, -1}; }
Factor slot(int s, bool inverse) { return {Factor::Kind::Slot, Affine{}, s, inverse, -1}; }
Factor joint(int k) { return {Factor::Kind::Joint, Affine{}, -1, false, k}; }
}  // namespace

std::vector<Factor> build_chain(const Machine& m, bool errors) {
  // T_w->t = E_w^-1 W^-1 prod_k J_k S E_t Trans(-l a), each joint
  //   J_k = Trans(c) L M(q+z) L^-1 Trans(-c) . Trans(r) E_k Trans(-r)
  // with the motion errors E_k in the frame of the axis's base: the tool side of the joint for
  // an axis that carries the workpiece, the workpiece side (E_k first) for one that carries the
  // tool. Linear axes always take the first order. (docs/conventions.md)
  std::vector<Factor> f;
  const std::size_t n = m.axes.size();
  if (errors) f.push_back(slot(workpiece_slot(), true));
  f.push_back(constant(Affine::translation(-m.workpiece.origin)));
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    const Vec3 c = ax.kind == AxisKind::Rotary ? ax.point : Vec3::Zero();
    const bool errors_first = ax.kind == AxisKind::Rotary && !ax.moves_workpiece;
    auto motion_errors = [&] {
      f.push_back(constant(Affine::translation(ax.point)));
      if (errors) f.push_back(slot(motion_slot(k), false));
      f.push_back(constant(Affine::translation(-ax.point)));
    };
    if (errors_first) motion_errors();
    f.push_back(constant(Affine::translation(c)));
    if (errors) f.push_back(slot(location_slot(k), false));
    f.push_back(joint(static_cast<int>(k)));
    if (errors) f.push_back(slot(location_slot(k), true));
    f.push_back(constant(Affine::translation(-c)));
    if (!errors_first) motion_errors();
  }
  f.push_back(constant(Affine::translation(m.tool.spindle_point)));
  if (errors) f.push_back(slot(tool_slot(n), false));
  Vec3 a = Vec3::Zero();
  a[m.tool.tool_axis] = 1.0;
  f.push_back(constant(Affine::translation(-m.tool.length * a)));
  return f;
}

void bind_chain(const Machine& m, const std::vector<Factor>& chain, bool errors, std::span<const double> q,
                std::span<const std::int8_t> dir, std::span<Affine> values) {
  assert(q.size() == m.axes.size() && values.size() == chain.size());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const Factor& fa = chain[i];
    if (fa.kind == Factor::Kind::Const) {
      values[i] = fa.value;
    } else if (fa.kind == Factor::Kind::Joint) {
      const Axis& ax = m.axes[fa.axis];
      values[i] = joint_motion(ax, q[fa.axis] + (errors ? zero_position(ax) : 0.0));
    } else {
      const Affine e = error_transform(slot_errors(m, fa.slot, q, dir));
      values[i] = fa.inverse ? e.inverse() : e;
    }
  }
}

Error6 slot_errors(const Machine& m, int slot, std::span<const double> q, std::span<const std::int8_t> dir) {
  const std::size_t n = m.axes.size();
  if (slot == workpiece_slot()) return m.workpiece_mounting;
  if (slot == tool_slot(n)) return m.tool_mounting;
  const std::size_t k = static_cast<std::size_t>((slot - 1) / 2);
  const Axis& ax = m.axes[k];
  if (slot == location_slot(k)) return location_without_zero(ax);
  const int d = dir.empty() ? 0 : dir[k];
  Error6 v;
  for (int c = 0; c < 6; ++c) v[c] = ax.motion[c].value(q[k], d);
  return v;
}

Affine multiply(std::span<const Affine> values) {
  Affine t;
  for (const auto& v : values) t = t * v;
  return t;
}

}  // namespace mtcal::detail
