#include "mtcal/io/history/queries.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <set>

#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal {

namespace {

// A limit of the tolerance file (µm) in the unit a series is stored in; throws for a unit that is
// not a length (the file's limits are lengths).
ToleranceBand band_in_unit(const ToleranceBand& um, const std::string& unit, const std::string& quantity,
                           const std::string& file) {
  const auto per = micrometres_per(unit);
  if (!per)
    throw InputError({file, 0, quantity}, "tolerance of " + printable(quantity) +
                                              " is a length in µm, but the store "
                                              "keeps " +
                                              printable(quantity) + " in '" + printable(unit) + "'");
  return {um.lo / *per, um.hi / *per};
}

// The axes the ISO 230-2 figures of the store name ("A_X" -> X), for the tolerance file's "any".
std::vector<std::string> figure_axes(HistoryStore& store, const ToleranceFile& f) {
  std::vector<std::string> axes;
  const auto any = f.iso230_2.find("any");
  if (any == f.iso230_2.end() || any->second.limits.empty()) return axes;
  for (const char* axis : {"X", "Y", "Z", "A", "B", "C", "U", "V", "W"})
    if (!store.latest_figure(any->second.limits.front().first + "_" + axis).empty()) axes.emplace_back(axis);
  return axes;
}

// Which quantities (name, is a figure): those asked for, else every parameter and figure the records have.
std::vector<std::pair<std::string, bool>> trend_quantities(const TrendRequest& o,
                                                           const std::vector<CalibrationRecord>& records) {
  std::vector<std::pair<std::string, bool>> wanted;
  for (const auto& p : o.parameters) wanted.emplace_back(p, false);
  for (const auto& f : o.figures) wanted.emplace_back(f, true);
  if (!wanted.empty()) return wanted;
  std::set<std::string> params, figs;
  for (const auto& r : records) {
    for (const auto& p : r.parameters)
      if (params.insert(p.name).second) wanted.emplace_back(p.name, false);
    for (const auto& f : r.figures)
      if (figs.insert(f.name).second) wanted.emplace_back(f.name, true);
  }
  return wanted;
}

// The bands of the tolerance file for the figures wanted; each tolerance must name one of the quantities.
std::map<std::string, ToleranceBand> trend_file_bands(const TrendRequest& o,
                                                      const std::vector<std::pair<std::string, bool>>& wanted) {
  for (const auto& s : o.tolerances)
    if (std::none_of(wanted.begin(), wanted.end(), [&](const auto& w) { return w.first == s.quantity; }))
      throw InputError({o.tolerance_source, 0, s.quantity},
                       "tolerance of " + printable(s.quantity) + ", which is not among the quantities of the trend");
  if (o.tolerance_file.empty()) return {};
  const ToleranceFile f = read_tolerance_file(o.tolerance_file);
  std::vector<std::string> axes;
  for (const auto& [name, figure] : wanted)
    if (figure && name.size() > 2 && name[name.size() - 2] == '_') axes.push_back(name.substr(name.size() - 1));
  return history_figure_bands(f, axes);
}

// from/to: a date includes its whole day at the end of the period.
std::pair<std::optional<HistoryTime>, std::optional<HistoryTime>> trend_period(const TrendRequest& o) {
  std::pair<std::optional<HistoryTime>, std::optional<HistoryTime>> period;
  if (!o.from.empty()) period.first = parse_history_time(o.from, o.from_source, "date");
  if (!o.to.empty())
    period.second =
        parse_history_time(o.to, o.to_source, "date") + std::chrono::seconds(o.to.size() == 10 ? 86400 - 1 : 0);
  return period;
}

}  // namespace

std::vector<HistoryTolerance> parse_history_tolerances(const std::vector<std::string>& specs,
                                                       const std::string& where_name) {
  std::vector<HistoryTolerance> out;
  for (const auto& s : specs) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({where_name, 0, ""}, "expected QUANTITY=VALUE or QUANTITY=LO:HI, found '" + printable(s) + "'");
    HistoryTolerance t;
    t.quantity = s.substr(0, eq);
    const std::string value = s.substr(eq + 1);
    const SourceLocation where{where_name, 0, t.quantity};
    const auto number = [&](const std::string& text) {
      const auto v = parse_number(text);
      if (!v)
        throw InputError(where, "tolerance of " + printable(t.quantity) + ": expected a number, found '" +
                                    printable(text) + "'");
      return *v;
    };
    if (const auto colon = value.find(':'); colon != std::string::npos) {
      t.range = ToleranceBand{number(value.substr(0, colon)), number(value.substr(colon + 1))};
      check_band(*t.range, t.quantity);
    } else {
      t.limit = number(value);
      if (!(*t.limit > 0))
        throw InputError(where, "tolerance of " + printable(t.quantity) + ": expected a permitted value > 0, found " +
                                    printable(value));
    }
    for (const auto& other : out)
      if (other.quantity == t.quantity)
        throw InputError(where, "tolerance of " + printable(t.quantity) + " is given twice");
    out.push_back(t);
  }
  return out;
}

