#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/util/units.hpp"
#include "mtcal/fitting/least_squares.hpp"
#include "mtcal/model/joints.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include <Eigen/Dense>

#include "mtcal/fitting/fit.hpp"
#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

constexpr double kPi = std::numbers::pi;

double wrap(double a) {  // to [0, 2 pi)
  a = std::fmod(a, 2 * kPi);
  return a < 0 ? a + 2 * kPi : a + 0.0;  // + 0.0 turns -0 into 0
}

struct Xy {
  double x, y;
};

std::vector<Xy> points_of(const std::vector<TracePoint>& t) {
  std::vector<Xy> p;
  for (const auto& s : t) p.push_back({s.radius * std::cos(s.angle), s.radius * std::sin(s.angle)});
  return p;
}

// Spread (max - min) of the distances of the points from (cx, cy).
double zone(const std::vector<Xy>& p, double cx, double cy) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& q : p) {
    const double d = std::hypot(q.x - cx, q.y - cy);
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return hi - lo;
}

// Least-squares centre (geometric circle fit in the plane).
std::array<double, 2> lsq_centre(const std::vector<Xy>& p, const std::string& source) {
  std::vector<Point3> pts;
  for (const auto& q : p) pts.emplace_back(q.x, q.y, 0.0);
  const auto f = fit_circle(pts);
  if (!f) throw InputError({source, 0, ""}, "the trace does not determine a circle");
  return {f->centre.x(), f->centre.y()};
}

// Minimum-zone centre: the centre of the two concentric circles of least radial separation that
// enclose the path (ISO 230-4 option). Nelder-Mead from the least-squares centre: the zone is a
// convex function of the centre near it, and the least-squares centre is within G of the optimum.
std::array<double, 2> minimum_zone_centre(const std::vector<Xy>& p, std::array<double, 2> start, double size) {
  std::array<std::array<double, 2>, 3> s = {start, start, start};
  s[1][0] += size;
  s[2][1] += size;
  std::array<double, 3> f;
  for (int i = 0; i < 3; ++i)
    f[static_cast<std::size_t>(i)] = zone(p, s[static_cast<std::size_t>(i)][0], s[static_cast<std::size_t>(i)][1]);
  for (int it = 0; it < 2000; ++it) {
    std::array<std::size_t, 3> o = {0, 1, 2};
    std::sort(o.begin(), o.end(), [&](std::size_t a, std::size_t b) { return f[a] < f[b]; });
    const auto best = s[o[0]], mid = s[o[1]], worst = s[o[2]];
    if (std::abs(f[o[2]] - f[o[0]]) < 1e-15 && std::hypot(worst[0] - best[0], worst[1] - best[1]) < 1e-12) break;
    const std::array<double, 2> c = {(best[0] + mid[0]) / 2, (best[1] + mid[1]) / 2};
    auto at = [&](double t) {
      return std::array<double, 2>{c[0] + t * (worst[0] - c[0]), c[1] + t * (worst[1] - c[1])};
    };
    const auto r = at(-1.0);
    const double fr = zone(p, r[0], r[1]);
    if (fr < f[o[0]]) {
      const auto e = at(-2.0);
      const double fe = zone(p, e[0], e[1]);
      if (fe < fr) {
        s[o[2]] = e, f[o[2]] = fe;
      } else {
        s[o[2]] = r, f[o[2]] = fr;
      }
    } else if (fr < f[o[1]]) {
      s[o[2]] = r, f[o[2]] = fr;
    } else {
      const auto k = at(0.5);
      const double fk = zone(p, k[0], k[1]);
      if (fk < f[o[2]]) {
        s[o[2]] = k, f[o[2]] = fk;
      } else {  // shrink towards the best
        for (std::size_t i : {o[1], o[2]}) {
          s[i] = {(s[i][0] + best[0]) / 2, (s[i][1] + best[1]) / 2};
          f[i] = zone(p, s[i][0], s[i][1]);
        }
      }
    }
  }
  const std::size_t b = static_cast<std::size_t>(std::min_element(f.begin(), f.end()) - f.begin());
  return s[b];
}

