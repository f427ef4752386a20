// mtcal volumetric, contributions, diagonals: volumetric accuracy of a machine model (Fletcher
// 2009; ISO 230-6 diagonals).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "budget.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/volumetric_study.hpp"
#include "mtcal/evaluation/volumetric_tolerance.hpp"
#include "mtcal/io/points/error_csv.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/io/json/acceptance_json.hpp"
#include "mtcal/io/json/volumetric_json.hpp"
#include "mtcal/report/volumetric.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parallel.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

using Clock = std::chrono::steady_clock;

// mm as um with 3 decimals; what rounds to zero prints as 0.000, never -0.000.
std::string um(double mm) { return fmt::format("{:.3f}", std::abs(mm) < 5e-7 ? 0.0 : mm * 1e3); }

std::vector<double> config(const ErrorMap& map, std::size_t i) {
  const auto q = map.configuration(i);
  return {q.begin(), q.end()};
}

// Where the configurations come from: a grid or a CSV file; and the map they give.
struct MapSource {
  std::string grid, points;
  bool no_travel_check = false, grid_kernel = false;
  int threads = 0;
};

void add_map_options(CLI::App* c, MapSource& s) {
  c->add_option("--grid", s.grid,
                "Grid over the volume, e.g. \"X=0:500:21,Y=0:400:21,Z=-300:0:21\" (lo:hi:count per axis, mm and deg; "
                "a single value holds an axis; axes not named are at 0)");
  c->add_option("--points", s.points,
                "CSV of configurations instead of a grid: columns named by axis letters (mm, deg), optional "
                "dir<axis> (+1/-1)");
  c->add_flag("--no-travel-check", s.no_travel_check, "Allow configurations outside the axes' travels");
  c->add_option("--threads", s.threads, "Threads (0: all cores)")->check(CLI::Range(0, 1024));
  c->add_flag("--grid-kernel", s.grid_kernel,
              "Evaluate a --grid with the grid kernel (each axis' transform once per grid value; about 4x faster, "
              "errors equal to the configuration-by-configuration ones to 1e-12 mm rather than bit for bit)");
}

// The configurations of a --grid or --points run, and the source that streams them (it refers to
// them: held behind a pointer so that they never move).
struct Configurations {
  GridValues grid;
  ConfigurationList list;
  ConfigurationSource source;
};

std::unique_ptr<Configurations> configurations(const Machine& m, const MapSource& s) {
  if (!s.grid.empty() == !s.points.empty())
    throw InputError({"--grid", 0, ""}, "expected exactly one of --grid, --points");
  auto c = std::make_unique<Configurations>();
  if (!s.grid.empty()) {
    // The exact VA indexes configurations with 32 bits; time, not memory, is the limit below that.
    c->grid = checked_grid(m, s.grid, !s.no_travel_check);
    c->source = ConfigurationSource::grid(c->grid);
  } else {
    c->list = read_configurations(m, s.points, !s.no_travel_check);
    if (c->list.size() == 0) throw InputError({s.points, 0, ""}, "expected at least one configuration, found none");
    c->source = ConfigurationSource::list(c->list);
  }
  return c;
}

// Configurations per second and thread of one streamed pass (evaluation, extremes, candidates)
// on the 5-axis HU40T example, measured with BM_VolumetricStream (bench/bench_volumetric.cpp:
// 3.7 M/s configuration by configuration, 15.7 M/s with the grid kernel), rounded down: the
// estimate errs long.
constexpr double kStreamedPerSecond = 3e6, kStreamedGridPerSecond = 12e6;

