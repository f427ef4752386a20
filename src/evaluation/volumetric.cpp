#include "mtcal/evaluation/volumetric.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include <fmt/format.h>

#include "../util/kernel.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

namespace {

constexpr std::size_t kChunk = std::size_t{1} << 18;  // configurations per batch call

void check_finite(const double* e, std::size_t index, std::size_t count) {
  for (int c = 0; c < 6; ++c)
    if (!std::isfinite(e[c]))
      throw Error(
          fmt::format("the model gives a non-finite error at configuration {} of {} (check the "
                      "machine's error values)",
                      index + 1, count));
}

// Evaluates map.q in chunks into map.error (translations only; rotations are not part of VA).
void evaluate_map(const ErrorModel& model, ErrorMap& map, std::span<const std::int8_t> dir,
                  const BatchOptions& options) {
  const std::size_t n = map.axes, count = n ? map.q.size() / n : 0;
  map.error.resize(count);
  std::vector<double> res(std::min(count, kChunk) * 6);
  for (std::size_t first = 0; first < count; first += kChunk) {
    const std::size_t len = std::min(kChunk, count - first);
    model.evaluate_batch(std::span(map.q).subspan(first * n, len * n),
                         dir.empty() ? dir : dir.subspan(first * n, len * n), std::span(res).first(len * 6), options);
    for (std::size_t r = 0; r < len; ++r) {
      check_finite(&res[r * 6], first + r, count);
      map.error[first + r] = Vec3(res[r * 6], res[r * 6 + 1], res[r * 6 + 2]);
    }
  }
}

double squared_distance(const Vec3& a, const Vec3& b) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

// k-d tree over the points for the farthest-pair search. Coordinates are copied in tree order
// (structure of arrays) so that leaf-against-leaf loops run over contiguous memory.
class FarthestPair {
 public:
  explicit FarthestPair(std::span<const Vec3> e) : e_(e) {
    const std::size_t n = e.size();
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), std::uint32_t{0});
    nodes_.reserve(2 * (n / kLeaf + 1));
    build(0, static_cast<std::uint32_t>(n));
    for (int d = 0; d < 3; ++d) {
      c_[d].resize(n);
      for (std::size_t i = 0; i < n; ++i) c_[d][i] = e[order_[i]][d];
    }
  }

  // best2 in: a squared distance achieved by pair (bi, bj); out: the largest over all pairs.
  void search(double& best2, std::size_t& bi, std::size_t& bj, std::uint64_t& evaluations) const {
    struct Item {
      double bound;
      std::uint32_t a, b;
    };
    std::vector<Item> stack{{bound(0, 0), 0, 0}};
    while (!stack.empty()) {
      const Item it = stack.back();
      stack.pop_back();
      // Rounding is monotone, so the box bound is never below a computed pair distance: a pair
      // of boxes skipped here holds no pair that a comparison of every pair would rank higher.
      if (it.bound <= best2) continue;
      const Node &A = nodes_[it.a], &B = nodes_[it.b];
      if (A.left < 0 && B.left < 0) {
        leaf_pairs(A, B, it.a == it.b, best2, bi, bj, evaluations);
        continue;
      }
      Item children[4];
      int count = 0;
      auto add = [&](std::uint32_t a, std::uint32_t b) { children[count++] = {bound(a, b), a, b}; };
      if (it.a == it.b) {
        add(A.left, A.left), add(A.left, A.right), add(A.right, A.right);
      } else if (B.left < 0 || (A.left >= 0 && A.end - A.begin >= B.end - B.begin)) {
        add(A.left, it.b), add(A.right, it.b);
      } else {
        add(it.a, B.left), add(it.a, B.right);
      }
      // Most promising last, so it is taken first: the bound rises quickly and prunes more.
      for (int k = 1; k < count; ++k)  // insertion sort of at most 3
        for (int m = k; m > 0 && children[m].bound < children[m - 1].bound; --m)
          std::swap(children[m], children[m - 1]);
      for (int k = 0; k < count; ++k)
        if (children[k].bound > best2) stack.push_back(children[k]);
    }
  }

 private:
  static constexpr std::uint32_t kLeaf = 24;
  struct Node {
    double lo[3], hi[3];
    std::uint32_t begin, end;
    std::int32_t left = -1, right = -1;
  };

  std::int32_t build(std::uint32_t begin, std::uint32_t end) {
    Node node;
    node.begin = begin, node.end = end;
    for (int d = 0; d < 3; ++d) node.lo[d] = std::numeric_limits<double>::infinity(), node.hi[d] = -node.lo[d];
    for (std::uint32_t i = begin; i < end; ++i)
      for (int d = 0; d < 3; ++d) {
        node.lo[d] = std::min(node.lo[d], e_[order_[i]][d]);
        node.hi[d] = std::max(node.hi[d], e_[order_[i]][d]);
      }
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(node);
    int dim = 0;
    for (int d = 1; d < 3; ++d)
      if (node.hi[d] - node.lo[d] > node.hi[dim] - node.lo[dim]) dim = d;
    // Equal points stay in one leaf, whatever their number: its bound is 0 and never searched.
    if (end - begin <= kLeaf || node.hi[dim] == node.lo[dim]) return id;
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](std::uint32_t a, std::uint32_t b) { return e_[a][dim] < e_[b][dim]; });
    const std::int32_t l = build(begin, mid);
    const std::int32_t r = build(mid, end);
    nodes_[static_cast<std::size_t>(id)].left = l;
    nodes_[static_cast<std::size_t>(id)].right = r;
    return id;
  }

  // Largest squared distance between a point of box a and a point of box b.
  double bound(std::uint32_t a, std::uint32_t b) const {
    const Node &A = nodes_[a], &B = nodes_[b];
    double s = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double w = std::max(A.hi[d] - B.lo[d], B.hi[d] - A.lo[d]);
      s += w * w;
    }
    return s;
  }

  void leaf_pairs(const Node& A, const Node& B, bool same, double& best2, std::size_t& bi, std::size_t& bj,
                  std::uint64_t& evaluations) const {
    const double *x = c_[0].data(), *y = c_[1].data(), *z = c_[2].data();
    for (std::uint32_t i = A.begin; i < A.end; ++i) {
      const std::uint32_t j0 = same ? i + 1 : B.begin;
      for (std::uint32_t j = j0; j < B.end; ++j) {
        const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 > best2) best2 = d2, bi = order_[i], bj = order_[j];
      }
      evaluations += B.end - j0;
    }
  }

  std::span<const Vec3> e_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
  std::vector<double> c_[3];
};