// The samples of one direction after the overshoot arcs are removed, in recorded order.
std::vector<TracePoint> trimmed(const std::vector<TracePoint>& all, CircleDirection d, const BallbarOptions& o) {
  std::vector<TracePoint> t;
  for (const auto& s : all)
    if (s.direction == d) t.push_back(s);
  std::vector<double> travel(t.size(), 0.0);
  for (std::size_t i = 1; i < t.size(); ++i) {
    double step = std::abs(t[i].angle - t[i - 1].angle);
    step = std::min(step, 2 * kPi - std::fmod(step, 2 * kPi));
    travel[i] = travel[i - 1] + step;
  }
  const double total = t.empty() ? 0.0 : travel.back();
  std::vector<TracePoint> kept;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (travel[i] >= o.overshoot_start * kRadPerDeg - 1e-12 && travel[i] <= total - o.overshoot_stop * kRadPerDeg + 1e-12)
      kept.push_back(t[i]);
  return kept;
}

CircularDeviation deviation(const std::vector<TracePoint>& t, const BallbarOptions& o, const std::string& source,
                            const char* name) {
  if (t.size() < 8)
    throw InputError({source, 0, ""},
                     fmt::format("the {} path has {} samples after the overshoot is removed; at least 8 "
                                 "are needed",
                                 name, t.size()));
  std::vector<double> a;
  for (const auto& s : t) a.push_back(wrap(s.angle));
  std::sort(a.begin(), a.end());
  double gap = a.front() + 2 * kPi - a.back();
  for (std::size_t i = 1; i < a.size(); ++i) gap = std::max(gap, a[i] - a[i - 1]);
  if (gap > 30 * kRadPerDeg)
    throw InputError({source, 0, ""},
                     fmt::format("the {} path leaves a gap of {:.0f} deg: a circular test goes round the "
                                 "whole circle (at most 30 deg between samples)",
                                 name, gap / kRadPerDeg));
  const auto p = points_of(t);
  CircularDeviation d;
  d.points = t.size();
  const auto c = lsq_centre(p, source);
  d.centre_x = c[0];
  d.centre_y = c[1];
  d.G = zone(p, c[0], c[1]);
  const auto mz = minimum_zone_centre(p, c, std::max(d.G, 1e-6));
  d.mz_centre_x = mz[0];
  d.mz_centre_y = mz[1];
  d.G_minimum_zone = std::min(d.G, zone(p, mz[0], mz[1]));
  d.F_max = -INFINITY;
  d.F_min = INFINITY;
  double sum = 0;
  for (const auto& s : t) {
    const double f = s.radius - o.nominal_radius;
    d.F_max = std::max(d.F_max, f);
    d.F_min = std::min(d.F_min, f);
    sum += f;
  }
  d.F_mean = sum / static_cast<double>(t.size());
  return d;
}

// Radius of a path at angle a, by linear interpolation between its samples round the circle.
double radius_at(const std::vector<std::pair<double, double>>& sorted, double a) {
  a = wrap(a);
  const auto it =
      std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(a, -std::numeric_limits<double>::infinity()));
  const auto& hi = it == sorted.end() ? sorted.front() : *it;
  const auto& lo = it == sorted.begin() ? sorted.back() : *(it - 1);
  double span = hi.first - lo.first, off = a - lo.first;
  if (span <= 0) span += 2 * kPi;
  if (off < 0) off += 2 * kPi;
  const double t = span > 0 ? off / span : 0.0;
  return lo.second + t * (hi.second - lo.second);
}

}  // namespace

BallbarEvaluation evaluate_ballbar(const std::vector<TracePoint>& trace, const BallbarOptions& o,
                                   const std::string& source) {
  if (!(o.nominal_radius > 0)) throw InputError({source, 0, ""}, "expected a nominal radius > 0");
  const auto cw = trimmed(trace, CircleDirection::CW, o), ccw = trimmed(trace, CircleDirection::CCW, o);
  BallbarEvaluation e;
  if (o.only) {
    const auto& t = *o.only == CircleDirection::CW ? cw : ccw;
    auto d = deviation(t, o, source, *o.only == CircleDirection::CW ? "cw" : "ccw");
    (*o.only == CircleDirection::CW ? e.cw : e.ccw) = d;
    e.F_max = d.F_max;
    e.F_min = d.F_min;
    return e;
  }
  if (cw.empty() || ccw.empty())
    throw InputError({source, 0, ""},
                     fmt::format("G(b) and H need both directions; the trace has only {} samples (evaluate "
                                 "one direction only)",
                                 cw.empty() ? "ccw" : "cw"));
  e.cw = deviation(cw, o, source, "cw");
  e.ccw = deviation(ccw, o, source, "ccw");
  std::vector<TracePoint> both = cw;
  both.insert(both.end(), ccw.begin(), ccw.end());
  const auto p = points_of(both);
  const auto c = lsq_centre(p, source);
  e.G_b = zone(p, c[0], c[1]);
  std::vector<std::pair<double, double>> sorted;
  for (const auto& s : ccw) sorted.emplace_back(wrap(s.angle), s.radius);
  std::sort(sorted.begin(), sorted.end());
  double h = 0;
  for (const auto& s : cw) h = std::max(h, std::abs(s.radius - radius_at(sorted, s.angle)));
  e.H = h;
  e.F_mean_bidirectional = 0.5 * (e.cw->F_mean + e.ccw->F_mean);
  e.F_max = std::max(e.cw->F_max, e.ccw->F_max);
  e.F_min = std::min(e.cw->F_min, e.ccw->F_min);
  return e;
}