// The time of `maps` streamed maps of two passes each, checked against --max-time and shown on a
// terminal before the work; bytes: what is held besides (the vectors of a histogram or grouping).
void check_streamed(const std::string& what, const MapSource& s, const ConfigurationSource& source, double maps,
                    double bytes, double output_bytes) {
  const double count = static_cast<double>(source.size());
  const double threads = static_cast<double>(worker_count(s.threads, source.size()));
  const double rate = s.grid_kernel && source.grid_values() ? kStreamedGridPerSecond : kStreamedPerSecond;
  const double seconds = 2 * maps * count / rate / threads;
  const std::string label =
      fmt::format("{} over {:.4g} configurations ({:.0f} pass{})", what, count, 2 * maps, 2 * maps > 1 ? "es" : "");
  check_estimate({label, bytes, seconds, output_bytes});
  if (seconds > 2 && ::isatty(STDERR_FILENO))
    std::cerr << fmt::format("  {}: about {} on {:.0f} thread{}\n", label, format_seconds(seconds), threads,
                             threads > 1 ? "s" : "");
}

StreamOptions stream_options(const MapSource& s, Progress& progress) {
  StreamOptions so;
  so.threads = s.threads;
  so.grid_kernel = s.grid_kernel;
  if (progress.active())
    so.progress = [&progress](std::size_t done, std::size_t total) { progress.update(done, total); };
  return so;
}

ReportSources sources(const ModelOptions& model, const MapSource& s) {
  return {command_line(), model.params, s.points, s.grid};
}

void print_contributions(const ContributionAnalysis& c, std::size_t top) {
  std::cout << fmt::format("  {:<6} {:>10} {:>10} {:>10} {:>11} {:>8}\n", "error", "dx um", "dy um", "dz um",
                           "along um", "share");
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    const auto& it = c.items[k];
    std::cout << fmt::format("  {:<6} {:>10} {:>10} {:>10} {:>11} {:>7.1f}%\n", it.error.str(), um(it.effect.x()),
                             um(it.effect.y()), um(it.effect.z()), um(it.along), it.share * 100);
  }
  if (c.items.size() > top) std::cout << fmt::format("  ... {} more (--top)\n", c.items.size() - top);
  std::cout << fmt::format("  first-order sum {:.3f} um of exact {:.3f} um; second-order remainder {:.4f} um\n",
                           c.first_order.norm() * 1e3, c.exact.norm() * 1e3, c.residual * 1e3);
}

// ---------------------------------------------------------------------------------------------
// mtcal volumetric

struct VolumetricOptions {
  ModelOptions model;
  MapSource source;
  std::string box, centre, histogram, out, report;
  std::optional<double> group_angle, group_magnitude;
  int box_scan = 0;
  bool json_out = false;
  ToleranceOptions tol;
};

// What the options ask of the map.
VolumetricRequest volumetric_request(const Machine& m, const VolumetricOptions& o) {
  VolumetricRequest r;
  if (!o.box.empty()) r.box = parse_box(m, o.box, "--box");
  r.box_scan = o.box_scan;
  if (!o.centre.empty()) r.centre = parse_joint_values(m, o.centre, "--centre");
  r.histogram = !o.histogram.empty();
  if (r.histogram && o.histogram != "auto") {
    const auto v = parse_number(o.histogram);
    if (!v || *v < 1 || *v > 1e6 || *v != std::floor(*v))
      throw InputError({"--histogram", 0, ""},
                       "expected a bin count from 1 to 1e6 or 'auto', found '" + printable(o.histogram) + "'");
    r.histogram_bins = static_cast<std::size_t>(*v);
  }
  if (o.group_angle || o.group_magnitude) {
    r.grouping.emplace();
    if (o.group_angle) r.grouping->angle_tolerance = *o.group_angle;
    if (o.group_magnitude) r.grouping->magnitude_tolerance = *o.group_magnitude;
  }
  r.threads = o.source.threads;
  return r;
}

