// Calibration history analysis: diff with E_n, weighted/ordinary straight-line drift, fleet ranking.
#include "mtcal/history/analysis.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <fmt/format.h>

#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"

namespace mtcal {

namespace {

using std::chrono::seconds;

// Predicted dates further than this from the first sample are not turned into a date (a nearly
// zero rate puts the crossing ages away; an int64 of seconds would overflow first).
constexpr double kHorizonYears = 10000.0;

std::optional<HistoryTime> time_at(HistoryTime origin, double years) {
  if (!std::isfinite(years) || std::abs(years) > kHorizonYears) return std::nullopt;
  return origin + seconds(static_cast<std::int64_t>(std::llround(years * kSecondsPerYear)));
}

double years_between(HistoryTime from, HistoryTime to) {
  return static_cast<double>((to - from).count()) / kSecondsPerYear;
}

std::string num(double v) { return fmt::format("{:.6g}", v); }

void check_quantity(const HistoryQuantity& q, const std::string& record) {
  if (!std::isfinite(q.value))
    throw InputError({record, 0, q.name}, "parameter " + printable(q.name) + ": value is not a finite number");
  if (q.u && (!std::isfinite(*q.u) || *q.u < 0))
    throw InputError({record, 0, q.name}, "parameter " + printable(q.name) +
                                              ": standard uncertainty must be a finite number >= 0, found " +
                                              num(*q.u));
}

}  // namespace

HistoryTime parse_history_time(std::string_view text, const std::string& where, const std::string& field) {
  if (!is_iso8601(text))
    throw InputError({where, 0, field},
                     "expected an ISO 8601 date (2026-11-24) or date-time "
                     "(2026-11-24T10:30:00Z), found '" +
                         printable(text) + "'");
  const auto digits = [&](std::size_t at, std::size_t n) {
    int v = 0;
    for (std::size_t i = at; i < at + n; ++i) v = v * 10 + (text[i] - '0');
    return v;
  };
  using namespace std::chrono;
  const year_month_day ymd{year{digits(0, 4)}, month{static_cast<unsigned>(digits(5, 2))},
                           day{static_cast<unsigned>(digits(8, 2))}};
  HistoryTime t = time_point_cast<seconds>(sys_days{ymd});
  if (text.size() == 10) return t;
  t += hours{digits(11, 2)} + minutes{digits(14, 2)};
  std::size_t i = 16;
  if (i < text.size() && text[i] == ':') {
    t += seconds{digits(i + 1, 2)};
    i += 3;
    if (i < text.size() && (text[i] == '.' || text[i] == ',')) {
      ++i;
      while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    }
  }
  // ISO 8601-1:2019 5.3.4.2: local time = UTC + offset, so UTC = local time - offset.
  if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
    const auto offset = hours{digits(i + 1, 2)} + minutes{digits(i + 4, 2)};
    t += text[i] == '+' ? -offset : offset;
  }
  return t;
}

std::string format_history_date(HistoryTime t) {
  const auto day = std::chrono::floor<std::chrono::days>(t);
  const std::chrono::year_month_day ymd{day};
  return fmt::format("{:04d}-{:02d}-{:02d}", static_cast<int>(ymd.year()), static_cast<unsigned>(ymd.month()),
                     static_cast<unsigned>(ymd.day()));
}

std::string format_history_time(HistoryTime t) {
  const auto day = std::chrono::floor<std::chrono::days>(t);
  const auto s = (t - day).count();
  return fmt::format("{}T{:02d}:{:02d}:{:02d}Z", format_history_date(t), s / 3600, s / 60 % 60, s % 60);
}

// ---------------------------------------------------------------------------------------------

const char* to_string(ChangeVerdict v) {
  switch (v) {
    case ChangeVerdict::Significant: return "significant";
    case ChangeVerdict::NotSignificant: return "not_significant";
    case ChangeVerdict::NotAssessable: return "not_assessable";
    case ChangeVerdict::Added: return "added";
    case ChangeVerdict::Removed: return "removed";
  }
  return "?";
}