// A good first pair: the extremes along 13 directions (axes, face and body diagonals), then
// steps to the farthest point from the current pair's ends until none is farther.
void lower_bound(std::span<const Vec3> e, double& best2, std::size_t& bi, std::size_t& bj, std::uint64_t& evaluations) {
  static const double dirs[13][3] = {{1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
                                     {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  std::vector<std::size_t> ext;
  for (const auto& d : dirs) {
    std::size_t lo = 0, hi = 0;
    double vlo = std::numeric_limits<double>::infinity(), vhi = -vlo;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const double v = d[0] * e[i].x() + d[1] * e[i].y() + d[2] * e[i].z();
      if (v < vlo) vlo = v, lo = i;
      if (v > vhi) vhi = v, hi = i;
    }
    ext.push_back(lo), ext.push_back(hi);
  }
  std::sort(ext.begin(), ext.end());
  ext.erase(std::unique(ext.begin(), ext.end()), ext.end());
  for (std::size_t a = 0; a < ext.size(); ++a)
    for (std::size_t b = a + 1; b < ext.size(); ++b) {
      const double d2 = squared_distance(e[ext[a]], e[ext[b]]);
      ++evaluations;
      if (d2 > best2) best2 = d2, bi = ext[a], bj = ext[b];
    }
  for (int step = 0; step < 4; ++step) {
    bool improved = false;
    for (std::size_t from : {bi, bj}) {
      for (std::size_t i = 0; i < e.size(); ++i) {
        const double d2 = squared_distance(e[from], e[i]);
        if (d2 > best2) best2 = d2, bi = std::min(from, i), bj = std::max(from, i), improved = true;
      }
      evaluations += e.size();
    }
    if (!improved) break;
  }
}

}  // namespace

ErrorMap grid_error_map(const ErrorModel& model, const std::vector<std::vector<double>>& axis_values,
                        const BatchOptions& options) {
  const std::size_t n = model.axis_count();
  if (axis_values.size() != n)
    throw ModelError(
        fmt::format("grid_error_map: {} axes of values for a machine with {} axes", axis_values.size(), n));
  std::size_t count = 1;
  for (const auto& v : axis_values) {
    if (v.empty()) throw ModelError("grid_error_map: an axis has no values");
    if (count > std::size_t{4'000'000'000} / v.size())
      throw InputError({"grid", 0, ""}, "more than 4e9 configurations; use a coarser grid");
    count *= v.size();
  }
  ErrorMap map;
  map.axes = n;
  map.q.resize(count * n);
  // Mixed-radix index: the last axis of the chain varies fastest (as parse_grid and evaluate_stream order them).
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t r = i;
    for (std::size_t k = n; k-- > 0;) {
      const std::size_t len = axis_values[k].size();
      map.q[i * n + k] = axis_values[k][r % len];
      r /= len;
    }
  }
  evaluate_map(model, map, {}, options);
  return map;
}

ErrorMap error_map(const ErrorModel& model, std::vector<double> q, std::span<const std::int8_t> dir,
                   const BatchOptions& options) {
  const std::size_t n = model.axis_count();
  if (n == 0 || q.size() % n != 0 || (!dir.empty() && dir.size() != q.size()))
    throw ModelError(fmt::format("error_map: {} joint values and {} directions for {} axes", q.size(), dir.size(), n));
  ErrorMap map;
  map.axes = n;
  map.q = std::move(q);
  map.dir.assign(dir.begin(), dir.end());
  evaluate_map(model, map, map.dir, options);
  return map;
}

ErrorMap sub_map(const ErrorMap& map, std::span<const double> lo, std::span<const double> hi) {
  if (lo.size() != map.axes || hi.size() != map.axes) throw ModelError("sub_map: box and map differ in axes");
  ErrorMap out;
  out.axes = map.axes;
  for (std::size_t i = 0; i < map.size(); ++i) {
    const auto q = map.configuration(i);
    bool inside = true;
    for (std::size_t k = 0; k < map.axes && inside; ++k) inside = q[k] >= lo[k] && q[k] <= hi[k];
    if (!inside) continue;
    out.q.insert(out.q.end(), q.begin(), q.end());
    const auto d = map.direction(i);
    out.dir.insert(out.dir.end(), d.begin(), d.end());
    out.error.push_back(map.error[i]);
  }
  return out;
}

VolumetricAccuracy volumetric_accuracy(std::span<const Vec3> e, const VaSearchOptions& options) {
  VolumetricAccuracy r;
  const std::size_t n = e.size();
  r.points = n;
  r.pairs = 0.5 * static_cast<double>(n) * (n > 0 ? static_cast<double>(n - 1) : 0.0);
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw InputError({"volumetric accuracy", 0, ""}, fmt::format("at most 4294967295 points, found {}", n));
  if (n < 2) return r;
  for (int c = 0; c < 3; ++c) {
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (e[i][c] < e[lo][c]) lo = i;
      if (e[i][c] > e[hi][c]) hi = i;
    }
    r.component[static_cast<std::size_t>(c)] = {e[hi][c] - e[lo][c], lo, hi};
  }
  double best2 = 0.0;
  std::size_t bi = 0, bj = 0;
  if (!options.initial_bound) {
    FarthestPair(e).search(best2, bi, bj, r.distance_evaluations);
  } else {
    lower_bound(e, best2, bi, bj, r.distance_evaluations);
    r.initial_bound = std::sqrt(best2);
    // A point can only be in a pair longer than the bound if the farthest corner of the set's
    // bounding box is farther from it than the bound: most points of a smooth map are not, and
    // the tree is built on the rest (same monotone-rounding argument as the box bound).
    Vec3 lo = e[0], hi = e[0];
    for (const Vec3& v : e) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    std::vector<Vec3> candidates;
    std::vector<std::size_t> index;
    for (std::size_t i = 0; i < n; ++i) {
      double far2 = 0.0;
      for (int d = 0; d < 3; ++d) {
        const double w = std::max(e[i][d] - lo[d], hi[d] - e[i][d]);
        far2 += w * w;
      }
      if (far2 > best2) candidates.push_back(e[i]), index.push_back(i);
    }
    std::size_t ci = 0, cj = 0;
    const double before = best2;
    FarthestPair(candidates).search(best2, ci, cj, r.distance_evaluations);
    if (best2 > before) bi = index[ci], bj = index[cj];
  }
  r.va = {std::sqrt(best2), std::min(bi, bj), std::max(bi, bj)};
  return r;
}

GroupingResult fletcher_grouping(std::span<const Vec3> e, const GroupingOptions& o) {
  if (!std::isfinite(o.angle_tolerance) || o.angle_tolerance < 1e-6 || o.angle_tolerance > 6)
    throw InputError({"group angle", 0, ""},
                     fmt::format("expected a tolerance between 1e-6 and 6 (a sum of unit-vector component "
                                 "differences), found {:g}",
                                 o.angle_tolerance));
  if (!std::isfinite(o.magnitude_tolerance) || o.magnitude_tolerance < 0 || o.magnitude_tolerance > 1)
    throw InputError({"group magnitude", 0, ""},
                     fmt::format("expected a fraction between 0 and 1, found {:g}", o.magnitude_tolerance));
  struct Group {
    Vec3 sum = Vec3::Zero();  // of unit directions
    double count = 0, largest = 0;
    std::uint64_t cell = 0;
    Vec3 mean() const { return sum / count; }
  };
  std::vector<Group> groups;
  std::vector<std::uint32_t> member(e.size());
  // Groups are found through a hash of their mean direction's cell (side = tolerance): a match
  // differs by at most the tolerance in each component, so it lies in one of the 27 cells around.
  const double cell = o.angle_tolerance;
  auto key = [](long ix, long iy, long iz) {
    const auto u = [](long v) { return static_cast<std::uint64_t>(v + (1L << 20)) & ((1ULL << 21) - 1); };
    return u(ix) << 42 | u(iy) << 21 | u(iz);
  };
  auto cell_of = [&](const Vec3& v) {
    return key(static_cast<long>(std::floor(v.x() / cell)), static_cast<long>(std::floor(v.y() / cell)),
               static_cast<long>(std::floor(v.z() / cell)));
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  constexpr std::uint32_t kZero = std::numeric_limits<std::uint32_t>::max();  // zero vectors: no direction
  for (std::size_t i = 0; i < e.size(); ++i) {
    const double mag = e[i].norm();
    if (mag == 0.0) {
      member[i] = kZero;
      continue;
    }
    const Vec3 u = e[i] / mag;
    std::uint32_t found = kZero;
    const long cx = static_cast<long>(std::floor(u.x() / cell)), cy = static_cast<long>(std::floor(u.y() / cell)),
               cz = static_cast<long>(std::floor(u.z() / cell));
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(key(cx + dx, cy + dy, cz + dz));
          if (it == cells.end()) continue;
          for (std::uint32_t g : it->second)
            if (g < found && (u - groups[g].mean()).lpNorm<1>() <= o.angle_tolerance) found = g;
        }
    if (found == kZero) {
      found = static_cast<std::uint32_t>(groups.size());
      groups.push_back({});
      groups.back().cell = cell_of(u);
      cells[groups.back().cell].push_back(found);
    }
    Group& g = groups[found];
    g.sum += u;
    g.count += 1;
    g.largest = std::max(g.largest, mag);
    const std::uint64_t now = cell_of(g.mean());
    if (now != g.cell) {
      auto& old = cells[g.cell];
      old.erase(std::find(old.begin(), old.end(), found));
      cells[now].push_back(found);
      g.cell = now;
    }
    member[i] = found;
  }
  GroupingResult r;
  r.groups = groups.size() + (std::find(member.begin(), member.end(), kZero) != member.end() ? 1 : 0);
  std::vector<Vec3> kept;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const double largest = member[i] == kZero ? 0.0 : groups[member[i]].largest;
    if (e[i].norm() >= o.magnitude_tolerance * largest) {
      r.kept.push_back(i);
      kept.push_back(e[i]);
    }
  }
  const double k = static_cast<double>(kept.size());
  r.comparisons = 0.5 * k * (k > 0 ? k - 1 : 0);
  const auto va = volumetric_accuracy(kept);
  if (!kept.empty()) r.va = {va.va.value, r.kept[va.va.i], r.kept[va.va.j]};
  return r;
}