void print_volumetric(const VolumetricOptions& o, const Machine& m, const ErrorMap& map, const VolumetricStudy& s,
                      double t_map) {
  const VolumetricAccuracy& va = s.va;
  std::cout << fmt::format("machine        {} ({})\n", m.name, m.topology.chain);
  std::cout << fmt::format(
      "points         {} ({:.6g} pairs); map {:.3f} s, exact VA {:.4f} s ({} distances computed)\n", va.points,
      va.pairs, t_map, s.seconds_va, va.distance_evaluations);
  std::cout << fmt::format("VA             {} um  from {}  to {}\n", um(va.va.value),
                           format_joint_values(m, config(map, va.va.i)), format_joint_values(m, config(map, va.va.j)));
  for (int c = 0; c < 3; ++c) {
    const auto& p = va.component[static_cast<std::size_t>(c)];
    std::cout << fmt::format("VA {}           {} um  from {}  to {}\n", "xyz"[c], um(p.value),
                             format_joint_values(m, config(map, p.i)), format_joint_values(m, config(map, p.j)));
  }
  std::cout << "contributions to the critical difference (first order, largest first):\n";
  print_contributions(s.critical, 8);
  if (s.box_va)
    std::cout << fmt::format("box {}: {} points, VA {} um (x {}, y {}, z {})\n", o.box, s.box_va->points,
                             um(s.box_va->va.value), um(s.box_va->component[0].value), um(s.box_va->component[1].value),
                             um(s.box_va->component[2].value));
  for (const auto& b : s.scan)
    std::cout << fmt::format("box {:5.3f} of the map: {:>9} points, VA {} um\n", b.fraction, b.points, um(b.va.value));
  if (s.pairs) {
    const auto& h = s.pairs->histogram;
    std::cout << fmt::format(
        "pairs          mean {:.3f} um, 50% {:.3f}, 90% {:.3f}, 95% {:.3f}, 99% {:.3f} um ({} bins of {:.3f} um, "
        "{:.3f} s)\n",
        s.pairs->mean * 1e3, h.quantile(0.5) * 1e3, h.quantile(0.9) * 1e3, h.quantile(0.95) * 1e3,
        h.quantile(0.99) * 1e3, h.counts.size(), h.width * 1e3, s.seconds_histogram);
  }
  if (s.grouping) {
    const auto& g = *s.grouping;
    std::cout << fmt::format(
        "grouping       angle {:g}, magnitude {:g}: {} groups, {} records kept, {:.6g} comparisons "
        "({:.1f}% fewer); VA {} um ({:+.3f}% of exact)\n",
        g.options.angle_tolerance, g.options.magnitude_tolerance, g.result.groups, g.result.kept.size(),
        g.result.comparisons, g.comparison_reduction_percent, um(g.result.va.value), g.difference_percent);
  }
  if (!o.out.empty()) std::cout << "wrote          " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report         " << o.report << "\n";
}

