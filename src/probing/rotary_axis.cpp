#include "mtcal/probing/rotary_axis.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal {

NominalRotaryAxis NominalRotaryAxis::from(const Axis& axis) {
  if (axis.kind != AxisKind::Rotary)
    throw ModelError(std::string("axis ") + axis.letter + " is linear; rotary-axis location needs A, B or C");
  return {axis.letter, axis.direction_axis, axis.point};
}

NominalRotaryAxis NominalRotaryAxis::by_letter(char letter) {
  if (letter < 'A' || letter > 'C')
    throw ModelError(std::string("'") + letter + "' is not a rotary axis letter (A, B or C)");
  return {letter, letter - 'A', Point3::Zero()};
}

std::array<std::string, kRotaryQuantities> rotary_quantity_names(char a) {
  const std::string L(1, a);
  switch (a) {
    case 'A': return {"EY0A", "EZ0A", "EB0A", "EC0A", "radius", "tilt"};
    case 'B': return {"EX0B", "EZ0B", "EA0B", "EC0B", "radius", "tilt"};
    default: return {"EX0C", "EY0C", "EA0C", "EB0C", "radius", "tilt"};
  }
}

namespace {

// atan2(y, x) and asin(x) for the small angles of axis-line errors (|angle| < 1e-3 rad, x > 0 for
// atan2) by their Taylor series, whose first omitted term is below 1e-24 relative there: the same
// values as the library functions to 1 ulp at a fraction of their cost (the all-triples estimator
// takes them 10^8 times); larger angles go to the library.
double atan2_small(double y, double x) {
  if (!(x > 0.0) || !(std::abs(y) < 1e-3 * x)) return std::atan2(y, x);
  const double t = y / x, t2 = t * t;
  return t - t * t2 * (1.0 / 3.0 - t2 * (1.0 / 5.0 - t2 * (1.0 / 7.0)));
}
double asin_small(double x) {
  if (!(std::abs(x) < 1e-3)) return std::asin(x);
  const double x2 = x * x;
  return x + x * x2 * (1.0 / 6.0 + x2 * (3.0 / 40.0 + x2 * (5.0 / 112.0)));
}

}  // namespace

std::array<double, kRotaryQuantities> location_from_line(const NominalRotaryAxis& axis, const Point3& point,
                                                         const Point3& direction, double radius) {
  const int k = axis.direction_axis, i = (k + 1) % 3, j = (k + 2) % 3;
  Point3 n = direction.normalized();
  if (n[k] < 0) n = -n;  // a line has no sense; measure it against + machine axis
  // Where the line crosses the plane through the nominal point perpendicular to the axis
  // (Cubas & Yeh 2022 eq. 4.1, with that plane instead of z = 0).
  const double t = (axis.point[k] - point[k]) / n[k];
  const Point3 p = point + t * n;
  const double pi = p[i] - axis.point[i], pj = p[j] - axis.point[j];
  // Angle to the nominal direction, by atan2: acos loses half the digits near 0. n is a unit
  // vector, so the sum of squares cannot overflow (hypot's scaling is not needed).
  const double tilt = atan2_small(std::sqrt(n[i] * n[i] + n[j] * n[j]), n[k]);
  double oa = 0, ob = 0;  // the two orientation errors in the order of the names
  switch (k) {
    case 2:  // C: n = Ry(EB0C) Rx(EA0C) z = (cos a sin b, -sin a, cos a cos b)
      oa = -asin_small(n.y());
      ob = atan2_small(n.x(), n.z());
      return {pi, pj, oa, ob, radius, tilt};
    case 0:  // A: n = Rz(EC0A) Ry(EB0A) x = (cos c cos b, sin c cos b, -sin b); names EY0A EZ0A
      oa = -asin_small(n.z());
      ob = atan2_small(n.y(), n.x());
      return {pi, pj, oa, ob, radius, tilt};
    default:  // B: n = Rz(EC0B) Rx(EA0B) y = (-sin c cos a, cos c cos a, sin a); names EX0B EZ0B
      oa = asin_small(n.z());
      ob = atan2_small(-n.x(), n.y());
      // i = z, j = x for k = y: report x first, then z, as the names say.
      return {pj, pi, oa, ob, radius, tilt};
  }
}

std::pair<Point3, Point3> line_from_location(const NominalRotaryAxis& axis,
                                             const std::array<double, kRotaryQuantities>& v) {
  const int k = axis.direction_axis, i = (k + 1) % 3, j = (k + 2) % 3;
  Point3 p = axis.point;
  Point3 n;
  const double a = v[2], b = v[3];
  switch (k) {
    case 2:
      p[i] += v[0];
      p[j] += v[1];
      n = Point3(std::cos(a) * std::sin(b), -std::sin(a), std::cos(a) * std::cos(b));
      break;
    case 0:
      p[i] += v[0];
      p[j] += v[1];
      n = Point3(std::cos(b) * std::cos(a), std::sin(b) * std::cos(a), -std::sin(a));
      break;
    default:
      p[j] += v[0];  // EX0B
      p[i] += v[1];  // EZ0B
      n = Point3(-std::sin(b) * std::cos(a), std::cos(b) * std::cos(a), std::sin(a));
  }
  return {p, n};
}

