// mtcal history diff | trend | rank: what changed, drift over time, and the fleet ranked, from the history store.
#include <algorithm>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/history/analysis.hpp"
#include "mtcal/io/instruments/acceptance_files.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/json/history_json.hpp"
#include "mtcal/io/history/queries.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/report/history.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

std::string num(double v) { return fmt::format("{:.4g}", v); }
std::string with_u(const std::optional<double>& v, const std::optional<double>& u) {
  if (!v) return "-";
  return u ? fmt::format("{} ± {}", num(*v), num(*u)) : num(*v);
}

// ---------------------------------------------------------------------------------------------
// The store and the tolerances

// --store, else $MTCAL_HISTORY, else history.store of the configuration file (cmd_history.cpp).
std::unique_ptr<HistoryStore> open_store(const std::string& option) { return open_cli_store(option); }

// ---------------------------------------------------------------------------------------------
// diff

struct DiffCliOptions {
  std::string store, first, second;
  double k = 2.0;
  bool json_out = false;
};

void print_diff_part(const std::string& title, const CalibrationDiff& d) {
  if (d.changes.empty()) return;
  std::size_t w = 9;
  for (const auto& c : d.changes) w = std::max(w, c.name.size());
  std::cout << fmt::format("{}\n{:<{}} {:>6} {:>20} {:>20} {:>20} {:>8}  {}\n", title, "name", w, "unit", "before ± u",
                           "after ± u", "change ± u", "E_n", "verdict");
  for (const auto& c : d.changes) {
    std::string verdict = to_string(c.verdict);
    std::replace(verdict.begin(), verdict.end(), '_', ' ');
    if (!c.reason.empty()) verdict += " (" + c.reason + ")";
    std::cout << fmt::format("{:<{}} {:>6} {:>20} {:>20} {:>20} {:>8}  {}\n", c.name, w, c.unit,
                             with_u(c.before, c.u_before), with_u(c.after, c.u_after), with_u(c.delta, c.u_delta),
                             c.en ? fmt::format("{:.2f}", *c.en) : std::string("-"), verdict);
  }
  std::cout << fmt::format("{} significant, {} not significant, {} not assessable, {} added, {} removed\n",
                           d.significant, d.not_significant, d.not_assessable, d.added, d.removed);
}