Json record_json(const CalibrationRecord& r) {
  Json j = Json::parse(record_to_json_line(r));
  j.erase("type");
  j.erase("result_json");
  j["result"] = Json::parse(r.result_json, nullptr, false);
  return j;
}

std::vector<CalibrationRecord> machine_records(HistoryStore& store, const std::string& machine) {
  RecordFilter filter;
  filter.machine = machine;
  std::vector<CalibrationRecord> records = store.list(filter);
  if (records.empty()) {
    std::string known;
    for (const auto& m : store.machines()) known += (known.empty() ? "" : ", ") + m;
    throw InputError({store.describe(), 0, "machine"}, "no records of machine '" + printable(machine) +
                                                           "' (machines in the store: " +
                                                           (known.empty() ? "none" : known) + ")");
  }
  return records;
}

MachineTrends machine_trends(HistoryStore& store, const TrendRequest& o, const std::vector<CalibrationRecord>& records) {
  const auto wanted = trend_quantities(o, records);
  const auto file_bands = trend_file_bands(o, wanted);
  const auto period = trend_period(o);
  MachineTrends m;
  m.machine = o.machine;
  m.serial = records.empty() ? std::string() : records.back().machine_serial;
  for (const auto& want : wanted) {
    // No structured bindings here: Debian's clang 14 refuses one captured by a lambda.
    const auto& name = want.first;
    const bool figure = want.second;
    auto series = figure ? store.figure_series(o.machine, name) : store.parameter_series(o.machine, name);
    const auto& from = period.first;
    const auto& to = period.second;
    std::erase_if(series, [&](const SeriesSample& s) {
      const HistoryTime at = parse_history_time(s.time, "record " + s.record_id);
      return (from && at < *from) || (to && at > *to);
    });
    if (series.empty())
      throw InputError({store.describe(), 0, name},
                       "machine '" + printable(o.machine) + "' has no " + (figure ? "figure " : "parameter ") +
                           printable(name) + (from || to ? " in the period asked for" : " in any record"));
    std::optional<ToleranceBand> band;
    const auto spec = std::find_if(o.tolerances.begin(), o.tolerances.end(),
                                   [&](const auto& s) { return s.quantity == name; });
    if (spec != o.tolerances.end())
      band = spec->band(figure);
    else if (const auto fb = file_bands.find(name); figure && fb != file_bands.end())
      band = band_in_unit(fb->second, series.front().unit, name, o.tolerance_file);
    m.series.push_back(trend_from_series(name, figure, series, band));
  }
  m.events = store.events(o.machine);
  return m;
}

// What a FleetRanker keeps per machine and quantity: the revision of the machine and the wanted
// band it was made for, and the fitted series or why it is left out.
struct FleetRanker::Entry {
  long long revision = 0;
  bool figure = false;
  ToleranceBand band;
  std::optional<FittedSeries> fitted;
  std::string note;
};

FleetRanker::FleetRanker(RankRequest request, bool lenient) : request_(std::move(request)), lenient_(lenient) {
  if (!request_.tolerance_file.empty())
    file_ = std::make_shared<const ToleranceFile>(read_tolerance_file(request_.tolerance_file));
}