int run_volumetric(const VolumetricOptions& o) {
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.source.points);
    inputs.push_back(o.tol.file);
    for (const auto& f : metadata_inputs()) inputs.push_back(f);
    check_outputs(inputs, {o.out, o.report});
  }
  const Tolerances limits = tolerances_for(o.tol, AcceptanceTest::Volumetric);
  if (!o.centre.empty() && o.box_scan == 0) throw InputError({"--centre", 0, ""}, "--centre goes with --box-scan");
  const Machine m = load(o.model);
  const ErrorModel model(m);
  if (!o.report.empty()) AtomicFile probe(o.report);  // refuse a bad report path before the work
  if (!o.out.empty()) AtomicFile probe(o.out);
  const VolumetricRequest request = volumetric_request(m, o);
  const auto cfg = configurations(m, o.source);
  {
    // Streamed: what is held is the vectors a histogram or a grouping needs (24 bytes each, and
    // the grouping's group index and kept list), and the exact VA's candidates (few).
    const double count = static_cast<double>(cfg->source.size()), axes = static_cast<double>(m.axes.size());
    const double held = request.grouping ? count * 40 : request.histogram ? count * 24 : 0;
    const double row = axes * 13 + (cfg->source.has_directions() ? axes * 3 : 0) + 3 * 17;
    check_streamed("volumetric", o.source, cfg->source, 1, held, o.out.empty() ? 0.0 : count * row);
  }
  std::optional<ErrorStreamCsv> file;
  if (!o.out.empty()) file.emplace(o.out, m, cfg->source.has_directions(), o.source.threads, true);
  const auto t0 = Clock::now();
  StreamedStudy streamed;
  {
    Progress progress("configurations evaluated, all passes", 2 * cfg->source.size());
    std::function<void(const ErrorChunk&)> observe;
    if (file) observe = [&](const ErrorChunk& chunk) { file->write(chunk); };
    try {
      streamed = study_volumetric(m, model, cfg->source, request, stream_options(o.source, progress), observe);
    } catch (const InputError& e) {
      rethrow_for_options(e, {{"box", "--box"}, {"histogram", "--histogram"}});
    }
  }
  // The map's time: the streamed passes (evaluation, extremes, candidates), less the searches.
  const double t_map = std::chrono::duration<double>(Clock::now() - t0).count() - streamed.study.seconds_va -
                       streamed.study.seconds_histogram;
  const ErrorMap& map = streamed.map;
  const VolumetricStudy& study = streamed.study;
  const ToleranceVerdict verdict = limits.empty() ? ToleranceVerdict{} : checked_verdict(tolerance_values(study.va), limits);
  if (file) file->commit();
  if (!o.report.empty())
    write_volumetric_report(o.report, model, map, study, o.box, sources(o.model, o.source), verdict);
  warn_missing_metadata(AcceptanceTest::Volumetric, o.tol.given());
  if (o.json_out || recording()) {
    Json j = to_json(m, map, study, t_map);
    if (!verdict.empty()) j["tolerances"] = to_json(verdict);
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    if (emit_json(j, o.json_out)) return verdict_exit_code(o.tol, verdict);
  }
  print_volumetric(o, m, map, study, t_map);
  print_verdict(verdict);
  return verdict_exit_code(o.tol, verdict);
}

// ---------------------------------------------------------------------------------------------
// mtcal contributions

struct ContributionOptions {
  ModelOptions model;
  MapSource source;
  std::string at, pair, report;
  std::size_t top = 10;
  std::optional<double> target_va;  // mm
  bool json_out = false, no_what_if = false;
};

ContributionStudy contribution_study(const Machine& m, const ErrorModel& model, const ContributionOptions& o) {
  const bool travel = !o.source.no_travel_check;
  if (!o.at.empty()) {
    auto a = parse_joint_values(m, o.at, "--at");
    check_joints(m, a, "--at", travel);
    return contributions_at(m, std::move(a));
  }
  if (!o.pair.empty()) {
    const auto semi = o.pair.find(';');
    if (semi == std::string::npos || o.pair.find(';', semi + 1) != std::string::npos)
      throw InputError({"--pair", 0, ""},
                       "expected two configurations separated by ';', e.g. \"X=0,Y=0;X=500,Y=400\", found '" + o.pair +
                           "'");
    auto b = parse_joint_values(m, o.pair.substr(0, semi), "--pair");
    auto a = parse_joint_values(m, o.pair.substr(semi + 1), "--pair");
    check_joints(m, b, "--pair", travel);
    check_joints(m, a, "--pair", travel);
    return contributions_between(m, std::move(b), std::move(a));
  }
  (void)model;
  const auto cfg = configurations(m, o.source);
  // The map, each error's removal, and a correction sequence's tries (at most n (n + 1) / 2 maps
  // for n errors; estimated at its worst).
  const double errors = static_cast<double>(nonzero_errors(m).size());
  const double maps = 1 + (o.no_what_if ? 0 : errors) + (o.target_va ? errors * (errors + 1) / 2 : 0);
  check_streamed("contributions", o.source, cfg->source, maps, 0, 0);
  Progress progress("configurations evaluated, all passes", 2 * cfg->source.size());
  return critical_pair_contributions(m, cfg->source, !o.no_what_if, stream_options(o.source, progress), o.target_va);
}

