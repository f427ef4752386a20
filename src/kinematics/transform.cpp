#include "mtcal/kinematics/transform.hpp"

#include <cmath>

namespace mtcal {
namespace {

Mat3 rx(double a) {
  const double c = std::cos(a), s = std::sin(a);
  Mat3 m;
  m << 1, 0, 0, 0, c, -s, 0, s, c;
  return m;
}
Mat3 ry(double b) {
  const double c = std::cos(b), s = std::sin(b);
  Mat3 m;
  m << c, 0, s, 0, 1, 0, -s, 0, c;
  return m;
}
Mat3 rz(double g) {
  const double c = std::cos(g), s = std::sin(g);
  Mat3 m;
  m << c, -s, 0, s, c, 0, 0, 0, 1;
  return m;
}
Mat3 hat(const Vec3& w) {
  Mat3 m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

}  // namespace

Mat3 axis_rotation(int axis, double angle) {
  switch (axis) {
    case 0: return rx(angle);
    case 1: return ry(angle);
    default: return rz(angle);
  }
}

Affine error_transform(const Error6& e) { return {rz(e[5]) * ry(e[4]) * rx(e[3]), Vec3(e[0], e[1], e[2])}; }

AffineDerivative error_transform_derivative(const Error6& e, int j) {
  AffineDerivative d;
  if (j < 3) {
    d.v[j] = 1.0;
    return d;
  }
  // d/dtheta of R_k(theta) = hat(e_k) R_k(theta): insert the generator at the factor's place.
  const Mat3 X = rx(e[3]), Y = ry(e[4]), Z = rz(e[5]);
  if (j == 3) d.D = Z * Y * hat(Vec3::UnitX()) * X;
  if (j == 4) d.D = Z * hat(Vec3::UnitY()) * Y * X;
  if (j == 5) d.D = hat(Vec3::UnitZ()) * Z * Y * X;
  return d;
}

Vec3 rotation_vector(const Mat3& R) {
  // R = cos(t) I + sin(t) [n]x + (1 - cos(t)) n n^T: the antisymmetric part gives sin(t) n.
  const Vec3 v(0.5 * (R(2, 1) - R(1, 2)), 0.5 * (R(0, 2) - R(2, 0)), 0.5 * (R(1, 0) - R(0, 1)));
  const double s = v.norm();
  const double c = 0.5 * (R.trace() - 1.0);
  const double theta = std::atan2(s, c);
  if (c > -0.99) return s > 0 ? Vec3(v * (theta / s)) : Vec3::Zero();
  // Near pi sin(t) vanishes; the symmetric part (1 - cos t) n n^T gives the axis.
  const Mat3 S = 0.5 * (R + R.transpose()) - c * Mat3::Identity();
  int k = 0;
  S.diagonal().maxCoeff(&k);
  Vec3 axis = S.col(k).normalized();
  if (axis.dot(v) < 0) axis = -axis;
  return axis * theta;
}

Mat3 left_jacobian_inverse(const Vec3& phi) {
  const double th = phi.norm();
  const Mat3 P = hat(phi);
  double coef;
  if (th < 1e-4) {
    // Series of 1/th^2 - (1 + cos th) / (2 th sin th) = 1/12 + th^2/720 + ...
    coef = 1.0 / 12.0 + th * th / 720.0;
  } else {
    coef = 1.0 / (th * th) - (1.0 + std::cos(th)) / (2.0 * th * std::sin(th));
  }
  return Mat3::Identity() - 0.5 * P + coef * P * P;
}

}  // namespace mtcal
