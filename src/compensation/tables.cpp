#include "mtcal/compensation/tables.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

std::string axis_field(char axis) { return std::string(1, axis); }

}  // namespace

AxisSampling default_sampling(const Machine& m, char axis, std::size_t points) {
  const Axis& ax = m.axis(axis);
  AxisSampling s{axis, 0.0, 0.0, points};
  if (ax.travel) {
    s.start = to_user_units(ax, ax.travel->min);
    s.end = to_user_units(ax, ax.travel->max);
  } else if (ax.kind == AxisKind::Rotary) {
    s.end = 360.0;  // one turn: the table of a modulo axis (LinuxCNC, Siemens _IS_MODULO)
  } else {
    throw InputError({m.source, 0, axis_field(axis)},
                     fmt::format("axis {} has no travel: expected a range to sample it over", axis));
  }
  return s;
}

std::vector<double> sample_positions(const AxisSampling& s, const std::string& where) {
  if (s.points < 2)
    throw InputError({where, 0, axis_field(s.axis)},
                     fmt::format("expected at least 2 positions along {}, found {}", s.axis, s.points));
  if (!std::isfinite(s.start) || !std::isfinite(s.end) || !(s.start < s.end))
    throw InputError({where, 0, axis_field(s.axis)},
                     fmt::format("expected a range start < end along {}, found {:g} to {:g}", s.axis, s.start, s.end));
  std::vector<double> out(s.points);
  const double step = (s.end - s.start) / static_cast<double>(s.points - 1);
  for (std::size_t i = 0; i < s.points; ++i) out[i] = s.start + step * static_cast<double>(i);
  out.back() = s.end;  // exact, not start + (n-1) * step rounded
  return out;
}

ComponentTable sample_component(const Machine& m, Component component, const AxisSampling& s,
                                const std::string& where) {
  const Axis& ax = m.axis(s.axis);
  ComponentTable t;
  t.error = ErrorName{ErrorKind::Motion, component, s.axis};
  t.position = sample_positions(s, where);
  const MotionFunction& f = ax.motion[static_cast<std::size_t>(index_of(component))];
  const double k = joint_unit_factor(ax);
  for (const double p : t.position) {
    t.forward.push_back(f.value(p * k, static_cast<int>(Approach::Forward)));
    t.reverse.push_back(f.value(p * k, static_cast<int>(Approach::Reverse)));
  }
  return t;
}

JointErrorTable sample_joint_error(const ErrorModel& model, const AxisSampling& s, std::span<const double> reference,
                                   const std::string& where) {
  const Machine& m = model.machine();
  const std::size_t n = m.axes.size();
  const auto index = m.axis_index(s.axis);
  if (!index) throw ModelError(fmt::format("axis {} is not in the topology {}", s.axis, m.topology.chain));
  if (!reference.empty() && reference.size() != n)
    throw InputError({where, 0, "reference"},
                     fmt::format("expected {} joint values for the reference position, found {}", n, reference.size()));
  JointErrorTable t;
  t.axis = s.axis;
  t.position = sample_positions(s, where);
  std::vector<double> q(n, 0.0);
  if (!reference.empty()) q.assign(reference.begin(), reference.end());
  std::vector<std::int8_t> dir(n, 0);
  const double k = joint_unit_factor(m.axes[*index]);
  for (const double p : t.position) {
    q[*index] = p * k;
    dir[*index] = static_cast<std::int8_t>(Approach::Forward);
    t.forward.push_back(model.evaluate(q, dir));
    dir[*index] = static_cast<std::int8_t>(Approach::Reverse);
    t.reverse.push_back(model.evaluate(q, dir));
  }
  return t;
}

}  // namespace mtcal
