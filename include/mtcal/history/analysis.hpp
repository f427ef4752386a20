// Calibration history analysis: what changed between two calibrations, drift over time, fleet ranking.
#pragma once

#include <chrono>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mtcal/history/record.hpp"

namespace mtcal {

// Instants of the history: UTC seconds since 1970-01-01 (std::chrono::system_clock's epoch).
using HistoryTime = std::chrono::sys_seconds;

// Seconds in a mean Gregorian year (365.2425 days, ISO 8601 / ISO 80000-3): drift rates are per
// this year, so that a rate does not depend on leap days between the samples.
inline constexpr double kSecondsPerYear = 365.2425 * 86400.0;

// The instant of an ISO 8601 date or date-time as records store it (is_iso8601): a date is its
// midnight UTC, a date-time without an offset is taken as UTC, fractions of a second are dropped.
// Throws InputError located at `where` (record id, field) for any other text.
HistoryTime parse_history_time(std::string_view text, const std::string& where = "date",
                               const std::string& field = "measured_at");

// "2026-11-24" (UTC date) and "2026-11-24T10:30:00Z" of an instant.
std::string format_history_date(HistoryTime t);
std::string format_history_time(HistoryTime t);

// ---------------------------------------------------------------------------------------------
// Difference of two calibrations

// One quantity of one calibration (an identified parameter or an evaluation figure).
struct HistoryQuantity {
  std::string name;
  double value = 0;
  std::optional<double> u;  // standard uncertainty (same unit), absent when not stated
  std::string unit;
};

struct DiffOptions {
  // Coverage factor of the expanded uncertainties in E_n (U = k u); ISO 13528:2015 clause 9.7 and
  // ISO/IEC 17043:2023 Annex B use k = 2 (about 95 % for a normal distribution, JCGM 100:2008 6.3).
  double coverage_factor = 2.0;
  // A change is significant when |E_n| > this (ISO 13528:2015 9.7.3: |E_n| > 1 is "unsatisfactory",
  // i.e. the two values disagree beyond their expanded uncertainties).
  double en_limit = 1.0;
};

enum class ChangeVerdict {
  Significant,     // |E_n| > limit
  NotSignificant,  // |E_n| <= limit
  NotAssessable,   // no E_n: an uncertainty is missing, both are zero, or the units differ (see reason)
  Added,           // only in the second calibration
  Removed,         // only in the first calibration
};
const char* to_string(ChangeVerdict v);

struct ParameterChange {
  std::string name, unit;
  std::optional<double> before, after;      // x1, x2
  std::optional<double> u_before, u_after;  // u1, u2
  std::optional<double> delta;              // x2 - x1 (when the units agree)
  std::optional<double> u_delta;            // sqrt(u1^2 + u2^2) when both u are stated
  std::optional<double> en;                 // E_n when assessable
  ChangeVerdict verdict = ChangeVerdict::NotAssessable;
  std::string reason;  // why not assessable ("no uncertainty in the first calibration"), else empty
};

struct CalibrationDiff {
  // Parameters of the first calibration in its order, then those only in the second.
  std::vector<ParameterChange> changes;
  std::size_t significant = 0, not_significant = 0, not_assessable = 0, added = 0, removed = 0;
  DiffOptions options;
};

// Parameter by parameter (matched by name): change delta = x2 - x1 with standard uncertainty
// u(delta) = sqrt(u1^2 + u2^2) (JCGM 100:2008 eq. (10), the two calibrations uncorrelated), and
// the normalised error E_n = delta / sqrt(U1^2 + U2^2), U = k u (ISO 13528:2015 eq. (37), ISO/IEC
// 17043). A parameter without uncertainty in either calibration is "not assessable", never passed.
// Throws InputError naming the parameter for a non-finite value, a negative or non-finite
// uncertainty, or a name given twice in one calibration; `first` and `second` name the records.
CalibrationDiff diff_calibrations(const std::vector<HistoryQuantity>& a, const std::vector<HistoryQuantity>& b,
                                  const DiffOptions& o = {}, const std::string& first = "the first calibration",
                                  const std::string& second = "the second calibration");

// ---------------------------------------------------------------------------------------------
// Trend of one quantity over time

struct TrendSample {
  HistoryTime at;
  double value = 0;
  std::optional<double> u;  // standard uncertainty, absent when not stated
  std::string record;       // the calibration it came from (id), for messages and reports
};

// A tolerance as an interval [lo, hi]; lo = -inf for "value <= hi" (a magnitude or range, as the
// acceptance tolerances of ISO 230-2 and ISO 230-4 read), [-T, T] for "|value| <= T" (a signed
// error such as a squareness).
struct ToleranceBand {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  static ToleranceBand symmetric(double t) { return {-t, t}; }
  static ToleranceBand at_most(double t) { return {-std::numeric_limits<double>::infinity(), t}; }
  bool contains(double v) const { return v >= lo && v <= hi; }
  bool one_sided() const { return !(lo > -std::numeric_limits<double>::infinity()); }
};
// Throws InputError naming `quantity` unless lo < hi, both not NaN, and (one-sided) hi > 0.
void check_band(const ToleranceBand& b, const std::string& quantity);

// How much of the tolerance a value uses: 0 at the band's centre (at 0 for a one-sided band), 1
// on a limit, > 1 outside. |v| / T for |v| <= T; v / T for v <= T; |v - m| / h for [m - h, m + h].
double band_utilisation(double v, const ToleranceBand& b);

struct TrendOptions {
  // Coverage factor of the interval of the predicted crossing date (rate +- k u(rate)).
  double coverage_factor = 2.0;
  // Weighted fit: scale the rate's uncertainty by the Birge ratio sqrt(chi2 / (n - 2)) when it
  // exceeds 1, i.e. when the samples scatter about the line more than their stated
  // uncertainties explain (Birge 1932; Bevington & Robinson 2003, sec. 6.5 and 11.1).
  bool inflate_by_birge_ratio = true;
};

enum class TrendFitKind {
  None,      // fewer than 2 samples, or all at one instant: no line
  Weighted,  // weights 1/u^2: every sample states u > 0
  Ordinary,  // ordinary least squares, uncertainty from the residuals
};
const char* to_string(TrendFitKind k);

enum class CrossingStatus {
  NoFit,            // no line (see TrendResult::note)
  NoTolerance,      // no band given
  AlreadyOutside,   // the latest sample is outside the band
  NotTowardsLimit,  // the fitted rate is zero, or leads away from a one-sided band's limit
  Predicted,        // the line reaches a limit at `date`
};
const char* to_string(CrossingStatus s);

struct LimitCrossing {
  CrossingStatus status = CrossingStatus::NoTolerance;
  std::optional<double> limit;            // the limit the line heads to
  std::optional<HistoryTime> date;        // where the fitted line reaches it
  std::optional<double> years_from_last;  // date - latest sample (negative: the line is already past it)
  // Interval of the date from the rate +- k u(rate), the line turning about the samples' (weighted)
  // mean time: earliest from the faster rate; latest absent when the slower rate is zero or leads
  // away ("possibly never").
  std::optional<HistoryTime> earliest, latest;
};

struct TrendResult {
  std::size_t n = 0;
  TrendFitKind kind = TrendFitKind::None;
  // The line value(t) = level + rate * (t - t_ref) in years, t_ref the (weighted) mean time of
  // the samples, where level and rate are uncorrelated.
  HistoryTime t_ref{};
  double level = 0;                   // fitted value at t_ref
  std::optional<double> u_level;      // its standard uncertainty
  double rate_per_year = 0;           // drift rate, unit per year
  std::optional<double> u_rate;       // its standard uncertainty (absent: see note)
  std::optional<double> residual_sd;  // sqrt(sum r^2 / (n - 2)) (unweighted residuals), n >= 3
  std::optional<double> birge_ratio;  // sqrt(chi2 / (n - 2)), weighted fit with n >= 3
  bool inflated = false;              // u_rate and u_level were scaled by the Birge ratio
  HistoryTime first{}, last{};        // first and latest sample
  double last_value = 0;              // the latest sample's value
  std::optional<ToleranceBand> band;
  std::optional<double> utilisation;  // band_utilisation(last_value), when a band is given
  LimitCrossing crossing;
  std::string note;  // what could not be determined and why ("2 samples: no uncertainty of the rate")
  // The fitted value at t.
  double at(HistoryTime t) const;
};

// Straight line through the samples in time order. Weighted least squares with weights 1/u_i^2
// when every sample states u > 0, else ordinary least squares (Bevington & Robinson 2003, eqs.
// (6.12) and (6.21)-(6.22) with the time centred at its weighted mean, which makes level and
// rate uncorrelated; NIST/SEMATECH e-Handbook 4.1.4.1 for s and the ordinary fit's
// uncertainties). Fewer than 2 samples or a single instant: no line (stated in note); 2 samples
// without stated uncertainties: a rate without uncertainty. With a band: the predicted date the
// line leaves it (see LimitCrossing). `quantity` names the series in errors: a non-finite
// value or a negative uncertainty throws InputError naming the quantity and the record.
TrendResult fit_trend(const std::vector<TrendSample>& samples, const std::optional<ToleranceBand>& band = std::nullopt,
                      const TrendOptions& o = {}, const std::string& quantity = "quantity");

// ---------------------------------------------------------------------------------------------
// Fleet ranking

// One quantity of one machine over time, with its tolerance.
struct RankSeries {
  std::string machine;
  std::string quantity;
  std::string unit;
  std::vector<TrendSample> samples;
  ToleranceBand band;
};

enum class RankOrder {
  Utilisation,  // largest share of the tolerance used first; ties: earliest predicted crossing
  TimeToLimit,  // earliest predicted crossing first (outside ones first, none last); ties: utilisation
};

struct RankOptions {
  RankOrder order = RankOrder::Utilisation;
  TrendOptions trend;
  int threads = 0;  // 0: all cores (util/parallel.hpp)
};

struct RankedQuantity {
  std::string quantity, unit;
  TrendResult trend;  // its band, utilisation and crossing included
};

struct RankedMachine {
  std::size_t rank = 0;  // 1 = needs attention first
  std::string machine;
  // The quantities with a band, the one that decides the rank first (largest utilisation).
  std::vector<RankedQuantity> quantities;
  double utilisation = 0;                // the largest over its quantities (latest values)
  std::optional<double> years_to_limit;  // the earliest predicted crossing from its latest sample
  bool outside = false;                  // some latest value is outside its band
};

struct FleetRanking {
  std::vector<RankedMachine> machines;  // in rank order
  RankOptions options;
};

// Fits every series (fit_trend) and ranks the machines: a machine's utilisation is the largest
// band_utilisation of its quantities' latest values, its time to limit the earliest predicted
// crossing (counted from each series' latest sample; a line already past its limit counts as 0).
// Series of one machine may have different dates. Throws InputError naming machine and quantity.
FleetRanking rank_fleet(const std::vector<RankSeries>& series, const RankOptions& o = {});

// A series as rank_fleet fits it: fit_trend(samples, band, o.trend) named "MACHINE QUANTITY" in errors.
struct FittedSeries {
  std::string machine, quantity, unit;
  TrendResult trend;
};
FittedSeries fit_rank_series(const RankSeries& s, const TrendOptions& o = {});
// The ranking of fitted series: rank_fleet is fit_rank_series of every series, then this. Fits
// kept from an earlier ranking (mtcal serve's fleet page refits only the machines whose records
// changed) give the same ranking as rank_fleet of all the series, in the same order.
FleetRanking rank_fitted(const std::vector<FittedSeries>& fitted, const RankOptions& o = {});

// ---------------------------------------------------------------------------------------------
// From store records

// The parameters and, separately, the figures of a record, with their uncertainties where stated.
std::vector<HistoryQuantity> parameter_quantities(const CalibrationRecord& r);
std::vector<HistoryQuantity> figure_quantities(const CalibrationRecord& r);

// Both diffs of two records: parameters and figures ("first"/"second" are the records' ids).
struct RecordDiff {
  std::string first, second;  // record ids
  CalibrationDiff parameters, figures;
};
RecordDiff diff_records(const CalibrationRecord& first, const CalibrationRecord& second, const DiffOptions& o = {});

// A store series as trend samples (times parsed with parse_history_time, located at the record).
std::vector<TrendSample> trend_samples(const std::vector<SeriesSample>& series);

// One quantity of one machine over time with its fit: what `history trend` gives per series.
struct QuantityTrend {
  std::string quantity, unit;
  bool figure = false;               // an evaluation figure, else an identified parameter
  std::vector<TrendSample> samples;  // in time order
  TrendResult trend;
};

// The trend of a store series: samples in time order and fit_trend. Throws InputError naming the
// quantity and the two records when the series changes its unit.
QuantityTrend trend_from_series(const std::string& quantity, bool figure, const std::vector<SeriesSample>& series,
                                const std::optional<ToleranceBand>& band = std::nullopt, const TrendOptions& o = {});

// What the trend report and `history trend --json` show of one machine.
struct MachineTrends {
  std::string machine, serial;
  std::vector<QuantityTrend> series;
  std::vector<Event> events;  // in date order
};

}  // namespace mtcal
