#include "mtcal/evaluation/motion_program.hpp"

#include <cmath>

namespace mtcal {

std::string_view to_string(GcodeMotion m) {
  switch (m) {
    case GcodeMotion::Rapid: return "rapid";
    case GcodeMotion::Linear: return "linear";
    case GcodeMotion::ArcCW: return "arc_cw";
    case GcodeMotion::ArcCCW: return "arc_ccw";
  }
  return "?";
}

std::string_view to_string(GcodePlane p) {
  switch (p) {
    case GcodePlane::XY: return "G17";
    case GcodePlane::ZX: return "G18";
    case GcodePlane::YZ: return "G19";
  }
  return "?";
}

PlaneAxes plane_axes(GcodePlane p) {
  switch (p) {
    case GcodePlane::XY: return {0, 1, 2};
    case GcodePlane::ZX: return {2, 0, 1};
    case GcodePlane::YZ: return {1, 2, 0};
  }
  return {0, 1, 2};
}

double path_length(const GcodeMove& m) {
  if (!m.is_arc())
    return std::sqrt((m.end[0] - m.start[0]) * (m.end[0] - m.start[0]) +
                     (m.end[1] - m.start[1]) * (m.end[1] - m.start[1]) +
                     (m.end[2] - m.start[2]) * (m.end[2] - m.start[2]));
  const PlaneAxes pa = plane_axes(m.plane);
  const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v), w = static_cast<std::size_t>(pa.w);
  const double r0 = std::hypot(m.start[u] - m.centre[u], m.start[v] - m.centre[v]);
  const double r1 = std::hypot(m.end[u] - m.centre[u], m.end[v] - m.centre[v]);
  // A helix unrolls into a right triangle: arc length in the plane, rise along the normal. With
  // the radius changing by at most the tolerance, the mean radius is exact to its square.
  return std::hypot(std::abs(m.sweep) * (r0 + r1) / 2, m.end[w] - m.start[w]);
}

GcodePosition position_at(const GcodeMove& m, double t) {
  if (t >= 1) return m.end;
  GcodePosition p;
  for (std::size_t s = 0; s < 6; ++s) p[s] = m.start[s] + (m.end[s] - m.start[s]) * t;
  if (!m.is_arc()) return p;
  const PlaneAxes pa = plane_axes(m.plane);
  const auto u = static_cast<std::size_t>(pa.u), v = static_cast<std::size_t>(pa.v);
  const double r0 = std::hypot(m.start[u] - m.centre[u], m.start[v] - m.centre[v]);
  const double r1 = std::hypot(m.end[u] - m.centre[u], m.end[v] - m.centre[v]);
  const double a = std::atan2(m.start[v] - m.centre[v], m.start[u] - m.centre[u]) + m.sweep * t;
  const double r = r0 + (r1 - r0) * t;
  p[u] = m.centre[u] + r * std::cos(a);
  p[v] = m.centre[v] + r * std::sin(a);
  return p;
}

}  // namespace mtcal
