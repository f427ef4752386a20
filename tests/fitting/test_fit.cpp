// Sphere, plane, line and circle fits against exact synthetic points, hand calculations, noise
// statistics (coverage of the reported covariance) and every degenerate input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mtcal/fitting/fit.hpp"
#include "examples.hpp"

using namespace mtcal;

namespace {

using mtcal::testing::kPi;

using Pts = std::vector<Point3>;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

Point3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  Point3 v;
  do v = Point3(g(rng), g(rng), g(rng));
  while (v.norm() < 1e-3);
  return v.normalized();
}

// Two unit vectors completing n to an orthonormal frame.
std::pair<Point3, Point3> frame(const Point3& n) {
  const Point3 a = std::abs(n.x()) < 0.9 ? Point3::UnitX() : Point3::UnitY();
  const Point3 e1 = (a - a.dot(n) * n).normalized();
  return {e1, n.cross(e1)};
}

Point3 gaussian(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> g(0.0, sigma);
  // One by one (argument order is unspecified): z, y, x is GCC's order, the noise the tests were tuned with.
  const double z = g(rng), y = g(rng), x = g(rng);
  return Point3(x, y, z);
}

// Index of the largest-magnitude component, as the fits define it.
int largest(const Point3& v) {
  int k = 0;
  v.cwiseAbs().maxCoeff(&k);
  return k;
}

bool finite_quality(const FitQuality& q) {
  for (double r : q.residuals)
    if (!std::isfinite(r)) return false;
  return std::isfinite(q.rms) && std::isfinite(q.sigma);
}

// No NaN or infinity anywhere in a fit's report.
template <class Fit>
bool all_finite(const Fit& f) {
  return finite_quality(f.quality) && f.covariance.allFinite();
}

bool zero_matrix(const Eigen::MatrixXd& m, Eigen::Index n) {
  return m.rows() == n && m.cols() == n && (m.array() == 0.0).all();
}

// Share of estimates within 3 reported standard deviations, and mean squared normalised errors:
// with the reported sigma (t-distributed, mean dof/(dof-2)) and with the reported covariance
// rescaled to the true noise (chi-square, mean 1): a covariance that is right, not just large.
struct Coverage {
  int inside = 0, total = 0;
  double z2 = 0.0, z2_true_sigma = 0.0;
  bool ok_variances = true;
  // rescale: (true noise / reported sigma)^2 of this trial.
  void add(double error, double variance, double rescale) {
    if (!(variance > 0.0) || !std::isfinite(variance) || !(rescale > 0.0) || !std::isfinite(rescale)) {
      ok_variances = false;
      return;
    }
    const double z = error * error / variance;
    ++total;
    inside += z <= 9.0 ? 1 : 0;
    z2 += z;
    z2_true_sigma += z / rescale;
  }
  double rate() const { return total ? static_cast<double>(inside) / total : 0.0; }
  double mean_z2() const { return total ? z2 / total : 0.0; }
  double mean_z2_true_sigma() const { return total ? z2_true_sigma / total : 0.0; }
  void expect_good(const std::string& what) const {
    EXPECT_TRUE(ok_variances) << what << ": a variance is not positive";
    EXPECT_GE(total, 200) << what;
    EXPECT_GE(rate(), 0.95) << what;
    EXPECT_GT(mean_z2(), 0.6) << what;
    EXPECT_LT(mean_z2(), 1.6) << what;
    EXPECT_GT(mean_z2_true_sigma(), 0.75) << what;
    EXPECT_LT(mean_z2_true_sigma(), 1.3) << what;
    ::testing::Test::RecordProperty(what + "_within_3_sigma", std::to_string(rate()));
    ::testing::Test::RecordProperty(what + "_mean_z2", std::to_string(mean_z2()));
    ::testing::Test::RecordProperty(what + "_mean_z2_true_sigma", std::to_string(mean_z2_true_sigma()));
  }
};

double rescale(double noise, const FitQuality& q) { return noise * noise / (q.sigma * q.sigma); }

Pts sphere_points(const Point3& c, double r, int n, double max_polar, const Point3& axis, std::mt19937_64& rng) {
  // Uniform on the cap of half-angle max_polar around axis.
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto [e1, e2] = frame(axis);
  Pts p;
  for (int i = 0; i < n; ++i) {
    const double cz = 1.0 - u(rng) * (1.0 - std::cos(max_polar));
    const double sz = std::sqrt(std::max(0.0, 1.0 - cz * cz)), phi = 2.0 * kPi * u(rng);
    p.push_back(c + r * (cz * axis + sz * (std::cos(phi) * e1 + std::sin(phi) * e2)));
  }
  return p;
}

