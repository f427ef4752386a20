#include "small_displacement.hpp"

#include <Eigen/Geometry>

namespace mtcal::testing {

using Iso = Eigen::Isometry3d;
using V3 = Eigen::Vector3d;

namespace {

V3 unit(int axis) { return V3::Unit(axis); }

// Nominal relative motion of an axis: tool side relative to workpiece side, command q.
Iso nominal_joint(const Axis& ax, double q) {
  Iso t = Iso::Identity();
  if (ax.kind == AxisKind::Linear) {
    t.translate(ax.direction_sign * q * unit(ax.direction_axis));
  } else {
    t.translate(ax.point);
    t.rotate(Eigen::AngleAxisd(ax.direction_sign * q, unit(ax.direction_axis)));
    t.translate(-ax.point);
  }
  return t;
}

Eigen::Matrix<double, 6, 1> stack(const V3& a, const V3& b) {
  Eigen::Matrix<double, 6, 1> v;
  v << a, b;
  return v;
}

}  // namespace

std::vector<FirstOrderEffect> small_displacement_effects(const Machine& m, std::span<const double> q) {
  const std::size_t n = m.axes.size();
  // body[k]: pose in the workpiece frame of the body on the tool side of joint k (body[0] is
  // the body the workpiece is fixed to, before joint 1).
  std::vector<Iso> body(n + 1);
  body[0] = Iso::Identity();
  body[0].translate(-m.workpiece.origin);
  for (std::size_t k = 0; k < n; ++k) body[k + 1] = body[k] * nominal_joint(m.axes[k], q[k]);
  const V3 a = unit(m.tool.tool_axis);
  const V3 tool_local = m.tool.spindle_point - m.tool.length * a;
  const V3 p = body[n] * tool_local;  // tool point in the workpiece frame

  // Effect of a small motion (d, eps) of frame F about point r (F coordinates).
  auto at_frame = [&](const Iso& F, const V3& r, const V3& d, const V3& eps) {
    const V3 t = F.inverse() * p;
    return stack(F.linear() * (d + eps.cross(t - r)), F.linear() * eps);
  };

  std::vector<FirstOrderEffect> out;
  for (std::size_t k = 0; k < n; ++k) {
    const Axis& ax = m.axes[k];
    // Motion errors: in the axis's base frame at its point (docs/conventions.md).
    const bool before = ax.kind == AxisKind::Rotary && !ax.moves_workpiece;
    const Iso& F = before ? body[k] : body[k + 1];
    for (int c = 0; c < 6; ++c) {
      const V3 d = c < 3 ? unit(c) : V3::Zero();
      const V3 eps = c >= 3 ? unit(c - 3) : V3::Zero();
      out.push_back({{ErrorKind::Motion, static_cast<Component>(c), ax.letter}, at_frame(F, ax.point, d, eps)});
    }
    // Location errors, acting on the joint as seen from the workpiece side (body[k]).
    const Eigen::Matrix3d Rb = body[k].linear();
    const V3 x = body[k + 1].inverse() * p;  // tool point in the tool-side body
    for (int c = 0; c < 6; ++c) {
      if (!ax.allows_location(static_cast<Component>(c))) continue;
      Eigen::Matrix<double, 6, 1> e;
      if (ax.kind == AxisKind::Linear) {
        // Zero position along the machine axis; orientation turns the direction of motion.
        const V3 u = ax.direction_sign * unit(ax.direction_axis);
        e = c < 3 ? stack(Rb * unit(c), V3::Zero()) : stack(Rb * (q[k] * unit(c - 3).cross(u)), V3::Zero());
      } else {
        const Eigen::Matrix3d R = nominal_joint(ax, q[k]).linear();
        const V3 xc = x - ax.point;  // relative to the axis point, tool side
        const V3 y = R * xc;         // the same point seen from the workpiece side
        if (c < 3) {                 // position of the line: (I - R) e
          e = stack(Rb * (unit(c) - R * unit(c)), V3::Zero());
        } else if (c - 3 == ax.direction_axis) {  // zero position: extra turn about + machine axis
          e = stack(Rb * unit(c - 3).cross(y), Rb * unit(c - 3));
        } else {  // orientation w: L R L^-1 = R + [w]R - R[w]
          const V3 w = unit(c - 3);
          e = stack(Rb * (w.cross(y) - R * w.cross(xc)), Rb * (w - R * w));
        }
      }
      out.push_back({{ErrorKind::Location, static_cast<Component>(c), ax.letter}, e});
    }
  }
  // Tool mounting at the spindle gauge point; workpiece mounting at the workpiece origin,
  // moving the workpiece (the tool relative to it moves the other way).
  Iso spindle = body[n];
  spindle.translate(m.tool.spindle_point);
  for (int c = 0; c < 6; ++c) {
    const V3 d = c < 3 ? unit(c) : V3::Zero();
    const V3 eps = c >= 3 ? unit(c - 3) : V3::Zero();
    out.push_back({{ErrorKind::Mounting, static_cast<Component>(c), 't'}, at_frame(spindle, V3::Zero(), d, eps)});
  }
  for (int c = 0; c < 6; ++c) {
    const V3 d = c < 3 ? unit(c) : V3::Zero();
    const V3 eps = c >= 3 ? unit(c - 3) : V3::Zero();
    out.push_back({{ErrorKind::Mounting, static_cast<Component>(c), 'w'}, stack(-d - eps.cross(p), -eps)});
  }
  return out;
}

}  // namespace mtcal::testing
