#include "mtcal/evaluation/volumetric_study.hpp"
#include "what_if.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::vector<double> configuration_at(const ErrorMap& map, std::size_t i) {
  const auto q = map.configuration(i);
  return {q.begin(), q.end()};
}

// The middle of the map's bounding box of joint values.
std::vector<double> map_centre(const ErrorMap& map) {
  std::vector<double> centre(map.axes);
  for (std::size_t k = 0; k < map.axes; ++k) {
    double lo = INFINITY, hi = -INFINITY;
    for (std::size_t i = 0; i < map.size(); ++i)
      lo = std::min(lo, map.q[i * map.axes + k]), hi = std::max(hi, map.q[i * map.axes + k]);
    centre[k] = 0.5 * (lo + hi);
  }
  return centre;
}

}  // namespace

ErrorMap error_map(const ErrorModel& model, ConfigurationList list, const std::string& where,
                   const BatchOptions& options) {
  if (list.q.empty()) throw InputError({where, 0, ""}, "expected at least one configuration, found none");
  return error_map(model, std::move(list.q), list.dir, options);
}

std::size_t rice_bins(double count) {
  return static_cast<std::size_t>(std::clamp(std::ceil(2.0 * std::cbrt(count)), 10.0, 200.0));
}

VolumetricStudy study_volumetric(const Machine& m, const ErrorMap& map, const VolumetricRequest& request) {
  VolumetricStudy s;
  auto t0 = Clock::now();
  s.va = volumetric_accuracy(map.error);
  s.seconds_va = seconds_since(t0);
  const VolumetricAccuracy& va = s.va;
  s.critical =
      contributions(m, map.configuration(va.va.j), map.direction(va.va.j),
                    std::optional<std::span<const double>>(map.configuration(va.va.i)), map.direction(va.va.i));

  // Reduced volume.
  if (request.box) {
    s.box = request.box;
    s.box_map = sub_map(map, s.box->lo, s.box->hi);
    if (s.box_map->size() == 0) throw InputError({"box", 0, ""}, "no configuration of the map lies inside the box");
    s.box_va = volumetric_accuracy(s.box_map->error);
  }
  if (request.box_scan > 0) {
    const std::vector<double> centre = request.centre ? *request.centre : map_centre(map);
    std::vector<double> fractions;
    for (int k = 1; k <= request.box_scan; ++k) fractions.push_back(static_cast<double>(k) / request.box_scan);
    s.scan = va_versus_box_size(map, centre, fractions);
  }
  if (request.histogram) {
    if (va.pairs > kMaxHistogramPairs)
      throw InputError({"histogram", 0, ""},
                       fmt::format("{:.3g} pairs would take minutes (limit {:.0e}); use a coarser grid or fewer points",
                                   va.pairs, kMaxHistogramPairs));
    const std::size_t bins = request.histogram_bins ? request.histogram_bins : rice_bins(va.pairs);
    t0 = Clock::now();
    s.pairs = pair_distribution(map.error, bins, va.va.value, request.threads);
    s.seconds_histogram = seconds_since(t0);
    std::vector<double> mags(map.size());
    for (std::size_t i = 0; i < map.size(); ++i) mags[i] = map.error[i].norm();
    // Rice's rule sizes each histogram for its own count (the errors are far fewer than their pairs).
    s.magnitudes = value_distribution(mags, request.histogram_bins ? bins : rice_bins(static_cast<double>(map.size())));
  }
  if (request.grouping) {
    GroupingComparison g;
    g.options = *request.grouping;
    g.result = fletcher_grouping(map.error, g.options);
    g.difference_percent = va.va.value > 0 ? 100 * (g.result.va.value - va.va.value) / va.va.value : 0.0;
    g.comparison_reduction_percent = va.pairs > 0 ? 100 * (1 - g.result.comparisons / va.pairs) : 0.0;
    s.grouping = g;
  }
  return s;
}

ContributionStudy contributions_at(const Machine& m, std::vector<double> a) {
  ContributionStudy s;
  s.mode = "at";
  s.a = std::move(a);
  s.analysis = contributions(m, s.a);
  return s;
}

ContributionStudy contributions_between(const Machine& m, std::vector<double> from, std::vector<double> to) {
  ContributionStudy s;
  s.mode = "pair";
  s.a = std::move(to);
  s.b = std::move(from);
  s.analysis = contributions(m, s.a, {}, std::optional<std::span<const double>>(s.b), {});
  return s;
}

ContributionStudy critical_pair_contributions(const Machine& m, const ErrorMap& map, bool what_if, int threads,
                                              std::optional<double> target_va) {
  ContributionStudy s;
  s.mode = "critical_pair";
  s.va = volumetric_accuracy(map.error);
  s.b = configuration_at(map, s.va->va.i);
  s.a = configuration_at(map, s.va->va.j);
  s.dir_b.assign(map.direction(s.va->va.i).begin(), map.direction(s.va->va.i).end());
  s.dir_a.assign(map.direction(s.va->va.j).begin(), map.direction(s.va->va.j).end());
  s.what_if_asked = what_if;
  s.analysis = contributions(m, s.a, s.dir_a, std::optional<std::span<const double>>(s.b), s.dir_b);
  // The exact answer to "which error first": the VA with that error removed, every other kept.
  if (what_if)
    for (const auto& e : nonzero_errors(m)) {
      const ErrorModel without(without_error(m, e));
      const ErrorMap wm = error_map(without, map.q, map.dir, {threads});
      const auto va = volumetric_accuracy(wm.error).va;
      WhatIf w;
      w.error = e;
      w.va = va.value;
      w.from = configuration_at(map, va.i);
      w.to = configuration_at(map, va.j);
      for (const auto& c : s.analysis.items)
        if (c.error == e) w.share = c.share;
      const double full = s.va->va.value;
      w.disagrees = (w.share > 0 && w.va > full) || (w.share <= 0 && w.va < full);
      if (w.disagrees) {
        // Why: the error's part in the pair that is critical without it, on the full machine.
        const auto there =
            contributions(m, map.configuration(va.j), map.direction(va.j),
                          std::optional<std::span<const double>>(map.configuration(va.i)), map.direction(va.i));
        detail::explain_disagreement(w, there);
      }
      s.what_if.push_back(w);
    }
  std::stable_sort(s.what_if.begin(), s.what_if.end(), [](const WhatIf& x, const WhatIf& y) { return x.va < y.va; });
  if (target_va) s.sequence = correction_sequence(m, map, *target_va, threads);
  return s;
}

CorrectionSequence correction_sequence(const Machine& m, const ErrorMap& map, double target_va, int threads) {
  if (!std::isfinite(target_va) || target_va < 0)
    throw InputError({"target VA", 0, ""}, fmt::format("expected a VA >= 0 in mm, found {}", target_va));
  CorrectionSequence seq;
  seq.target = target_va;
  seq.start = volumetric_accuracy(map.error).va.value;
  double va = seq.start;
  Machine current = m;
  std::vector<ErrorName> left = nonzero_errors(m);
  while (va > target_va && !left.empty()) {
    std::size_t best = 0;
    double best_va = INFINITY;
    for (std::size_t k = 0; k < left.size(); ++k) {
      const ErrorModel without(without_error(current, left[k]));
      const double v = volumetric_accuracy(error_map(without, map.q, map.dir, {threads}).error).va.value;
      if (v < best_va) best_va = v, best = k;
    }
    current = without_error(current, left[best]);
    seq.steps.push_back({left[best], best_va});
    va = best_va;
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(best));
  }
  seq.reached = va <= target_va;
  return seq;
}

}  // namespace mtcal
