// Rigid transforms used by the error model: exact error transforms, rotation vector and its Jacobian.
#pragma once

#include <array>

#include <Eigen/Core>

namespace mtcal {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Rigid transform x -> R x + t (the upper 3x4 block of a homogeneous transform).
struct Affine {
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();

  static Affine identity() { return {}; }
  static Affine translation(const Vec3& v) { return {Mat3::Identity(), v}; }
  Affine operator*(const Affine& o) const { return {R * o.R, R * o.t + t}; }
  Affine inverse() const {
    Mat3 Rt = R.transpose();
    return {Rt, -(Rt * t)};
  }
};

// Six error components (dx dy dz in mm, a b c in rad) of one error slot.
using Error6 = std::array<double, 6>;

// Exact transform of six error components: Trans(dx,dy,dz) * Rz(c) * Ry(b) * Rx(a).
// No small-angle simplification: the rotations are complete (Viprey 2015, eq. 1).
Affine error_transform(const Error6& e);
// Derivative of error_transform with respect to component j (a transform-shaped matrix whose
// bottom row would be zero): dT = [D | v].
struct AffineDerivative {
  Mat3 D = Mat3::Zero();
  Vec3 v = Vec3::Zero();
};
AffineDerivative error_transform_derivative(const Error6& e, int j);

// Rotation about machine axis `axis` (0 x, 1 y, 2 z) by angle.
Mat3 axis_rotation(int axis, double angle);

// Rotation vector (axis * angle, |angle| <= pi) of a rotation matrix: the exact logarithm.
Vec3 rotation_vector(const Mat3& R);
// Inverse of the left Jacobian of SO(3) at rotation vector phi: if dR R^T = [w]x then
// d phi = left_jacobian_inverse(phi) * w.
Mat3 left_jacobian_inverse(const Vec3& phi);

}  // namespace mtcal