std::shared_ptr<const FleetRanker::Ranking> FleetRanker::rank(HistoryStore& store) {
  const RankRequest& o = request_;
  if (o.tolerances.empty() && !file_)
    throw InputError({o.tolerance_source, 0, ""},
                     "a ranking needs tolerances: give a tolerance Q=V or a tolerance file");
  // The revisions first: a write after this read raises a revision that the next call sees, so
  // what is read below is never kept under a revision newer than its data.
  std::vector<MachineRevision> revisions = store.machine_revisions();
  if (last_ && revisions == revisions_) return last_;
  std::map<std::string, long long> revision_of;
  for (const auto& r : revisions) revision_of[r.machine] = r.revision;
  // quantity -> (figure?, band in µm for the file's figures / as given for a tolerance)
  struct Wanted {
    bool figure = false;
    ToleranceBand band;
    bool from_file = false;
  };
  std::map<std::string, Wanted> wanted;
  if (file_)
    for (const auto& [name, band] : history_figure_bands(*file_, figure_axes(store, *file_))) wanted[name] = {true, band, true};
  for (const auto& s : o.tolerances) {
    const bool parameter = !store.latest_parameter(s.quantity).empty();
    if (!parameter && store.latest_figure(s.quantity).empty()) {
      if (lenient_) continue;  // not recorded yet
      throw InputError({o.tolerance_source, 0, s.quantity},
                       "no machine in the store has a parameter or figure named " + printable(s.quantity));
    }
    wanted[s.quantity] = {!parameter, s.band(!parameter), false};
  }
  auto out = std::make_shared<Ranking>();
  std::map<std::pair<std::string, std::string>, std::shared_ptr<const Entry>> entries;
  std::vector<FittedSeries> fitted;
  for (const auto& [name, w] : wanted) {
    const auto latest = w.figure ? store.latest_figure(name) : store.latest_parameter(name);
    for (const auto& l : latest) {
      const std::pair<std::string, std::string> key{l.machine, name};
      // A machine first recorded after the revisions were read has none yet: kept under -1, read again next time.
      const auto rev = revision_of.find(l.machine);
      const long long revision = rev == revision_of.end() ? -1 : rev->second;
      std::shared_ptr<const Entry> entry;
      if (const auto kept = entries_.find(key); kept != entries_.end() && kept->second->revision == revision &&
                                                revision >= 0 && kept->second->figure == w.figure &&
                                                kept->second->band.lo == w.band.lo && kept->second->band.hi == w.band.hi)
        entry = kept->second;
      if (!entry) {
        auto e = std::make_shared<Entry>();
        e->revision = revision;
        e->figure = w.figure;
        e->band = w.band;
        ++out->fitted;
        auto samples = w.figure ? store.figure_series(l.machine, name) : store.parameter_series(l.machine, name);
        if (samples.empty()) continue;
        const std::string unit = samples.front().unit;
        try {
          const ToleranceBand band = w.from_file ? band_in_unit(w.band, unit, name, o.tolerance_file) : w.band;
          const QuantityTrend q = trend_from_series(name, w.figure, samples, band);  // unit checks, time order
          e->fitted = fit_rank_series({l.machine, name, unit, q.samples, band}, o.options.trend);
        } catch (const InputError& x) {
          if (!lenient_) throw;
          e->note = "machine " + printable(l.machine) + ": " + x.what();
        }
        entry = std::move(e);
      }
      if (entry->fitted) fitted.push_back(*entry->fitted);
      if (!entry->note.empty()) out->notes.push_back(entry->note);
      entries.emplace(key, std::move(entry));
    }
  }
  if (fitted.empty() && !lenient_) {
    std::string names;
    for (const auto& [name, w] : wanted) names += (names.empty() ? "" : ", ") + name;
    throw InputError({store.describe(), 0, ""},
                     "no machine in the store has any of the quantities with a tolerance (" + names + ")");
  }
  out->ranking = rank_fitted(fitted, o.options);
  // The machines whose fitted series (the entries, in quantity order) are not the last ranking's:
  // compared by identity while the last ranking's entries are still held in entries_.
  const auto fits_by_machine = [](const auto& map) {
    std::map<std::string, std::vector<const Entry*>> by;
    for (const auto& [key, entry] : map)
      if (entry->fitted) by[key.first].push_back(entry.get());
    return by;
  };
  const auto now_fits = fits_by_machine(entries);
  const auto last_fits = fits_by_machine(entries_);
  for (const auto& [machine, fits] : now_fits)
    if (const auto was = last_fits.find(machine); !last_ || was == last_fits.end() || was->second != fits)
      out->changed.push_back(machine);
  out->serial = ++serial_;
  entries_ = std::move(entries);
  revisions_ = std::move(revisions);
  last_ = out;
  return out;
}

StoreRanking rank_store(HistoryStore& store, const RankRequest& o) {
  StoreRanking out;
  out.ranking = FleetRanker(o, false).rank(store)->ranking;
  for (const auto& m : store.machines())
    if (std::none_of(out.ranking.machines.begin(), out.ranking.machines.end(),
                     [&](const auto& r) { return r.machine == m; }))
      out.not_ranked.push_back(m);
  return out;
}

}  // namespace mtcal