CalibrationDiff diff_calibrations(const std::vector<HistoryQuantity>& a, const std::vector<HistoryQuantity>& b,
                                  const DiffOptions& o, const std::string& first, const std::string& second) {
  if (!(o.coverage_factor > 0) || !std::isfinite(o.coverage_factor))
    throw InputError({"diff options", 0, "coverage_factor"}, "the coverage factor must be a number > 0");
  if (!(o.en_limit > 0) || !std::isfinite(o.en_limit))
    throw InputError({"diff options", 0, "en_limit"}, "the E_n limit must be a number > 0");
  auto index = [](const std::vector<HistoryQuantity>& qs, const std::string& record) {
    std::map<std::string, std::size_t> by_name;
    for (std::size_t i = 0; i < qs.size(); ++i) {
      check_quantity(qs[i], record);
      if (!by_name.emplace(qs[i].name, i).second)
        throw InputError({record, 0, qs[i].name}, "parameter " + printable(qs[i].name) + " is given twice");
    }
    return by_name;
  };
  const auto in_a = index(a, first);
  const auto in_b = index(b, second);

  CalibrationDiff d;
  d.options = o;
  for (const auto& x : a) {
    ParameterChange c;
    c.name = x.name;
    c.unit = x.unit;
    c.before = x.value;
    c.u_before = x.u;
    const auto it = in_b.find(x.name);
    if (it == in_b.end()) {
      c.verdict = ChangeVerdict::Removed;
      d.changes.push_back(std::move(c));
      continue;
    }
    const HistoryQuantity& y = b[it->second];
    c.after = y.value;
    c.u_after = y.u;
    if (x.unit != y.unit) {
      c.unit.clear();
      c.reason = "units differ: " + printable(x.unit) + " in " + first + ", " + printable(y.unit) + " in " + second;
    } else {
      c.delta = y.value - x.value;
      if (x.u && y.u) {
        // JCGM 100:2008 eq. (10) with sensitivity coefficients +-1 and no correlation.
        c.u_delta = std::hypot(*x.u, *y.u);
        const double expanded = o.coverage_factor * *c.u_delta;  // sqrt(U1^2 + U2^2), U = k u
        if (expanded > 0) {
          c.en = *c.delta / expanded;  // ISO 13528:2015 eq. (37)
          c.verdict = std::abs(*c.en) > o.en_limit ? ChangeVerdict::Significant : ChangeVerdict::NotSignificant;
        } else {
          c.reason = "both uncertainties are zero: E_n is undefined";
        }
      } else if (!x.u && !y.u) {
        c.reason = "no uncertainty in either calibration";
      } else {
        c.reason = "no uncertainty in " + (x.u ? second : first);
      }
    }
    d.changes.push_back(std::move(c));
  }
  for (const auto& y : b) {
    if (in_a.count(y.name)) continue;
    ParameterChange c;
    c.name = y.name;
    c.unit = y.unit;
    c.after = y.value;
    c.u_after = y.u;
    c.verdict = ChangeVerdict::Added;
    d.changes.push_back(std::move(c));
  }
  for (const auto& c : d.changes) switch (c.verdict) {
      case ChangeVerdict::Significant: ++d.significant; break;
      case ChangeVerdict::NotSignificant: ++d.not_significant; break;
      case ChangeVerdict::NotAssessable: ++d.not_assessable; break;
      case ChangeVerdict::Added: ++d.added; break;
      case ChangeVerdict::Removed: ++d.removed; break;
    }
  return d;
}

// ---------------------------------------------------------------------------------------------

