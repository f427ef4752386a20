#include "mtcal/compensation/compensation.hpp"

#include <algorithm>
#include <cmath>

#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal {

const char* to_string(TableQuantity q) {
  switch (q) {
    case TableQuantity::Error: return "error";
    case TableQuantity::Correction: return "correction";
    case TableQuantity::ActualPosition: return "actual position";
  }
  return "?";
}

double interpolate_held(std::span<const double> positions, std::span<const double> values, double x) {
  if (positions.empty() || positions.size() != values.size())
    throw ModelError("interpolate_held: expected as many values as positions (at least one)");
  if (x <= positions.front()) return values.front();
  if (x >= positions.back()) return values.back();
  const auto it = std::upper_bound(positions.begin(), positions.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - positions.begin());  // positions[i-1] <= x < positions[i]
  const double t = (x - positions[i - 1]) / (positions[i] - positions[i - 1]);
  return values[i - 1] + t * (values[i] - values[i - 1]);
}

ResidualSummary predict_residual(const ErrorModel& model, const std::vector<std::vector<double>>& axis_values,
                                 const CorrectionRule& rule, int threads) {
  const std::size_t n = model.axis_count();
  if (axis_values.size() != n)
    throw ModelError("predict_residual: expected joint values for each of the " + std::to_string(n) + " axes");
  std::size_t count = 1;
  for (const auto& v : axis_values) {
    if (v.empty()) throw ModelError("predict_residual: an axis has no joint value");
    count *= v.size();
  }
  // Two error vectors per configuration (forward, reverse), before and after.
  std::vector<Vec3> before(2 * count), after(2 * count);
  const std::size_t chunk = 256;
  parallel_for((count + chunk - 1) / chunk, threads, [&](std::size_t chunk_index, std::size_t) {
    std::vector<double> q(n), qc(n);
    std::vector<std::int8_t> dir(n);
    for (std::size_t k = chunk_index * chunk; k < std::min(count, (chunk_index + 1) * chunk); ++k) {
      // Mixed radix, the last axis of the chain fastest (as grid_error_map orders it).
      std::size_t rest = k;
      for (std::size_t a = n; a-- > 0;) {
        q[a] = axis_values[a][rest % axis_values[a].size()];
        rest /= axis_values[a].size();
      }
      const Affine nominal = model.nominal_pose(q);
      for (int d = 0; d < 2; ++d) {
        std::fill(dir.begin(), dir.end(), static_cast<std::int8_t>(d == 0 ? 1 : -1));
        before[2 * k + d] = model.evaluate(q, dir).translation;
        const AppliedCorrection c = rule(q, dir);
        qc = q;
        for (std::size_t a = 0; a < c.joint.size() && a < n; ++a) qc[a] += c.joint[a];
        after[2 * k + d] = volumetric_error(model.actual_pose(qc, dir), nominal).translation + c.cartesian;
      }
    }
  });
  ResidualSummary s;
  s.configurations = count;
  for (std::size_t i = 0; i < before.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      s.max_before[a] = std::max(s.max_before[a], std::abs(before[i][a]));
      s.max_after[a] = std::max(s.max_after[a], std::abs(after[i][a]));
      s.max_norm_before = std::max(s.max_norm_before, before[i].norm());
      s.max_norm_after = std::max(s.max_norm_after, after[i].norm());
    }
  s.va_before = volumetric_accuracy(before).va.value;
  s.va_after = volumetric_accuracy(after).va.value;
  return s;
}

}  // namespace mtcal
