// Exact error transforms, rotation vector and its Jacobian against independent constructions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "mtcal/kinematics/transform.hpp"

using namespace mtcal;

TEST(Transform, ErrorTransformIsTranslationTimesZYXRotation) {
  const Error6 e{0.1, -0.2, 0.3, 0.4, -0.5, 0.6};
  const Affine a = error_transform(e);
  const Mat3 R = (Eigen::AngleAxisd(0.6, Vec3::UnitZ()) * Eigen::AngleAxisd(-0.5, Vec3::UnitY()) *
                  Eigen::AngleAxisd(0.4, Vec3::UnitX()))
                     .toRotationMatrix();
  EXPECT_LE((a.R - R).norm(), 1e-15);
  EXPECT_LE((a.t - Vec3(0.1, -0.2, 0.3)).norm(), 0.0);
}

TEST(Transform, ErrorTransformDerivativeMatchesCentralDifferences) {
  const Error6 e{1e-3, -2e-3, 3e-3, 2e-5, -3e-5, 1e-2};
  for (int j = 0; j < 6; ++j) {
    const double h = 1e-6;
    Error6 p = e, m = e;
    p[j] += h;
    m[j] -= h;
    const Affine ap = error_transform(p), am = error_transform(m);
    const auto d = error_transform_derivative(e, j);
    EXPECT_LE(((ap.R - am.R) / (2 * h) - d.D).norm(), 1e-9) << j;
    EXPECT_LE(((ap.t - am.t) / (2 * h) - d.v).norm(), 1e-9) << j;
  }
}

TEST(Transform, RotationVectorInvertsAngleAxis) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (double angle : {0.0, 1e-12, 1e-7, 1e-3, 0.5, 2.0, 3.1, 3.14159}) {
    for (int i = 0; i < 20; ++i) {
      const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
      const Mat3 R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
      const Vec3 r = rotation_vector(R);
      EXPECT_LE((r - angle * axis).norm(), 1e-9 * std::max(1.0, angle)) << angle;
    }
  }
}

TEST(Transform, LeftJacobianInverseMatchesNumericDifferentiation) {
  // For R(phi) = exp(phi), d phi = Jl^-1(phi) w where dR R^T = [w]x.
  for (const Vec3& phi : {Vec3(0, 0, 0), Vec3(1e-6, -2e-6, 3e-6), Vec3(0.3, -0.2, 0.5), Vec3(1.0, 1.2, -0.4)}) {
    const Mat3 R = Eigen::AngleAxisd(phi.norm(), phi.norm() > 0 ? phi.normalized() : Vec3::UnitX()).toRotationMatrix();
    const Mat3 Jinv = left_jacobian_inverse(phi);
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-7;
      Vec3 w = Vec3::Zero();
      w[k] = h;
      const Mat3 Rp = Eigen::AngleAxisd(h, Vec3::Unit(k)).toRotationMatrix() * R;
      const Mat3 Rm = Eigen::AngleAxisd(-h, Vec3::Unit(k)).toRotationMatrix() * R;
      const Vec3 numeric = (rotation_vector(Rp) - rotation_vector(Rm)) / (2 * h);
      EXPECT_LE((numeric - Jinv.col(k)).norm(), 1e-6) << phi.transpose() << " " << k;
    }
  }
}