void check_band(const ToleranceBand& b, const std::string& quantity) {
  if (std::isnan(b.lo) || std::isnan(b.hi) || !std::isfinite(b.hi))
    throw InputError({"tolerance", 0, quantity}, "tolerance of " + printable(quantity) +
                                                     ": the upper limit must be a finite number, found " + num(b.hi));
  if (!(b.lo < b.hi))
    throw InputError({"tolerance", 0, quantity}, "tolerance of " + printable(quantity) +
                                                     ": the lower limit must be below the upper limit, found [" +
                                                     num(b.lo) + ", " + num(b.hi) + "]");
  if (b.one_sided() && !(b.hi > 0))
    throw InputError({"tolerance", 0, quantity},
                     "tolerance of " + printable(quantity) + ": a permitted value must be > 0, found " + num(b.hi));
}

double band_utilisation(double v, const ToleranceBand& b) {
  if (b.one_sided()) return v / b.hi;
  const double mid = 0.5 * (b.lo + b.hi), half = 0.5 * (b.hi - b.lo);
  return std::abs(v - mid) / half;
}

const char* to_string(TrendFitKind k) {
  switch (k) {
    case TrendFitKind::None: return "none";
    case TrendFitKind::Weighted: return "weighted";
    case TrendFitKind::Ordinary: return "ordinary";
  }
  return "?";
}

const char* to_string(CrossingStatus s) {
  switch (s) {
    case CrossingStatus::NoFit: return "no_fit";
    case CrossingStatus::NoTolerance: return "no_tolerance";
    case CrossingStatus::AlreadyOutside: return "already_outside";
    case CrossingStatus::NotTowardsLimit: return "not_towards_limit";
    case CrossingStatus::Predicted: return "predicted";
  }
  return "?";
}

double TrendResult::at(HistoryTime t) const { return level + rate_per_year * years_between(t_ref, t); }

namespace {

TrendResult fit_sorted(const std::vector<TrendSample>& samples, const std::optional<ToleranceBand>& band,
                       const TrendOptions& o, bool weighted, const std::string& zero_u);

}  // namespace

TrendResult fit_trend(const std::vector<TrendSample>& samples, const std::optional<ToleranceBand>& band,
                      const TrendOptions& o, const std::string& quantity) {
  if (!(o.coverage_factor > 0) || !std::isfinite(o.coverage_factor))
    throw InputError({"trend options", 0, "coverage_factor"}, "the coverage factor must be a number > 0");
  if (band) check_band(*band, quantity);
  bool weighted = !samples.empty();
  std::string zero_u;
  for (const auto& s : samples) {
    if (!std::isfinite(s.value))
      throw InputError({s.record, 0, quantity},
                       printable(quantity) + " in record " + printable(s.record) + ": value is not a finite number");
    if (s.u && (!std::isfinite(*s.u) || *s.u < 0))
      throw InputError({s.record, 0, quantity}, printable(quantity) + " in record " + printable(s.record) +
                                                    ": standard uncertainty must be a finite number >= 0, found " +
                                                    num(*s.u));
    if (!s.u) weighted = false;
    if (s.u && *s.u == 0) {
      weighted = false;
      if (zero_u.empty()) zero_u = s.record;
    }
  }
  const auto earlier = [](const TrendSample& x, const TrendSample& y) { return x.at < y.at; };
  if (std::is_sorted(samples.begin(), samples.end(), earlier)) return fit_sorted(samples, band, o, weighted, zero_u);
  std::vector<TrendSample> sorted = samples;
  std::stable_sort(sorted.begin(), sorted.end(), earlier);
  return fit_sorted(sorted, band, o, weighted, zero_u);
}

