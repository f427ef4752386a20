#include "mtcal/compensation/skew.hpp"

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

  const auto sampling = resolve_sampling(m, o, 2, 1000000, target);
  const auto grid = residual_grid(m, sampling, o.residual_points);
  const SkewFactors f = out.factors;
  out.summary.residual = predict_residual(
      ErrorModel(m), grid,
      [&](std::span<const double> q, std::span<const std::int8_t>) {
        const Vec3 programmed(q[ix], q[iy], q[iz]);
        const Vec3 cmd = skew_command(f, programmed);
        AppliedCorrection c;
        c.joint.assign(m.axes.size(), 0.0);
        c.joint[ix] = cmd.x() - programmed.x();
        c.joint[iy] = cmd.y() - programmed.y();
        return c;
      },
      o.threads);
  out.summary.target = target;
  out.summary.quantity = TableQuantity::Error;
  out.summary.sign_source =
      target == "klipper"
          ? "Klipper klippy/extras/skew_correction.py: calc_unskew() gives the position reached, x + y*xy_skew + "
            "z*xz_skew, y + z*yz_skew; calc_skew() is applied to every move (docs/Skew_Correction.md)"
          : "Marlin Marlin/src/module/planner.h skew()/unskew() and gcode/calibrate/M852.cpp (I = XY, J = XZ, "
            "K = YZ skew factor): the factors are the shear of the axes, the firmware subtracts it";
  out.summary.not_compensated = errors_not_held(
      m, residual_grid(m, sampling, std::min<std::size_t>(o.residual_points, 5)),
      [&](const ErrorName& n) { return is_squareness(m, n); }, o.threads);
  return out;
}

}  // namespace mtcal