namespace {

void require_centres(const std::vector<MeasuredCentre>& centres) {
  if (centres.size() < 3)
    throw InputError({"centres", 0, ""}, fmt::format("expected at least 3 sphere centres, found {}", centres.size()));
  std::vector<Point3> pts;
  for (const auto& c : centres) pts.push_back(c.centre);
  if (!fit_plane(pts))
    throw InputError({"centres", 0, ""}, "the sphere centres lie on one line (or coincide): no circle, no axis");
}

void fill_line(RotaryEstimate& e, const NominalRotaryAxis& axis, const Point3& centre, const Point3& normal) {
  const int k = axis.direction_axis;
  Point3 n = normal.normalized();
  if (n[k] < 0) n = -n;
  e.axis_direction = n;
  e.axis_point = centre + ((axis.point[k] - centre[k]) / n[k]) * n;
}

}  // namespace

LeastSquaresEstimate estimate_by_least_squares(const NominalRotaryAxis& axis,
                                               const std::vector<MeasuredCentre>& centres) {
  require_centres(centres);
  std::vector<Point3> pts;
  for (const auto& c : centres) pts.push_back(c.centre);
  auto fit = fit_circle(pts);
  if (!fit) throw InputError({"centres", 0, ""}, "no circle could be fitted through the sphere centres");
  LeastSquaresEstimate e;
  e.circle = *fit;
  e.value = location_from_line(axis, fit->centre, fit->normal, fit->radius);
  fill_line(e, axis, fit->centre, fit->normal);
  // Spread: the centres' residual standard deviation (mm), as an angle over the radius for the
  // orientation errors and the tilt.
  for (std::size_t q = 0; q < kRotaryQuantities; ++q)
    e.spread[q] = (q == 2 || q == 3 || q == 5) ? fit->quality.sigma / fit->radius : fit->quality.sigma;
  // First-order propagation of the fit's covariance over (cx cy cz n_i n_j r).
  const int k0 = [&] {
    int k = 0;
    fit->normal.cwiseAbs().maxCoeff(&k);
    return k;
  }();
  const int ni = (k0 + 1) % 3, nj = (k0 + 2) % 3;
  auto quantities = [&](const Eigen::Matrix<double, 6, 1>& p) {
    Point3 n = fit->normal;
    n[ni] = p[3];
    n[nj] = p[4];
    n[k0] = std::copysign(std::sqrt(std::max(0.0, 1.0 - p[3] * p[3] - p[4] * p[4])), fit->normal[k0]);
    return location_from_line(axis, p.head<3>(), n, p[5]);
  };
  Eigen::Matrix<double, 6, 1> p0;
  p0 << fit->centre, fit->normal[ni], fit->normal[nj], fit->radius;
  Eigen::Matrix<double, kRotaryQuantities, 6> J;
  for (int c = 0; c < 6; ++c) {
    const double h = c < 3 || c == 5 ? 1e-6 : 1e-8;
    Eigen::Matrix<double, 6, 1> a = p0, b = p0;
    a[c] += h;
    b[c] -= h;
    const auto qa = quantities(a), qb = quantities(b);
    for (std::size_t q = 0; q < kRotaryQuantities; ++q) J(static_cast<Eigen::Index>(q), c) = (qa[q] - qb[q]) / (2 * h);
  }
  if (fit->covariance.rows() == 6) {
    const Eigen::Matrix<double, kRotaryQuantities, kRotaryQuantities> cov = J * fit->covariance * J.transpose();
    for (std::size_t q = 0; q < kRotaryQuantities; ++q)
      e.uncertainty[q] = std::sqrt(std::max(0.0, cov(static_cast<Eigen::Index>(q), static_cast<Eigen::Index>(q))));
  }
  return e;
}

