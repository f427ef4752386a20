#include "mtcal/evaluation/diagonals.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

double DiagonalProfile::largest_deviation() const {
  double mx = 0;
  for (double v : deviation) mx = std::max(mx, std::abs(v));
  return mx;
}

namespace {

DiagonalProfile run(const ErrorModel& model, std::string name, std::vector<double> start, std::vector<double> end,
                    std::size_t points) {
  DiagonalProfile d;
  d.name = std::move(name);
  const std::size_t n = model.axis_count();
  std::vector<double> q(points * n);
  for (std::size_t i = 0; i < points; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(points - 1);
    for (std::size_t k = 0; k < n; ++k) q[i * n + k] = start[k] + t * (end[k] - start[k]);
  }
  // The targets' last point is the end itself, not start + 1 * (end - start) rounded.
  std::copy(end.begin(), end.end(), q.end() - static_cast<std::ptrdiff_t>(n));
  std::vector<double> e(points * 6);
  model.evaluate_batch(q, {}, e);
  const Vec3 p0 = model.nominal_pose(start).t;
  const Vec3 along = model.nominal_pose(end).t - p0;
  d.length = along.norm();
  d.direction = along / d.length;
  const Vec3 e0(e[0], e[1], e[2]);
  for (std::size_t i = 0; i < points; ++i) {
    const Vec3 ei(e[i * 6], e[i * 6 + 1], e[i * 6 + 2]);
    if (!ei.allFinite()) throw Error("the model gives a non-finite error on diagonal " + d.name);
    d.position.push_back(d.direction.dot(model.nominal_pose(std::span(q).subspan(i * n, n)).t - p0));
    d.deviation.push_back(d.direction.dot(ei - e0));
  }
  const auto [mn, mx] = std::minmax_element(d.deviation.begin(), d.deviation.end());
  d.range = *mx - *mn;
  d.start = std::move(start);
  d.end = std::move(end);
  return d;
}

}  // namespace

std::vector<DiagonalProfile> diagonal_displacements(const ErrorModel& model, std::span<const double> lo,
                                                    std::span<const double> hi, const DiagonalOptions& o) {
  const Machine& m = model.machine();
  const std::size_t n = m.axes.size();
  if (lo.size() != n || hi.size() != n) throw ModelError("diagonal_displacements: box and machine differ in axes");
  if (o.points < 2 || o.points > 1'000'000)
    throw InputError({"points", 0, ""}, fmt::format("expected 2 to 1e6 points per diagonal, found {}", o.points));
  // The three linear axes in X Y Z order.
  std::array<std::size_t, 3> lin{};
  for (int c = 0; c < 3; ++c) {
    const auto k = m.axis_index("XYZ"[c]);
    if (!k)
      throw InputError({"box", 0, ""}, fmt::format("diagonal tests need linear axes X, Y and Z; {} has no {}",
                                                   m.topology.chain, "XYZ"[c]));
    if (!(lo[*k] < hi[*k]))
      throw InputError({"box", 0, std::string(1, "XYZ"[c])},
                       fmt::format("expected a range lo < hi for {}, found {:g} to {:g} mm", "XYZ"[c], lo[*k], hi[*k]));
    lin[static_cast<std::size_t>(c)] = *k;
  }
  const std::vector<double> base(lo.begin(), lo.end());
  auto corner = [&](std::array<int, 3> at_hi) {  // at_hi[c]: 1 for hi, 0 for lo
    std::vector<double> q = base;
    for (int c = 0; c < 3; ++c)
      q[lin[static_cast<std::size_t>(c)]] = at_hi[static_cast<std::size_t>(c)] ? hi[lin[static_cast<std::size_t>(c)]]
                                                                               : lo[lin[static_cast<std::size_t>(c)]];
    return q;
  };
  std::vector<DiagonalProfile> out;
  // Body diagonals: from a corner to the opposite one; the name gives the sign of travel per axis.
  const std::array<std::array<int, 3>, 4> body_starts{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  for (const auto& s : body_starts) {
    const std::array<int, 3> e{1 - s[0], 1 - s[1], 1 - s[2]};
    std::string name = "body ";
    for (int c = 0; c < 3; ++c) name += s[static_cast<std::size_t>(c)] ? 'N' : 'P';
    out.push_back(run(model, name, corner(s), corner(e), o.points));
  }
  if (o.face_diagonals) {
    // Faces: the plane of two axes, at lo or hi of the third; two diagonals each.
    const std::array<std::array<int, 3>, 3> planes{{{0, 1, 2}, {1, 2, 0}, {2, 0, 1}}};  // XY, YZ, ZX; third axis last
    for (const auto& p : planes)
      for (int side = 0; side < 2; ++side)
        for (int diag = 0; diag < 2; ++diag) {
          std::array<int, 3> s{}, e{};
          s[static_cast<std::size_t>(p[2])] = e[static_cast<std::size_t>(p[2])] = side;
          s[static_cast<std::size_t>(p[0])] = diag, e[static_cast<std::size_t>(p[0])] = 1 - diag;
          s[static_cast<std::size_t>(p[1])] = 0, e[static_cast<std::size_t>(p[1])] = 1;
          const std::string name = fmt::format("face {}{} {}{} {}{}", "XYZ"[p[0]], "XYZ"[p[1]], "XYZ"[p[2]],
                                               side ? '+' : '-', diag ? 'N' : 'P', 'P');
          out.push_back(run(model, name, corner(s), corner(e), o.points));
        }
  }
  return out;
}

}  // namespace mtcal