namespace {

TrendResult fit_sorted(const std::vector<TrendSample>& samples, const std::optional<ToleranceBand>& band,
                       const TrendOptions& o, bool weighted, const std::string& zero_u) {
  TrendResult r;
  r.n = samples.size();
  r.band = band;
  if (samples.empty()) {
    r.note = "no samples";
    r.crossing.status = band ? CrossingStatus::NoFit : CrossingStatus::NoTolerance;
    return r;
  }
  r.first = samples.front().at;
  r.last = samples.back().at;
  r.last_value = samples.back().value;
  if (band) r.utilisation = band_utilisation(r.last_value, *band);

  const std::size_t n = samples.size();
  const HistoryTime origin = r.first;
  if (n < 2 || r.first == r.last) {
    r.note = n < 2 ? "1 sample: no line (2 needed)" : "every sample at one instant: no line";
    r.level = samples.back().value;
    r.t_ref = r.last;
  } else {
    // Bevington & Robinson 2003 eq. (6.12) with weights w_i (1/u_i^2, or 1) and the time centred
    // at its weighted mean tm: rate = sum w (t - tm) y / Sxx, level = sum w y / W, and (6.21)-(6.22)
    // u(rate)^2 = 1 / Sxx, u(level)^2 = 1 / W for the weighted fit; Cov(level, rate) = 0.
    // Times and weights once per sample (a fleet ranking fits thousands of series: no allocation
    // per fit once a thread's buffers have grown).
    thread_local std::vector<double> t_buffer, w_buffer;
    t_buffer.resize(n);
    w_buffer.resize(n);
    double W = 0, tw = 0, yw = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double ti = years_between(origin, samples[i].at);
      const double wi = weighted ? 1.0 / (*samples[i].u * *samples[i].u) : 1.0;
      t_buffer[i] = ti;
      w_buffer[i] = wi;
      W += wi;
      tw += wi * ti;
      yw += wi * samples[i].value;
    }
    const auto t = [&](std::size_t i) { return t_buffer[i]; };
    const auto w = [&](std::size_t i) { return w_buffer[i]; };
    const double tm = tw / W, level = yw / W;
    double sxx = 0, sxy = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double dt = t(i) - tm, wi = w(i);
      sxx += wi * dt * dt;
      sxy += wi * dt * (samples[i].value - level);
    }
    const double rate = sxy / sxx;
    double chi2 = 0, rss = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double res = samples[i].value - level - rate * (t(i) - tm);
      rss += res * res;
      chi2 += w(i) * res * res;
    }
    r.kind = weighted ? TrendFitKind::Weighted : TrendFitKind::Ordinary;
    r.t_ref = *time_at(origin, tm);
    // The rounding of t_ref to a whole second moves the level along the line.
    r.level = level + rate * (years_between(origin, r.t_ref) - tm);
    r.rate_per_year = rate;
    const double dof = static_cast<double>(n) - 2.0;
    if (n >= 3) r.residual_sd = std::sqrt(rss / dof);
    if (weighted) {
      r.u_rate = 1.0 / std::sqrt(sxx);
      r.u_level = 1.0 / std::sqrt(W);
      if (n >= 3) {
        r.birge_ratio = std::sqrt(chi2 / dof);
        if (o.inflate_by_birge_ratio && *r.birge_ratio > 1) {
          *r.u_rate *= *r.birge_ratio;
          *r.u_level *= *r.birge_ratio;
          r.inflated = true;
        }
      } else {
        r.note =
            "2 samples: the rate's uncertainty comes from their stated uncertainties alone (the scatter is "
            "not checked)";
      }
    } else {
      // NIST/SEMATECH e-Handbook 4.1.4.1 (and Bevington & Robinson eq. (6.23)): s^2 = RSS / (n - 2),
      // u(rate) = s / sqrt(Sxx), u(level at the mean time) = s / sqrt(n).
      const bool none = std::none_of(samples.begin(), samples.end(), [](const auto& x) { return x.u.has_value(); });
      const std::string why = !zero_u.empty() ? "record " + printable(zero_u) + " states a zero uncertainty"
                              : none          ? std::string("no sample states an uncertainty")
                                              : std::string("not every sample states an uncertainty");
      if (n >= 3) {
        const double s = std::sqrt(rss / dof);
        r.u_rate = s / std::sqrt(sxx);
        r.u_level = s / std::sqrt(static_cast<double>(n));
        r.note = why + ": ordinary least squares, uncertainty from the scatter about the line";
      } else {
        r.note = why + ": ordinary least squares; 2 samples give no uncertainty of the rate (3 needed)";
      }
    }
  }

  // Where the line leaves the band.
  LimitCrossing& c = r.crossing;
  if (!band) {
    c.status = CrossingStatus::NoTolerance;
    return r;
  }
  if (!band->contains(r.last_value)) {
    c.status = CrossingStatus::AlreadyOutside;
    c.limit = r.last_value > band->hi ? band->hi : band->lo;
    return r;
  }
  if (r.kind == TrendFitKind::None) {
    c.status = CrossingStatus::NoFit;
    return r;
  }
  const double rate = r.rate_per_year;
  const double limit = rate > 0 ? band->hi : band->lo;
  if (rate == 0 || !std::isfinite(limit)) {
    c.status = CrossingStatus::NotTowardsLimit;
    return r;
  }
  c.status = CrossingStatus::Predicted;
  c.limit = limit;
  // The line turns about (t_ref, level): with rate r' it reaches the limit at t_ref + (L - level) / r'.
  const double tref = years_between(origin, r.t_ref);
  const double reach = (limit - r.level) / rate;
  c.date = time_at(origin, tref + reach);
  c.years_from_last = tref + reach - years_between(origin, r.last);
  if (r.u_rate) {
    const double sign = rate > 0 ? 1.0 : -1.0;
    const double fast = rate + sign * o.coverage_factor * *r.u_rate;
    const double slow = rate - sign * o.coverage_factor * *r.u_rate;
    const double t_fast = tref + (limit - r.level) / fast;
    if (slow * sign > 0) {
      const double t_slow = tref + (limit - r.level) / slow;
      c.earliest = time_at(origin, std::min(t_fast, t_slow));
      c.latest = time_at(origin, std::max(t_fast, t_slow));
    } else {
      // The slower rate stops or turns back: the limit may never be reached.
      c.earliest = time_at(origin, t_fast);
    }
  }
  if (!c.date)
    r.note += std::string(r.note.empty() ? "" : "; ") + "the line reaches the limit more than " +
              fmt::format("{:g}", kHorizonYears) + " years away";
  return r;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