std::uint64_t Histogram::total() const { return std::accumulate(counts.begin(), counts.end(), std::uint64_t{0}); }

double Histogram::quantile(double p) const {
  if (!(p >= 0 && p <= 1)) throw ModelError(fmt::format("quantile: expected 0 <= p <= 1, found {:g}", p));
  const std::uint64_t n = total();
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  const double target = p * static_cast<double>(n);
  double before = 0;
  for (std::size_t b = 0; b < counts.size(); ++b) {
    const double c = static_cast<double>(counts[b]);
    if (c > 0 && before + c >= target)
      return lo + (static_cast<double>(b) + std::clamp((target - before) / c, 0.0, 1.0)) * width;
    before += c;
  }
  return lo + static_cast<double>(counts.size()) * width;
}

namespace {

// One row of the pair histogram: distances from point i to points i+1 .. n-1. The distance and
// bin loop is the vectorisable part; the counting is scalar over 4 interleaved copies of the
// histogram so that equal consecutive bins do not wait on each other.
MTCAL_KERNEL_CLONES
void pair_row(const double* x, const double* y, const double* z, std::size_t i, std::size_t n, double scale,
              std::uint32_t last, double* d, std::uint32_t* bin, std::uint64_t* counts4, std::size_t bins, double& sum,
              double& min) {
  const double xi = x[i], yi = y[i], zi = z[i];
  constexpr std::size_t kBlock = 512;
  for (std::size_t j0 = i + 1; j0 < n; j0 += kBlock) {
    const std::size_t len = std::min(kBlock, n - j0);
    for (std::size_t k = 0; k < len; ++k) {
      const double dx = x[j0 + k] - xi, dy = y[j0 + k] - yi, dz = z[j0 + k] - zi;
      const double v = std::sqrt(dx * dx + dy * dy + dz * dz);
      d[k] = v;
      // Written so that a NaN (never from finite input) still lands in a valid bin.
      const double b = v * scale;
      bin[k] = b < static_cast<double>(last) ? static_cast<std::uint32_t>(b) : last;
    }
    double s0 = 0, s1 = 0;
    std::size_t k = 0;
    for (; k + 1 < len; k += 2) {
      ++counts4[(k & 3) * bins + bin[k]];
      ++counts4[((k + 1) & 3) * bins + bin[k + 1]];
      s0 += d[k], s1 += d[k + 1];
      min = std::min(min, std::min(d[k], d[k + 1]));
    }
    if (k < len) ++counts4[(k & 3) * bins + bin[k]], s0 += d[k], min = std::min(min, d[k]);
    sum += s0 + s1;
  }
}

}  // namespace

