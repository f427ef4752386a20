// Calibration history analysis: diff and E_n, drift fits and crossing dates by hand, properties, ranking.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "mtcal/history/analysis.hpp"
#include "mtcal/util/errors.hpp"

using namespace mtcal;

namespace {

// 365.2425 days in seconds is a whole number (31,556,952 s): samples k years apart are exact.
const HistoryTime kOrigin = parse_history_time("2020-01-01");
HistoryTime years(double y) { return kOrigin + std::chrono::seconds(std::llround(y * kSecondsPerYear)); }
double years_of(HistoryTime t) { return static_cast<double>((t - kOrigin).count()) / kSecondsPerYear; }

TrendSample sample(double y, double v, std::optional<double> u = std::nullopt) {
  return {years(y), v, u, "r" + std::to_string(static_cast<int>(y * 100))};
}

const ParameterChange& change(const CalibrationDiff& d, const std::string& name) {
  for (const auto& c : d.changes)
    if (c.name == name) return c;
  throw std::runtime_error("no change " + name);
}

template <class F>
std::string history_analysis_error_of(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Dates

TEST(HistoryTime, ParsesDatesDateTimesAndOffsets) {
  // 1970 to 2025 are 56 years with 14 leap days (1972 ... 2024): 2026-01-01 is day 56 * 365 + 14
  // = 20454; 2026-11-24 is 304 (January to October) + 23 days later, day 20781.
  EXPECT_EQ(parse_history_time("2026-01-01").time_since_epoch().count(), 20454LL * 86400);
  EXPECT_EQ(parse_history_time("2026-11-24").time_since_epoch().count(), 20781LL * 86400);
  EXPECT_EQ(parse_history_time("2026-11-24T10:30:00Z").time_since_epoch().count(), 20781LL * 86400 + 37800);
  EXPECT_EQ(parse_history_time("2026-11-24T10:30").time_since_epoch().count(), 20781LL * 86400 + 37800);
  // 10:30:15.75 at +02:00 is 08:30:15 UTC (the fraction dropped); -01:30 adds 1.5 h.
  EXPECT_EQ(parse_history_time("2026-11-24T10:30:15.75+02:00").time_since_epoch().count(),
            20781LL * 86400 + 8 * 3600 + 30 * 60 + 15);
  EXPECT_EQ(parse_history_time("2026-11-24T10:30:00-01:30").time_since_epoch().count(), 20781LL * 86400 + 43200);
  EXPECT_EQ(format_history_date(parse_history_time("2024-02-29T23:59:59Z")), "2024-02-29");
  EXPECT_EQ(format_history_time(parse_history_time("2024-02-29T23:59:59+00:00")), "2024-02-29T23:59:59Z");
  EXPECT_EQ(format_history_date(parse_history_time("1969-12-31T12:00:00Z")), "1969-12-31");
  for (const char* bad : {"", "2026-13-01", "2025-02-29", "24.11.2026", "2026-11-24 10:30", "2026-11-24T25:00"}) {
    const std::string m = history_analysis_error_of([&] { parse_history_time(bad, "record 7"); });
    EXPECT_NE(m.find("ISO 8601"), std::string::npos) << bad;
    EXPECT_NE(m.find("record 7"), std::string::npos) << m;
  }
}

// ---------------------------------------------------------------------------------------------
// Diff

TEST(HistoryDiff, HandComputedChangesAndNormalisedErrors) {
  const std::vector<HistoryQuantity> a{{"EXX", 10, 1.0, "um"},   {"EC0Y", 5, 2.0, "urad"},
                                       {"EB0Z", 1, 3.0, "urad"}, {"EX0C", 0.5, std::nullopt, "mm"},
                                       {"EA0Z", 4, 0.0, "urad"}, {"EY0C", 2, 0.1, "mm"},
                                       {"EZ0B", 7, 1.0, "um"}};
  const std::vector<HistoryQuantity> b{{"EXX", 13, 1.0, "um"},   {"EC0Y", 7, 2.0, "urad"},   {"EB0Z", 11, 4.0, "urad"},
                                       {"EX0C", 0.7, 0.1, "mm"}, {"EA0Z", 4.5, 0.0, "urad"}, {"EY0C", 2, 100.0, "um"},
                                       {"EA0C", 9, 1.0, "urad"}};
  const CalibrationDiff d = diff_calibrations(a, b);
  // EXX: delta 3, u = sqrt(1 + 1) = 1.4142136, E_n = 3 / (2 sqrt 2) = 1.0606602 > 1: significant.
  const auto& exx = change(d, "EXX");
  EXPECT_DOUBLE_EQ(*exx.delta, 3.0);
  EXPECT_NEAR(*exx.u_delta, 1.4142136, 1e-7);
  EXPECT_NEAR(*exx.en, 1.0606602, 1e-7);
  EXPECT_EQ(exx.verdict, ChangeVerdict::Significant);
  // EC0Y: delta 2, u = 2 sqrt 2, E_n = 2 / (4 sqrt 2) = 0.3535534: not significant.
  EXPECT_NEAR(*change(d, "EC0Y").en, 0.3535534, 1e-7);
  EXPECT_EQ(change(d, "EC0Y").verdict, ChangeVerdict::NotSignificant);
  // EB0Z: delta 10, u = sqrt(9 + 16) = 5, E_n = 10 / (2 * 5) = 1 exactly: |E_n| > 1 fails, so not significant.
  EXPECT_DOUBLE_EQ(*change(d, "EB0Z").u_delta, 5.0);
  EXPECT_DOUBLE_EQ(*change(d, "EB0Z").en, 1.0);
  EXPECT_EQ(change(d, "EB0Z").verdict, ChangeVerdict::NotSignificant);
  // EX0C: the first calibration states no uncertainty: a change, but not assessable, and said why.
  const auto& x0c = change(d, "EX0C");
  EXPECT_NEAR(*x0c.delta, 0.2, 1e-15);
  EXPECT_FALSE(x0c.u_delta);
  EXPECT_FALSE(x0c.en);
  EXPECT_EQ(x0c.verdict, ChangeVerdict::NotAssessable);
  EXPECT_EQ(x0c.reason, "no uncertainty in the first calibration");
  // EA0Z: both uncertainties zero: E_n undefined, not a pass.
  EXPECT_EQ(change(d, "EA0Z").verdict, ChangeVerdict::NotAssessable);
  EXPECT_NE(change(d, "EA0Z").reason.find("zero"), std::string::npos);
  // EY0C: mm against um: never subtracted.
  EXPECT_EQ(change(d, "EY0C").verdict, ChangeVerdict::NotAssessable);
  EXPECT_FALSE(change(d, "EY0C").delta);
  EXPECT_NE(change(d, "EY0C").reason.find("units differ"), std::string::npos);
  EXPECT_EQ(change(d, "EZ0B").verdict, ChangeVerdict::Removed);
  EXPECT_EQ(change(d, "EA0C").verdict, ChangeVerdict::Added);
  EXPECT_DOUBLE_EQ(*change(d, "EA0C").after, 9.0);
  // Order: the first calibration's, then the added ones.
  ASSERT_EQ(d.changes.size(), 8u);
  EXPECT_EQ(d.changes.front().name, "EXX");
  EXPECT_EQ(d.changes.back().name, "EA0C");
  EXPECT_EQ(d.significant, 1u);
  EXPECT_EQ(d.not_significant, 2u);
  EXPECT_EQ(d.not_assessable, 3u);
  EXPECT_EQ(d.added, 1u);
  EXPECT_EQ(d.removed, 1u);
}

TEST(HistoryDiff, CoverageFactorAndLimitAreOptions) {
  // delta 3, u(delta) = sqrt 2: E_n = 3 / (k sqrt 2); with k = 3 it is 0.7071068.
  DiffOptions o;
  o.coverage_factor = 3;
  const auto d = diff_calibrations({{"EXX", 10, 1.0, "um"}}, {{"EXX", 13, 1.0, "um"}}, o);
  EXPECT_NEAR(*d.changes[0].en, 0.7071068, 1e-7);
  EXPECT_EQ(d.changes[0].verdict, ChangeVerdict::NotSignificant);
  // Negative changes are judged by |E_n|.
  const auto n = diff_calibrations({{"EXX", 13, 1.0, "um"}}, {{"EXX", 10, 1.0, "um"}});
  EXPECT_NEAR(*n.changes[0].en, -1.0606602, 1e-7);
  EXPECT_EQ(n.changes[0].verdict, ChangeVerdict::Significant);
}

TEST(HistoryDiff, IdenticalCalibrationsAreNotSignificantAndEmptyIsEmpty) {
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> v(-100, 100), u(1e-9, 5);
  std::vector<HistoryQuantity> a;
  for (int i = 0; i < 50; ++i) a.push_back({"P" + std::to_string(i), v(gen), u(gen), "um"});
  const auto d = diff_calibrations(a, a);
  EXPECT_EQ(d.not_significant, 50u);
  for (const auto& c : d.changes) EXPECT_EQ(*c.en, 0.0);
  EXPECT_TRUE(diff_calibrations({}, {}).changes.empty());
}

TEST(HistoryDiff, BadInputNamesRecordAndParameter) {
  const double nan = std::nan("");
  auto m = history_analysis_error_of([&] { diff_calibrations({{"EXX", nan, 1.0, "um"}}, {}, {}, "record 4", "record 5"); });
  EXPECT_NE(m.find("record 4"), std::string::npos) << m;
  EXPECT_NE(m.find("EXX"), std::string::npos) << m;
  m = history_analysis_error_of([&] { diff_calibrations({}, {{"EC0Y", 1, -1.0, "urad"}}, {}, "record 4", "record 5"); });
  EXPECT_NE(m.find("record 5"), std::string::npos) << m;
  EXPECT_NE(m.find("uncertainty"), std::string::npos) << m;
  m = history_analysis_error_of([&] { diff_calibrations({{"EXX", 1, 1.0, "um"}, {"EXX", 2, 1.0, "um"}}, {}); });
  EXPECT_NE(m.find("twice"), std::string::npos) << m;
  DiffOptions o;
  o.coverage_factor = 0;
  EXPECT_FALSE(history_analysis_error_of([&] { diff_calibrations({}, {}, o); }).empty());
}

TEST(HistoryDiff, RecordsGiveParameterAndFigureDiffs) {
  CalibrationRecord r1, r2;
  r1.id = "11";
  r2.id = "12";
  r1.parameters = {{"EC0Y", 20, 2.0, "urad"}};
  r2.parameters = {{"EC0Y", 30, 2.0, "urad"}};
  r1.figures = {{"A_X", 12, "um", std::nullopt}, {"B_X", 5, "um", 0.5}};
  r2.figures = {{"A_X", 14, "um", std::nullopt}, {"B_X", 8, "um", 0.5}};
  const RecordDiff d = diff_records(r1, r2);
  EXPECT_EQ(d.first, "11");
  // delta 10, u = 2 sqrt 2, E_n = 10 / (4 sqrt 2) = 1.7677670.
  EXPECT_NEAR(*d.parameters.changes[0].en, 1.7677670, 1e-7);
  // Figures state no uncertainty: a change of 2 um, not assessable.
  EXPECT_DOUBLE_EQ(*d.figures.changes[0].delta, 2.0);
  EXPECT_EQ(d.figures.changes[0].verdict, ChangeVerdict::NotAssessable);
  EXPECT_EQ(d.figures.changes[0].reason, "no uncertainty in either calibration");
  // A figure that states u is judged like a parameter: delta 3, u = sqrt(0.5) = 0.7071068, E_n = 3 / 1.4142136
  // = 2.1213203.
  EXPECT_NEAR(*d.figures.changes[1].en, 2.1213203, 1e-7);
  EXPECT_EQ(d.figures.changes[1].verdict, ChangeVerdict::Significant);
}

// ---------------------------------------------------------------------------------------------
// Trend

TEST(HistoryTrend, OrdinaryFitByHand) {
  // t = 0, 1, 2, 3 years, y = 1, 3, 2, 5, no uncertainties: ordinary least squares.
  // tm = 1.5, ym = 2.75, Sxx = 2.25 + 0.25 + 0.25 + 2.25 = 5,
  // Sxy = (-1.5)(-1.75) + (-0.5)(0.25) + (0.5)(-0.75) + (1.5)(2.25) = 5.5 -> rate 1.1 per year.
  // Residuals -0.1, 0.8, -1.3, 0.6: RSS 2.7, s^2 = 2.7 / 2 = 1.35,
  // u(rate) = s / sqrt(Sxx) = sqrt(0.27) = 0.5196152, u(level) = s / sqrt(4) = 0.5809475.
  const auto r = fit_trend({sample(0, 1), sample(2, 2), sample(1, 3), sample(3, 5)}, ToleranceBand::symmetric(6));
  EXPECT_EQ(r.kind, TrendFitKind::Ordinary);
  EXPECT_EQ(r.n, 4u);
  EXPECT_EQ(r.t_ref, years(1.5));
  EXPECT_NEAR(r.level, 2.75, 1e-12);
  EXPECT_NEAR(r.rate_per_year, 1.1, 1e-12);
  EXPECT_NEAR(*r.u_rate, 0.5196152, 1e-7);
  EXPECT_NEAR(*r.u_level, 0.5809475, 1e-7);
  EXPECT_NEAR(*r.residual_sd, std::sqrt(1.35), 1e-12);
  EXPECT_FALSE(r.birge_ratio);
  EXPECT_NE(r.note.find("ordinary least squares"), std::string::npos);
  EXPECT_EQ(r.last, years(3));
  EXPECT_DOUBLE_EQ(r.last_value, 5.0);
  EXPECT_DOUBLE_EQ(*r.utilisation, 5.0 / 6.0);
  EXPECT_NEAR(r.at(years(3)), 4.4, 1e-12);
  // |value| <= 6, rising: the line reaches 6 at 1.5 + (6 - 2.75) / 1.1 = 4.4545455 years, 1.4545455
  // after the latest sample. Rates 1.1 +- 2 * 0.5196152 = 2.1392305 and 0.0607695 turn the line
  // about (1.5, 2.75): earliest 1.5 + 3.25 / 2.1392305 = 3.0192379, latest 1.5 + 3.25 / 0.0607695 = 54.980762.
  ASSERT_EQ(r.crossing.status, CrossingStatus::Predicted);
  EXPECT_DOUBLE_EQ(*r.crossing.limit, 6.0);
  EXPECT_NEAR(years_of(*r.crossing.date), 4.4545455, 1e-6);
  EXPECT_NEAR(*r.crossing.years_from_last, 1.4545455, 1e-7);
  EXPECT_NEAR(years_of(*r.crossing.earliest), 3.0192379, 1e-6);
  EXPECT_NEAR(years_of(*r.crossing.latest), 54.980762, 1e-5);
}

TEST(HistoryTrend, WeightedFitByHand) {
  // t = 0, 1, 2; y = 0, 2, 3; u = 1, 1, 2 -> w = 1, 1, 0.25, W = 2.25.
  // tm = (0 + 1 + 0.5) / 2.25 = 2/3, level = (0 + 2 + 0.75) / 2.25 = 11/9.
  // Sxx = 4/9 + 1/9 + 0.25 * 16/9 = 1; Sxy = (2/3)(11/9) + (1/3)(7/9) + 0.25 (4/3)(16/9) = 5/3.
  // rate = 5/3, u(rate) = 1 / sqrt(Sxx) = 1, u(level) = 1 / sqrt(W) = 2/3.
  // Residuals -1/9, 2/9, -4/9: chi2 = 1/81 + 4/81 + 0.25 * 16/81 = 1/9, Birge ratio sqrt(1/9 / 1) = 1/3
  // (< 1: nothing inflated); unweighted RSS 21/81, residual sd sqrt(21/81).
  const auto r = fit_trend({sample(0, 0, 1.0), sample(1, 2, 1.0), sample(2, 3, 2.0)});
  EXPECT_EQ(r.kind, TrendFitKind::Weighted);
  EXPECT_EQ(r.t_ref, years(2.0 / 3.0));
  EXPECT_NEAR(r.level, 11.0 / 9.0, 1e-12);
  EXPECT_NEAR(r.rate_per_year, 5.0 / 3.0, 1e-12);
  EXPECT_NEAR(*r.u_rate, 1.0, 1e-12);
  EXPECT_NEAR(*r.u_level, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(*r.birge_ratio, 1.0 / 3.0, 1e-12);
  EXPECT_FALSE(r.inflated);
  EXPECT_NEAR(*r.residual_sd, std::sqrt(21.0 / 81.0), 1e-12);
  EXPECT_EQ(r.crossing.status, CrossingStatus::NoTolerance);
}

TEST(HistoryTrend, BirgeRatioInflatesToTheScatter) {
  // The ordinary data set with u = 0.1 each: chi2 = RSS / 0.01 = 270, Birge ratio sqrt(270 / 2) = 11.61895;
  // the stated u(rate) 0.1 / sqrt(5) = 0.04472136 times it is the scatter-based 0.5196152 again.
  std::vector<TrendSample> s{sample(0, 1, 0.1), sample(1, 3, 0.1), sample(2, 2, 0.1), sample(3, 5, 0.1)};
  const auto r = fit_trend(s);
  EXPECT_EQ(r.kind, TrendFitKind::Weighted);
  EXPECT_NEAR(*r.birge_ratio, 11.61895, 1e-5);
  EXPECT_TRUE(r.inflated);
  EXPECT_NEAR(*r.u_rate, 0.5196152, 1e-7);
  TrendOptions o;
  o.inflate_by_birge_ratio = false;
  EXPECT_NEAR(*fit_trend(s, std::nullopt, o).u_rate, 0.04472136, 1e-8);
}

TEST(HistoryTrend, DegenerateInputsAreStated) {
  auto r = fit_trend({});
  EXPECT_EQ(r.kind, TrendFitKind::None);
  EXPECT_EQ(r.note, "no samples");
  r = fit_trend({sample(1, 4)}, ToleranceBand::symmetric(10));
  EXPECT_EQ(r.kind, TrendFitKind::None);
  EXPECT_EQ(r.crossing.status, CrossingStatus::NoFit);
  EXPECT_NE(r.note.find("1 sample"), std::string::npos);
  EXPECT_DOUBLE_EQ(*r.utilisation, 0.4);
  // One sample outside is outside, fit or not.
  EXPECT_EQ(fit_trend({sample(1, 12)}, ToleranceBand::symmetric(10)).crossing.status, CrossingStatus::AlreadyOutside);
  // Two samples at one instant.
  r = fit_trend({sample(1, 4), sample(1, 5)});
  EXPECT_EQ(r.kind, TrendFitKind::None);
  EXPECT_NE(r.note.find("one instant"), std::string::npos);
  // Two samples without u: the line through them, no uncertainty.
  r = fit_trend({sample(0, 1), sample(2, 5)}, ToleranceBand::symmetric(10));
  EXPECT_EQ(r.kind, TrendFitKind::Ordinary);
  EXPECT_NEAR(r.rate_per_year, 2.0, 1e-12);
  EXPECT_FALSE(r.u_rate);
  EXPECT_NE(r.note.find("3 needed"), std::string::npos);
  // Reaches 10 at 2 + 5 / 2 = 4.5 years; no interval without u(rate).
  EXPECT_NEAR(years_of(*r.crossing.date), 4.5, 1e-6);
  EXPECT_FALSE(r.crossing.earliest);
  // Two samples with u = 1: w = 1, tm = 1, Sxx = 1 + 1 = 2, u(rate) = 1 / sqrt(2) from the stated uncertainties.
  r = fit_trend({sample(0, 1, 1.0), sample(2, 5, 1.0)});
  EXPECT_EQ(r.kind, TrendFitKind::Weighted);
  EXPECT_NEAR(*r.u_rate, 1.0 / std::sqrt(2.0), 1e-12);
  EXPECT_FALSE(r.birge_ratio);
  EXPECT_NE(r.note.find("not checked"), std::string::npos);
  // A zero uncertainty cannot weigh: ordinary fit, and the record named.
  r = fit_trend({sample(0, 1, 1.0), sample(1, 2, 0.0), sample(2, 3.5, 1.0)});
  EXPECT_EQ(r.kind, TrendFitKind::Ordinary);
  EXPECT_NE(r.note.find("r100"), std::string::npos) << r.note;
}

TEST(HistoryTrend, CrossingCases) {
  // Constant values: rate 0, never reaches the band's limits.
  auto r = fit_trend({sample(0, 3), sample(1, 3), sample(2, 3)}, ToleranceBand::symmetric(10));
  EXPECT_EQ(r.rate_per_year, 0.0);
  EXPECT_EQ(r.crossing.status, CrossingStatus::NotTowardsLimit);
  // A magnitude (value <= 10) that falls: never reaches its only limit.
  r = fit_trend({sample(0, 8), sample(1, 6), sample(2, 5)}, ToleranceBand::at_most(10));
  EXPECT_EQ(r.crossing.status, CrossingStatus::NotTowardsLimit);
  // The same falling signed error with |value| <= 10 heads to -10: 8, 6, 5 -> rate -1.5, level 19/3 at t = 1;
  // reaches -10 at 1 + (-10 - 19/3) / (-1.5) = 11.888889 years.
  r = fit_trend({sample(0, 8), sample(1, 6), sample(2, 5)}, ToleranceBand::symmetric(10));
  ASSERT_EQ(r.crossing.status, CrossingStatus::Predicted);
  EXPECT_DOUBLE_EQ(*r.crossing.limit, -10.0);
  EXPECT_NEAR(years_of(*r.crossing.date), 11.888889, 1e-6);
  // [lo, hi] = [2, 6]: the latest value 5 uses |5 - 4| / 2 = 0.5 of it.
  r = fit_trend({sample(0, 3), sample(1, 4), sample(2, 5)}, ToleranceBand{2, 6});
  EXPECT_DOUBLE_EQ(*r.utilisation, 0.5);
  EXPECT_NEAR(years_of(*r.crossing.date), 3.0, 1e-6);  // 3 + 1 per year reaches 6 at t = 3
  // The latest sample outside: already outside, whatever the line does.
  r = fit_trend({sample(0, 12), sample(1, 11)}, ToleranceBand::symmetric(10));
  EXPECT_EQ(r.crossing.status, CrossingStatus::AlreadyOutside);
  EXPECT_DOUBLE_EQ(*r.crossing.limit, 10.0);
  EXPECT_GT(*r.utilisation, 1.0);
  // Latest inside but the fitted line already past the limit: predicted in the past.
  r = fit_trend({sample(0, 0), sample(1, 20), sample(2, 9)}, ToleranceBand::symmetric(10));
  ASSERT_EQ(r.crossing.status, CrossingStatus::Predicted);
  EXPECT_LT(*r.crossing.years_from_last, 0.0);
  // Scatter so large that rate - 2u <= 0: no latest date ("possibly never").
  r = fit_trend({sample(0, 0), sample(1, 3), sample(2, -2), sample(3, 2)}, ToleranceBand::symmetric(10));
  ASSERT_EQ(r.crossing.status, CrossingStatus::Predicted);
  EXPECT_TRUE(r.crossing.earliest);
  EXPECT_FALSE(r.crossing.latest);
  // A drift too slow to date: no date, and said so.
  r = fit_trend({sample(0, 0), sample(1, 1e-9), sample(2, 2e-9)}, ToleranceBand::symmetric(10));
  ASSERT_EQ(r.crossing.status, CrossingStatus::Predicted);
  EXPECT_FALSE(r.crossing.date);
  EXPECT_NE(r.note.find("10000 years"), std::string::npos) << r.note;
}

TEST(HistoryTrend, BadInputs) {
  auto m = history_analysis_error_of([] { fit_trend({sample(0, std::nan("")), sample(1, 1)}, std::nullopt, {}, "EC0Y"); });
  EXPECT_NE(m.find("EC0Y"), std::string::npos) << m;
  EXPECT_NE(m.find("r0"), std::string::npos) << m;
  m = history_analysis_error_of([] { fit_trend({sample(0, 1, -0.5)}, std::nullopt, {}, "EC0Y"); });
  EXPECT_NE(m.find("uncertainty"), std::string::npos) << m;
  m = history_analysis_error_of([] { fit_trend({sample(0, 1)}, ToleranceBand{5, 1}, {}, "A_X"); });
  EXPECT_NE(m.find("A_X"), std::string::npos) << m;
  m = history_analysis_error_of([] { fit_trend({sample(0, 1)}, ToleranceBand::at_most(0), {}, "A_X"); });
  EXPECT_NE(m.find("> 0"), std::string::npos) << m;
  m = history_analysis_error_of([] { fit_trend({sample(0, 1)}, ToleranceBand{0, std::numeric_limits<double>::infinity()}, {}, "A_X"); });
  EXPECT_NE(m.find("upper limit"), std::string::npos) << m;
}

TEST(HistoryTrend, ExactLinesAreRecoveredAtEveryScale) {
  // Property: samples on a line (any scale, any order, random dates) give its rate, u(rate) = 0
  // for the ordinary fit, and the weighted fit's rate does not depend on a common factor of u.
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> t(0, 30), unit(-1, 1), ulog(-3, 3);
  for (const double scale : {1e-9, 1e-3, 1.0, 1e6}) {
    for (int rep = 0; rep < 20; ++rep) {
      const double a = unit(gen) * scale, b = unit(gen) * scale;
      std::vector<TrendSample> s;
      for (int i = 0; i < 12; ++i) {
        const HistoryTime at = years(t(gen));
        s.push_back({at, a + b * years_of(at), std::pow(10.0, ulog(gen)) * scale, "r" + std::to_string(i)});
      }
      const auto w = fit_trend(s);
      EXPECT_NEAR(w.rate_per_year, b, 1e-9 * scale) << scale;
      EXPECT_NEAR(w.at(years(0)), a, 1e-8 * scale);
      for (auto& x : s) *x.u *= 1000.0;
      EXPECT_NEAR(fit_trend(s).rate_per_year, w.rate_per_year, 1e-12 * scale);
      for (auto& x : s) x.u.reset();
      const auto ols = fit_trend(s);
      EXPECT_NEAR(ols.rate_per_year, b, 1e-9 * scale);
      EXPECT_LT(*ols.u_rate, 1e-7 * scale);
    }
  }
  // All zero: rate 0, no drift.
  const auto z = fit_trend({sample(0, 0, 1e-3), sample(1, 0, 1e-3), sample(2, 0, 1e-3)}, ToleranceBand::symmetric(1));
  EXPECT_EQ(z.rate_per_year, 0.0);
  EXPECT_EQ(z.crossing.status, CrossingStatus::NotTowardsLimit);
}

TEST(HistoryTrend, OrdinaryFitAgreesWithTheNormalEquations) {
  // Independent reference: the 2x2 normal equations in raw (uncentred) sums,
  // [n St; St Stt] [a; b] = [Sy; Sty], and Cov = s^2 inv(N) for u(b).
  std::mt19937_64 gen(9);
  std::uniform_real_distribution<double> t(0, 10), noise(-2, 2);
  for (int rep = 0; rep < 50; ++rep) {
    std::vector<TrendSample> s;
    double n = 0, st = 0, stt = 0, sy = 0, sty = 0;
    std::vector<double> ts, ys;
    for (int i = 0; i < 8; ++i) {
      const TrendSample x = sample(std::round(t(gen) * 1000) / 1000, 3 - 0.7 * i + noise(gen));
      const double ti = years_of(x.at);
      s.push_back(x);
      ts.push_back(ti);
      ys.push_back(x.value);
      n += 1, st += ti, stt += ti * ti, sy += x.value, sty += ti * x.value;
    }
    const double det = n * stt - st * st;
    const double a = (stt * sy - st * sty) / det, b = (n * sty - st * sy) / det;
    double rss = 0;
    for (std::size_t i = 0; i < ts.size(); ++i) rss += std::pow(ys[i] - a - b * ts[i], 2);
    const double ub = std::sqrt(rss / (n - 2) * n / det);
    const auto r = fit_trend(s);
    EXPECT_NEAR(r.rate_per_year, b, 1e-9);
    EXPECT_NEAR(*r.u_rate, ub, 1e-9);
    EXPECT_NEAR(r.at(years(0)), a, 1e-9);
  }
}

TEST(HistoryTrend, WeightedRateUncertaintyMatchesMonteCarlo) {
  // Stated u that are the true noise: the spread of the fitted rates over many simulated
  // histories must be u(rate) (within 5 % for 4,000 repetitions: the sd of an sd estimate is
  // about 1/sqrt(2 * 4000) = 1.1 %).
  std::mt19937_64 gen(21);
  const std::vector<double> t{0, 0.5, 1.2, 2, 3.1, 4, 5.5};
  const std::vector<double> u{0.5, 1.0, 0.3, 0.8, 2.0, 0.4, 1.5};
  double sum = 0, sum2 = 0, stated = 0;
  const int reps = 4000;
  for (int k = 0; k < reps; ++k) {
    std::vector<TrendSample> s;
    for (std::size_t i = 0; i < t.size(); ++i) {
      std::normal_distribution<double> e(0, u[i]);
      s.push_back(sample(t[i], 2 + 0.3 * t[i] + e(gen), u[i]));
    }
    TrendOptions o;
    o.inflate_by_birge_ratio = false;
    const auto r = fit_trend(s, std::nullopt, o);
    sum += r.rate_per_year;
    sum2 += r.rate_per_year * r.rate_per_year;
    stated = *r.u_rate;
  }
  const double mean = sum / reps, sd = std::sqrt(sum2 / reps - mean * mean);
  EXPECT_NEAR(mean, 0.3, 3 * stated / std::sqrt(reps));
  EXPECT_NEAR(sd / stated, 1.0, 0.05);
}

TEST(HistoryTrend, StoreSeriesBecomeSamples) {
  const std::vector<SeriesSample> series{{"2024-01-01", 1.0, 0.5, "a1", "um"},
                                         {"2024-07-01T12:00:00Z", 2.0, {}, "a2", "um"}};
  const auto s = trend_samples(series);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(format_history_time(s[1].at), "2024-07-01T12:00:00Z");
  EXPECT_EQ(*s[0].u, 0.5);
  EXPECT_EQ(s[1].record, "a2");
  const auto m = history_analysis_error_of([] { trend_samples({{"1.1.2024", 1.0, {}, "a9", "um"}}); });
  EXPECT_NE(m.find("record a9"), std::string::npos) << m;
}

// ---------------------------------------------------------------------------------------------
// Ranking

TEST(HistoryRank, ByUtilisationAndByTimeToLimit) {
  // A: 3, 4, 5 over 2 years, |v| <= 10: utilisation 0.5, rate 1/year, reaches 10 at t = 7, 5 years after the last.
  // B: 8, 8, 8: utilisation 0.8, not drifting. C: 9, 10, 12: latest outside (1.2).
  // D: figure G <= 20 at 4, 6, 8: utilisation 0.4, reaches 20 at t = 8, 6 years after the last;
  //    D's EXX 1, 1, 1 (0.1) is its other quantity.
  auto series = [](const std::string& m, const std::string& q, std::vector<double> v, ToleranceBand b) {
    RankSeries s{m, q, "um", {}, b};
    for (std::size_t i = 0; i < v.size(); ++i) s.samples.push_back(sample(static_cast<double>(i), v[i]));
    return s;
  };
  const std::vector<RankSeries> fleet{
      series("A", "EXX", {3, 4, 5}, ToleranceBand::symmetric(10)),
      series("B", "EXX", {8, 8, 8}, ToleranceBand::symmetric(10)),
      series("C", "EXX", {9, 10, 12}, ToleranceBand::symmetric(10)),
      series("D", "EXX", {1, 1, 1}, ToleranceBand::symmetric(10)),
      series("D", "G", {4, 6, 8}, ToleranceBand::at_most(20)),
  };
  RankOptions o;
  o.threads = 2;
  auto r = rank_fleet(fleet, o);
  ASSERT_EQ(r.machines.size(), 4u);
  EXPECT_EQ(r.machines[0].machine, "C");
  EXPECT_TRUE(r.machines[0].outside);
  EXPECT_DOUBLE_EQ(*r.machines[0].years_to_limit, 0.0);
  EXPECT_EQ(r.machines[1].machine, "B");
  EXPECT_FALSE(r.machines[1].years_to_limit);
  EXPECT_EQ(r.machines[2].machine, "A");
  EXPECT_NEAR(*r.machines[2].years_to_limit, 5.0, 1e-6);
  EXPECT_EQ(r.machines[3].machine, "D");
  EXPECT_DOUBLE_EQ(r.machines[3].utilisation, 0.4);
  EXPECT_NEAR(*r.machines[3].years_to_limit, 6.0, 1e-6);
  EXPECT_EQ(r.machines[3].quantities.front().quantity, "G");  // the deciding quantity first
  EXPECT_EQ(r.machines[3].rank, 4u);

  o.order = RankOrder::TimeToLimit;
  r = rank_fleet(fleet, o);
  std::vector<std::string> order;
  for (const auto& m : r.machines) order.push_back(m.machine);
  EXPECT_EQ(order, (std::vector<std::string>{"C", "A", "D", "B"}));
  // The same for any thread count.
  o.threads = 1;
  const auto one = rank_fleet(fleet, o);
  for (std::size_t i = 0; i < one.machines.size(); ++i) {
    EXPECT_EQ(one.machines[i].machine, r.machines[i].machine);
    EXPECT_EQ(one.machines[i].utilisation, r.machines[i].utilisation);
  }
}

TEST(HistoryRank, TiesAndBadSeries) {
  // Equal utilisation: the earlier crossing first; then the name.
  RankSeries a{"M2", "EXX", "um", {sample(0, 5), sample(1, 5)}, ToleranceBand::symmetric(10)};
  RankSeries b{"M1", "EXX", "um", {sample(0, 5), sample(1, 5)}, ToleranceBand::symmetric(10)};
  RankSeries c{"M3", "EXX", "um", {sample(0, 4), sample(1, 5)}, ToleranceBand::symmetric(10)};
  auto r = rank_fleet({a, b, c});
  EXPECT_EQ(r.machines[0].machine, "M3");
  EXPECT_EQ(r.machines[1].machine, "M1");
  EXPECT_EQ(r.machines[2].machine, "M2");
  RankSeries empty{"M9", "EC0Y", "urad", {}, ToleranceBand::symmetric(10)};
  auto m = history_analysis_error_of([&] { rank_fleet({a, empty}); });
  EXPECT_NE(m.find("M9"), std::string::npos) << m;
  EXPECT_NE(m.find("EC0Y"), std::string::npos) << m;
  RankSeries nan_value{"M8", "EXX", "um", {sample(0, std::nan(""))}, ToleranceBand::symmetric(10)};
  m = history_analysis_error_of([&] { rank_fleet({nan_value}); });
  EXPECT_NE(m.find("M8"), std::string::npos) << m;
  EXPECT_TRUE(rank_fleet({}).machines.empty());
}