namespace {
void check_rank_samples(const RankSeries& s) {
  if (s.samples.empty())
    throw InputError({s.machine, 0, s.quantity}, "machine " + printable(s.machine) + ": no samples of " + printable(s.quantity));
}
}  // namespace

FittedSeries fit_rank_series(const RankSeries& s, const TrendOptions& o) {
  check_rank_samples(s);
  return {s.machine, s.quantity, s.unit, fit_trend(s.samples, s.band, o, s.machine + " " + s.quantity)};
}

FleetRanking rank_fleet(const std::vector<RankSeries>& series, const RankOptions& o) {
  for (const auto& s : series) check_rank_samples(s);  // before any fit, as before
  std::vector<FittedSeries> fitted(series.size());
  parallel_for(series.size(), o.threads,
               [&](std::size_t i, std::size_t) { fitted[i] = fit_rank_series(series[i], o.trend); });
  return rank_fitted(fitted, o);
}

FleetRanking rank_fitted(const std::vector<FittedSeries>& series, const RankOptions& o) {
  std::map<std::string, std::size_t> index;  // machine -> position in the result
  FleetRanking out;
  out.options = o;
  for (std::size_t i = 0; i < series.size(); ++i) {
    const auto [it, inserted] = index.emplace(series[i].machine, out.machines.size());
    if (inserted) {
      out.machines.emplace_back();
      out.machines.back().machine = series[i].machine;
    }
    RankedMachine& m = out.machines[it->second];
    const TrendResult& f = series[i].trend;
    std::optional<double> years;
    if (f.crossing.status == CrossingStatus::AlreadyOutside)
      years = 0.0;
    else if (f.crossing.status == CrossingStatus::Predicted && f.crossing.years_from_last)
      years = std::max(0.0, *f.crossing.years_from_last);
    if (years && (!m.years_to_limit || *years < *m.years_to_limit)) m.years_to_limit = years;
    const double u = *f.utilisation;
    if (m.quantities.empty() || u > m.utilisation) m.utilisation = u;
    if (f.crossing.status == CrossingStatus::AlreadyOutside) m.outside = true;
    m.quantities.push_back({series[i].quantity, series[i].unit, f});
  }
  for (auto& m : out.machines)
    std::stable_sort(m.quantities.begin(), m.quantities.end(),
                     [](const auto& x, const auto& y) { return *x.trend.utilisation > *y.trend.utilisation; });

  const auto years_less = [](const std::optional<double>& x, const std::optional<double>& y) {
    if (x && y) return *x < *y;
    return x.has_value() && !y.has_value();  // a predicted crossing before none
  };
  std::stable_sort(out.machines.begin(), out.machines.end(), [&](const RankedMachine& x, const RankedMachine& y) {
    if (o.order == RankOrder::Utilisation) {
      if (x.utilisation != y.utilisation) return x.utilisation > y.utilisation;
      if (years_less(x.years_to_limit, y.years_to_limit) || years_less(y.years_to_limit, x.years_to_limit))
        return years_less(x.years_to_limit, y.years_to_limit);
    } else {
      if (years_less(x.years_to_limit, y.years_to_limit) || years_less(y.years_to_limit, x.years_to_limit))
        return years_less(x.years_to_limit, y.years_to_limit);
      if (x.utilisation != y.utilisation) return x.utilisation > y.utilisation;
    }
    return x.machine < y.machine;
  });
  for (std::size_t i = 0; i < out.machines.size(); ++i) out.machines[i].rank = i + 1;
  return out;
}