namespace {

// Accumulators of one thread over its share of the triples.
struct Sums {
  std::array<double, kRotaryQuantities> s{}, s2{};
  std::size_t valid = 0, degenerate = 0;
};
struct KeptSums {
  std::array<double, kRotaryQuantities> s{}, s2{};
  std::array<std::size_t, kRotaryQuantities> kept{};
  std::vector<double> point_sum;         // [centre * 6 + quantity]
  std::vector<std::size_t> point_count;  // [centre * 6 + quantity]
  std::array<std::vector<std::size_t>, kRotaryQuantities> hist;
};

// Calls fn(i, j, k) for every triple i < j < k whose first index belongs to thread t of T
// (interleaved, so that the long rows of small i are shared out evenly).
template <class Fn>
void for_triples(std::size_t n, std::size_t t, std::size_t T, Fn&& fn) {
  for (std::size_t i = t; i + 2 < n; i += T)
    for (std::size_t j = i + 1; j + 1 < n; ++j)
      for (std::size_t k = j + 1; k < n; ++k) fn(i, j, k);
}

constexpr std::size_t kTasks = 64;

}  // namespace

TriplesCost triples_cost(std::size_t centres, int histogram_bins) {
  const double n = static_cast<double>(centres);
  const double bins = static_cast<double>(std::max(1, histogram_bins));
  // Per task and for the total: point_sum (double) and point_count (size_t) per centre and
  // quantity, and a histogram per quantity.
  const double per_task = n * kRotaryQuantities * 16 + bins * kRotaryQuantities * 8;
  return {centres < 3 ? 0.0 : n * (n - 1) * (n - 2) / 6, static_cast<double>(kTasks + 1) * per_task};
}