Pts circle_points(const Point3& c, const Point3& n, double r, int count, double arc, double phase = 0.3) {
  const auto [e1, e2] = frame(n);
  Pts p;
  for (int i = 0; i < count; ++i) {
    const double t = phase + arc * i / (arc >= 2 * kPi - 1e-12 ? count : count - 1);
    p.push_back(c + r * (std::cos(t) * e1 + std::sin(t) * e2));
  }
  return p;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Sphere, free radius

TEST(FitSphere, ExactPointsRecoverCentreAndRadius) {
  std::mt19937_64 rng(11);
  const Point3 c(12.5, -30.0, 250.0);
  for (double cap : {kPi, kPi / 2, kPi / 6}) {
    const Pts p = sphere_points(c, 12.7, 40, cap, Point3(0.2, -0.3, 0.9).normalized(), rng);
    const auto f = fit_sphere(p);
    ASSERT_TRUE(f) << cap;
    EXPECT_TRUE(all_finite(*f));
    EXPECT_LE((f->centre - c).norm(), 1e-10) << cap;
    EXPECT_NEAR(f->radius, 12.7, 1e-10) << cap;
    ASSERT_EQ(f->quality.residuals.size(), p.size());
    for (double r : f->quality.residuals) EXPECT_LE(std::abs(r), 1e-10);
    EXPECT_EQ(f->quality.dof, 36);
    EXPECT_GE(f->quality.iterations, 1);
    EXPECT_LE(f->quality.iterations, 50);
    ASSERT_EQ(f->covariance.rows(), 4);
    ASSERT_EQ(f->covariance.cols(), 4);
    EXPECT_LE(f->covariance.cwiseAbs().maxCoeff(), 1e-18);
  }
}

TEST(FitSphere, HandCalculationOctahedron) {
  // Distances 2+e on +-x, 2-e on +-y, 2 on +-z: by symmetry the centre stays, r = mean = 2.
  // J rows (-u, -1) give J^T J = diag(2, 2, 2, 6); sigma^2 = 4 e^2 / (6 - 4) = 2 e^2.
  const double e = 0.01;
  const Point3 c(1, 2, 3);
  const Pts p{c + Point3(2 + e, 0, 0),  c + Point3(-2 - e, 0, 0), c + Point3(0, 2 - e, 0),
              c + Point3(0, -2 + e, 0), c + Point3(0, 0, 2),      c + Point3(0, 0, -2)};
  const auto f = fit_sphere(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->centre - c).norm(), 1e-12);
  EXPECT_NEAR(f->radius, 2.0, 1e-12);
  const std::vector<double> expected{e, e, -e, -e, 0, 0};  // outside positive, input order
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(f->quality.residuals[i], expected[i], 1e-12) << i;
  EXPECT_EQ(f->quality.dof, 2);
  EXPECT_NEAR(f->quality.rms, e * std::sqrt(4.0 / 6.0), 1e-14);
  EXPECT_NEAR(f->quality.sigma, e * std::sqrt(2.0), 1e-14);
  Eigen::Vector4d d(e * e, e * e, e * e, e * e / 3);
  EXPECT_LE((f->covariance - Eigen::MatrixXd(d.asDiagonal())).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(FitSphere, FourPointsHaveZeroDofAndZeroCovariance) {
  const Point3 c(-1, 4, 0.5);
  const Pts p{c + Point3(3, 0, 0), c + Point3(0, 3, 0), c + Point3(0, 0, 3),
              c + Point3(-3, 0, 0) * 0.6 + Point3(0, 0, -3) * 0.8};
  const auto f = fit_sphere(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->centre - c).norm(), 1e-12);
  EXPECT_NEAR(f->radius, 3.0, 1e-12);
  EXPECT_EQ(f->quality.dof, 0);
  EXPECT_EQ(f->quality.sigma, 0.0);
  EXPECT_TRUE(zero_matrix(f->covariance, 4));
}

TEST(FitSphere, NoisyPointsWithinReportedCovariance) {
  std::mt19937_64 rng(2024);
  const Point3 c(50, -20, 100);
  const double r = 10.0, noise = 0.003;
  Coverage cov;
  double sigma_sum = 0;
  const int trials = 200;
  for (int t = 0; t < trials; ++t) {
    Pts p = sphere_points(c, r, 25, kPi / 2, Point3(0, 0, 1), rng);
    for (auto& x : p) x += gaussian(rng, noise);
    const auto f = fit_sphere(p);
    ASSERT_TRUE(f) << t;
    EXPECT_TRUE(all_finite(*f));
    for (int i = 0; i < 3; ++i) cov.add(f->centre(i) - c(i), f->covariance(i, i), rescale(noise, f->quality));
    cov.add(f->radius - r, f->covariance(3, 3), rescale(noise, f->quality));
    sigma_sum += f->quality.sigma;
  }
  cov.expect_good("sphere");
  EXPECT_NEAR(sigma_sum / trials / noise, 1.0, 0.1);
}

TEST(FitSphere, DegenerateInputGivesNullopt) {
  const Point3 c(1, 2, 3);
  EXPECT_FALSE(fit_sphere(Pts{}));
  EXPECT_FALSE(fit_sphere(Pts{c + Point3(1, 0, 0), c + Point3(0, 1, 0), c + Point3(0, 0, 1)}));  // 3 points
  EXPECT_FALSE(fit_sphere(Pts(6, Point3(0.1, 0.2, 0.3))));                                       // coincident
  EXPECT_FALSE(fit_sphere(Pts{c, c, c, c + Point3(1, 1, 1), c + Point3(1, 1, 1)}));              // two points
  EXPECT_FALSE(fit_sphere(circle_points(c, Point3(1, 2, 2).normalized(), 5.0, 12, 2 * kPi)));    // circle
  Pts plane;  // coplanar, not on a circle
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) plane.push_back(c + Point3(i, j * j, 0));
  EXPECT_FALSE(fit_sphere(plane));
  Pts line;
  for (int i = 0; i < 6; ++i) line.push_back(c + i * Point3(1, -2, 0.5));
  EXPECT_FALSE(fit_sphere(line));
  Pts good{c + Point3(3, 0, 0), c + Point3(0, 3, 0), c + Point3(0, 0, 3), c - Point3(3, 0, 0), c - Point3(0, 0, 3)};
  ASSERT_TRUE(fit_sphere(good));
  for (double bad : {kNaN, kInf}) {
    Pts b = good;
    b[2].y() = bad;
    EXPECT_FALSE(fit_sphere(b));
  }
}

