// Least-squares sphere, plane, line and 3D circle fits: closed-form starts, Gauss-Newton, covariance.
#include "mtcal/fitting/fit.hpp"
#include "mtcal/fitting/least_squares.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace mtcal {

namespace {

using Eigen::Index;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;

// Below this spread (relative to the coordinate magnitude) the points are one point: centroid
// rounding alone leaves residue of ~1e-16 relative, which must not pass as geometry.
constexpr double kCoincident = 1e-12;
// Smallest / largest singular value of the centred points below which they are collinear
// (second value) or coplanar (third value).
constexpr double kFlat = 1e-9;
// Column-equilibrated Jacobian with a smaller singular value ratio leaves a parameter undetermined.
// Looser than kFlat squared but tighter than kFlat, so kFlat decides the ordinary degenerate cases.
constexpr double kRank = 1e-10;
constexpr double kStepTol = 1e-13;   // converged: step below this, relative to the problem's size
constexpr double kFloorStep = 1e-9;  // steps below this that stop shrinking are rounding noise
constexpr int kMaxIterations = 50;

// The points centred on their centroid with the principal axes of their spread.
struct Cloud {
  Vector3d centroid;
  MatrixXd y;        // n x 3, point minus centroid
  Vector3d sv;       // singular values of y, descending
  Matrix3d V;        // right singular vectors (columns), matching sv
  double spread{};   // RMS distance from the centroid
  bool collinear{};  // second singular value negligible
  bool coplanar{};   // third singular value negligible
};

// nullopt for non-finite input or (numerically) coincident points.
std::optional<Cloud> analyse(std::span<const Point3> pts) {
  const Index n = static_cast<Index>(pts.size());
  if (n == 0) return std::nullopt;
  Cloud c;
  c.centroid.setZero();
  double magnitude = 0.0;
  for (const Point3& p : pts) {
    if (!p.allFinite()) return std::nullopt;
    c.centroid += p;
    magnitude = std::max(magnitude, p.cwiseAbs().maxCoeff());
  }
  c.centroid /= static_cast<double>(n);
  c.y.resize(n, 3);
  for (Index m = 0; m < n; ++m) c.y.row(m) = (pts[static_cast<std::size_t>(m)] - c.centroid).transpose();
  // SVD of the points themselves, not an eigen-decomposition of their scatter matrix: the latter
  // squares the condition number and could not see a 1e-9 flatness.
  const Eigen::JacobiSVD<MatrixXd> svd(c.y, Eigen::ComputeFullV);
  // Fewer than 3 points give fewer than 3 singular values: the missing ones are zero.
  c.sv.setZero();
  c.sv.head(svd.singularValues().size()) = svd.singularValues();
  c.V = svd.matrixV();
  if (!(c.sv(0) > kCoincident * std::sqrt(static_cast<double>(n)) * magnitude)) return std::nullopt;
  c.spread = c.sv.norm() / std::sqrt(static_cast<double>(n));
  c.collinear = !(c.sv(1) > kFlat * c.sv(0));
  c.coplanar = !(c.sv(2) > kFlat * c.sv(0));
  return c;
}

Index largest_component(const Vector3d& v) {
  Index k = 0;
  v.cwiseAbs().maxCoeff(&k);
  return k;
}

Vector3d canonical_sign(const Vector3d& v) { return v(largest_component(v)) < 0 ? Vector3d(-v) : v; }

// d(unit vector)/d(v_i) when v_k = sqrt(1 - v_i^2 - v_j^2) follows from the other two.
Vector3d dependent_tangent(const Vector3d& v, Index k, Index i) {
  Vector3d t = Vector3d::Zero();
  t(i) = 1.0;
  t(k) = -v(i) / v(k);
  return t;
}

FitQuality make_quality(std::vector<double> residuals, double ssr, int dof, int iterations) {
  FitQuality q;
  double sum = 0.0;
  for (double r : residuals) sum += r * r;
  q.rms = residuals.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(residuals.size()));
  q.sigma = dof > 0 ? std::sqrt(ssr / dof) : 0.0;
  q.dof = dof;
  q.iterations = iterations;
  q.residuals = std::move(residuals);
  return q;
}