TraceDiagnosis diagnose_ballbar(const std::vector<TracePoint>& trace, const BallbarOptions& o, const std::string& plane,
                                const std::string& source) {
  const auto cw = trimmed(trace, CircleDirection::CW, o), ccw = trimmed(trace, CircleDirection::CCW, o);
  if (cw.size() < 8 || ccw.size() < 8)
    throw InputError({source, 0, ""},
                     "the diagnostic fit needs both directions (squareness and servo mismatch differ "
                     "only in how they change with the direction)");
  const std::string a1(1, plane.size() == 2 ? plane[0] : 'X'), a2(1, plane.size() == 2 ? plane[1] : 'Y');
  const double R = o.nominal_radius;
  constexpr double tau = 5 * kRadPerDeg;  // decay of a reversal spike
  struct Column {
    std::string name, unit;
    double scale;  // value in its unit = coefficient * scale
  };
  const std::vector<Column> cols = {{"centre offset " + a1, "um", 1e3},
                                    {"centre offset " + a2, "um", 1e3},
                                    {"radius offset", "um", 1e3},
                                    {"scaling mismatch " + a1 + a2, "um/m", 1e6},
                                    {"squareness " + a1 + a2, "um/m", 1e6},
                                    {"servo mismatch " + a1 + a2, "um/m", 1e6},
                                    {"backlash " + a1, "um", 1e3},
                                    {"backlash " + a2, "um", 1e3},
                                    {"reversal spike " + a1, "um", 1e3},
                                    {"reversal spike " + a2, "um", 1e3},
                                    {"straightness " + a1 + " (bow in " + a2 + ")", "um", 1e3},
                                    {"straightness " + a2 + " (bow in " + a1 + ")", "um", 1e3},
                                    {"cyclic cos 4a", "um", 1e3},
                                    {"cyclic sin 4a", "um", 1e3},
                                    {"cyclic cos 5a", "um", 1e3},
                                    {"cyclic sin 5a", "um", 1e3},
                                    {"cyclic cos 6a", "um", 1e3},
                                    {"cyclic sin 6a", "um", 1e3}};
  std::vector<TracePoint> all = cw;
  all.insert(all.end(), ccw.begin(), ccw.end());
  const Eigen::Index n = static_cast<Eigen::Index>(all.size()), p = static_cast<Eigen::Index>(cols.size());
  Eigen::MatrixXd A(n, p);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& s = all[static_cast<std::size_t>(i)];
    const double a = s.angle, d = s.direction == CircleDirection::CCW ? 1.0 : -1.0;
    const double c = std::cos(a), sn = std::sin(a);
    const double v1 = -d * sn, v2 = d * c;  // directions of motion of the two axes
    auto sgn = [](double v) { return std::abs(v) < 1e-9 ? 0.0 : (v > 0 ? 1.0 : -1.0); };
    // Angle travelled since the last reversal of each axis (axis 1 reverses at 0 and pi, axis 2 at
    // pi/2 and 3pi/2).
    const double since1 = std::fmod(wrap(d * a), kPi), since2 = std::fmod(wrap(d * a - d * kPi / 2), kPi);
    A.row(i) << c, sn, 1.0, 0.5 * R * std::cos(2 * a), -0.5 * R * std::sin(2 * a), d * 0.5 * R * std::sin(2 * a),
        -0.5 * sgn(v1) * c, -0.5 * sgn(v2) * sn, std::exp(-since1 / tau), std::exp(-since2 / tau), c * c * sn,
        sn * sn * c, std::cos(4 * a), std::sin(4 * a), std::cos(5 * a), std::sin(5 * a), std::cos(6 * a),
        std::sin(6 * a);
    b[i] = s.radius - R;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto sv = svd.singularValues();
  if (!(sv[p - 1] > 1e-9 * sv[0]))
    throw InputError({source, 0, ""},
                     "the trace does not separate the diagnostic terms (too few samples round the circle)");
  const Eigen::VectorXd x = svd.solve(b);
  const Eigen::VectorXd r = b - A * x;
  TraceDiagnosis out;
  out.dof = static_cast<int>(n - p);
  const double sigma2 = out.dof > 0 ? r.squaredNorm() / out.dof : 0.0;
  const Eigen::MatrixXd cov = analyse_jacobian(A, sigma2, JacobianOptions{1e-9, false}).covariance;
  const Eigen::VectorXd fitted = A * x;
  const double fitted_rms = std::sqrt(fitted.squaredNorm() / static_cast<double>(n));
  out.residual_rms = std::sqrt(r.squaredNorm() / static_cast<double>(n)) * 1e3;
  for (Eigen::Index j = 0; j < p; ++j) {
    const auto& col = cols[static_cast<std::size_t>(j)];
    const double contribution = std::sqrt((A.col(j) * x[j]).squaredNorm() / static_cast<double>(n));
    out.terms.push_back({col.name, col.unit, x[j] * col.scale, std::sqrt(std::max(0.0, cov(j, j))) * col.scale,
                         fitted_rms > 0 ? 100.0 * contribution / fitted_rms : 0.0});
  }
  return out;
}