// ---------------------------------------------------------------------------------------------
// Sphere, known radius

TEST(FitSphereKnownRadius, ExactPointsRecoverCentre) {
  std::mt19937_64 rng(5);
  const Point3 c(-100, 7, 33);
  for (double cap : {kPi, kPi / 3, kPi / 12}) {
    const Pts p = sphere_points(c, 6.35, 15, cap, Point3(1, 1, -1).normalized(), rng);
    const auto f = fit_sphere_known_radius(p, 6.35);
    ASSERT_TRUE(f) << cap;
    EXPECT_TRUE(all_finite(*f));
    EXPECT_LE((f->centre - c).norm(), 1e-10) << cap;
    EXPECT_EQ(f->radius, 6.35);
    EXPECT_EQ(f->quality.dof, 12);
    ASSERT_EQ(f->covariance.rows(), 3);
    ASSERT_EQ(f->covariance.cols(), 3);
    EXPECT_LE(f->covariance.cwiseAbs().maxCoeff(), 1e-18);
    // The true side as a hint changes nothing.
    const auto g = fit_sphere_known_radius(p, 6.35, c + Point3(0.1, 0, 0));
    ASSERT_TRUE(g);
    EXPECT_TRUE(all_finite(*g));
    EXPECT_LE((g->centre - c).norm(), 1e-10) << cap;
  }
}

TEST(FitSphereKnownRadius, ThreePointsMirrorSolutionsFollowTheHint) {
  // Circumcircle of the three points: centre 0, radius 3; with R = 5 the centres are (0, 0, +-4).
  const Pts p{Point3(3, 0, 0), Point3(0, 3, 0), Point3(-3, 0, 0)};
  const auto up = fit_sphere_known_radius(p, 5.0, Point3(0, 0, 10));
  const auto down = fit_sphere_known_radius(p, 5.0, Point3(0.5, 0, -1));
  ASSERT_TRUE(up);
  EXPECT_TRUE(all_finite(*up));
  ASSERT_TRUE(down);
  EXPECT_TRUE(all_finite(*down));
  EXPECT_LE((up->centre - Point3(0, 0, 4)).norm(), 1e-12);
  EXPECT_LE((down->centre - Point3(0, 0, -4)).norm(), 1e-12);
  EXPECT_EQ(up->quality.dof, 0);
  EXPECT_TRUE(zero_matrix(up->covariance, 3));
  for (double r : down->quality.residuals) EXPECT_LE(std::abs(r), 1e-12);
  // No hint: the side the canonical plane normal (+z) points to.
  const auto none = fit_sphere_known_radius(p, 5.0);
  ASSERT_TRUE(none);
  EXPECT_TRUE(all_finite(*none));
  EXPECT_LE((none->centre - Point3(0, 0, 4)).norm(), 1e-12);

  // General position: mirror images of the true centre across the plane of the points.
  std::mt19937_64 rng(8);
  for (int t = 0; t < 20; ++t) {
    const Point3 c = 100 * random_unit(rng);
    const Pts q{c + 8 * random_unit(rng), c + 8 * random_unit(rng), c + 8 * random_unit(rng)};
    const Point3 n = (q[1] - q[0]).cross(q[2] - q[0]).normalized();
    const Point3 mirror = c - 2 * n.dot(c - q[0]) * n;
    const auto a = fit_sphere_known_radius(q, 8.0, c + 0.5 * (c - mirror));
    const auto b = fit_sphere_known_radius(q, 8.0, mirror + 0.5 * (mirror - c));
    ASSERT_TRUE(a && b) << t;
    EXPECT_LE((a->centre - c).norm(), 1e-9) << t;
    EXPECT_LE((b->centre - mirror).norm(), 1e-9) << t;
  }
}

