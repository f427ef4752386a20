// Benchmarks of the history analysis (issue 19: `trend` over 10 years of monthly calibrations of
// 1,000 machines, 120,000 records, <= 1 s): the fleet ranking's drift fits (closed-form centred
// least squares, rank_fleet) against a generic least-squares baseline (Eigen's column-pivoting
// Householder QR per series and the covariance from the inverse normal matrix) in the same run.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <benchmark/benchmark.h>

#include "mtcal/history/analysis.hpp"

namespace {

using namespace mtcal;

// machines x months: a squareness-like parameter drifting 0 ... 3 urad/year from a random start,
// 1.5 urad noise, each calibration stating u = 1.5 urad (or none: the ordinary fit).
std::vector<RankSeries> fleet(std::size_t machines, std::size_t months, bool with_u) {
  std::mt19937_64 gen(42);
  std::uniform_real_distribution<double> start(-20, 20), rate(0, 3);
  std::normal_distribution<double> noise(0, 1.5);
  const HistoryTime t0 = parse_history_time("2016-01-01");
  std::vector<RankSeries> out;
  for (std::size_t m = 0; m < machines; ++m) {
    RankSeries s{"M" + std::to_string(m), "EC0Y", "urad", {}, ToleranceBand::symmetric(60)};
    const double a = start(gen), b = rate(gen);
    for (std::size_t k = 0; k < months; ++k) {
      const double years = static_cast<double>(k) / 12.0;
      const auto at = t0 + std::chrono::seconds(std::llround(years * kSecondsPerYear));
      s.samples.push_back({at, a + b * years + noise(gen), with_u ? std::optional<double>(1.5) : std::nullopt,
                           std::to_string(m * months + k)});
    }
    out.push_back(std::move(s));
  }
  return out;
}

struct BaselineFit {
  double rate, u_rate, years_to_limit;
};

// The same weighted straight line by a general least-squares solver, per series, then sorted by
// the share of the tolerance used: what one would write without the centred closed form.
std::vector<BaselineFit> baseline_rank(const std::vector<RankSeries>& series) {
  std::vector<BaselineFit> out;
  std::vector<std::pair<double, std::size_t>> order;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const auto& s = series[i];
    const auto n = static_cast<Eigen::Index>(s.samples.size());
    Eigen::MatrixXd a(n, 2);
    Eigen::VectorXd y(n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto& x = s.samples[static_cast<std::size_t>(k)];
      const double w = x.u ? 1.0 / *x.u : 1.0;
      a(k, 0) = w;
      a(k, 1) = w * static_cast<double>((x.at - s.samples.front().at).count()) / kSecondsPerYear;
      y(k) = w * x.value;
    }
    const Eigen::Vector2d p = a.colPivHouseholderQr().solve(y);
    const Eigen::Matrix2d cov = (a.transpose() * a).inverse();
    const double t_last = a(n - 1, 1) / a(n - 1, 0);
    const double limit = p(1) > 0 ? s.band.hi : s.band.lo;
    out.push_back({p(1), std::sqrt(cov(1, 1)), (limit - p(0)) / p(1) - t_last});
    order.emplace_back(band_utilisation(s.samples.back().value, s.band), i);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
  benchmark::DoNotOptimize(order.data());
  return out;
}

void BM_HistoryRank(benchmark::State& state) {
  const auto series = fleet(static_cast<std::size_t>(state.range(0)), 120, state.range(1) != 0);
  RankOptions o;
  o.threads = 1;
  // The two must agree before either is timed: the same rates, and for the weighted fit the same
  // u(rate) from the stated uncertainties (without the Birge-ratio scaling the baseline lacks).
  RankOptions same = o;
  same.trend.inflate_by_birge_ratio = false;
  const auto check = rank_fleet(series, same);
  const auto base = baseline_rank(series);
  for (const auto& m : check.machines) {
    const auto& t = m.quantities[0].trend;
    const BaselineFit& b = base[std::stoul(m.machine.substr(1))];
    if (std::abs(t.rate_per_year - b.rate) > 1e-9 || (state.range(1) && std::abs(*t.u_rate - b.u_rate) > 1e-9)) {
      state.SkipWithError("rank_fleet and the QR baseline disagree");
      return;
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(rank_fleet(series, o).machines.data());
  state.counters["samples"] = static_cast<double>(state.range(0) * 120);
}
BENCHMARK(BM_HistoryRank)->Args({1000, 1})->Args({1000, 0})->Unit(benchmark::kMillisecond);

void BM_HistoryRank_QR_Baseline(benchmark::State& state) {
  const auto series = fleet(static_cast<std::size_t>(state.range(0)), 120, true);
  for (auto _ : state) benchmark::DoNotOptimize(baseline_rank(series).data());
  state.counters["samples"] = static_cast<double>(state.range(0) * 120);
}
BENCHMARK(BM_HistoryRank_QR_Baseline)->Arg(1000)->Unit(benchmark::kMillisecond);

// One machine's trend (the work of `history trend` after the store's query): 120 samples.
void BM_HistoryTrend_120(benchmark::State& state) {
  const auto series = fleet(1, 120, true);
  const auto band = std::optional<ToleranceBand>(series[0].band);
  for (auto _ : state) benchmark::DoNotOptimize(fit_trend(series[0].samples, band).rate_per_year);
}
BENCHMARK(BM_HistoryTrend_120)->Unit(benchmark::kMicrosecond);

}  // namespace