// sigma^2 (J^T J)^-1 at the solution (analyse_jacobian: columns equilibrated, so that the rank
// test does not depend on units, mm against rad); nullopt when a parameter is not determined by
// the points.
std::optional<MatrixXd> covariance(const MatrixXd& J, double sigma2, int dof) {
  const Index p = J.cols();
  const VectorXd norms = J.colwise().norm().transpose();
  if (!norms.allFinite() || !(norms.minCoeff() > 0.0)) return std::nullopt;
  // Scaled here by multiplying with the inverse norms (analyse_jacobian divides), as this fit has
  // always done: the same bits in every reported uncertainty.
  const VectorXd scale = norms.cwiseInverse();
  const JacobianAnalysis a = analyse_jacobian(J * scale.asDiagonal(), 1.0, JacobianOptions{kRank, false});
  if (!a.full_rank()) return std::nullopt;
  if (dof <= 0) return MatrixXd::Zero(p, p);
  MatrixXd cov = sigma2 * (scale.asDiagonal() * a.covariance * scale.asDiagonal());
  if (!cov.allFinite()) return std::nullopt;
  return cov;
}

// Gauss-Newton with step halving. eval(state, r, J*) fills the residuals and, if J is non-null,
// the Jacobian d r / d delta at delta = 0; advance(state, delta) applies a step. inv_scale turns
// a step into a relative size (1/length for lengths, 1 for angles). nullopt: no convergence.
template <class State, class Eval, class Advance>
std::optional<State> gauss_newton(State s, const Eval& eval, const Advance& advance, const VectorXd& inv_scale,
                                  double ssr_floor, int& iterations) {
  VectorXd r, r_try;
  MatrixXd J;
  eval(s, r, &J);
  if (!r.allFinite() || !J.allFinite()) return std::nullopt;
  double ssr = r.squaredNorm();
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 1; it <= kMaxIterations; ++it) {
    iterations = it;
    // Equilibrate so that column pivoting and its rank decision see comparable columns.
    VectorXd norms = J.colwise().norm().transpose();
    for (Index c = 0; c < norms.size(); ++c)
      if (!(norms(c) > 0.0)) norms(c) = 1.0;
    const MatrixXd Jn = J * norms.cwiseInverse().asDiagonal();
    const VectorXd delta = Jn.colPivHouseholderQr().solve(-r).cwiseQuotient(norms);
    if (!delta.allFinite()) return std::nullopt;
    const double size = delta.cwiseProduct(inv_scale).lpNorm<Eigen::Infinity>();
    // Halving protects the far-from-solution steps of short arcs and caps; near the solution
    // the full step is always taken.
    bool accepted = false;
    State trial = s;
    double t = 1.0;
    for (int h = 0; h < 20; ++h, t *= 0.5) {
      trial = advance(s, VectorXd(t * delta));
      eval(trial, r_try, nullptr);
      const double ssr_try = r_try.squaredNorm();
      if (std::isfinite(ssr_try) && ssr_try <= ssr * (1.0 + 1e-12) + ssr_floor) {
        ssr = ssr_try;
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      // No descent left: either we sit on the rounding floor, or the problem is hopeless.
      if (size <= kFloorStep) return s;
      return std::nullopt;
    }
    s = trial;
    eval(s, r, &J);
    if (!r.allFinite() || !J.allFinite()) return std::nullopt;
    if (size <= kStepTol) return s;
    if (size <= kFloorStep && size >= 0.5 * previous) return s;
    previous = size;
  }
  return std::nullopt;
}

// Algebraic circle through the points (u_m, v_m) in a plane: centre (a, b) and radius.
struct Circle2 {
  double a, b, r;
};
std::optional<Circle2> kasa_circle(const VectorXd& u, const VectorXd& v) {
  const Index n = u.size();
  MatrixXd A(n, 3);
  A.col(0) = 2.0 * u;
  A.col(1) = 2.0 * v;
  A.col(2).setOnes();
  const VectorXd b = u.cwiseAbs2() + v.cwiseAbs2();
  const Eigen::Vector3d x = A.colPivHouseholderQr().solve(b);
  const double r2 = x(2) + x(0) * x(0) + x(1) * x(1);
  if (!x.allFinite() || !(r2 > 0.0)) return std::nullopt;
  return Circle2{x(0), x(1), std::sqrt(r2)};
}