Distribution pair_distribution(std::span<const Vec3> e, std::size_t bins, double upper, int threads) {
  if (bins == 0 || bins > 1'000'000)
    throw InputError({"histogram bins", 0, ""}, fmt::format("expected 1 to 1e6 bins, found {}", bins));
  for (const Vec3& v : e)
    if (!v.allFinite())
      throw InputError({"pair distribution", 0, ""}, "expected finite error vectors, found a non-finite one");
  const VolumetricAccuracy va = volumetric_accuracy(e);
  if (upper == 0.0) upper = va.va.value;
  if (!(upper >= va.va.value) || !std::isfinite(upper))
    throw InputError({"histogram range", 0, ""},
                     fmt::format("expected an upper bound >= the largest difference {:.9g} mm, found {:.9g}",
                                 va.va.value, upper));
  const std::size_t n = e.size();
  Distribution r;
  r.count = n < 2 ? 0 : static_cast<std::uint64_t>(n) * (n - 1) / 2;
  r.max = va.va.value;
  r.histogram.lo = 0.0;
  r.histogram.width = upper / static_cast<double>(bins);
  r.histogram.counts.assign(bins, 0);
  if (n < 2) return r;
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) x[i] = e[i].x(), y[i] = e[i].y(), z[i] = e[i].z();
  const double scale = upper > 0 ? static_cast<double>(bins) / upper : 0.0;
  // Tasks of about equal pair counts: row i holds n - 1 - i pairs.
  const std::size_t tasks = std::min<std::size_t>(n - 1, 256);
  std::vector<std::size_t> start(tasks + 1, n - 1);
  {
    const double total = static_cast<double>(r.count);
    std::size_t t = 0;
    double acc = 0;
    start[0] = 0;
    for (std::size_t i = 0; i + 1 < n && t + 1 < tasks; ++i) {
      acc += static_cast<double>(n - 1 - i);
      if (acc >= total * static_cast<double>(t + 1) / static_cast<double>(tasks)) start[++t] = i + 1;
    }
    for (std::size_t k = t + 1; k <= tasks; ++k) start[k] = n - 1;
  }
  // Each worker keeps 4 copies of the histogram: at most 1 GiB of them in all.
  const std::size_t workers =
      std::min(worker_count(threads, tasks), std::max<std::size_t>(1, (std::size_t{1} << 30) / (32 * bins)));
  std::vector<std::vector<std::uint64_t>> counts(workers, std::vector<std::uint64_t>(4 * bins, 0));
  std::vector<double> task_sum(tasks, 0.0), task_min(tasks, std::numeric_limits<double>::infinity());
  parallel_for(tasks, static_cast<int>(workers), [&](std::size_t t, std::size_t w) {
    std::vector<double> d(512);
    std::vector<std::uint32_t> bin(512);
    for (std::size_t i = start[t]; i < start[t + 1]; ++i) {
      double row = 0;
      pair_row(x.data(), y.data(), z.data(), i, n, scale, static_cast<std::uint32_t>(bins - 1), d.data(), bin.data(),
               counts[w].data(), bins, row, task_min[t]);
      task_sum[t] += row;
    }
  });
  for (const auto& c : counts)
    for (std::size_t k = 0; k < 4 * bins; ++k) r.histogram.counts[k % bins] += c[k];
  // Sums combined in task order: the mean does not depend on the thread count.
  double sum = 0;
  for (double s : task_sum) sum += s;
  r.mean = sum / static_cast<double>(r.count);
  r.min = *std::min_element(task_min.begin(), task_min.end());
  return r;
}