TEST(FitSphereKnownRadius, NoisyPointsWithinReportedCovariance) {
  std::mt19937_64 rng(77);
  const Point3 c(5, 5, -40);
  const double r = 12.7, noise = 0.002;
  Coverage cov;
  for (int t = 0; t < 200; ++t) {
    Pts p = sphere_points(c, r, 12, kPi / 3, Point3(0, 1, 0), rng);
    for (auto& x : p) x += gaussian(rng, noise);
    const auto f = fit_sphere_known_radius(p, r, c + Point3(0, -3, 0));
    ASSERT_TRUE(f) << t;
    EXPECT_TRUE(all_finite(*f));
    for (int i = 0; i < 3; ++i) cov.add(f->centre(i) - c(i), f->covariance(i, i), rescale(noise, f->quality));
  }
  cov.expect_good("sphere_known_radius");
}

TEST(FitSphereKnownRadius, DegenerateInputGivesNullopt) {
  const Pts tri{Point3(3, 0, 0), Point3(0, 3, 0), Point3(-3, 0, 0)};
  EXPECT_FALSE(fit_sphere_known_radius(Pts{Point3(3, 0, 0), Point3(0, 3, 0)}, 5.0));
  EXPECT_FALSE(fit_sphere_known_radius(Pts{Point3(0, 0, 0), Point3(1, 1, 1), Point3(2, 2, 2)}, 5.0));  // line
  EXPECT_FALSE(fit_sphere_known_radius(Pts(5, Point3(1, 2, 3)), 5.0));                                 // one point
  EXPECT_FALSE(fit_sphere_known_radius(tri, 0.0));
  EXPECT_FALSE(fit_sphere_known_radius(tri, -5.0));
  EXPECT_FALSE(fit_sphere_known_radius(tri, kNaN));
  EXPECT_FALSE(fit_sphere_known_radius(tri, 5.0, Point3(0, 0, kNaN)));
  // A radius below the points' circumradius: the centre's height is not determined.
  EXPECT_FALSE(fit_sphere_known_radius(tri, 2.0));
  Pts b = tri;
  b[1].x() = kInf;
  EXPECT_FALSE(fit_sphere_known_radius(b, 5.0));
}

// ---------------------------------------------------------------------------------------------
// Plane

TEST(FitPlane, ExactPointsRecoverPlane) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-20, 20);
  const Point3 n = Point3(0.3, -0.4, 0.6).normalized(), p0(100, 200, 300);
  const auto [e1, e2] = frame(n);
  Pts p;
  for (int i = 0; i < 30; ++i) p.push_back(p0 + u(rng) * e1 + u(rng) * e2);
  const auto f = fit_plane(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->normal - n).norm(), 1e-12);
  Point3 mean = Point3::Zero();
  for (const auto& x : p) mean += x / 30.0;
  EXPECT_LE((f->point - mean).norm(), 1e-12);
  for (double r : f->quality.residuals) EXPECT_LE(std::abs(r), 1e-10);
  EXPECT_EQ(f->quality.dof, 27);
  EXPECT_EQ(f->quality.iterations, 0);
  EXPECT_EQ(f->covariance.rows(), 3);
}

TEST(FitPlane, HandCalculationSaddle) {
  // z = e x y on (+-1, +-1): plane z = 0, residuals e, -e, -e, e; J rows (x, y, -1) give
  // J^T J = 4 I and sigma^2 = 4 e^2 / (4 - 3), so the covariance is e^2 I.
  const double e = 0.02;
  const Pts p{Point3(1, 1, e), Point3(1, -1, -e), Point3(-1, 1, -e), Point3(-1, -1, e)};
  const auto f = fit_plane(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->normal - Point3::UnitZ()).norm(), 1e-15);
  EXPECT_LE(f->point.norm(), 1e-15);
  const std::vector<double> expected{e, -e, -e, e};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(f->quality.residuals[i], expected[i], 1e-15);
  EXPECT_EQ(f->quality.dof, 1);
  EXPECT_NEAR(f->quality.sigma, 2 * e, 1e-15);
  EXPECT_NEAR(f->quality.rms, e, 1e-15);
  EXPECT_LE((f->covariance - e * e * Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-17);
}

