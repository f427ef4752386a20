#include "mtcal/compensation/skew.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/kinematics/error_model.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

Vec3 skew_command(const SkewFactors& f, const Vec3& p) {
  return {p.x() - p.y() * f.xy - p.z() * (f.xz - f.xy * f.yz), p.y() - p.z() * f.yz, p.z()};
}

Vec3 skew_reached(const SkewFactors& f, const Vec3& c) {
  return {c.x() + c.y() * f.xy + c.z() * f.xz, c.y() + c.z() * f.yz, c.z()};
}

SkewTangents skew_tangents(const SkewFactors& f) { return {-f.xy, f.xy * f.yz - f.xz, -f.yz}; }

RrfM556 rrf_m556(const SkewTangents& t, double reference_length) {
  return {reference_length, t.xy * reference_length, t.yz * reference_length, t.xz * reference_length};
}

Vec3 rrf_command(const RrfM556& m556, const Vec3& p) {
  const double tan_xy = m556.x / m556.s, tan_yz = m556.y / m556.s, tan_xz = m556.z / m556.s;
  return {p.x() + tan_xy * p.y() + tan_xz * p.z(), p.y() + tan_yz * p.z(), p.z()};
}

FluidncSkew fluidnc_skew(const SkewTangents& t, double reference_length) {
  FluidncSkew s;
  for (double& d : s.distance) d = reference_length;
  s.offset[1][0] = t.xy * reference_length;  // section y: offset_x_mm
  s.offset[2][0] = t.xz * reference_length;  // section z: offset_x_mm
  s.offset[2][1] = t.yz * reference_length;  // section z: offset_y_mm
  return s;
}

Vec3 fluidnc_command(const FluidncSkew& s, const Vec3& p) {
  Vec3 m = Vec3::Zero();
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m[j] += p[i] * (s.offset[i][j] / s.distance[i] + (i == j ? 1.0 : 0.0));
  return m;
}

namespace {

// Squareness: the orientation of a linear axis line (ISO 230-1 location errors EB0X EC0X, EA0Y
// EC0Y, EA0Z EB0Z): what a shear of the three axes can hold.
bool is_squareness(const Machine& m, const ErrorName& n) {
  if (n.kind != ErrorKind::Location || !is_rotation(n.component)) return false;
  const auto i = m.axis_index(n.body);
  return i && m.axes[*i].kind == AxisKind::Linear;
}

}  // namespace

