#include "mtcal/model/joints.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {

double joint_unit_factor(const Axis& ax) { return ax.kind == AxisKind::Linear ? 1.0 : std::numbers::pi / 180.0; }
std::string_view joint_unit_name(const Axis& ax) { return ax.kind == AxisKind::Linear ? "mm" : "deg"; }

double to_user_units(const Axis& ax, double q) {
  const double v = q / joint_unit_factor(ax);
  return parse_number(fmt::format("{:.12g}", v)).value_or(v);
}

void check_joints(const Machine& m, const std::vector<double>& q, const std::string& where, bool travel) {
  for (std::size_t k = 0; k < m.axes.size(); ++k) {
    const Axis& ax = m.axes[k];
    const double f = joint_unit_factor(ax);
    if (!(std::abs(q[k]) <= kMaxJointValue * f))
      throw InputError({where, 0, std::string(1, ax.letter)},
                       fmt::format("{}={:g} {} is not a joint position (expected a finite value within +-{:g})",
                                   ax.letter, q[k] / f, joint_unit_name(ax), kMaxJointValue));
    if (!travel || !ax.travel) continue;
    const double tol = 1e-9 * std::max(1.0, std::abs(ax.travel->max - ax.travel->min));
    if (!(q[k] >= ax.travel->min - tol && q[k] <= ax.travel->max + tol)) {
      throw InputError({where, 0, std::string(1, ax.letter)},
                       fmt::format("{}={:g} {} is outside the travel [{:g}, {:g}] of axis {}", ax.letter, q[k] / f,
                                   joint_unit_name(ax), ax.travel->min / f, ax.travel->max / f, ax.letter));
    }
  }
}

}  // namespace mtcal