TEST(FitPlane, NormalSignAndResidualSign) {
  for (const Point3& n0 : {Point3(-0.6, 0, -0.8), Point3(0.3, -0.9, 0.2).normalized(), Point3(-1, 0, 0)}) {
    const auto [e1, e2] = frame(n0);
    const Point3 p0(1, 2, 3);
    Pts p{p0, p0 + e1, p0 + e2, p0 - e1 + 2 * e2, p0 + 0.1 * n0};  // last one off the plane along n0
    const auto f = fit_plane(p);
    ASSERT_TRUE(f);
    EXPECT_TRUE(all_finite(*f));
    EXPECT_GT(f->normal(largest(f->normal)), 0.0);
    EXPECT_NEAR(std::abs(f->normal.dot(n0)), 1.0, 1e-2);
    // The point displaced along n0 lies on the side of n0: positive if n0 agrees with the normal.
    const double side = f->normal.dot(n0) > 0 ? 1.0 : -1.0;
    EXPECT_GT(side * f->quality.residuals[4], 0.0);
  }
}

TEST(FitPlane, ThreePointsHaveZeroDofAndZeroCovariance) {
  const auto f = fit_plane(Pts{Point3(0, 0, 5), Point3(1, 0, 5), Point3(0, 1, 5)});
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->normal - Point3::UnitZ()).norm(), 1e-15);
  EXPECT_EQ(f->quality.dof, 0);
  EXPECT_EQ(f->quality.sigma, 0.0);
  EXPECT_TRUE(zero_matrix(f->covariance, 3));
}

TEST(FitPlane, NoisyPointsWithinReportedCovariance) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(-30, 30);
  const Point3 n = Point3(0.1, 0.25, 0.9).normalized(), p0(100, -50, 300);
  const auto [e1, e2] = frame(n);
  const int k = largest(n), i = (k + 1) % 3, j = (k + 2) % 3;
  const double d = n.dot(p0), noise = 0.01;
  Coverage cov;
  for (int t = 0; t < 200; ++t) {
    Pts p;
    for (int m = 0; m < 15; ++m) p.push_back(p0 + u(rng) * e1 + u(rng) * e2 + gaussian(rng, noise));
    const auto f = fit_plane(p);
    ASSERT_TRUE(f);
    EXPECT_TRUE(all_finite(*f));
    ASSERT_EQ(largest(f->normal), k);
    cov.add(f->normal(i) - n(i), f->covariance(0, 0), rescale(noise, f->quality));
    cov.add(f->normal(j) - n(j), f->covariance(1, 1), rescale(noise, f->quality));
    cov.add(f->normal.dot(f->point) - d, f->covariance(2, 2), rescale(noise, f->quality));
  }
  cov.expect_good("plane");
}

TEST(FitPlane, DegenerateInputGivesNullopt) {
  EXPECT_FALSE(fit_plane(Pts{}));
  EXPECT_FALSE(fit_plane(Pts{Point3(0, 0, 0), Point3(1, 0, 0)}));
  EXPECT_FALSE(fit_plane(Pts{Point3(0, 0, 0), Point3(1, 2, 3), Point3(2, 4, 6), Point3(-1, -2, -3)}));
  EXPECT_FALSE(fit_plane(Pts(4, Point3(0.1, 0.7, 0.3))));
  EXPECT_FALSE(fit_plane(Pts{Point3(0, 0, 0), Point3(0, 0, 0), Point3(1, 1, 0), Point3(1, 1, 0)}));
  EXPECT_FALSE(fit_plane(Pts{Point3(0, 0, 0), Point3(1, 0, 0), Point3(0, kNaN, 0)}));
}

// ---------------------------------------------------------------------------------------------
// Line

TEST(FitLine, ExactPointsRecoverLine) {
  const Point3 u = Point3(-0.2, 0.3, -0.9).normalized(), p0(10, 20, 30);
  Pts p;
  for (int i = 0; i < 7; ++i) p.push_back(p0 + (i * i - 3.0 * i) * u);
  const auto f = fit_line(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->direction + u).norm(), 1e-14);  // sign: z component made positive
  EXPECT_GT(f->direction.z(), 0.0);
  EXPECT_LE((f->point - p0).cross(u).norm(), 1e-12);
  for (double r : f->quality.residuals) EXPECT_LE(r, 1e-12);
  EXPECT_EQ(f->quality.dof, 10);
  EXPECT_EQ(f->covariance.rows(), 4);
}

TEST(FitLine, HandCalculation) {
  // (+-1, +-e, 0) about the x axis: distances e, dof 2*4 - 4, sigma^2 = 4 e^2 / 4; J rows
  // (-t, 0, -1, 0) and (0, -t, 0, -1) with t = +-1 give J^T J = 4 I, covariance e^2/4 I.
  const double e = 0.05;
  const Pts p{Point3(-1, e, 0), Point3(1, e, 0), Point3(-1, -e, 0), Point3(1, -e, 0)};
  const auto f = fit_line(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->direction - Point3::UnitX()).norm(), 1e-15);
  EXPECT_LE(f->point.norm(), 1e-15);
  for (double r : f->quality.residuals) EXPECT_NEAR(r, e, 1e-15);
  EXPECT_EQ(f->quality.dof, 4);
  EXPECT_NEAR(f->quality.sigma, e, 1e-15);
  EXPECT_NEAR(f->quality.rms, e, 1e-15);
  EXPECT_LE((f->covariance - e * e / 4 * Eigen::MatrixXd::Identity(4, 4)).cwiseAbs().maxCoeff(), 1e-17);
}

