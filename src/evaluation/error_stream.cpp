#include "mtcal/evaluation/error_stream.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

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
  const GridValues* grid = source.grid_values();
  const bool by_grid = grid && options.grid_kernel && model.grid_structured();
  // Without a sink the grid's errors are only checked and searched for the largest: slices of
  // 64 Ki configurations (3 MB of errors) stay in cache instead of streaming through memory.
  const std::size_t chunk =
      std::max<std::size_t>(1, !sink && by_grid ? std::min<std::size_t>(options.chunk, std::size_t{1} << 16)
                                                : options.chunk);
  const std::size_t rows = std::min(count, chunk);
  // Uninitialised (every element is written before it is read): zero-filling 88 MB per million
  // configurations would cost more than the grid kernel. The grid kernel needs no
  // configurations: they are filled only for a sink (and the largest errors' are recomputed).
  const bool need_q = sink || !by_grid;
  const std::unique_ptr<double[]> q_buffer(new double[need_q ? rows * n : 0]), res_buffer(new double[rows * 6]);
  const std::span<double> q(q_buffer.get(), need_q ? rows * n : 0), res(res_buffer.get(), rows * 6);
  std::vector<std::int8_t> dir(with_dir ? rows * n : 0);
  StreamSummary sum;
  sum.count = count;
  double bt = -1, br = -1;  // the first configuration of the largest error wins
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
    if (need_q)
      parallel_for_ranges(len, slices, options.threads, [&](std::size_t b, std::size_t e, std::size_t) {
        source.fill_range(first + b, e - b, &q[b * n], with_dir ? &dir[b * n] : nullptr);
      });
    const auto t0 = std::chrono::steady_clock::now();
    if (by_grid)
      model.evaluate_grid(*grid, first, res.first(len * 6), BatchOptions{options.threads});
    else
      model.evaluate_batch(q.first(len * n), std::span(dir).first(with_dir ? len * n : 0), res.first(len * 6),
                           BatchOptions{options.threads});
    sum.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<Extremes> ext(slices);
    const std::size_t per = len / slices, extra = len % slices;
    parallel_for(slices, options.threads, [&](std::size_t c, std::size_t) {
      const std::size_t b = c * per + std::min(c, extra), e = b + per + (c < extra ? 1 : 0);
      Extremes x;
      // Pass 1: finiteness and the largest sums of squares. Pass 2: hypot (exact to rounding, as
      // always reported) only where the sum of squares is within 1e-12 relative of the largest,
      // the first configuration of the largest hypot winning; below 1e-100 (where the squares
      // could underflow) every configuration is a candidate.
      double mt2 = 0.0, ma2 = 0.0;
      std::size_t end = e;
      for (std::size_t r = b; r < e; ++r) {
        const double* v = &res[r * 6];
        if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]) && std::isfinite(v[3]) &&
              std::isfinite(v[4]) && std::isfinite(v[5]))) {
          x.bad = r;
          end = r;
          break;
        }
        mt2 = std::max(mt2, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        ma2 = std::max(ma2, v[3] * v[3] + v[4] * v[4] + v[5] * v[5]);
      }
      const double lt = mt2 > 1e-200 ? mt2 * (1 - 1e-12) : 0.0, la = ma2 > 1e-200 ? ma2 * (1 - 1e-12) : 0.0;
      for (std::size_t r = b; r < end; ++r) {
        const double* v = &res[r * 6];
        if (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] >= lt) {
          const double t = std::hypot(v[0], v[1], v[2]);
          if (t > x.t) x.t = t, x.at_t = r;
        }
        if (v[3] * v[3] + v[4] * v[4] + v[5] * v[5] >= la) {
          const double w = std::hypot(v[3], v[4], v[5]);
          if (w > x.a) x.a = w, x.at_a = r;
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
      if (x.t > bt) {
        bt = x.t;
        sum.max_translation.at.resize(n);
        source.fill(first + x.at_t, sum.max_translation.at.data(), nullptr);
      }
      if (x.a > br) {
        br = x.a;
        sum.max_rotation.at.resize(n);
        source.fill(first + x.at_a, sum.max_rotation.at.data(), nullptr);
      }
    }
    if (sink)
      sink(ErrorChunk{first, n, std::span<const double>(q.first(need_q ? len * n : 0)),
                      std::span<const std::int8_t>(dir).first(with_dir ? len * n : 0),
                      std::span<const double>(res.first(len * 6))});
    // Progress at the caller's chunk size, not per cache-sized slice.
    if (options.progress && (first + len == count || (first + len) / std::max<std::size_t>(1, options.chunk) !=
                                                         first / std::max<std::size_t>(1, options.chunk)))
      options.progress(first + len, count);
  }
  sum.max_translation.value = count ? bt : 0.0;
  sum.max_rotation.value = count ? br : 0.0;
  return sum;
}

}  // namespace mtcal
