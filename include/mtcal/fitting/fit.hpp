// Least-squares fits of measured points: sphere, plane, circle in 3D, line; with residuals and covariance.
#pragma once

#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace mtcal {

using Point3 = Eigen::Vector3d;

// What every fit reports besides its geometry.
struct FitQuality {
  std::vector<double> residuals;  // signed geometric residual per point (mm), in input order
  double rms = 0.0;               // sqrt(sum r^2 / n)
  double sigma = 0.0;             // sqrt(sum r^2 / (n - p)): residual standard deviation; 0 if n == p
  int dof = 0;                    // n - p (redundancy); covariance is zero when dof == 0
  int iterations = 0;             // Gauss-Newton iterations used (0 for closed-form fits)
};

// Sphere |x - centre| = radius. Geometric least squares (Gauss-Newton from the algebraic
// Kasa fit). covariance: of (cx, cy, cz, r), or of (cx, cy, cz) when the radius is known.
struct SphereFit {
  Point3 centre = Point3::Zero();
  double radius = 0.0;
  Eigen::MatrixXd covariance;  // sigma^2 (J^T J)^-1
  FitQuality quality;
};
// Free radius: needs >= 4 points not all on one plane (or circle). Known radius: >= 3 points not
// all on one line; of the two mirror solutions of 3 points the one nearer the algebraic start /
// the hint (if given) is returned. nullopt for degenerate input or no convergence.
std::optional<SphereFit> fit_sphere(std::span<const Point3> points);
std::optional<SphereFit> fit_sphere_known_radius(std::span<const Point3> points, double radius,
                                                 const std::optional<Point3>& hint = std::nullopt);

// Plane through point with unit normal (orthogonal regression: smallest singular vector).
// Normal sign: the component of largest magnitude is made positive. covariance: 3x3 of
// (n_i, n_j, d) with k, i, j as for CircleFit and d the offset of the plane along its normal.
struct PlaneFit {
  Point3 point = Point3::Zero();  // centroid of the points
  Point3 normal = Point3::UnitZ();
  Eigen::MatrixXd covariance;
  FitQuality quality;
};
// >= 3 points not all on one line; nullopt otherwise.
std::optional<PlaneFit> fit_plane(std::span<const Point3> points);

// Line through point along unit direction (orthogonal regression: largest singular vector).
// Direction sign: the component of largest magnitude is made positive. Residuals are distances
// to the line (>= 0). covariance: 4x4 of (u_i, u_j, p_i, p_j): with k the direction's largest
// component and i = (k+1)%3, j = (k+2)%3, the direction's i, j components and where the line
// crosses the plane x_k = point_k.
struct LineFit {
  Point3 point = Point3::Zero();  // centroid
  Point3 direction = Point3::UnitX();
  Eigen::MatrixXd covariance;
  FitQuality quality;
};
// >= 2 distinct points; nullopt otherwise.
std::optional<LineFit> fit_line(std::span<const Point3> points);

// Circle in 3D: centre, unit normal of its plane, radius. Plane by orthogonal regression, then
// geometric circle fit in that plane, then a joint Gauss-Newton refinement of all six parameters
// on the 3D residuals (radial and out-of-plane distance per point). Exactly 3 points give the
// circumscribed circle. Normal sign: largest-magnitude component positive.
// covariance: 6x6 of (cx, cy, cz, n_i, n_j, r), where k is the normal's largest component and
// i = (k+1)%3, j = (k+2)%3 its other two (n_k follows from |n| = 1); zero when dof == 0.
// The centre's variance along the normal is that of the plane's offset (full-rank block).
// dof counts residual equations: 2n - 6 (radial and out-of-plane per point); rms is of the radial
// residuals, sigma of both. The covariance weights the radial and the out-of-plane residuals by
// their own variances (each estimated with n - 3 degrees of freedom).
struct CircleFit {
  Point3 centre = Point3::Zero();
  Point3 normal = Point3::UnitZ();
  double radius = 0.0;
  Eigen::MatrixXd covariance;
  FitQuality quality;  // residuals: in-plane radial deviation per point
};
// >= 3 points not all on one line; nullopt otherwise.
std::optional<CircleFit> fit_circle(std::span<const Point3> points);
// The circle through exactly three points (closed form, no allocation): nullopt if they are
// (nearly) collinear. Used for the all-triples analysis, so it must be fast.
struct Circle3 {
  Point3 centre;
  Point3 normal;  // unit, sign as in fit_circle
  double radius;
};
std::optional<Circle3> circle_through(const Point3& a, const Point3& b, const Point3& c);

}  // namespace mtcal
