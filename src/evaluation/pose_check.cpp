#include "mtcal/evaluation/pose_check.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {

PoseCheck check_reached_poses(const Machine& machine, std::span<const ReachedPose> poses,
                              const PoseCheckOptions& options, const std::string& source) {
  const CommandedJointSolver solver(machine);
  PoseCheck out;
  out.tool_length = options.tool_length.value_or(machine.tool.length);
  if (!std::isfinite(out.tool_length) || out.tool_length < 0)
    throw InputError({source, 0, "tool length"}, fmt::format("expected a tool length >= 0 mm, found {}", out.tool_length));
  Vec3 a = Vec3::Zero();
  a[machine.tool.tool_axis] = 1.0;
  std::vector<Vec3> errors;
  double sum2 = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const ReachedPose& p = poses[i];
    if (p.q.size() != machine.axes.size() || p.commanded.rotary.size() != solver.rotary_count())
      throw InputError({source, p.line, ""},
                       fmt::format("expected {} joints and {} rotary coordinates for topology {}, found {} and {}",
                                   machine.axes.size(), solver.rotary_count(), machine.topology.chain, p.q.size(),
                                   p.commanded.rotary.size()));
    const Affine actual = solver.actual_pose(p.q, out.tool_length);
    const Affine nominal = solver.nominal_pose(solver.nominal_inverse(p.commanded, out.tool_length), out.tool_length);
    PoseDeviation d;
    d.error = actual.t - p.commanded.point;
    const Vec3 da = actual.R * a, dn = nominal.R * a;
    d.direction_error = std::atan2(da.cross(dn).norm(), da.dot(dn));
    if (!d.error.allFinite() || !std::isfinite(d.direction_error))
      throw Error(fmt::format("{}:{}: the machine gives a non-finite tool point at this pose (check the joints and "
                              "the machine's error values)",
                              source, p.line));
    const double n = d.error.norm();
    if (n > out.max_error || i == 0) out.max_error = n, out.max_index = i;
    sum2 += n * n;
    out.max_direction_error = std::max(out.max_direction_error, d.direction_error);
    errors.push_back(d.error);
    out.poses.push_back(d);
  }
  out.rms_error = poses.empty() ? 0.0 : std::sqrt(sum2 / static_cast<double>(poses.size()));
  out.va = volumetric_accuracy(errors);
  return out;
}

}  // namespace mtcal