SkewCompensation compensate_skew(const Machine& m, const CompensationOptions& o, const std::string& target) {
  for (const char letter : {'X', 'Y', 'Z'}) {
    const auto i = m.axis_index(letter);
    if (!i || m.axes[*i].direction() != Vec3::Unit(letter - 'X'))
      throw InputError({m.source, 0, std::string(1, letter)},
                       fmt::format("{} skew correction works on linear axes X, Y, Z along +x, +y, +z; {} has {}",
                                   target, m.topology.chain, i ? "another direction" : "no such axis"));
  }
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Rotary)
      throw InputError({m.source, 0, std::string(1, ax.letter)},
                       fmt::format("{} skew correction works on a 3-axis machine; {} has rotary axis {}", target,
                                   m.topology.chain, ax.letter));
  // The squareness alone, and the shear it gives per unit length of each axis (the model is a
  // rotation; over 1 mm the difference from a shear is of the order of the angle squared).
  Machine square = m;
  std::vector<std::string> names;
  for (const auto& p : m.parameters())
    if (p.value != 0.0 && is_squareness(m, p.error)) names.push_back(p.error.str());
  if (names.empty())
    throw InputError({m.source, 0, ""}, fmt::format("nothing to compensate for {}: the model has no squareness error "
                                                    "(EC0Y, EB0Z, EA0Z ...)",
                                                    target));
  square.keep_only(names);
  const ErrorModel sq(square);
  const std::size_t ix = *m.axis_index('X'), iy = *m.axis_index('Y'), iz = *m.axis_index('Z');
  auto error_at = [&](std::size_t axis, double value) {
    std::vector<double> q(m.axes.size(), 0.0);
    q[axis] = value;
    return sq.evaluate(q).translation;
  };
  const Vec3 e0 = error_at(ix, 0.0), ey = error_at(iy, 1.0), ez = error_at(iz, 1.0);
  SkewCompensation out;
  out.factors.xy = ey.x() - e0.x();
  out.factors.xz = ez.x() - e0.x();
  out.factors.yz = ez.y() - e0.y();

  out.tangents = skew_tangents(out.factors);
  out.reference_length = o.skew_reference_length;
  const double len = o.skew_reference_length;
  // GCodes2.cpp case 556 reads S with GetPositiveFValue(); Skewed.cpp takes distance_mm in
  // [1, 100000] and offsets in [-1000, 1000] mm.
  const bool fluidnc = target == "fluidnc", rrf = target == "rrf";
  if (!fluidnc && !rrf && target != "klipper" && target != "marlin")
    throw ModelError("compensate_skew: unknown firmware '" + target + "' (klipper, marlin, rrf, fluidnc)");
  if ((rrf || fluidnc) && (!std::isfinite(len) || len <= 0.0 || (fluidnc && (len < 1.0 || len > 100000.0))))
    throw InputError({m.source, 0, "skew reference length"},
                     fmt::format("expected a {} reference length {}, found {:g} mm", target,
                                 fluidnc ? "from 1 to 100000 mm (distance_mm)" : "above 0 mm (M556 S)", len));
  const RrfM556 m556 = rrf_m556(out.tangents, len);
  const FluidncSkew fs = fluidnc_skew(out.tangents, len);
  if (fluidnc)
    for (const auto& row : fs.offset)
      for (double v : row)
        if (std::abs(v) > 1000.0)
          throw InputError({m.source, 0, "skew reference length"},
                           fmt::format("expected FluidNC offsets within +-1000 mm, found {:g} mm over {:g} mm: "
                                       "choose a shorter reference length",
                                       v, len));

  const auto sampling = resolve_sampling(m, o, 2, 1000000, target);
  const auto grid = residual_grid(m, sampling, o.residual_points);
  const SkewFactors f = out.factors;
  out.summary.residual = predict_residual(
      ErrorModel(m), grid,
      [&](std::span<const double> q, std::span<const std::int8_t>) {
        const Vec3 programmed(q[ix], q[iy], q[iz]);
        const Vec3 cmd = rrf       ? rrf_command(m556, programmed)
                         : fluidnc ? fluidnc_command(fs, programmed)
                                   : skew_command(f, programmed);
        AppliedCorrection c;
        c.joint.assign(m.axes.size(), 0.0);
        c.joint[ix] = cmd.x() - programmed.x();
        c.joint[iy] = cmd.y() - programmed.y();
        return c;
      },
      o.threads);
  out.summary.target = target;
  out.summary.quantity = rrf || fluidnc ? TableQuantity::Correction : TableQuantity::Error;
  if (target == "klipper")
    out.summary.sign_source =
        "Klipper klippy/extras/skew_correction.py: calc_unskew() gives the position reached, x + y*xy_skew + "
        "z*xz_skew, y + z*yz_skew; calc_skew() is applied to every move (docs/Skew_Correction.md)";
  else if (target == "marlin")
    out.summary.sign_source =
        "Marlin Marlin/src/module/planner.h skew()/unskew() and gcode/calibrate/M852.cpp (I = XY, J = XZ, "
        "K = YZ skew factor): the factors are the shear of the axes, the firmware subtracts it";
  else if (rrf)
    out.summary.sign_source =
        "RepRapFirmware src/GCodes/GCodes2.cpp case 556 (tanXY = X/S, tanYZ = Y/S, tanXZ = Z/S) and "
        "src/Movement/Move.cpp Move::AxisTransform(): the machine position is x + tanXY*y + tanXZ*z, y + tanYZ*z "
        "(M556 P0), so the deviations are corrections added per S mm";
  else
    out.summary.sign_source =
        "FluidNC pull request #849 (not released) src/Kinematics/Skewed.cpp SkewAxis / Skewed::init() and "
        "GenericCartesian.cpp Mtx::transform(): motor_j = p_j + sum_i p_i*offset_<j>_mm/distance_mm of section i, "
        "so the offsets are corrections added per distance_mm";
  if (fluidnc)
    out.summary.warnings.push_back(
        "FluidNC's Skewed kinematics is only in the unmerged pull request #849 (bdring/FluidNC, checked against "
        "its head b39123a; not in the released source): the snippet needs a FluidNC build with that kinematics");
  out.summary.not_compensated = errors_not_held(
      m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
      [&](const ErrorName& n) { return is_squareness(m, n); }, o.threads);
  return out;
}

}  // namespace mtcal
