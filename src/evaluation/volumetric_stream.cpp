// Streamed volumetric studies: the exact VA, component ranges, distributions, boxes and
// contributions of a map that is never held, in two evaluation passes over its configurations.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "mtcal/evaluation/volumetric_study.hpp"
#include "what_if.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::size_t kNone = static_cast<std::size_t>(-1);

// The 13 directions of volumetric_accuracy's first bound (axes, face and body diagonals).
constexpr double kDirs[13][3] = {{1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
                                 {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};

struct Extreme {
  double value = 0.0;
  std::size_t index = kNone;
  Vec3 e = Vec3::Zero();
};

// First pass over a set of error vectors (arriving in index order): the component extremes, the
// extremes along 13 directions, the largest distance from a centre chosen before the pass, and
// the magnitudes' range. The first index of an extreme wins, as in volumetric_accuracy.
struct FirstPass {
  std::size_t count = 0, first = kNone;
  Extreme lo[3], hi[3], dlo[13], dhi[13];
  double r2 = 0.0;  // largest |e - centre|^2
  double mlo = kInf, mhi = -kInf;

  void add(std::size_t i, const Vec3& e, const Vec3& centre, bool magnitudes) {
    if (count++ == 0) {
      first = i;
      for (int c = 0; c < 3; ++c) lo[c] = hi[c] = {e[c], i, e};
      for (int d = 0; d < 13; ++d) {
        const double v = kDirs[d][0] * e.x() + kDirs[d][1] * e.y() + kDirs[d][2] * e.z();
        dlo[d] = dhi[d] = {v, i, e};
      }
    } else {
      for (int c = 0; c < 3; ++c) {
        if (e[c] < lo[c].value) lo[c] = {e[c], i, e};
        if (e[c] > hi[c].value) hi[c] = {e[c], i, e};
      }
      for (int d = 0; d < 13; ++d) {
        const double v = kDirs[d][0] * e.x() + kDirs[d][1] * e.y() + kDirs[d][2] * e.z();
        if (v < dlo[d].value) dlo[d] = {v, i, e};
        if (v > dhi[d].value) dhi[d] = {v, i, e};
      }
    }
    r2 = std::max(r2, (e - centre).squaredNorm());
    if (magnitudes) {
      const double m = e.norm();
      mlo = std::min(mlo, m), mhi = std::max(mhi, m);
    }
  }
  // b holds later indices than *this.
  void merge(const FirstPass& b) {
    if (b.count == 0) return;
    if (count == 0) {
      *this = b;
      return;
    }
    count += b.count;
    for (int c = 0; c < 3; ++c) {
      if (b.lo[c].value < lo[c].value) lo[c] = b.lo[c];
      if (b.hi[c].value > hi[c].value) hi[c] = b.hi[c];
    }
    for (int d = 0; d < 13; ++d) {
      if (b.dlo[d].value < dlo[d].value) dlo[d] = b.dlo[d];
      if (b.dhi[d].value > dhi[d].value) dhi[d] = b.dhi[d];
    }
    r2 = std::max(r2, b.r2);
    mlo = std::min(mlo, b.mlo), mhi = std::max(mhi, b.mhi);
  }
};

// The filter of the second pass: a vector can be an end of a pair at least as long as the lower
// bound lb (a pair of the first pass's extremes) only if the farthest corner of the set's
// bounding box, and the sphere of radius R about the centre, reach that far from it
// (|e - p| <= |e - c| + |c - p| <= |e - c| + R). The margin (1e-9 relative) covers the rounding
// of these bounds, so that no vector of a longest pair is ever dropped.
struct Filter {
  Vec3 lo, hi, centre;
  double r = 0.0, lb2 = 0.0;
  bool all_equal = true;

  bool keep(const Vec3& e) const {
    double far2 = 0.0;
    for (int d = 0; d < 3; ++d) {
      const double w = std::max(e[d] - lo[d], hi[d] - e[d]);
      far2 += w * w;
    }
    if (far2 < lb2 * (1 - 1e-9)) return false;
    const double s = std::sqrt((e - centre).squaredNorm()) + r;
    return s * s >= lb2 * (1 - 1e-9);
  }
};

Filter make_filter(const FirstPass& p, const Vec3& centre) {
  Filter f;
  f.centre = centre;
  if (p.count == 0) return f;
  for (int c = 0; c < 3; ++c) f.lo[c] = p.lo[c].value, f.hi[c] = p.hi[c].value;
  f.all_equal = f.lo == f.hi;
  f.r = std::sqrt(p.r2);
  // The longest pair among the extremes.
  std::vector<Extreme> ext;
  for (int d = 0; d < 13; ++d) ext.push_back(p.dlo[d]), ext.push_back(p.dhi[d]);
  for (std::size_t a = 0; a < ext.size(); ++a)
    for (std::size_t b = a + 1; b < ext.size(); ++b) f.lb2 = std::max(f.lb2, (ext[a].e - ext[b].e).squaredNorm());
  return f;
}

// Second-pass state of one set: the candidates (index order) and the magnitude histogram.
struct SecondPass {
  std::vector<Vec3> e;
  std::vector<std::size_t> index;
};

// A set of the map: the whole map, the box, or a box of the scan.
struct Set {
  bool whole = true;
  std::vector<double> lo, hi;  // joint box (internal units), when not whole
  Vec3 centre = Vec3::Zero();
  FirstPass p1;
  Filter filter;
  SecondPass p2;
  bool inside(const double* q) const {
    if (whole) return true;
    for (std::size_t k = 0; k < lo.size(); ++k)
      if (!(q[k] >= lo[k] && q[k] <= hi[k])) return false;
    return true;
  }
};

// The exact VA of a set from its two passes (indices into the source), the numbers of
// volumetric_accuracy on the set's vectors.
VolumetricAccuracy finish(const Set& s, std::uint64_t* evaluations = nullptr) {
  VolumetricAccuracy r;
  const std::size_t n = s.p1.count;
  r.points = n;
  r.pairs = 0.5 * static_cast<double>(n) * (n > 0 ? static_cast<double>(n - 1) : 0.0);
  if (n < 2) {
    if (n == 1) r.va = {0.0, s.p1.first, s.p1.first};
    return r;
  }
  for (int c = 0; c < 3; ++c)
    r.component[static_cast<std::size_t>(c)] = {s.p1.hi[c].value - s.p1.lo[c].value, s.p1.lo[c].index,
                                                s.p1.hi[c].index};
  r.initial_bound = std::sqrt(s.filter.lb2);
  if (s.filter.all_equal) {
    r.va = {0.0, s.p1.first, s.p1.first};
    return r;
  }
  const VolumetricAccuracy c = volumetric_accuracy(s.p2.e);
  r.distance_evaluations = c.distance_evaluations;
  if (evaluations) *evaluations += c.distance_evaluations;
  const std::size_t i = s.p2.index[c.va.i], j = s.p2.index[c.va.j];
  r.va = {c.va.value, std::min(i, j), std::max(i, j)};
  return r;
}

// Evenly spaced configurations of the source, evaluated: the sets' centres (the middle of the
// sample's bounding box of errors; any centre gives the same answer, a central one fewer
// candidates).
void choose_centres(const ErrorModel& model, const ConfigurationSource& source, std::vector<Set>& sets, int threads) {
  const std::size_t count = source.size(), n = source.axes(), samples = std::min<std::size_t>(count, 4096);
  if (samples == 0) return;
  std::vector<double> q(samples * n), res(samples * 6);
  std::vector<std::int8_t> dir(source.has_directions() ? samples * n : 0);
  for (std::size_t k = 0; k < samples; ++k)
    source.fill(k * count / samples, &q[k * n], dir.empty() ? nullptr : &dir[k * n]);
  model.evaluate_batch(q, dir, res, {threads});
  Vec3 all_lo = Vec3::Constant(kInf), all_hi = Vec3::Constant(-kInf);
  for (std::size_t k = 0; k < samples; ++k) {
    const Vec3 e(res[k * 6], res[k * 6 + 1], res[k * 6 + 2]);
    if (!e.allFinite()) continue;
    all_lo = all_lo.cwiseMin(e), all_hi = all_hi.cwiseMax(e);
  }
  const Vec3 all = all_lo.allFinite() ? Vec3(0.5 * (all_lo + all_hi)) : Vec3::Zero();
  for (auto& s : sets) {
    Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
    for (std::size_t k = 0; k < samples; ++k) {
      const Vec3 e(res[k * 6], res[k * 6 + 1], res[k * 6 + 2]);
      if (e.allFinite() && s.inside(&q[k * n])) lo = lo.cwiseMin(e), hi = hi.cwiseMax(e);
    }
    s.centre = lo.allFinite() ? Vec3(0.5 * (lo + hi)) : all;
  }
}

struct StreamWork {
  const ErrorModel& model;
  const ConfigurationSource& source;
  const StreamOptions& options;
  std::size_t passes_done = 0, passes_total = 1;
};

// One evaluation pass; per_chunk(chunk) is called in order.
// Below this many configurations a pass runs on the calling thread: starting and joining
// workers several times a chunk would cost more than the work (the correction sequence streams
// hundreds of small maps).
constexpr std::size_t kParallelFrom = std::size_t{1} << 16;
int threads_for(const StreamOptions& o, std::size_t count) { return count < kParallelFrom ? 1 : o.threads; }

void pass(StreamWork& w, const std::function<void(const ErrorChunk&)>& per_chunk) {
  StreamOptions so = w.options;
  so.threads = threads_for(w.options, w.source.size());
  so.chunk = std::min<std::size_t>(so.chunk, std::size_t{1} << 18);
  const std::size_t count = w.source.size();
  if (w.options.progress) {
    const std::size_t before = w.passes_done * count, total = w.passes_total * count;
    so.progress = [&w, before, total](std::size_t done, std::size_t) { w.options.progress(before + done, total); };
  }
  evaluate_stream(w.model, w.source, per_chunk, so);
  ++w.passes_done;
}

std::size_t slices_of(std::size_t len) { return std::min<std::size_t>(64, std::max<std::size_t>(1, len / 4096)); }

// The two passes over a list of sets. magnitudes: the magnitude distribution of set 0 (bins);
// keep: every error vector of the map (for the pair histogram and the grouping).
struct TwoPassResult {
  std::optional<Distribution> magnitudes;
  std::vector<Vec3> all;
  std::map<std::size_t, Vec3> samples;  // every stride-th configuration's error
};
TwoPassResult two_passes(StreamWork& w, std::vector<Set>& sets, std::size_t magnitude_bins, bool keep_all,
                         std::size_t sample_stride, const std::function<void(const ErrorChunk&)>& observe) {
  TwoPassResult out;
  const int threads = threads_for(w.options, w.source.size());
  const bool mags = magnitude_bins > 0;
  if (keep_all) out.all.reserve(w.source.size());
  pass(w, [&](const ErrorChunk& c) {
    if (observe) observe(c);
    const std::size_t len = c.size(), slices = slices_of(len), n = c.axes;
    std::vector<std::vector<FirstPass>> part(slices, std::vector<FirstPass>(sets.size()));
    const std::size_t per = len / slices, extra = len % slices;
    parallel_for(slices, threads, [&](std::size_t t, std::size_t) {
      const std::size_t b = t * per + std::min(t, extra), e = b + per + (t < extra ? 1 : 0);
      for (std::size_t r = b; r < e; ++r) {
        const Vec3 v(c.error[r * 6], c.error[r * 6 + 1], c.error[r * 6 + 2]);
        for (std::size_t k = 0; k < sets.size(); ++k)
          if (sets[k].inside(&c.q[r * n])) part[t][k].add(c.first + r, v, sets[k].centre, mags && k == 0);
      }
    });
    for (std::size_t t = 0; t < slices; ++t)
      for (std::size_t k = 0; k < sets.size(); ++k) sets[k].p1.merge(part[t][k]);
    for (std::size_t r = 0; r < len; ++r) {
      const std::size_t i = c.first + r;
      const Vec3 v(c.error[r * 6], c.error[r * 6 + 1], c.error[r * 6 + 2]);
      if (keep_all) out.all.push_back(v);
      if (sample_stride && i % sample_stride == 0) out.samples.emplace(i, v);
    }
  });
  for (auto& s : sets) s.filter = make_filter(s.p1, s.centre);
  // The magnitude histogram: value_distribution's bins over [min, max] and its sum in index order.
  Distribution md;
  double msum = 0;
  if (mags) {
    md.count = sets[0].p1.count;
    md.histogram.counts.assign(magnitude_bins, 0);
    if (md.count) {
      md.min = sets[0].p1.mlo, md.max = sets[0].p1.mhi;
      md.histogram.lo = md.min;
      md.histogram.width = (md.max - md.min) / static_cast<double>(magnitude_bins);
    }
  }
  bool need_second = mags;
  for (const auto& s : sets) need_second = need_second || (s.p1.count >= 2 && !s.filter.all_equal);
  if (need_second) {
    const std::size_t workers = worker_count(threads, 64);
    std::vector<std::vector<std::uint64_t>> counts(mags ? workers : 0, std::vector<std::uint64_t>(magnitude_bins));
    std::vector<double> m;
    pass(w, [&](const ErrorChunk& c) {
      const std::size_t len = c.size(), slices = slices_of(len), n = c.axes;
      const std::size_t per = len / slices, extra = len % slices;
      std::vector<std::vector<SecondPass>> part(slices, std::vector<SecondPass>(sets.size()));
      if (mags) m.resize(len);
      parallel_for(slices, threads, [&](std::size_t t, std::size_t worker) {
        const std::size_t b = t * per + std::min(t, extra), e = b + per + (t < extra ? 1 : 0);
        for (std::size_t r = b; r < e; ++r) {
          const Vec3 v(c.error[r * 6], c.error[r * 6 + 1], c.error[r * 6 + 2]);
          for (std::size_t k = 0; k < sets.size(); ++k) {
            const Set& s = sets[k];
            if (s.p1.count < 2 || s.filter.all_equal || !s.inside(&c.q[r * n]) || !s.filter.keep(v)) continue;
            part[t][k].e.push_back(v);
            part[t][k].index.push_back(c.first + r);
          }
          if (mags) {
            const double x = v.norm();
            m[r] = x;
            const double bin = md.histogram.width > 0 ? (x - md.min) / md.histogram.width : 0.0;
            ++counts[worker][std::min(magnitude_bins - 1, static_cast<std::size_t>(bin))];
          }
        }
      });
      for (std::size_t t = 0; t < slices; ++t)
        for (std::size_t k = 0; k < sets.size(); ++k) {
          auto& to = sets[k].p2;
          to.e.insert(to.e.end(), part[t][k].e.begin(), part[t][k].e.end());
          to.index.insert(to.index.end(), part[t][k].index.begin(), part[t][k].index.end());
        }
      for (std::size_t r = 0; r < (mags ? len : 0); ++r) msum += m[r];
    });
    for (const auto& cw : counts)
      for (std::size_t b = 0; b < magnitude_bins; ++b) md.histogram.counts[b] += cw[b];
  }
  if (mags) {
    if (md.count) md.mean = msum / static_cast<double>(md.count);
    out.magnitudes = md;
  }
  return out;
}

// The joint bounding box of the source's configurations.
void joint_range(const ConfigurationSource& source, std::vector<double>& lo, std::vector<double>& hi) {
  const std::size_t n = source.axes();
  lo.assign(n, kInf), hi.assign(n, -kInf);
  if (const GridValues* g = source.grid_values()) {
    for (std::size_t k = 0; k < n; ++k)
      for (double v : (*g)[k]) lo[k] = std::min(lo[k], v), hi[k] = std::max(hi[k], v);
    return;
  }
  std::vector<double> q(n);
  for (std::size_t i = 0; i < source.size(); ++i) {
    source.fill(i, q.data(), nullptr);
    for (std::size_t k = 0; k < n; ++k) lo[k] = std::min(lo[k], q[k]), hi[k] = std::max(hi[k], q[k]);
  }
}

// The held map: the sampled configurations first, then every other one referred to.
struct Held {
  ErrorMap map;
  std::map<std::size_t, std::size_t> at;  // source index -> index into map
  std::size_t operator()(std::size_t i) const { return at.at(i); }
};
Held hold(const ConfigurationSource& source, const std::map<std::size_t, Vec3>& samples,
          const std::map<std::size_t, Vec3>& others) {
  Held h;
  const std::size_t n = source.axes();
  h.map.axes = n;
  auto add = [&](std::size_t i, const Vec3& e) {
    if (h.at.count(i)) return;
    h.at[i] = h.map.error.size();
    h.map.q.resize(h.map.q.size() + n);
    if (source.has_directions()) h.map.dir.resize(h.map.dir.size() + n);
    source.fill(i, &h.map.q[h.map.q.size() - n], source.has_directions() ? &h.map.dir[h.map.dir.size() - n] : nullptr);
    h.map.error.push_back(e);
  };
  for (const auto& [i, e] : samples) add(i, e);
  for (const auto& [i, e] : others) add(i, e);
  return h;
}

void note(std::map<std::size_t, Vec3>& known, const Set& s, const PointPair& p) {
  auto find = [&](std::size_t i) -> Vec3 {
    for (int c = 0; c < 3; ++c) {
      if (s.p1.lo[c].index == i) return s.p1.lo[c].e;
      if (s.p1.hi[c].index == i) return s.p1.hi[c].e;
    }
    const auto it = std::lower_bound(s.p2.index.begin(), s.p2.index.end(), i);
    if (it != s.p2.index.end() && *it == i) return s.p2.e[static_cast<std::size_t>(it - s.p2.index.begin())];
    for (int d = 0; d < 13; ++d) {
      if (s.p1.dlo[d].index == i) return s.p1.dlo[d].e;
      if (s.p1.dhi[d].index == i) return s.p1.dhi[d].e;
    }
    throw ModelError(fmt::format("streamed study: configuration {} is not held", i));
  };
  known.emplace(p.i, find(p.i));
  known.emplace(p.j, find(p.j));
}

PointPair remap(const Held& h, const PointPair& p) { return {p.value, h(p.i), h(p.j)}; }
VolumetricAccuracy remap(const Held& h, VolumetricAccuracy va) {
  if (va.points == 0) return va;
  va.va = remap(h, va.va);
  if (va.points >= 2)
    for (auto& c : va.component) c = remap(h, c);
  return va;
}

}  // namespace

std::size_t study_passes(const VolumetricRequest& request) {
  // Two passes (the boxes of a scan ride along as sets of the same passes).
  (void)request;
  return 2;
}

StreamedStudy study_volumetric(const Machine& m, const ErrorModel& model, const ConfigurationSource& source,
                               const VolumetricRequest& request, const StreamOptions& options,
                               const std::function<void(const ErrorChunk&)>& observe) {
  const std::size_t count = source.size(), n = source.axes();
  const double pairs = 0.5 * static_cast<double>(count) * (count > 0 ? static_cast<double>(count - 1) : 0.0);
  if (request.histogram && pairs > kMaxHistogramPairs)
    throw InputError({"histogram", 0, ""},
                     fmt::format("{:.3g} pairs would take minutes (limit {:.0e}); use a coarser grid or fewer points",
                                 pairs, kMaxHistogramPairs));
  if (count > std::numeric_limits<std::uint32_t>::max())
    throw InputError({"volumetric accuracy", 0, ""}, fmt::format("at most 4294967295 points, found {}", count));
  std::vector<Set> sets(1);
  std::size_t box_set = 0, scan_first = 0;
  if (request.box) {
    if (request.box->lo.size() != n || request.box->hi.size() != n)
      throw ModelError("sub_map: box and map differ in axes");
    box_set = sets.size();
    Set s;
    s.whole = false, s.lo = request.box->lo, s.hi = request.box->hi;
    sets.push_back(s);
  }
  std::vector<double> fractions;
  if (request.box_scan > 0) {
    std::vector<double> lo, hi;
    joint_range(source, lo, hi);
    std::vector<double> centre(n);
    if (request.centre) {
      if (request.centre->size() != n) throw ModelError("va_versus_box_size: centre and map differ in axes");
      centre = *request.centre;
    } else {
      for (std::size_t k = 0; k < n; ++k) centre[k] = 0.5 * (lo[k] + hi[k]);
    }
    scan_first = sets.size();
    for (int k = 1; k <= request.box_scan; ++k) {
      const double f = static_cast<double>(k) / request.box_scan;
      fractions.push_back(f);
      Set s;
      s.whole = false;
      s.lo.resize(n), s.hi.resize(n);
      for (std::size_t a = 0; a < n; ++a) {
        const double half = 0.5 * f * (hi[a] - lo[a]);
        s.lo[a] = std::max(lo[a], centre[a] - half);
        s.hi[a] = std::min(hi[a], centre[a] + half);
      }
      sets.push_back(s);
    }
  }
  choose_centres(model, source, sets, threads_for(options, count));
  StreamWork w{model, source, options, 0, study_passes(request)};
  const std::size_t mag_bins =
      request.histogram ? (request.histogram_bins ? request.histogram_bins : rice_bins(static_cast<double>(count))) : 0;
  const std::size_t stride = std::max<std::size_t>(1, (count + kMapSamples - 1) / kMapSamples);
  TwoPassResult tp = two_passes(w, sets, mag_bins, request.histogram || request.grouping.has_value(), stride, observe);

  StreamedStudy out;
  VolumetricStudy& s = out.study;
  auto t1 = Clock::now();
  std::map<std::size_t, Vec3> known;
  const VolumetricAccuracy va = finish(sets[0]);
  s.seconds_va = seconds_since(t1);
  s.candidates = sets[0].p2.e.size();
  note(known, sets[0], va.va);
  for (const auto& c : va.component) note(known, sets[0], c);
  std::optional<VolumetricAccuracy> box_va;
  if (request.box) {
    if (sets[box_set].p1.count == 0)
      throw InputError({"box", 0, ""}, "no configuration of the map lies inside the box");
    box_va = finish(sets[box_set]);
    note(known, sets[box_set], box_va->va);
    if (box_va->points >= 2)
      for (const auto& c : box_va->component) note(known, sets[box_set], c);
  }
  std::vector<BoxVa> scan;
  for (std::size_t k = 0; k < fractions.size(); ++k) {
    const Set& set = sets[scan_first + k];
    BoxVa b;
    b.fraction = fractions[k];
    b.lo = set.lo, b.hi = set.hi;
    b.points = set.p1.count;
    if (b.points) {
      b.va = finish(set).va;
      note(known, set, b.va);
    }
    scan.push_back(std::move(b));
  }
  if (request.histogram) {
    const std::size_t bins = request.histogram_bins ? request.histogram_bins : rice_bins(va.pairs);
    t1 = Clock::now();
    s.pairs = pair_distribution(tp.all, bins, va.va.value, request.threads);
    s.seconds_histogram = seconds_since(t1);
    s.magnitudes = tp.magnitudes;
  }
  if (request.grouping) {
    GroupingComparison g;
    g.options = *request.grouping;
    g.result = fletcher_grouping(tp.all, g.options);
    g.difference_percent = va.va.value > 0 ? 100 * (g.result.va.value - va.va.value) / va.va.value : 0.0;
    g.comparison_reduction_percent = va.pairs > 0 ? 100 * (1 - g.result.comparisons / va.pairs) : 0.0;
    if (!g.result.kept.empty()) {
      known.emplace(g.result.va.i, tp.all[g.result.va.i]);
      known.emplace(g.result.va.j, tp.all[g.result.va.j]);
    }
    s.grouping = g;
  }
  const Held held = hold(source, tp.samples, known);
  s.va = remap(held, va);
  if (box_va) {
    s.box = request.box;
    s.box_va = remap(held, *box_va);
  }
  for (auto& b : scan)
    if (b.points) b.va = remap(held, b.va);
  s.scan = std::move(scan);
  if (s.grouping && !s.grouping->result.kept.empty()) s.grouping->result.va = remap(held, s.grouping->result.va);
  s.map_points = count;
  s.sample_points = tp.samples.size();
  out.map = held.map;
  if (box_va) s.box_map = out.map;
  if (count >= 1)
    s.critical = contributions(m, out.map.configuration(s.va.va.j), out.map.direction(s.va.va.j),
                               std::optional<std::span<const double>>(out.map.configuration(s.va.va.i)),
                               out.map.direction(s.va.va.i));
  return out;
}

namespace {

// The exact VA of a source with the two vectors of its critical pair.
struct StreamedVa {
  VolumetricAccuracy va;
  Vec3 ei, ej;
};
StreamedVa streamed_va(const ErrorModel& model, const ConfigurationSource& source, const StreamOptions& options) {
  StreamedVa r;
  if (source.size() < kParallelFrom) {
    // A small map is held (at most 1.5 MB of vectors): one pass instead of three.
    std::vector<Vec3> all;
    all.reserve(source.size());
    StreamWork w{model, source, options, 0, 1};
    pass(w, [&](const ErrorChunk& c) {
      for (std::size_t k = 0; k < c.size(); ++k)
        all.emplace_back(c.error[k * 6], c.error[k * 6 + 1], c.error[k * 6 + 2]);
    });
    r.va = volumetric_accuracy(all);
    r.ei = all[r.va.va.i], r.ej = all[r.va.va.j];
    return r;
  }
  std::vector<Set> sets(1);
  choose_centres(model, source, sets, threads_for(options, source.size()));
  StreamWork w{model, source, options, 0, 2};
  two_passes(w, sets, 0, false, 0, {});
  r.va = finish(sets[0]);
  std::map<std::size_t, Vec3> known;
  note(known, sets[0], r.va.va);
  r.ei = known.at(r.va.va.i), r.ej = known.at(r.va.va.j);
  return r;
}

std::vector<double> configuration(const ConfigurationSource& source, std::size_t i, std::vector<std::int8_t>* dir) {
  std::vector<double> q(source.axes());
  if (dir) dir->assign(source.has_directions() ? source.axes() : 0, 0);
  source.fill(i, q.data(), dir && source.has_directions() ? dir->data() : nullptr);
  return q;
}

// Progress over several streamed maps: map k of `maps` reports its own passes as a part of all.
StreamOptions part_of(const StreamOptions& o, std::size_t k, std::size_t maps) {
  StreamOptions p = o;
  if (o.progress)
    p.progress = [&o, k, maps](std::size_t done, std::size_t total) { o.progress(k * total + done, maps * total); };
  return p;
}

}  // namespace

VolumetricAccuracy streamed_volumetric_accuracy(const ErrorModel& model, const ConfigurationSource& source,
                                                const StreamOptions& options) {
  return streamed_va(model, source, options).va;
}

ContributionStudy critical_pair_contributions(const Machine& m, const ConfigurationSource& source, bool what_if,
                                              const StreamOptions& options, std::optional<double> target_va) {
  if (source.size() == 0) throw InputError({"map", 0, ""}, "expected at least one configuration, found none");
  const std::vector<ErrorName> errors = what_if ? nonzero_errors(m) : std::vector<ErrorName>{};
  const std::size_t maps = 1 + errors.size();
  ContributionStudy s;
  s.mode = "critical_pair";
  const ErrorModel model(m);
  s.va = streamed_va(model, source, part_of(options, 0, maps)).va;
  s.b = configuration(source, s.va->va.i, nullptr);
  s.a = configuration(source, s.va->va.j, nullptr);
  {
    std::vector<std::int8_t> d;
    configuration(source, s.va->va.i, &d), s.dir_b = d;
    configuration(source, s.va->va.j, &d), s.dir_a = d;
  }
  s.what_if_asked = what_if;
  s.analysis = contributions(m, s.a, s.dir_a, std::optional<std::span<const double>>(s.b), s.dir_b);
  for (std::size_t k = 0; k < errors.size(); ++k) {
    const ErrorName& e = errors[k];
    const ErrorModel without(without_error(m, e));
    const auto va = streamed_va(without, source, part_of(options, k + 1, maps)).va.va;
    WhatIf w;
    w.error = e;
    w.va = va.value;
    std::vector<std::int8_t> di, dj;
    w.from = configuration(source, va.i, &di);
    w.to = configuration(source, va.j, &dj);
    for (const auto& c : s.analysis.items)
      if (c.error == e) w.share = c.share;
    const double full = s.va->va.value;
    w.disagrees = (w.share > 0 && w.va > full) || (w.share <= 0 && w.va < full);
    if (w.disagrees) {
      const auto there = contributions(m, w.to, dj, std::optional<std::span<const double>>(w.from), di);
      detail::explain_disagreement(w, there);
    }
    s.what_if.push_back(w);
  }
  std::stable_sort(s.what_if.begin(), s.what_if.end(), [](const WhatIf& x, const WhatIf& y) { return x.va < y.va; });
  if (target_va) {
    if (!std::isfinite(*target_va) || *target_va < 0)
      throw InputError({"target VA", 0, ""}, fmt::format("expected a VA >= 0 in mm, found {}", *target_va));
    CorrectionSequence seq;
    seq.target = *target_va;
    seq.start = s.va->va.value;
    double va = seq.start;
    Machine current = m;
    std::vector<ErrorName> left = nonzero_errors(m);
    while (va > *target_va && !left.empty()) {
      std::size_t best = 0;
      double best_va = INFINITY;
      for (std::size_t k = 0; k < left.size(); ++k) {
        const ErrorModel without(without_error(current, left[k]));
        StreamOptions quiet = options;
        quiet.progress = {};
        const double v = streamed_va(without, source, quiet).va.va.value;
        if (v < best_va) best_va = v, best = k;
      }
      current = without_error(current, left[best]);
      seq.steps.push_back({left[best], best_va});
      va = best_va;
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(best));
    }
    seq.reached = va <= *target_va;
    s.sequence = seq;
  }
  return s;
}

}  // namespace mtcal