TEST(FitLine, TwoPointsHaveZeroDofAndZeroCovariance) {
  const auto f = fit_line(Pts{Point3(1, 1, 1), Point3(1, 1, -3)});
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE((f->direction - Point3::UnitZ()).norm(), 1e-15);
  EXPECT_LE((f->point - Point3(1, 1, -1)).norm(), 1e-15);
  EXPECT_EQ(f->quality.dof, 0);
  EXPECT_TRUE(zero_matrix(f->covariance, 4));
}

TEST(FitLine, NoisyPointsWithinReportedCovariance) {
  std::mt19937_64 rng(123);
  std::uniform_real_distribution<double> s(-50, 50);
  const Point3 u = Point3(0.3, 0.9, -0.2).normalized(), p0(-5, 40, 12);
  const int k = largest(u), i = (k + 1) % 3, j = (k + 2) % 3;
  const double noise = 0.005;
  Coverage cov;
  for (int t = 0; t < 200; ++t) {
    Pts p;
    for (int m = 0; m < 10; ++m) p.push_back(p0 + s(rng) * u + gaussian(rng, noise));
    const auto f = fit_line(p);
    ASSERT_TRUE(f);
    EXPECT_TRUE(all_finite(*f));
    ASSERT_EQ(largest(f->direction), k);
    // Where the true line crosses the plane x_k = point_k.
    const Point3 cross = p0 + (f->point(k) - p0(k)) / u(k) * u;
    cov.add(f->direction(i) - u(i), f->covariance(0, 0), rescale(noise, f->quality));
    cov.add(f->direction(j) - u(j), f->covariance(1, 1), rescale(noise, f->quality));
    cov.add(f->point(i) - cross(i), f->covariance(2, 2), rescale(noise, f->quality));
    cov.add(f->point(j) - cross(j), f->covariance(3, 3), rescale(noise, f->quality));
  }
  cov.expect_good("line");
}

TEST(FitLine, DegenerateInputGivesNullopt) {
  EXPECT_FALSE(fit_line(Pts{}));
  EXPECT_FALSE(fit_line(Pts{Point3(1, 2, 3)}));
  EXPECT_FALSE(fit_line(Pts{Point3(1, 2, 3), Point3(1, 2, 3)}));
  EXPECT_FALSE(fit_line(Pts(7, Point3(0.1, 0.1, 0.1))));
  EXPECT_FALSE(fit_line(Pts{Point3(1, 2, 3), Point3(kInf, 2, 3)}));
}

// ---------------------------------------------------------------------------------------------
// Circle in 3D

TEST(FitCircle, ExactPointsRecoverCircle) {
  const Point3 c(250, -120, 80), n = Point3(0.2, -0.3, 0.93).normalized();
  for (double arc : {2 * kPi, kPi / 2, kPi / 9}) {
    const Pts p = circle_points(c, n, 75.0, 12, arc);
    const auto f = fit_circle(p);
    ASSERT_TRUE(f) << arc;
    EXPECT_TRUE(all_finite(*f));
    EXPECT_LE((f->centre - c).norm(), 1e-10) << arc;
    EXPECT_LE((f->normal - n).norm(), 1e-12) << arc;
    EXPECT_NEAR(f->radius, 75.0, 1e-10) << arc;
    for (double r : f->quality.residuals) EXPECT_LE(std::abs(r), 1e-10);
    EXPECT_EQ(f->quality.dof, 18);
    EXPECT_EQ(f->covariance.rows(), 6);
  }
}