int run_diff(const DiffCliOptions& o) {
  auto store = open_store(o.store);
  auto get = [&](const std::string& id) {
    auto r = store->get(id);
    if (!r) throw InputError({store->describe(), 0, "id"}, "no record '" + printable(id) + "' in the store");
    return *r;
  };
  const CalibrationRecord a = get(o.first), b = get(o.second);
  DiffOptions d;
  d.coverage_factor = o.k;
  const RecordDiff diff = diff_records(a, b, d);
  if (a.machine_name != b.machine_name)
    warn("records " + a.id + " and " + b.id + " are of different machines (" + a.machine_name + ", " + b.machine_name +
         ")");
  if (o.json_out) {
    Json j = to_json(diff);
    j["machines"] = {a.machine_name, b.machine_name};
    j["measured_at"] = {a.measured_at, b.measured_at};
    print_json(j);
    return 0;
  }
  std::cout << fmt::format("record {} ({}, {}, {}) -> record {} ({}, {}, {})\n", a.id, a.machine_name, a.measured_at,
                           a.command, b.id, b.machine_name, b.measured_at, b.command);
  std::cout << fmt::format("significant: |E_n| > 1, E_n = change / sqrt(U1² + U2²), U = {:g} u\n", o.k);
  print_diff_part("parameters", diff.parameters);
  print_diff_part("figures", diff.figures);
  if (diff.parameters.changes.empty() && diff.figures.changes.empty())
    std::cout << "neither record has parameters or figures\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// trend

struct TrendCliOptions {
  std::string store, machine, report, tolerance_file, from, to;
  std::vector<std::string> parameters, figures, tolerances;
  bool json_out = false;
};

std::string crossing_line(const TrendResult& t) {
  const LimitCrossing& c = t.crossing;
  switch (c.status) {
    case CrossingStatus::NoTolerance: return "no tolerance given";
    case CrossingStatus::NoFit: return "no line";
    case CrossingStatus::AlreadyOutside: return "already outside at the latest calibration";
    case CrossingStatus::NotTowardsLimit: return "not drifting towards a limit";
    case CrossingStatus::Predicted: break;
  }
  if (!c.date) return "beyond 10,000 years";
  std::string s = "leaves it " + format_history_date(*c.date);
  if (c.earliest)
    s += fmt::format(" (between {} and {})", format_history_date(*c.earliest),
                     c.latest ? format_history_date(*c.latest) : std::string("possibly never"));
  if (c.years_from_last && *c.years_from_last < 0) s += ", the fitted line is already past the limit";
  return s;
}

TrendRequest trend_request(const TrendCliOptions& o) {
  TrendRequest r;
  r.machine = o.machine;
  r.parameters = o.parameters;
  r.figures = o.figures;
  r.tolerances = parse_history_tolerances(o.tolerances, "--tolerance");
  r.tolerance_file = o.tolerance_file;
  r.from = o.from;
  r.to = o.to;
  r.tolerance_source = "--tolerance";
  r.from_source = "--from";
  r.to_source = "--to";
  return r;
}

void print_trends(const MachineTrends& m, const std::vector<CalibrationRecord>& records) {
  std::cout << fmt::format("machine {}{}: {} calibrations from {} to {}, {} events\n", m.machine,
                           m.serial.empty() ? "" : " (serial " + m.serial + ")", records.size(),
                           records.front().measured_at, records.back().measured_at, m.events.size());
  for (const auto& q : m.series) {
    const TrendResult& t = q.trend;
    std::cout << fmt::format("{} ({}, {}): {} samples, latest {} {} on {}", q.quantity,
                             q.figure ? "figure" : "parameter", q.unit, t.n, num(t.last_value), q.unit,
                             format_history_date(t.last));
    if (t.kind != TrendFitKind::None)
      std::cout << fmt::format("; drift {} {}/year ({} fit)", with_u(t.rate_per_year, t.u_rate), q.unit,
                               to_string(t.kind));
    std::cout << "\n";
    if (t.band)
      std::cout << fmt::format("  tolerance {}: {:.0f} % used, {}\n",
                               t.band->one_sided()         ? fmt::format("<= {}", num(t.band->hi))
                               : t.band->lo == -t.band->hi ? fmt::format("|value| <= {}", num(t.band->hi))
                                                           : fmt::format("[{}, {}]", num(t.band->lo), num(t.band->hi)),
                               100 * *t.utilisation, crossing_line(t));
    if (!t.note.empty()) std::cout << "  note: " << t.note << "\n";
  }
  for (const auto& e : m.events) std::cout << fmt::format("event {} {}: {}\n", e.date, to_string(e.kind), e.note);
}

int run_trend(const TrendCliOptions& o) {
  check_outputs({o.tolerance_file}, {o.report});
  if (!o.report.empty()) AtomicFile check(o.report);  // refuse a bad report path before the work
  auto store = open_store(o.store);
  const std::vector<CalibrationRecord> records = machine_records(*store, o.machine);
  const MachineTrends m = machine_trends(*store, trend_request(o), records);
  if (!o.report.empty()) write_trend_report(o.report, command_line(), m, records, store->describe());
  if (o.json_out) {
    Json j = to_json(m);
    if (!o.report.empty()) j["report"] = o.report;
    print_json(j);
    return 0;
  }
  print_trends(m, records);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// rank

struct RankCliOptions {
  std::string store, tolerance_file, by = "utilisation";
  std::vector<std::string> tolerances;
  int threads = 0;
  bool json_out = false;
};

int run_rank(const RankCliOptions& o) {
  check_outputs({o.tolerance_file}, {});
  if (o.tolerances.empty() && o.tolerance_file.empty())
    throw InputError({"--tolerance", 0, ""}, "a ranking needs tolerances: give --tolerance Q=V or --tolerance-file");
  RankRequest request;
  request.tolerances = parse_history_tolerances(o.tolerances, "--tolerance");
  request.tolerance_file = o.tolerance_file;
  request.options.threads = o.threads;
  request.options.order = o.by == "time" ? RankOrder::TimeToLimit : RankOrder::Utilisation;
  request.tolerance_source = "--tolerance";
  auto store = open_store(o.store);
  const StoreRanking ranked = rank_store(*store, request);
  const FleetRanking& ranking = ranked.ranking;
  const std::vector<std::string>& unranked = ranked.not_ranked;
  if (o.json_out) {
    Json j = to_json(ranking);
    j["not_ranked"] = unranked;
    print_json(j);
    return 0;
  }
  std::size_t w = 7;
  for (const auto& m : ranking.machines) w = std::max(w, m.machine.size());
  std::cout << fmt::format("{:>4}  {:<{}} {:>7} {:>16}  {}\n", "rank", "machine", w, "used", "years to limit",
                           "deciding quantity: latest, tolerance, drift/year");
  for (const auto& m : ranking.machines) {
    const RankedQuantity& q = m.quantities.front();
    const TrendResult& t = q.trend;
    const std::string years = m.outside          ? std::string("0 (outside)")
                              : m.years_to_limit ? fmt::format("{:.2f}", *m.years_to_limit)
                                                 : std::string("-");
    std::cout << fmt::format("{:>4}  {:<{}} {:>6.0f}% {:>16}  {}: {} {} on {}, {}, {}\n", m.rank, m.machine, w,
                             100 * m.utilisation, years, q.quantity, num(t.last_value), q.unit,
                             format_history_date(t.last),
                             t.band->one_sided() ? fmt::format("<= {}", num(t.band->hi))
                                                 : fmt::format("[{}, {}]", num(t.band->lo), num(t.band->hi)),
                             t.kind == TrendFitKind::None ? std::string("no drift fit")
                                                          : with_u(t.rate_per_year, t.u_rate));
  }
  if (!unranked.empty()) {
    std::string names;
    for (const auto& m : unranked) names += (names.empty() ? "" : ", ") + m;
    std::cout << "not ranked (no quantity with a tolerance): " << names << "\n";
  }
  return 0;
}

}  // namespace

std::vector<Command> add_history_analysis_commands(CLI::App& history) {
  const char* store_help =
      "The history store: a SQLite file, sqlite:PATH or postgresql://user@host/db; default $MTCAL_HISTORY, then "
      "history.store in the configuration file";
  auto d = std::make_shared<DiffCliOptions>();
  auto* diff = history.add_subcommand(
      "diff",
      "What changed between two calibrations, parameter by parameter: change = x2 - x1 with u = sqrt(u1² + u2²) "
      "(GUM), E_n = change / sqrt(U1² + U2²) with U = 2u; significant when |E_n| > 1; a parameter without "
      "uncertainty is 'not assessable'; figures the same (most state no uncertainty)");
  diff->add_option("ID1", d->first, "The earlier record's id (mtcal history list)")->required();
  diff->add_option("ID2", d->second, "The later record's id")->required();
  diff->add_option("--store", d->store, store_help);
  diff->add_option("--coverage-factor", d->k, "k of the expanded uncertainties U = k u in E_n (default 2)")
      ->check(CLI::PositiveNumber & kFinite);
  diff->add_flag("--json", d->json_out,
                 "Machine-readable output: first, second, coverage_factor, en_limit, parameters and figures "
                 "{summary, changes: [{name, unit, before, u_before, after, u_after, delta, u_delta, en, verdict, "
                 "reason}]}, machines, measured_at");
  diff->footer(
      "Examples:\n"
      "  mtcal history diff 12 15 --store shop.db\n"
      "  mtcal history diff 12 15 --store postgresql://mtcal@db.example/fleet --json\n");

  auto t = std::make_shared<TrendCliOptions>();
  auto* trend = history.add_subcommand(
      "trend",
      "Drift of parameters or figures of one machine over time: a straight line weighted by 1/u² (ordinary least "
      "squares where a calibration states no u), the drift rate per year with its uncertainty, and the date the "
      "line leaves the tolerance with an interval from rate ± 2u(rate)");
  trend->add_option("--machine", t->machine, "The machine's name as recorded")->required();
  trend->add_option("--parameter", t->parameters, "An identified parameter (ISO 230 name, e.g. EC0Y); repeatable");
  trend->add_option("--figure", t->figures, "An evaluation figure (e.g. A_X, G, VA); repeatable. Neither: all of both");
  trend->add_option("--tolerance", t->tolerances,
                    "Q=V: |value| <= V for a parameter, value <= V for a figure; Q=LO:HI: LO <= value <= HI; in the "
                    "quantity's recorded unit; repeatable");
  trend->add_option("--tolerance-file", t->tolerance_file,
                    "Acceptance tolerance YAML (docs/reports.md): limits of the figures (ISO 230-2 Q of axis X as "
                    "Q_X, G, VA ...), µm converted to the recorded unit");
  trend->add_option("--from", t->from, "Only calibrations measured at or after this ISO 8601 date (or date-time)");
  trend->add_option("--to", t->to, "Only calibrations measured up to this date (inclusive) or date-time");
  trend->add_option("--report", t->report,
                    "Write an HTML trend report: a timeline per quantity with ±2u bands, tolerance lines, the drift "
                    "line and predicted crossing, events; the calibrations' metadata");
  trend->add_option("--store", t->store, store_help);
  trend->add_flag("--json", t->json_out,
                  "Machine-readable output: machine, serial, series [{quantity, kind, unit, samples, trend {n, fit, "
                  "rate_per_year, u_rate_per_year, tolerance, utilisation, crossing {status, date, earliest, latest} "
                  "...}}], events");
  trend->footer(
      "Examples:\n"
      "  mtcal history trend --machine HU40T --parameter EC0Y --tolerance EC0Y=50 --store shop.db\n"
      "  mtcal history trend --machine HU40T --figure A_X --tolerance-file examples/acceptance/tolerances.yaml "
      "--report trend.html\n"
      "  mtcal history trend --machine HU40T --json\n");

  auto r = std::make_shared<RankCliOptions>();
  auto* rank = history.add_subcommand(
      "rank",
      "The machines of the store ranked by how far they are from tolerance: the largest share of a tolerance "
      "their latest values use (|value| / T), then the earliest predicted date a drift line leaves it");
  rank->add_option("--tolerance", r->tolerances,
                   "Q=V or Q=LO:HI as for trend (a parameter: |value| <= V; a figure: value <= V); repeatable");
  rank->add_option("--tolerance-file", r->tolerance_file,
                   "Acceptance tolerance YAML: its figures' limits (ISO 230-2 per axis and 'any', ISO 230-4, "
                   "volumetric)");
  rank->add_option("--by", r->by,
                   "utilisation (default): share of the tolerance used; time: earliest predicted crossing first")
      ->check(CLI::IsMember({"utilisation", "time"}));
  rank->add_option("--threads", r->threads, "Threads for the fits (0: all cores)")->check(CLI::NonNegativeNumber);
  rank->add_option("--store", r->store, store_help);
  rank->add_flag("--json", r->json_out,
                 "Machine-readable output: order, machines [{rank, machine, utilisation, years_to_limit, outside, "
                 "quantities [{quantity, unit, latest, latest_at, tolerance, utilisation, n, rate_per_year, "
                 "u_rate_per_year, crossing}]}], not_ranked");
  rank->footer(
      "Examples:\n"
      "  mtcal history rank --tolerance-file examples/acceptance/tolerances.yaml --store shop.db\n"
      "  mtcal history rank --tolerance EC0Y=50 --tolerance EXX=0.01 --by time --json\n");
  return {{diff, [d] { return run_diff(*d); }}, {trend, [t] { return run_trend(*t); }}, {rank, [r] {
                                                                                           return run_rank(*r);
                                                                                         }}};
}

}  // namespace mtcal::cli
