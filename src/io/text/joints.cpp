#include "mtcal/io/text/joints.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

std::vector<std::pair<std::string, std::string>> items(std::string_view spec, std::string_view what) {
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t start = 0;
  while (start <= spec.size()) {
    std::size_t end = spec.find(',', start);
    if (end == std::string_view::npos) end = spec.size();
    std::string item(spec.substr(start, end - start));
    auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({std::string(what), 0, item},
                       "expected AXIS=VALUE items separated by commas, found '" + printable(item) + "'");
    out.emplace_back(item.substr(0, eq), item.substr(eq + 1));
    start = end + 1;
  }
  return out;
}

double to_number(const std::string& s, const std::string& field, std::string_view what) {
  const auto v = parse_number(s);
  if (!v) throw InputError({std::string(what), 0, field}, "expected a number, found '" + printable(s) + "'");
  return *v;
}

// A joint position as typed: a bare number in the machine's user unit (mm, deg), or with a unit
// suffix of the axis' dimension ("0.4m", "30deg", "0.5rad").
double joint_value(const Axis& ax, const std::string& s, const std::string& field, std::string_view what) {
  return parse_quantity(s, ax.kind == AxisKind::Linear ? Dimension::Length : Dimension::Angle, joint_unit_factor(ax),
                        false, {std::string(what), 0, field});
}

std::size_t axis_of(const Machine& m, const std::string& name, std::vector<bool>& seen, std::string_view what) {
  auto idx = name.size() == 1 ? m.axis_index(name[0]) : std::nullopt;
  if (!idx)
    throw InputError({std::string(what), 0, name},
                     "axis '" + printable(name) + "' is not in topology " + m.topology.chain);
  if (seen[*idx]) throw InputError({std::string(what), 0, name}, "axis '" + printable(name) + "' given twice");
  seen[*idx] = true;
  return *idx;
}

}  // namespace

std::vector<double> parse_joint_values(const Machine& m, std::string_view spec, std::string_view where) {
  std::vector<double> q(m.axes.size(), 0.0);
  std::vector<bool> seen(m.axes.size(), false);
  for (const auto& [name, value] : items(spec, where)) {
    const std::size_t k = axis_of(m, name, seen, where);
    q[k] = joint_value(m.axes[k], value, name, where);
  }
  return q;
}

JointBox parse_box(const Machine& m, std::string_view spec, std::string_view where) {
  const std::size_t n = m.axes.size();
  JointBox b{std::vector<double>(n, -INFINITY), std::vector<double>(n, INFINITY), std::vector<bool>(n, false)};
  std::vector<bool> seen(n, false);
  for (const auto& [name, value] : items(spec, where)) {
    const std::size_t k = axis_of(m, name, seen, where);
    const auto colon = value.find(':');
    if (colon == std::string::npos) {
      b.lo[k] = b.hi[k] = joint_value(m.axes[k], value, name, where);
    } else {
      if (value.find(':', colon + 1) != std::string::npos)
        throw InputError({std::string(where), 0, name},
                         "expected lo:hi or a single value, found '" + printable(value) + "'");
      b.lo[k] = joint_value(m.axes[k], value.substr(0, colon), name, where);
      b.hi[k] = joint_value(m.axes[k], value.substr(colon + 1), name, where);
      if (b.lo[k] > b.hi[k])
        throw InputError({std::string(where), 0, name}, "expected lo <= hi, found '" + printable(value) + "'");
    }
    b.named[k] = true;
  }
  return b;
}

std::string format_joint_values(const Machine& m, const std::vector<double>& q, std::string_view separator) {
  std::string s;
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    s += fmt::format("{}{}={:g}", k ? separator : "", m.axes[k].letter, to_user_units(m.axes[k], q[k]));
  return s;
}

std::vector<std::vector<double>> parse_grid(const Machine& m, std::string_view spec, std::string_view where) {
  std::vector<std::vector<double>> g(m.axes.size(), std::vector<double>{0.0});
  std::vector<bool> seen(m.axes.size(), false);
  for (const auto& [name, value] : items(spec, where)) {
    const std::size_t k = axis_of(m, name, seen, where);
    const double f = joint_unit_factor(m.axes[k]);
    std::vector<std::string> parts;
    std::size_t s = 0;
    while (true) {
      auto c = value.find(':', s);
      parts.push_back(value.substr(s, c == std::string::npos ? std::string::npos : c - s));
      if (c == std::string::npos) break;
      s = c + 1;
    }
    if (parts.size() == 1) {
      g[k] = {joint_value(m.axes[k], parts[0], name, where)};
      continue;
    }
    if (parts.size() != 3)
      throw InputError({std::string(where), 0, name},
                       "expected lo:hi:count or a single value, found '" + printable(value) + "'");
    // In the machine's user unit, as the samples are spaced there.
    const double lo = joint_value(m.axes[k], parts[0], name, where) / f,
                 hi = joint_value(m.axes[k], parts[1], name, where) / f;
    const double cnt = to_number(parts[2], name, where);
    if (cnt < 1 || cnt != std::floor(cnt) || cnt > 1e7)
      throw InputError({std::string(where), 0, name},
                       "expected a whole count from 1 to 1e7, found '" + printable(parts[2]) + "'");
    const auto count = static_cast<std::size_t>(cnt);
    g[k].assign(count, lo * f);
    for (std::size_t i = 1; i < count; ++i) {
      // Weighted mean rather than lo + (hi - lo) t: no overflow, and the end lands on hi exactly.
      const double t = static_cast<double>(i) / static_cast<double>(count - 1);
      g[k][i] = (lo * (1.0 - t) + hi * t) * f;
    }
  }
  return g;
}

}  // namespace mtcal