TEST(FitCircle, HandCalculationThreePoints) {
  const Pts p{Point3(1, 0, 0), Point3(0, 1, 0), Point3(-1, 0, 0)};
  const auto f = fit_circle(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE(f->centre.norm(), 1e-15);
  EXPECT_LE((f->normal - Point3::UnitZ()).norm(), 1e-15);
  EXPECT_NEAR(f->radius, 1.0, 1e-15);
  EXPECT_EQ(f->quality.dof, 0);
  EXPECT_EQ(f->quality.sigma, 0.0);
  EXPECT_TRUE(zero_matrix(f->covariance, 6));
  // Reversed order gives the same normal: the sign is by convention, not by orientation.
  const auto g = fit_circle(Pts{p[2], p[1], p[0]});
  ASSERT_TRUE(g);
  EXPECT_TRUE(all_finite(*g));
  EXPECT_LE((g->normal - Point3::UnitZ()).norm(), 1e-15);
}

TEST(FitCircle, ResidualsAreRadialInInputOrder) {
  // Radii 1+e, 1-e, 1+e, 1-e: centre 0, r 1, radial residuals +-e.
  const double e = 0.01;
  const Pts p{Point3(1 + e, 0, 0), Point3(0, 1 - e, 0), Point3(-1 - e, 0, 0), Point3(0, -1 + e, 0)};
  const auto f = fit_circle(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE(f->centre.norm(), 1e-14);
  EXPECT_NEAR(f->radius, 1.0, 1e-14);
  const std::vector<double> expected{e, -e, e, -e};
  for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(f->quality.residuals[i], expected[i], 1e-14) << i;
  EXPECT_NEAR(f->quality.rms, e, 1e-14);
  EXPECT_EQ(f->quality.dof, 2);
  EXPECT_NEAR(f->quality.sigma, std::sqrt(4 * e * e / 2), 1e-14);

  // Heights +-e instead: no radial residual; the out-of-plane part only enters sigma.
  const Pts q{Point3(1, 0, e), Point3(0, 1, -e), Point3(-1, 0, e), Point3(0, -1, -e)};
  const auto g = fit_circle(q);
  ASSERT_TRUE(g);
  EXPECT_TRUE(all_finite(*g));
  EXPECT_LE(g->centre.norm(), 1e-14);
  EXPECT_LE((g->normal - Point3::UnitZ()).norm(), 1e-14);
  EXPECT_NEAR(g->radius, 1.0, 1e-14);
  EXPECT_NEAR(g->quality.rms, 0.0, 1e-14);
  EXPECT_NEAR(g->quality.sigma, std::sqrt(4 * e * e / 2), 1e-14);
}

TEST(FitCircle, CentreVarianceAlongTheNormalIsThePlaneOffsets) {
  // Eight points on the unit circle at heights +-e alternately: centre 0, normal z, no radial
  // residual. The plane's offset enters only the out-of-plane rows (-1 each, orthogonal to the
  // other columns), so the centre's variance along the normal is sigma_a^2 / 8, with the
  // out-of-plane variance sigma_a^2 = 8 e^2 / (8 - 3) estimated from the out-of-plane residuals
  // alone: the plane is estimated, the centre block has full rank.
  const double e = 0.01;
  Pts p;
  for (int m = 0; m < 8; ++m) p.push_back(Point3(std::cos(m * kPi / 4), std::sin(m * kPi / 4), m % 2 ? -e : e));
  const auto f = fit_circle(p);
  ASSERT_TRUE(f);
  EXPECT_TRUE(all_finite(*f));
  EXPECT_LE(f->centre.norm(), 1e-14);
  EXPECT_LE((f->normal - Point3::UnitZ()).norm(), 1e-14);
  EXPECT_NEAR(f->radius, 1.0, 1e-14);
  EXPECT_EQ(f->quality.dof, 10);
  EXPECT_NEAR(f->quality.sigma * f->quality.sigma, 0.8 * e * e, 1e-17);
  EXPECT_NEAR(f->covariance(2, 2), 0.2 * e * e, 1e-18);
  EXPECT_LE((f->covariance.block<2, 1>(0, 2).norm()), 1e-18);
}

TEST(FitCircle, NormalSignLargestComponentPositive) {
  for (const Point3& n0 : {Point3(0.2, -0.3, -0.93), Point3(-0.9, 0.1, 0.3), Point3(0.3, -0.8, 0.1)}) {
    const auto f = fit_circle(circle_points(Point3(1, 2, 3), n0.normalized(), 4.0, 7, 2.0));
    ASSERT_TRUE(f);
    EXPECT_TRUE(all_finite(*f));
    EXPECT_GT(f->normal(largest(f->normal)), 0.0);
    EXPECT_NEAR(std::abs(f->normal.dot(n0.normalized())), 1.0, 1e-12);
  }
}

TEST(FitCircle, NoisyPointsWithinReportedCovariance) {
  std::mt19937_64 rng(31);
  const Point3 c(120, 40, -300), n = Point3(0.15, -0.2, 0.95).normalized();
  const double r = 80.0, noise = 0.004;
  const int k = largest(n), i = (k + 1) % 3, j = (k + 2) % 3;
  for (double arc : {2 * kPi, 2 * kPi / 3}) {
    Coverage cov;
    double sigma_sum = 0.0;
    for (int t = 0; t < 200; ++t) {
      Pts p = circle_points(c, n, r, 9, arc, 0.1 * t);
      for (auto& x : p) x += gaussian(rng, noise);
      const auto f = fit_circle(p);
      ASSERT_TRUE(f) << t;
      EXPECT_TRUE(all_finite(*f));
      ASSERT_EQ(largest(f->normal), k);
      for (int a = 0; a < 3; ++a) cov.add(f->centre(a) - c(a), f->covariance(a, a), rescale(noise, f->quality));
      cov.add(f->normal(i) - n(i), f->covariance(3, 3), rescale(noise, f->quality));
      cov.add(f->normal(j) - n(j), f->covariance(4, 4), rescale(noise, f->quality));
      cov.add(f->radius - r, f->covariance(5, 5), rescale(noise, f->quality));
      sigma_sum += f->quality.sigma;
    }
    cov.expect_good(arc > 6 ? "circle_full" : "circle_arc120");
    EXPECT_NEAR(sigma_sum / 200 / noise, 1.0, 0.1) << arc;
  }
}

TEST(FitCircle, DegenerateInputGivesNullopt) {
  EXPECT_FALSE(fit_circle(Pts{}));
  EXPECT_FALSE(fit_circle(Pts{Point3(1, 0, 0), Point3(0, 1, 0)}));
  EXPECT_FALSE(fit_circle(Pts{Point3(0, 0, 0), Point3(1, 1, 0), Point3(2, 2, 0), Point3(5, 5, 0)}));
  EXPECT_FALSE(fit_circle(Pts(3, Point3(3, 3, 3))));
  EXPECT_FALSE(fit_circle(Pts{Point3(1, 0, 0), Point3(0, 1, 0), Point3(1, 0, 0), Point3(0, 1, 0)}));
  EXPECT_FALSE(fit_circle(Pts{Point3(1, 0, 0), Point3(0, 1, 0), Point3(-1, 0, kNaN)}));
}

// ---------------------------------------------------------------------------------------------
// Circle through three points

TEST(CircleThrough, HandCalculation) {
  const auto c = circle_through(Point3(1, 0, 0), Point3(0, 1, 0), Point3(-1, 0, 0));
  ASSERT_TRUE(c);
  EXPECT_LE(c->centre.norm(), 1e-16);
  EXPECT_LE((c->normal - Point3::UnitZ()).norm(), 1e-16);
  EXPECT_DOUBLE_EQ(c->radius, 1.0);
  // Clockwise order: same normal by the sign convention.
  const auto d = circle_through(Point3(-1, 0, 0), Point3(0, 1, 0), Point3(1, 0, 0));
  ASSERT_TRUE(d);
  EXPECT_LE((d->normal - Point3::UnitZ()).norm(), 1e-16);
  // Right triangle: the centre is the midpoint of the hypotenuse.
  const auto e = circle_through(Point3(0, 0, 2), Point3(6, 0, 2), Point3(0, 8, 2));
  ASSERT_TRUE(e);
  EXPECT_LE((e->centre - Point3(3, 4, 2)).norm(), 1e-14);
  EXPECT_NEAR(e->radius, 5.0, 1e-14);
}

TEST(CircleThrough, EquidistantInPlaneAndAgreesWithFitCircle) {
  std::mt19937_64 rng(17);
  for (int t = 0; t < 500; ++t) {
    const Point3 o = 200 * random_unit(rng);
    const Point3 a = o + 30 * random_unit(rng), b = o + 30 * random_unit(rng), c = o + 30 * random_unit(rng);
    const auto r = circle_through(a, b, c);
    ASSERT_TRUE(r) << t;
    const double s = 1e-10 * std::max(1.0, r->radius);
    EXPECT_NEAR((a - r->centre).norm(), r->radius, s);
    EXPECT_NEAR((b - r->centre).norm(), r->radius, s);
    EXPECT_NEAR((c - r->centre).norm(), r->radius, s);
    EXPECT_NEAR(r->normal.norm(), 1.0, 1e-15);
    EXPECT_NEAR(r->normal.dot(b - a), 0.0, 1e-11);
    EXPECT_NEAR(r->normal.dot(c - a), 0.0, 1e-11);
    EXPECT_GT(r->normal(largest(r->normal)), 0.0);
    const auto f = fit_circle(Pts{a, b, c});
    ASSERT_TRUE(f) << t;
    EXPECT_TRUE(all_finite(*f));
    EXPECT_LE((f->centre - r->centre).norm(), s) << t;
    EXPECT_LE((f->normal - r->normal).norm(), 1e-9) << t;
    EXPECT_NEAR(f->radius, r->radius, s) << t;
  }
}

TEST(CircleThrough, DegenerateInputGivesNullopt) {
  const Point3 a(1, 2, 3), b(4, 5, 6);
  EXPECT_FALSE(circle_through(a, a, a));
  EXPECT_FALSE(circle_through(a, a, b));
  EXPECT_FALSE(circle_through(a, b, 2 * b - a));
  EXPECT_FALSE(circle_through(a, b, a + 0.5 * (b - a)));
  // Threshold: |(b-a)x(c-a)| against 1e-12 times the squared longest side.
  EXPECT_FALSE(circle_through(Point3(0, 0, 0), Point3(2, 0, 0), Point3(1, 1e-13, 0)));
  EXPECT_TRUE(circle_through(Point3(0, 0, 0), Point3(2, 0, 0), Point3(1, 1e-10, 0)));
  EXPECT_FALSE(circle_through(a, b, Point3(kNaN, 0, 0)));
  EXPECT_FALSE(circle_through(a, b, Point3(0, kInf, 0)));
}