TriplesEstimate estimate_by_triples(const NominalRotaryAxis& axis, const std::vector<MeasuredCentre>& centres,
                                    const TriplesOptions& options) {
  require_centres(centres);
  const std::size_t n = centres.size();
  std::size_t threads = worker_count(options.threads, kTasks);
  threads = std::min(threads, std::max<std::size_t>(1, n / 8));
  // Sums are taken relative to the least-squares estimate so that tiny errors (um, urad) do
  // not drown in the rounding of large sums.
  const auto ref = estimate_by_least_squares(axis, centres).value;

  auto triple = [&](std::size_t i, std::size_t j, std::size_t k, std::array<double, kRotaryQuantities>& q) {
    const auto c = circle_through(centres[i].centre, centres[j].centre, centres[k].centre);
    if (!c) return false;
    q = location_from_line(axis, c->centre, c->normal, c->radius);
    for (std::size_t m = 0; m < kRotaryQuantities; ++m) q[m] -= ref[m];
    return true;
  };

  // Pass 1: mean and standard deviation of every quantity over all valid triples.
  // The work is cut into a fixed number of tasks (rows i with the same i mod kTasks), whatever
  // the thread count, and their sums are added in task order: the same inputs give the same
  // bits on any machine.
  std::mutex progress_mutex;
  std::size_t shares_done = 0;
  auto report = [&] {
    if (!options.progress) return;
    const std::lock_guard lock(progress_mutex);
    options.progress(++shares_done, 2 * kTasks);
  };
  std::vector<Sums> pass1(kTasks);
  parallel_for(kTasks, static_cast<int>(threads), [&](std::size_t task, std::size_t) {
    Sums s;  // local: neighbouring tasks' sums would share cache lines
    std::array<double, kRotaryQuantities> q;
    for_triples(n, task, kTasks, [&](std::size_t i, std::size_t j, std::size_t k) {
      if (!triple(i, j, k, q)) {
        ++s.degenerate;
        return;
      }
      ++s.valid;
      for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
        s.s[m] += q[m];
        s.s2[m] += q[m] * q[m];
      }
    });
    pass1[task] = s;
    report();
  });
  Sums all;
  for (const auto& s : pass1) {
    all.valid += s.valid;
    all.degenerate += s.degenerate;
    for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
      all.s[m] += s.s[m];
      all.s2[m] += s.s2[m];
    }
  }
  TriplesEstimate e;
  e.triples = all.valid + all.degenerate;
  e.degenerate = all.degenerate;
  if (all.valid == 0) throw InputError({"centres", 0, ""}, "every triple of centres is degenerate (collinear)");
  std::array<double, kRotaryQuantities> mean{}, sd{};
  const double nv = static_cast<double>(all.valid);
  for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
    mean[m] = all.s[m] / nv;
    sd[m] = std::sqrt(std::max(0.0, all.s2[m] / nv - mean[m] * mean[m]));
    e.mean_all[m] = mean[m] + ref[m];
  }

  // Pass 2: per quantity, keep the triples within reject_sigma standard deviations (the
  // normal-distribution rule of Cubas & Yeh), and collect per-centre sums and histograms.
  const int bins = std::max(1, options.histogram_bins);
  std::array<double, kRotaryQuantities> lo{}, width{};
  for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
    const double half = sd[m] > 0 ? 4 * sd[m] : std::max(1e-12, 1e-9 * std::abs(e.mean_all[m]));
    lo[m] = mean[m] - half;
    width[m] = 2 * half / bins;
  }
  const double k_sigma = options.reject_sigma;
  std::vector<KeptSums> pass2(kTasks);
  parallel_for(kTasks, static_cast<int>(threads), [&](std::size_t task, std::size_t) {
    KeptSums s;
    s.point_sum.assign(n * kRotaryQuantities, 0.0);
    s.point_count.assign(n * kRotaryQuantities, 0);
    for (auto& h : s.hist) h.assign(static_cast<std::size_t>(bins), 0);
    std::array<double, kRotaryQuantities> q;
    for_triples(n, task, kTasks, [&](std::size_t i, std::size_t j, std::size_t k) {
      if (!triple(i, j, k, q)) return;
      for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
        const double b = std::floor((q[m] - lo[m]) / width[m]);
        if (b >= 0 && b < bins) ++s.hist[m][static_cast<std::size_t>(b)];
        if (k_sigma > 0 && std::abs(q[m] - mean[m]) > k_sigma * sd[m]) continue;
        s.s[m] += q[m];
        s.s2[m] += q[m] * q[m];
        ++s.kept[m];
        for (std::size_t c : {i, j, k}) {
          s.point_sum[c * kRotaryQuantities + m] += q[m];
          ++s.point_count[c * kRotaryQuantities + m];
        }
      }
    });
    pass2[task] = std::move(s);
    report();
  });
  KeptSums total;
  total.point_sum.assign(n * kRotaryQuantities, 0.0);
  total.point_count.assign(n * kRotaryQuantities, 0);
  for (auto& h : total.hist) h.assign(static_cast<std::size_t>(bins), 0);
  for (const auto& s : pass2) {
    for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
      total.s[m] += s.s[m];
      total.s2[m] += s.s2[m];
      total.kept[m] += s.kept[m];
      for (int b = 0; b < bins; ++b)
        total.hist[m][static_cast<std::size_t>(b)] += s.hist[m][static_cast<std::size_t>(b)];
    }
    for (std::size_t x = 0; x < n * kRotaryQuantities; ++x) {
      total.point_sum[x] += s.point_sum[x];
      total.point_count[x] += s.point_count[x];
    }
  }
  for (std::size_t m = 0; m < kRotaryQuantities; ++m) {
    e.kept[m] = total.kept[m];
    e.histograms[m] = {lo[m] + ref[m], lo[m] + ref[m] + width[m] * bins, total.hist[m]};
    if (total.kept[m] == 0) {  // everything rejected (cannot happen for k >= 1): fall back
      e.value[m] = e.mean_all[m];
      e.spread[m] = sd[m];
      continue;
    }
    const double kept = static_cast<double>(total.kept[m]);
    const double mk = total.s[m] / kept;
    e.value[m] = mk + ref[m];
    e.spread[m] = std::sqrt(std::max(0.0, total.s2[m] / kept - mk * mk));
    // U-statistic variance: 9 zeta_1 / n with zeta_1 the variance of the per-centre means.
    double s = 0, s2 = 0;
    std::size_t used = 0;
    for (std::size_t c = 0; c < n; ++c) {
      const std::size_t cnt = total.point_count[c * kRotaryQuantities + m];
      if (cnt == 0) continue;
      const double hbar = total.point_sum[c * kRotaryQuantities + m] / static_cast<double>(cnt) - mk;
      s += hbar;
      s2 += hbar * hbar;
      ++used;
    }
    if (used > 1) {
      const double u = static_cast<double>(used);
      const double zeta1 = (s2 - s * s / u) / (u - 1);
      e.uncertainty[m] = std::sqrt(std::max(0.0, 9.0 * zeta1 / static_cast<double>(n)));
    }
  }
  const double through = static_cast<double>((n - 1) * (n - 2) / 2);  // triples through one centre
  e.rejected_share.assign(n, 0.0);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t m = 0; m < 4; ++m)
      e.rejected_share[c] = std::max(e.rejected_share[c],
                                     1.0 - static_cast<double>(total.point_count[c * kRotaryQuantities + m]) / through);
  // The axis line of the triples' estimate, for plotting and merging.
  const auto [point, direction] = line_from_location(axis, e.value);
  e.axis_point = point;
  e.axis_direction = direction;
  // The tilt is a magnitude: the mean of the triples' tilts is biased upwards by noise, so it is
  // taken from the mean orientation errors instead, with first-order uncertainty.
  const int k = axis.direction_axis;
  const double ti = std::hypot(direction[(k + 1) % 3], direction[(k + 2) % 3]);
  e.value[5] = std::atan2(ti, direction[k]);
  e.uncertainty[5] = e.value[5] > 0
                         ? std::hypot(e.value[2] * e.uncertainty[2], e.value[3] * e.uncertainty[3]) / e.value[5]
                         : std::hypot(e.uncertainty[2], e.uncertainty[3]);
  return e;
}

}  // namespace mtcal