// Algebraic (Kasa) sphere of centred points: centre (centred coordinates) and radius.
std::optional<Eigen::Vector4d> kasa_sphere(const MatrixXd& y) {
  const Index n = y.rows();
  MatrixXd A(n, 4);
  A.leftCols(3) = 2.0 * y;
  A.col(3).setOnes();
  const VectorXd b = y.rowwise().squaredNorm();
  const Eigen::Vector4d x = A.colPivHouseholderQr().solve(b);
  const double r2 = x(3) + x.head<3>().squaredNorm();
  if (!x.allFinite() || !(r2 > 0.0)) return std::nullopt;
  return Eigen::Vector4d(x(0), x(1), x(2), std::sqrt(r2));
}

// Residuals |y - c| - R and their Jacobian with respect to c (and R when free).
void sphere_residuals(const MatrixXd& y, const Vector3d& c, double R, bool free_radius, VectorXd& r, MatrixXd* J) {
  const Index n = y.rows();
  r.resize(n);
  if (J) J->resize(n, free_radius ? 4 : 3);
  for (Index m = 0; m < n; ++m) {
    const Vector3d d = y.row(m).transpose() - c;
    const double dist = d.norm();
    r(m) = dist - R;
    if (J) {
      // A point on the centre has no defined direction; it then constrains only the radius.
      const Vector3d unit = dist > 0.0 ? Vector3d(d / dist) : Vector3d::Zero();
      J->row(m).head<3>() = -unit.transpose();
      if (free_radius) (*J)(m, 3) = -1.0;
    }
  }
}

std::vector<double> to_vector(const VectorXd& v) { return {v.data(), v.data() + v.size()}; }

struct KnownRadiusCandidate {
  Vector3d c;  // centred coordinates
  double ssr;
  int iterations;
};

std::optional<KnownRadiusCandidate> refine_known_radius(const Cloud& cl, double R, const Vector3d& start) {
  const Index n = cl.y.rows();
  const double scale = cl.spread + R;
  auto eval = [&](const Vector3d& c, VectorXd& r, MatrixXd* J) { sphere_residuals(cl.y, c, R, false, r, J); };
  auto advance = [](const Vector3d& c, const VectorXd& d) { return Vector3d(c + d); };
  int iterations = 0;
  const auto c = gauss_newton(start, eval, advance, VectorXd::Constant(3, 1.0 / scale),
                              static_cast<double>(n) * std::pow(1e-14 * scale, 2), iterations);
  if (!c) return std::nullopt;
  VectorXd r;
  eval(*c, r, nullptr);
  return KnownRadiusCandidate{*c, r.squaredNorm(), iterations};
}

// Circle state during the joint refinement: centre (centred coordinates), unit normal with an
// orthonormal in-plane basis, radius. Steps are (a, b, h, alpha, beta, dr): centre moves by
// a E1 + b E2 + h N, the normal tilts by alpha E1 + beta E2.
struct CircleState {
  Vector3d C, N, E1, E2;
  double r{};
};

CircleState advance_circle(const CircleState& s, const VectorXd& d) {
  CircleState t;
  t.C = s.C + d(0) * s.E1 + d(1) * s.E2 + d(2) * s.N;
  t.N = (s.N + d(3) * s.E1 + d(4) * s.E2).normalized();
  t.E1 = (s.E1 - s.E1.dot(t.N) * t.N).normalized();
  t.E2 = t.N.cross(t.E1);
  t.r = s.r + d(5);
  return t;
}

// Residuals: n in-plane radial deviations, then n signed distances from the plane.
void circle_residuals(const MatrixXd& y, const CircleState& s, VectorXd& r, MatrixXd* J) {
  const Index n = y.rows();
  r.resize(2 * n);
  if (J) J->setZero(2 * n, 6);
  for (Index m = 0; m < n; ++m) {
    const Vector3d d = y.row(m).transpose() - s.C;
    const double z = s.N.dot(d);
    const Vector3d p = d - z * s.N;
    const double rho = p.norm();
    r(m) = rho - s.r;
    r(n + m) = z;
    if (J) {
      const Vector3d u = rho > 0.0 ? Vector3d(p / rho) : Vector3d::Zero();
      const double u1 = u.dot(s.E1), u2 = u.dot(s.E2);
      // Tilting the plane about the centre changes a point's in-plane distance by -z (u . dN).
      (*J)(m, 0) = -u1;
      (*J)(m, 1) = -u2;
      (*J)(m, 3) = -z * u1;
      (*J)(m, 4) = -z * u2;
      (*J)(m, 5) = -1.0;
      (*J)(n + m, 2) = -1.0;
      (*J)(n + m, 3) = s.E1.dot(d);
      (*J)(n + m, 4) = s.E2.dot(d);
    }
  }
}

}  // namespace