// "EC0Y (7.500 um against it), EXX (6.528), EXZ (4.500)": the first three errors it cancelled.
std::string cancelled_list(const WhatIf& w, const char* unit) {
  std::string out;
  for (std::size_t k = 0; k < w.cancelled.size() && k < 3; ++k)
    out += fmt::format("{}{} ({}{})", k ? ", " : "", w.cancelled[k].first.str(), um(w.cancelled[k].second),
                       k ? "" : fmt::format(" {} against it", unit));
  return out;
}

void print_contribution_study(const ContributionOptions& o, const Machine& m, const ContributionStudy& s) {
  const ContributionAnalysis& c = s.analysis;
  if (s.b.empty())
    std::cout << fmt::format("error at {}: ({}, {}, {}) um\n", format_joint_values(m, s.a), um(c.exact.x()),
                             um(c.exact.y()), um(c.exact.z()));
  else
    std::cout << fmt::format("difference e(to) - e(from), from {} to {}: ({}, {}, {}) um, |.| {} um\n",
                             format_joint_values(m, s.b), format_joint_values(m, s.a), um(c.exact.x()), um(c.exact.y()),
                             um(c.exact.z()), um(c.exact.norm()));
  if (s.va) std::cout << fmt::format("VA {} um: that is the critical pair of the map\n", um(s.va->va.value));
  print_contributions(c, o.top);
  if (!s.what_if.empty()) {
    std::cout << "VA with one error removed (exact, recomputed over the map), best first:\n";
    for (std::size_t k = 0; k < s.what_if.size() && k < o.top; ++k)
      std::cout << fmt::format("  {:<6} VA {} um  (gain {} um)\n", s.what_if[k].error.str(), um(s.what_if[k].va),
                               um(s.va->va.value - s.what_if[k].va));
    // Where the first-order share and the exact removal disagree, and why.
    for (const auto& w : s.what_if) {
      if (!w.disagrees) continue;
      std::cout << fmt::format(
          "  note: {} has a first-order share of {:.1f}% of the critical difference, yet removing it {} the VA "
          "from {} to {} um: without it the pair from {} to {} is critical",
          w.error.str(), 100 * w.share, w.va > s.va->va.value ? "raises" : "lowers", um(s.va->va.value), um(w.va),
          format_joint_values(m, w.from), format_joint_values(m, w.to));
      if (w.along_there < 0 && !w.cancelled.empty())
        std::cout << fmt::format(", where {} ({} um along it) was cancelling {}", w.error.str(), um(w.along_there),
                                 cancelled_list(w, "um"));
      std::cout << "\n";
    }
  }
  if (s.sequence) {
    const auto& q = *s.sequence;
    std::cout << fmt::format("correct these errors in this order to reach VA <= {} um (greedy, exact VA after each):\n",
                             um(q.target));
    std::cout << fmt::format("  start  VA {} um\n", um(q.start));
    for (std::size_t k = 0; k < q.steps.size(); ++k)
      std::cout << fmt::format("  {:>2}. {:<6} VA {} um\n", k + 1, q.steps[k].error.str(), um(q.steps[k].va));
    std::cout << (q.reached ? fmt::format("  target reached with {} error(s) corrected\n", q.steps.size())
                            : std::string("  target not reached: every error removed\n"));
  }
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_contributions(const ContributionOptions& o) {
  const int modes = !o.at.empty() + !o.pair.empty() + !o.source.grid.empty() + !o.source.points.empty();
  if (modes != 1) throw InputError({"contributions", 0, ""}, "expected exactly one of --at, --pair, --grid, --points");
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.source.points);
    check_outputs(inputs, {o.report});
  }
  const Machine m = load(o.model);
  const ErrorModel model(m);
  if (!o.report.empty()) AtomicFile probe(o.report);
  const ContributionStudy s = contribution_study(m, model, o);
  if (!o.report.empty()) write_contributions_report(o.report, m, s, sources(o.model, o.source));
  if (!o.json_out) {
    print_contribution_study(o, m, s);
    return 0;
  }
  Json j = to_json(m, s, o.top);
  if (!o.report.empty()) j["report"] = o.report;
  print_json(j);
  return 0;
}