// ---------------------------------------------------------------------------------------------

std::vector<HistoryQuantity> parameter_quantities(const CalibrationRecord& r) {
  std::vector<HistoryQuantity> out;
  for (const auto& p : r.parameters) out.push_back({p.name, p.value, p.uncertainty, p.unit});
  return out;
}

std::vector<HistoryQuantity> figure_quantities(const CalibrationRecord& r) {
  std::vector<HistoryQuantity> out;
  for (const auto& f : r.figures) out.push_back({f.name, f.value, f.uncertainty, f.unit});
  return out;
}

RecordDiff diff_records(const CalibrationRecord& first, const CalibrationRecord& second, const DiffOptions& o) {
  RecordDiff d;
  d.first = first.id;
  d.second = second.id;
  const std::string a = "record " + first.id, b = "record " + second.id;
  d.parameters = diff_calibrations(parameter_quantities(first), parameter_quantities(second), o, a, b);
  d.figures = diff_calibrations(figure_quantities(first), figure_quantities(second), o, a, b);
  return d;
}

std::vector<TrendSample> trend_samples(const std::vector<SeriesSample>& series) {
  std::vector<TrendSample> out;
  out.reserve(series.size());
  for (const auto& s : series)
    out.push_back({parse_history_time(s.time, "record " + s.record_id), s.value, s.uncertainty, s.record_id});
  return out;
}

QuantityTrend trend_from_series(const std::string& quantity, bool figure, const std::vector<SeriesSample>& series,
                                const std::optional<ToleranceBand>& band, const TrendOptions& o) {
  QuantityTrend q;
  q.quantity = quantity;
  q.figure = figure;
  for (std::size_t i = 0; i < series.size(); ++i) {
    if (i == 0) q.unit = series[i].unit;
    if (series[i].unit != q.unit)
      throw InputError({"record " + series[i].record_id, 0, quantity},
                       printable(quantity) + " is in " + printable(q.unit) + " in record " +
                           printable(series[0].record_id) + " but in " + printable(series[i].unit) + " in record " +
                           printable(series[i].record_id) + ": a trend needs one unit");
  }
  q.samples = trend_samples(series);
  std::stable_sort(q.samples.begin(), q.samples.end(), [](const auto& x, const auto& y) { return x.at < y.at; });
  q.trend = fit_trend(q.samples, band, o, quantity);
  return q;
}

}  // namespace mtcal