std::optional<SphereFit> fit_sphere(std::span<const Point3> points) {
  if (points.size() < 4) return std::nullopt;
  const auto cl = analyse(points);
  if (!cl || cl->coplanar) return std::nullopt;
  const auto start = kasa_sphere(cl->y);
  if (!start) return std::nullopt;
  const Index n = cl->y.rows();
  const double scale = cl->spread + (*start)(3);
  auto eval = [&](const Eigen::Vector4d& x, VectorXd& r, MatrixXd* J) {
    sphere_residuals(cl->y, x.head<3>(), x(3), true, r, J);
  };
  auto advance = [](const Eigen::Vector4d& x, const VectorXd& d) { return Eigen::Vector4d(x + d); };
  int iterations = 0;
  const auto x = gauss_newton(*start, eval, advance, VectorXd::Constant(4, 1.0 / scale),
                              static_cast<double>(n) * std::pow(1e-14 * scale, 2), iterations);
  if (!x || !((*x)(3) > 0.0)) return std::nullopt;
  VectorXd r;
  MatrixXd J;
  eval(*x, r, &J);
  const int dof = static_cast<int>(n) - 4;
  const double ssr = r.squaredNorm();
  auto cov = covariance(J, dof > 0 ? ssr / dof : 0.0, dof);
  if (!cov) return std::nullopt;
  SphereFit f;
  f.centre = cl->centroid + x->head<3>();
  f.radius = (*x)(3);
  f.covariance = std::move(*cov);
  f.quality = make_quality(to_vector(r), ssr, dof, iterations);
  if (!f.centre.allFinite() || !std::isfinite(f.radius)) return std::nullopt;
  return f;
}

std::optional<SphereFit> fit_sphere_known_radius(std::span<const Point3> points, double radius,
                                                 const std::optional<Point3>& hint) {
  if (points.size() < 3 || !std::isfinite(radius) || !(radius > 0.0)) return std::nullopt;
  if (hint && !hint->allFinite()) return std::nullopt;
  const auto cl = analyse(points);
  if (!cl || cl->collinear) return std::nullopt;

  // Starts on both sides of the best plane, at the height that puts the in-plane circle on the
  // sphere: the two mirror solutions when the points are (nearly) coplanar.
  const Vector3d N = canonical_sign(cl->V.col(2));
  const Vector3d E1 = cl->V.col(0), E2 = cl->V.col(1);
  const auto circle = kasa_circle(cl->y * E1, cl->y * E2);
  if (!circle) return std::nullopt;
  const Vector3d in_plane = circle->a * E1 + circle->b * E2;
  const double h = std::sqrt(std::max(radius * radius - circle->r * circle->r, 0.0));
  const Vector3d upper = in_plane + h * N;
  std::vector<Vector3d> starts{upper, in_plane - h * N};
  // Without a hint, near-ties go to the side of the algebraic start; for coplanar points (where
  // it does not exist) to the side the canonical plane normal points to.
  Vector3d reference = upper;
  if (!cl->coplanar && points.size() >= 4) {
    if (const auto k = kasa_sphere(cl->y)) {
      starts.push_back(k->head<3>());
      reference = k->head<3>();
    }
  }

  std::vector<KnownRadiusCandidate> found;
  for (const Vector3d& s : starts)
    if (auto c = refine_known_radius(*cl, radius, s)) found.push_back(*c);
  if (found.empty()) return std::nullopt;

  const Index n = cl->y.rows();
  const KnownRadiusCandidate* best = nullptr;
  if (hint) {
    const Vector3d target = *hint - cl->centroid;
    for (const auto& c : found)
      if (!best || (c.c - target).norm() < (best->c - target).norm()) best = &c;
  } else {
    double least = std::numeric_limits<double>::infinity();
    for (const auto& c : found) least = std::min(least, c.ssr);
    const double tie = least * (1.0 + 1e-6) + static_cast<double>(n) * std::pow(1e-12 * (cl->spread + radius), 2);
    for (const auto& c : found)
      if (c.ssr <= tie && (!best || (c.c - reference).norm() < (best->c - reference).norm())) best = &c;
  }

  VectorXd r;
  MatrixXd J;
  sphere_residuals(cl->y, best->c, radius, false, r, &J);
  const int dof = static_cast<int>(n) - 3;
  const double ssr = r.squaredNorm();
  auto cov = covariance(J, dof > 0 ? ssr / dof : 0.0, dof);
  if (!cov) return std::nullopt;
  SphereFit f;
  f.centre = cl->centroid + best->c;
  f.radius = radius;
  f.covariance = std::move(*cov);
  f.quality = make_quality(to_vector(r), ssr, dof, best->iterations);
  if (!f.centre.allFinite()) return std::nullopt;
  return f;
}