// ---------------------------------------------------------------------------------------------
// mtcal diagonals

struct DiagonalCommandOptions {
  ModelOptions model;
  std::string box, out, report;
  std::size_t points = 21;
  bool json_out = false, no_face = false, no_travel_check = false;
};

// --box: the linear axes X Y Z need a range; every other axis is held at its value or 0.
JointBox diagonal_box(const Machine& m, const DiagonalCommandOptions& o) {
  JointBox box = parse_box(m, o.box, "--box");
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (!box.named[k]) {
      if (m.axes[k].kind == AxisKind::Linear &&
          (m.axes[k].letter == 'X' || m.axes[k].letter == 'Y' || m.axes[k].letter == 'Z'))
        throw InputError({"--box", 0, std::string(1, m.axes[k].letter)},
                         fmt::format("expected a range lo:hi for {} (the box's linear axes), found none",
                                     m.axes[k].letter));
      box.lo[k] = box.hi[k] = 0.0;
    }
  check_joints(m, box.lo, "--box", !o.no_travel_check);
  check_joints(m, box.hi, "--box", !o.no_travel_check);
  return box;
}

void print_diagonals(const DiagonalCommandOptions& o, const std::vector<DiagonalProfile>& diagonals) {
  std::cout << fmt::format("{:<16} {:>10} {:>12} {:>12} {:>12}\n", "diagonal", "length mm", "range um", "end um",
                           "max |d| um");
  for (const auto& d : diagonals)
    std::cout << fmt::format("{:<16} {:>10.1f} {:>12} {:>12} {:>12}\n", d.name, d.length, um(d.range),
                             um(d.deviation.back()), um(d.largest_deviation()));
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
}

int run_diagonals(const DiagonalCommandOptions& o) {
  check_outputs(model_inputs(o.model), {o.out, o.report});
  const Machine m = load(o.model);
  const ErrorModel model(m);
  const JointBox box = diagonal_box(m, o);
  if (!o.report.empty()) AtomicFile probe(o.report);
  if (!o.out.empty()) AtomicFile probe(o.out);
  const auto diagonals = diagonal_displacements(model, box.lo, box.hi, {o.points, !o.no_face});
  if (!o.out.empty()) write_diagonals_csv(o.out, diagonals);
  if (!o.report.empty())
    write_diagonals_report(o.report, m, diagonals, o.box, {command_line(), o.model.params, "", ""});
  if (!o.json_out) {
    print_diagonals(o, diagonals);
    return 0;
  }
  Json j = to_json(m, diagonals);
  if (!o.out.empty()) j["out"] = o.out;
  if (!o.report.empty()) j["report"] = o.report;
  print_json(j);
  return 0;
}

}  // namespace

