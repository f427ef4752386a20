// Method comparison: per-parameter statistics of the long "method,test,parameter,value" table.
#include "mtcal/evaluation/compare.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "mtcal/util/errors.hpp"

namespace mtcal {
namespace {

// Mean and sample standard deviation of v (n >= 1); the deviation is exactly 0 for equal
// values, which the two-pass formula could leave at a rounding residue.
std::pair<double, std::optional<double>> mean_stdev(const std::vector<double>& v) {
  const double n = static_cast<double>(v.size());
  double sum = 0;
  for (double x : v) sum += x;
  const double mean = sum / n;
  if (v.size() < 2) return {mean, std::nullopt};
  if (std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); })) return {v.front(), 0.0};
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / (n - 1))};
}

// Pearson r of paired values; absent below 3 pairs or when either side is constant (r is then
// 0/0, not a measure of agreement).
std::optional<double> pearson(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() < 3) return std::nullopt;
  auto constant = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [&](double x) { return x == v.front(); });
  };
  if (constant(a) || constant(b)) return std::nullopt;
  const double ma = mean_stdev(a).first, mb = mean_stdev(b).first;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (!(saa > 0) || !(sbb > 0)) return std::nullopt;
  return std::clamp(sab / std::sqrt(saa * sbb), -1.0, 1.0);
}

}  // namespace

MethodComparison compare_methods(const ComparisonData& data) {
  MethodComparison out;
  out.source = data.source;
  out.methods = data.methods;
  // Per parameter in order of first appearance, per method, its (test, value) pairs in file order.
  struct Series {
    std::string name;
    std::array<std::vector<std::pair<std::string, double>>, 2> by_method;
  };
  std::vector<Series> series;
  std::map<std::string, std::size_t> index;
  for (const auto& v : data.values) {
    const auto [it, inserted] = index.emplace(v.parameter, series.size());
    if (inserted) series.push_back({v.parameter, {}});
    series[it->second].by_method[v.method].emplace_back(v.test, v.value);
  }

  ComparisonSummary& sum = out.summary;
  for (const auto& s : series) {
    ParameterComparison p;
    p.name = s.name;
    for (std::size_t k = 0; k < 2; ++k) {
      std::vector<double> values;
      for (const auto& tv : s.by_method[k]) values.push_back(tv.second);
      p.stats[k].n = values.size();
      if (!values.empty()) std::tie(p.stats[k].mean, p.stats[k].stdev) = mean_stdev(values);
    }
    const auto& a = p.stats[0];
    const auto& b = p.stats[1];
    if (a.mean && b.mean) p.abs_diff = std::abs(*a.mean - *b.mean);
    if (a.stdev && b.stdev) p.overlap = *p.abs_diff <= *a.stdev + *b.stdev;
    std::vector<double> pa, pb;
    for (const auto& [test, value] : s.by_method[0]) {
      const auto& other = s.by_method[1];
      const auto hit =
          std::find_if(other.begin(), other.end(), [&test = test](const auto& tv) { return tv.first == test; });
      if (hit == other.end()) continue;
      pa.push_back(value);
      pb.push_back(hit->second);
    }
    p.paired = pa.size();
    p.pearson_r = pearson(pa, pb);

    ++sum.parameters;
    if (a.n > 0 && b.n > 0)
      ++sum.both_methods;
    else
      sum.one_method_only.push_back(p.name);
    if (p.overlap) ++(*p.overlap ? sum.overlap : sum.no_overlap);
    if (p.pearson_r) {
      ++sum.with_correlation;
      if (std::abs(*p.pearson_r) >= kStrongCorrelation) ++sum.strong_correlation;
      if (*p.pearson_r >= kStrongCorrelation) ++sum.strong_positive;
      if (*p.pearson_r <= -kStrongCorrelation) ++sum.strong_negative;
    }
    out.parameters.push_back(std::move(p));
  }
  return out;
}

}  // namespace mtcal
