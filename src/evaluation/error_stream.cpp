#include "mtcal/evaluation/error_stream.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/model/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

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

void ConfigurationSource::fill_range(std::size_t first, std::size_t count, double* q, std::int8_t* dir) const {
  const std::size_t n = axes_;
  if (list_ || count == 0) {
    for (std::size_t r = 0; r < count; ++r) fill(first + r, q + r * n, dir ? dir + r * n : nullptr);
    return;
  }
  std::vector<std::size_t> digit(n);
  std::size_t index = first;
  for (std::size_t k = n; k-- > 0;) {
    digit[k] = index % (*grid_)[k].size();
    index /= (*grid_)[k].size();
  }
  for (std::size_t r = 0; r < count; ++r) {
    for (std::size_t k = 0; k < n; ++k) q[r * n + k] = (*grid_)[k][digit[k]];
    for (std::size_t k = n; k-- > 0;) {
      if (++digit[k] < (*grid_)[k].size()) break;
      digit[k] = 0;
    }
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
  const GridValues* grid = source.grid_values();
  const bool by_grid = grid && model.grid_structured();
  struct Extremes {
    double t = -1, a = -1;
    std::size_t at_t = 0, at_a = 0;
    std::size_t bad = static_cast<std::size_t>(-1);
  };
  for (std::size_t first = 0; first < count; first += chunk) {
    const std::size_t len = std::min(chunk, count - first);
    // Filling, checking and the largest errors run in contiguous slices over the threads, combined
    // in slice order: the first configuration of the largest error wins as in one pass.
    const std::size_t slices = std::min<std::size_t>(64, std::max<std::size_t>(1, len / 4096));
    parallel_for_ranges(len, slices, options.threads, [&](std::size_t b, std::size_t e, std::size_t) {
      source.fill_range(first + b, e - b, &q[b * n], with_dir ? &dir[b * n] : nullptr);
    });
    const auto t0 = std::chrono::steady_clock::now();
    if (by_grid)
      model.evaluate_grid(*grid, first, std::span(res).first(len * 6), BatchOptions{options.threads});
    else
      model.evaluate_batch(std::span(q).first(len * n), std::span(dir).first(with_dir ? len * n : 0),
                           std::span(res).first(len * 6), BatchOptions{options.threads});
    sum.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<Extremes> ext(slices);
    const std::size_t per = len / slices, extra = len % slices;
    parallel_for(slices, options.threads, [&](std::size_t c, std::size_t) {
      const std::size_t b = c * per + std::min(c, extra), e = b + per + (c < extra ? 1 : 0);
      Extremes x;
      for (std::size_t r = b; r < e; ++r) {
        const double* v = &res[r * 6];
        if (!std::all_of(v, v + 6, [](double w) { return std::isfinite(w); })) {
          x.bad = r;
          break;
        }
        // hypot (exact to rounding, as always reported) only where the plain sum of squares,
        // within 1e-12 relative of it, does not rule out a new largest value (above 1e-100, where
        // the squares cannot underflow).
        const double t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], a2 = v[3] * v[3] + v[4] * v[4] + v[5] * v[5];
        if (!(x.t > 1e-100 && t2 < x.t * x.t * (1 - 1e-12))) {
          const double t = std::hypot(v[0], v[1], v[2]);
          if (t > x.t) x.t = t, x.at_t = r;
        }
        if (!(x.a > 1e-100 && a2 < x.a * x.a * (1 - 1e-12))) {
          const double a = std::hypot(v[3], v[4], v[5]);
          if (a > x.a) x.a = a, x.at_a = r;
        }
      }
      ext[c] = x;
    });
    for (const Extremes& x : ext) {
      if (x.bad != static_cast<std::size_t>(-1))
        throw Error(
            fmt::format("the model gives a non-finite error at configuration {} of {} (check the "
                        "machine's error values)",
                        first + x.bad + 1, count));
    }
    for (const Extremes& x : ext) {
      if (x.t > bt) bt = x.t, sum.max_translation.at.assign(&q[x.at_t * n], &q[x.at_t * n] + n);
      if (x.a > br) br = x.a, sum.max_rotation.at.assign(&q[x.at_a * n], &q[x.at_a * n] + n);
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