std::optional<PlaneFit> fit_plane(std::span<const Point3> points) {
  if (points.size() < 3) return std::nullopt;
  const auto cl = analyse(points);
  if (!cl || cl->collinear) return std::nullopt;
  const Vector3d nrm = canonical_sign(cl->V.col(2));
  const Index k = largest_component(nrm), i = (k + 1) % 3, j = (k + 2) % 3;
  const Vector3d ti = dependent_tangent(nrm, k, i), tj = dependent_tangent(nrm, k, j);
  const Index n = cl->y.rows();
  // Residual n(n_i, n_j) . y - d' in centred coordinates (d' = 0 at the solution), which keeps
  // J^T J well conditioned far from the origin; d = n . centroid + d' is mapped afterwards.
  const VectorXd r = cl->y * nrm;
  MatrixXd J(n, 3);
  J.col(0) = cl->y * ti;
  J.col(1) = cl->y * tj;
  J.col(2).setConstant(-1.0);
  const int dof = static_cast<int>(n) - 3;
  const double ssr = r.squaredNorm();
  const auto cov = covariance(J, dof > 0 ? ssr / dof : 0.0, dof);
  if (!cov) return std::nullopt;
  Matrix3d T = Matrix3d::Identity();
  T(2, 0) = cl->centroid.dot(ti);
  T(2, 1) = cl->centroid.dot(tj);
  PlaneFit f;
  f.point = cl->centroid;
  f.normal = nrm;
  f.covariance = T * *cov * T.transpose();
  f.quality = make_quality(to_vector(r), ssr, dof, 0);
  if (!f.covariance.allFinite()) return std::nullopt;
  return f;
}

std::optional<LineFit> fit_line(std::span<const Point3> points) {
  if (points.size() < 2) return std::nullopt;
  const auto cl = analyse(points);
  if (!cl) return std::nullopt;
  const Vector3d u = canonical_sign(cl->V.col(0));
  const Index k = largest_component(u), i = (k + 1) % 3, j = (k + 2) % 3;
  const Vector3d ti = dependent_tangent(u, k, i), tj = dependent_tangent(u, k, j);
  const Vector3d e[2] = {cl->V.col(1), cl->V.col(2)};
  const Index n = cl->y.rows();
  // Two perpendicular residual components per point: a line has 2n equations for 4 parameters.
  MatrixXd J(2 * n, 4);
  std::vector<double> residuals(static_cast<std::size_t>(n));
  double ssr = 0.0;
  for (Index m = 0; m < n; ++m) {
    const Vector3d y = cl->y.row(m).transpose();
    const double t = u.dot(y);
    const double dist = (y - t * u).norm();
    residuals[static_cast<std::size_t>(m)] = dist;
    ssr += dist * dist;
    for (int a = 0; a < 2; ++a) J.row(2 * m + a) << -t * e[a].dot(ti), -t * e[a].dot(tj), -e[a](i), -e[a](j);
  }
  const int dof = 2 * static_cast<int>(n) - 4;
  auto cov = covariance(J, dof > 0 ? ssr / dof : 0.0, dof);
  if (!cov) return std::nullopt;
  LineFit f;
  f.point = cl->centroid;
  f.direction = u;
  f.covariance = std::move(*cov);
  f.quality = make_quality(std::move(residuals), ssr, dof, 0);
  return f;
}