std::vector<Command> add_volumetric_commands(CLI::App& app) {
  std::vector<Command> out;
  {
    auto o = std::make_shared<VolumetricOptions>();
    auto* c = app.add_subcommand(
        "volumetric",
        "Volumetric accuracy (Fletcher 2009): the exact largest difference between the error vectors of "
        "any two points of a grid or list of configurations, per component too, with the critical pair "
        "and what makes it; optional pair histogram, reduced volumes and Fletcher's grouping");
    add_model_options(c, o->model);
    add_map_options(c, o->source);
    c->add_option("--box", o->box,
                  "Also the VA of a sub-box of the map, e.g. \"X=0:250,Y=0:200\" (lo:hi; axes not named: all)");
    c->add_option("--box-scan", o->box_scan, "VA of N boxes centred on --centre, sides 1/N, 2/N .. 1 of the map's")
        ->check(CLI::Range(1, 1000));
    c->add_option("--centre", o->centre, "Centre of the --box-scan boxes (default: the middle of the map)");
    c->add_option("--histogram", o->histogram,
                  "Histogram of |e_i - e_j| over all pairs and of |e_i|: a bin count or 'auto'");
    c->add_option("--group-angle", o->group_angle,
                  "Fletcher's grouping: angle tolerance (sum of unit-vector component "
                  "differences; default 0.1 when only --group-magnitude is given)")
        ->check(kFinite);
    c->add_option("--group-magnitude", o->group_magnitude, "Fletcher's grouping: magnitude tolerance (default 0.9)")
        ->check(kFinite);
    c->add_option("--out", o->out, "Write the error map as CSV: axis columns (mm, deg), dx, dy, dz (mm)");
    c->add_option("--report", o->report,
                  "Write an HTML report: critical pair, error map, contributions, distributions");
    add_tolerance_options(c, o->tol, "VA, VAx, VAy, VAz");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: points pairs va va_x va_y va_z critical_pair ... (mm)");
    out.push_back({c, [o] { return run_volumetric(*o); }});
  }
  {
    auto o = std::make_shared<ContributionOptions>();
    auto* c = app.add_subcommand(
        "contributions",
        "Contribution of every error (first order, ranked, um and %) to the error at a configuration, "
        "to the difference of two, or to a map's critical pair with the exact VA gained by removing "
        "each error (Fletcher 2009, 5)");
    add_model_options(c, o->model);
    add_map_options(c, o->source);
    c->add_option("--at", o->at, "One configuration, e.g. \"X=100,Y=50,Z=-20\" (mm, deg)");
    c->add_option("--pair", o->pair,
                  "Two configurations FROM;TO, e.g. \"X=0,Y=0,Z=0;X=500,Y=400,Z=-300\": e(TO) - e(FROM)");
    c->add_option("--top", o->top, "Errors listed")->check(CLI::Range(1, 100000))->capture_default_str();
    c->add_flag("--no-what-if", o->no_what_if, "With --grid/--points: skip the VA with each error removed");
    c->add_option("--target-va", o->target_va,
                  "With --grid/--points: the greedy sequence of errors to correct to reach this VA, mm or with a "
                  "unit (20um)")
        ->transform(length_in(1.0, "LENGTH"))
        ->check(CLI::NonNegativeNumber & kFinite);
    c->add_option("--report", o->report, "Write an HTML report");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: exact first_order residual items[error effect along share] (mm)");
    out.push_back({c, [o] { return run_contributions(*o); }});
  }
  {
    auto o = std::make_shared<DiagonalCommandOptions>();
    auto* c = app.add_subcommand("diagonals",
                                 "ISO 230-6 diagonal displacement tests simulated on the model: the 4 body "
                                 "diagonals and 12 face diagonals of a box, error along each and its range");
    add_model_options(c, o->model);
    c->add_option("--box", o->box,
                  "The box, e.g. \"X=0:500,Y=0:400,Z=-300:0\" (mm; rotary axes as single values, "
                  "default 0)")
        ->required();
    c->add_option("--points", o->points, "Targets per diagonal, ends included")
        ->check(CLI::Range(2, 1000000))
        ->capture_default_str();
    c->add_flag("--no-face", o->no_face, "Body diagonals only");
    c->add_flag("--no-travel-check", o->no_travel_check, "Allow a box outside the axes' travels");
    c->add_option("--out", o->out, "Write CSV: diagonal, position (mm), deviation (mm)");
    c->add_option("--report", o->report, "Write an HTML report with the deviation curves");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: diagonals[name from to length direction range position deviation] (mm)");
    out.push_back({c, [o] { return run_diagonals(*o); }});
  }
  return out;
}

}  // namespace mtcal::cli
