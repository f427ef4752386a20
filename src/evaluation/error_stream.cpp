#include "mtcal/evaluation/error_stream.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

std::size_t grid_count(const GridValues& values) {
  std::size_t count = 1;
  for (const auto& v : values) count *= v.size();
  return count;
}

void check_grid(const Machine& m, const GridValues& values, const std::string& where, bool travel_check,
                std::size_t max_count) {
  std::size_t count = 1;
  for (const auto& v : values) {
    if (count > max_count / v.size())
      throw InputError({where, 0, ""}, fmt::format("more than {:g} configurations; use a coarser grid",
                                                   static_cast<double>(max_count)));
    count *= v.size();
  }
  // The travels are boxes: the grid lies inside when its lowest and highest corner do.
  const std::size_t n = m.axes.size();
  std::vector<double> lo(n), hi(n);
  for (std::size_t k = 0; k < n; ++k) {
    lo[k] = *std::min_element(values[k].begin(), values[k].end());
    hi[k] = *std::max_element(values[k].begin(), values[k].end());
  }
  check_joints(m, lo, where, travel_check);
  check_joints(m, hi, where, travel_check);
}

ConfigurationSource ConfigurationSource::list(const ConfigurationList& list) {
  ConfigurationSource s;
  s.list_ = &list;
  s.axes_ = list.axes;
  s.size_ = list.size();
  return s;
}

ConfigurationSource ConfigurationSource::grid(const GridValues& values) {
  ConfigurationSource s;
  s.grid_ = &values;
  s.axes_ = values.size();
  s.size_ = grid_count(values);
  return s;
}

void ConfigurationSource::fill(std::size_t index, double* q, std::int8_t* dir) const {
  const std::size_t n = axes_;
  if (list_) {
    std::copy_n(&list_->q[index * n], n, q);
    if (dir && !list_->dir.empty()) std::copy_n(&list_->dir[index * n], n, dir);
    return;
  }
  for (std::size_t k = n; k-- > 0;) {
    const std::size_t len = (*grid_)[k].size();
    q[k] = (*grid_)[k][index % len];
    index /= len;
  }
}

StreamSummary evaluate_stream(const ErrorModel& model, const ConfigurationSource& source,
                              const std::function<void(const ErrorChunk&)>& sink, const StreamOptions& options) {
  const std::size_t n = source.axes(), count = source.size();
  if (n != model.axis_count())
    throw ModelError(
        fmt::format("evaluate_stream: configurations of {} axes for a machine with {} axes", n, model.axis_count()));
  const bool with_dir = source.has_directions();
  const std::size_t chunk = std::max<std::size_t>(1, options.chunk);
  const std::size_t rows = std::min(count, chunk);
  std::vector<double> q(rows * n), res(rows * 6);
  std::vector<std::int8_t> dir(with_dir ? rows * n : 0);
  StreamSummary sum;
  sum.count = count;
  double bt = -1, br = -1;  // the first configuration of the largest error wins
  for (std::size_t first = 0; first < count; first += chunk) {
    const std::size_t len = std::min(chunk, count - first);
    for (std::size_t r = 0; r < len; ++r) source.fill(first + r, &q[r * n], with_dir ? &dir[r * n] : nullptr);
    const auto t0 = std::chrono::steady_clock::now();
    model.evaluate_batch(std::span(q).first(len * n), std::span(dir).first(with_dir ? len * n : 0),
                         std::span(res).first(len * 6), BatchOptions{options.threads});
    sum.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t r = 0; r < len; ++r) {
      const double* e = &res[r * 6];
      if (!std::all_of(e, e + 6, [](double v) { return std::isfinite(v); }))
        throw Error(
            fmt::format("the model gives a non-finite error at configuration {} of {} (check the "
                        "machine's error values)",
                        first + r + 1, count));
      const double t = std::hypot(e[0], e[1], e[2]), a = std::hypot(e[3], e[4], e[5]);
      if (t > bt) bt = t, sum.max_translation.at.assign(&q[r * n], &q[r * n] + n);
      if (a > br) br = a, sum.max_rotation.at.assign(&q[r * n], &q[r * n] + n);
    }
    if (sink)
      sink(ErrorChunk{first, n, std::span<const double>(q).first(len * n),
                      std::span<const std::int8_t>(dir).first(with_dir ? len * n : 0),
                      std::span<const double>(res).first(len * 6)});
    if (options.progress) options.progress(first + len, count);
  }
  sum.max_translation.value = count ? bt : 0.0;
  sum.max_rotation.value = count ? br : 0.0;
  return sum;
}

}  // namespace mtcal