Distribution value_distribution(std::span<const double> values, std::size_t bins) {
  if (bins == 0 || bins > 1'000'000)
    throw InputError({"histogram bins", 0, ""}, fmt::format("expected 1 to 1e6 bins, found {}", bins));
  Distribution r;
  r.count = values.size();
  r.histogram.counts.assign(bins, 0);
  if (values.empty()) return r;
  const auto [mn, mx] = std::minmax_element(values.begin(), values.end());
  r.min = *mn, r.max = *mx;
  r.histogram.lo = r.min;
  r.histogram.width = (r.max - r.min) / static_cast<double>(bins);
  double sum = 0;
  for (double v : values) {
    sum += v;
    const double b = r.histogram.width > 0 ? (v - r.min) / r.histogram.width : 0.0;
    ++r.histogram.counts[std::min(bins - 1, static_cast<std::size_t>(b))];
  }
  r.mean = sum / static_cast<double>(values.size());
  return r;
}

std::vector<BoxVa> va_versus_box_size(const ErrorMap& map, std::span<const double> centre,
                                      std::span<const double> fractions) {
  const std::size_t n = map.axes;
  if (centre.size() != n) throw ModelError("va_versus_box_size: centre and map differ in axes");
  std::vector<double> lo(n, std::numeric_limits<double>::infinity()), hi(n, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < map.size(); ++i)
    for (std::size_t k = 0; k < n; ++k)
      lo[k] = std::min(lo[k], map.q[i * n + k]), hi[k] = std::max(hi[k], map.q[i * n + k]);
  std::vector<BoxVa> out;
  for (double f : fractions) {
    if (!(f > 0 && f <= 1))
      throw InputError({"box fractions", 0, ""}, fmt::format("expected fractions in (0, 1], found {:g}", f));
    BoxVa b;
    b.fraction = f;
    b.lo.resize(n), b.hi.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const double half = 0.5 * f * (hi[k] - lo[k]);
      b.lo[k] = std::max(lo[k], centre[k] - half);
      b.hi[k] = std::min(hi[k], centre[k] + half);
    }
    std::vector<std::size_t> index;
    std::vector<Vec3> e;
    for (std::size_t i = 0; i < map.size(); ++i) {
      bool inside = true;
      for (std::size_t k = 0; k < n && inside; ++k) inside = map.q[i * n + k] >= b.lo[k] && map.q[i * n + k] <= b.hi[k];
      if (inside) index.push_back(i), e.push_back(map.error[i]);
    }
    b.points = e.size();
    const auto va = volumetric_accuracy(e);
    if (!e.empty()) b.va = {va.va.value, index[va.va.i], index[va.va.j]};
    out.push_back(std::move(b));
  }
  return out;
}

}  // namespace mtcal