std::optional<CircleFit> fit_circle(std::span<const Point3> points) {
  if (points.size() < 3) return std::nullopt;
  const auto cl = analyse(points);
  if (!cl || cl->collinear) return std::nullopt;
  CircleState s;
  s.N = cl->V.col(2);
  s.E1 = cl->V.col(0);
  s.E2 = s.N.cross(s.E1);
  const auto c2 = kasa_circle(cl->y * s.E1, cl->y * s.E2);
  if (!c2) return std::nullopt;
  s.C = c2->a * s.E1 + c2->b * s.E2;
  s.r = c2->r;

  const Index n = cl->y.rows();
  const double scale = cl->spread + s.r;
  VectorXd inv_scale(6);
  inv_scale << 1.0 / scale, 1.0 / scale, 1.0 / scale, 1.0, 1.0, 1.0 / scale;
  auto eval = [&](const CircleState& st, VectorXd& r, MatrixXd* J) { circle_residuals(cl->y, st, r, J); };
  int iterations = 0;
  auto sol = gauss_newton(s, eval, advance_circle, inv_scale, 2.0 * static_cast<double>(n) * std::pow(1e-14 * scale, 2),
                          iterations);
  if (!sol || !(sol->r > 0.0)) return std::nullopt;
  // Fix the sign before the final Jacobian so that local steps and the reported normal agree.
  if (sol->N(largest_component(sol->N)) < 0) {
    sol->N = -sol->N;
    sol->E2 = -sol->E2;
  }
  VectorXd r;
  MatrixXd J;
  eval(*sol, r, &J);
  const int dof = 2 * static_cast<int>(n) - 6;
  const double ssr = r.squaredNorm();
  // The radial and the out-of-plane residuals may differ in noise (probed sphere centres are
  // noisier along the probe's axis): each gets its own variance, from its own 3 parameters'
  // worth of redundancy, and the covariance is that of the weighted problem.
  std::optional<MatrixXd> local;
  if (n > 3) {
    const double pooled = ssr / dof;
    const double var_r = std::max(r.head(n).squaredNorm() / static_cast<double>(n - 3), 1e-6 * pooled);
    const double var_a = std::max(r.tail(n).squaredNorm() / static_cast<double>(n - 3), 1e-6 * pooled);
    if (pooled > 0) {
      MatrixXd Jw = J;
      Jw.topRows(n) /= std::sqrt(var_r);
      Jw.bottomRows(n) /= std::sqrt(var_a);
      local = covariance(Jw, 1.0, dof);
    } else {
      local = covariance(J, 0.0, dof);
    }
  } else {
    local = covariance(J, 0.0, dof);
  }
  if (!local) return std::nullopt;
  // From local steps (a, b, h, alpha, beta, dr) to (cx, cy, cz, n_i, n_j, r).
  const Index k = largest_component(sol->N), i = (k + 1) % 3, j = (k + 2) % 3;
  MatrixXd M = MatrixXd::Zero(6, 6);
  M.block<3, 1>(0, 0) = sol->E1;
  M.block<3, 1>(0, 1) = sol->E2;
  M.block<3, 1>(0, 2) = sol->N;
  M(3, 3) = sol->E1(i);
  M(3, 4) = sol->E2(i);
  M(4, 3) = sol->E1(j);
  M(4, 4) = sol->E2(j);
  M(5, 5) = 1.0;
  CircleFit f;
  f.centre = cl->centroid + sol->C;
  f.normal = sol->N;
  f.radius = sol->r;
  f.covariance = M * *local * M.transpose();
  f.quality = make_quality(to_vector(r.head(n)), ssr, dof, iterations);
  if (!f.centre.allFinite() || !f.normal.allFinite() || !std::isfinite(f.radius) || !f.covariance.allFinite())
    return std::nullopt;
  return f;
}

std::optional<Circle3> circle_through(const Point3& a, const Point3& b, const Point3& c) {
  const Vector3d u = b - a, v = c - a, w = u.cross(v);
  const double uu = u.squaredNorm(), vv = v.squaredNorm(), ww = w.squaredNorm();
  const double longest2 = std::max(std::max(uu, vv), (c - b).squaredNorm());
  const double wn = std::sqrt(ww);
  // Written so that NaN, infinities and coincident points all fail the comparison.
  if (!(wn > 1e-12 * longest2)) return std::nullopt;
  const Vector3d offset = (uu * v.cross(w) + vv * w.cross(u)) / (2.0 * ww);
  const double radius = offset.norm();
  if (!std::isfinite(radius)) return std::nullopt;
  Vector3d normal = w / wn;
  const Vector3d m = normal.cwiseAbs();
  const int k = m(0) >= m(1) ? (m(0) >= m(2) ? 0 : 2) : (m(1) >= m(2) ? 1 : 2);
  if (normal(k) < 0) normal = -normal;
  return Circle3{a + offset, normal, radius};
}

}  // namespace mtcal
