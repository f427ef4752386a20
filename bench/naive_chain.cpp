#include "naive_chain.hpp"

#include <array>

#include <Eigen/Geometry>

namespace mtcal::bench {
namespace {

using Mat4 = Eigen::Matrix4d;

Mat4 trans(const Vec3& v) {
  Mat4 m = Mat4::Identity();
  m.block<3, 1>(0, 3) = v;
  return m;
}

Mat4 rot(const Eigen::Matrix3d& r) {
  Mat4 m = Mat4::Identity();
  m.block<3, 3>(0, 0) = r;
  return m;
}

// Exact error transform Trans(dx, dy, dz) Rz(c) Ry(b) Rx(a) of six components.
Mat4 error_matrix(const std::array<double, 6>& e) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(e[5], Vec3::UnitZ()) * Eigen::AngleAxisd(e[4], Vec3::UnitY()) *
                             Eigen::AngleAxisd(e[3], Vec3::UnitX()))
                                .toRotationMatrix();
  return trans(Vec3(e[0], e[1], e[2])) * rot(r);
}

Mat4 rigid_inverse(const Mat4& m) {
  Mat4 inv = Mat4::Identity();
  const Eigen::Matrix3d rt = m.block<3, 3>(0, 0).transpose();
  inv.block<3, 3>(0, 0) = rt;
  inv.block<3, 1>(0, 3) = -(rt * m.block<3, 1>(0, 3));
  return inv;
}

// Index of the location component that is the axis's zero position: the translation along a
// linear axis, the rotation about a rotary one.
int zero_component(const Axis& ax) { return ax.kind == AxisKind::Linear ? ax.direction_axis : 3 + ax.direction_axis; }

// Nominal motion of the axis by s: along or about its direction through the origin.
Mat4 motion(const Axis& ax, double s) {
  if (ax.kind == AxisKind::Linear) return trans(ax.direction() * s);
  return rot(Eigen::AngleAxisd(s, ax.direction()).toRotationMatrix());
}

}  // namespace

std::vector<Mat4> naive_chain(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir,
                              bool errors) {
  std::vector<Mat4> f;
  if (errors) f.push_back(rigid_inverse(error_matrix(m.workpiece_mounting)));
  f.push_back(trans(-m.workpiece.origin));
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    const Axis& ax = m.axes[k];
    const Vec3 c = ax.kind == AxisKind::Rotary ? ax.point : Vec3::Zero();
    const Vec3 r = ax.point;
    // Motion errors sit in the axis's base frame: after the joint for an axis carrying the
    // workpiece, before it for a rotary axis carrying the tool (docs/conventions.md).
    const bool errors_first = ax.kind == AxisKind::Rotary && !ax.moves_workpiece;
    auto motion_errors = [&] {
      f.push_back(trans(r));
      if (errors) {
        const int d = dir.empty() ? 0 : dir[k];
        std::array<double, 6> e{};
        for (std::size_t i = 0; i < 6; ++i) e[i] = ax.motion[i].value(q[k], d);
        f.push_back(error_matrix(e));
      }
      f.push_back(trans(-r));
    };
    if (errors_first) motion_errors();
    f.push_back(trans(c));
    if (errors) {
      const int zc = zero_component(ax);
      std::array<double, 6> loc = ax.location;
      const double z = loc[static_cast<std::size_t>(zc)];
      loc[static_cast<std::size_t>(zc)] = 0.0;
      const Mat4 L = error_matrix(loc);
      f.push_back(L);
      f.push_back(motion(ax, q[k] + z));
      f.push_back(rigid_inverse(L));
    } else {
      f.push_back(motion(ax, q[k]));
    }
    f.push_back(trans(-c));
    if (!errors_first) motion_errors();
  }
  f.push_back(trans(m.tool.spindle_point));
  if (errors) f.push_back(error_matrix(m.tool_mounting));
  Vec3 a = Vec3::Zero();
  a[m.tool.tool_axis] = 1.0;
  f.push_back(trans(-m.tool.length * a));
  return f;
}

Mat4 naive_product(const std::vector<Mat4>& factors) {
  Mat4 t = Mat4::Identity();
  for (const Mat4& x : factors) t = t * x;
  return t;
}

VolumetricError naive_evaluate(const Machine& m, std::span<const double> q, std::span<const std::int8_t> dir) {
  const Mat4 actual = naive_product(naive_chain(m, q, dir, true));
  const Mat4 nominal = naive_product(naive_chain(m, q, dir, false));
  const Eigen::Matrix3d dr = actual.block<3, 3>(0, 0) * nominal.block<3, 3>(0, 0).transpose();
  const Eigen::AngleAxisd aa(dr);
  VolumetricError v;
  v.translation = actual.block<3, 1>(0, 3) - nominal.block<3, 1>(0, 3);
  v.rotation = aa.angle() * aa.axis();
  return v;
}

}  // namespace mtcal::bench