std::vector<TracePoint> predict_ballbar(const Machine& m, const std::string& plane, const std::vector<double>& centre,
                                        double radius, double step) {
  if (plane != "XY" && plane != "YZ" && plane != "ZX")
    throw ModelError("expected the plane XY, YZ or ZX, found '" + printable(plane) + "'");
  const auto a1 = m.axis_index(plane[0]), a2 = m.axis_index(plane[1]);
  if (!a1 || !a2)
    throw ModelError("plane " + plane + " needs linear axes " + plane[0] + " and " + plane[1] + " in " +
                     m.topology.chain);
  if (centre.size() != m.axes.size()) throw ModelError("expected one centre value per axis");
  if (!(radius > 0) || !(step > 0) || step > 0.5 || !std::isfinite(radius))
    throw ModelError("expected a finite radius > 0 and a step in (0, 0.5] rad");
  // Centre values beyond a kilometre (or 2800 turns) make the chain overflow to inf/NaN.
  check_joints(m, centre, "centre", false);
  const ErrorModel model(m);
  const Vec3 ball = model.actual_pose(centre).t;  // the centre ball, set with the tool at the centre
  const double s1 = m.axes[*a1].direction_sign, s2 = m.axes[*a2].direction_sign;
  const int count = static_cast<int>(std::ceil(2 * kPi / step));
  std::vector<TracePoint> out;
  for (CircleDirection d : {CircleDirection::CW, CircleDirection::CCW}) {
    const double sense = d == CircleDirection::CCW ? 1.0 : -1.0;
    for (int k = 0; k < count; ++k) {  // once round: a repeated end sample would weigh its angle twice
      const double a = sense * 2 * kPi * k / count;
      std::vector<double> q = centre;
      q[*a1] += s1 * radius * std::cos(a);
      q[*a2] += s2 * radius * std::sin(a);
      // Direction of motion of each plane axis along the path (reversal terms act on it).
      std::vector<std::int8_t> dir(m.axes.size(), 0);
      const double v1 = -s1 * sense * std::sin(a), v2 = s2 * sense * std::cos(a);
      dir[*a1] = static_cast<std::int8_t>(std::abs(v1) < 1e-12 ? 0 : (v1 > 0 ? 1 : -1));
      dir[*a2] = static_cast<std::int8_t>(std::abs(v2) < 1e-12 ? 0 : (v2 > 0 ? 1 : -1));
      const Vec3 tip = model.actual_pose(q, dir).t;
      const double length = (tip - ball).norm();
      if (!std::isfinite(length))
        throw ModelError(
            fmt::format("the predicted bar length is not finite at {:g} deg ({}): the model's errors "
                        "are too large for this circle",
                        wrap(a) * 180 / kPi, d == CircleDirection::CW ? "cw" : "ccw"));
      out.push_back({d, wrap(a), length});
    }
  }
  return out;
}

}  // namespace mtcal
