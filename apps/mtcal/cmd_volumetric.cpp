// mtcal volumetric, contributions, diagonals: volumetric accuracy of a machine model (Fletcher
// 2009; ISO 230-6 diagonals).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "eval_report.hpp"
#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/diagonals.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/io/joints.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/parse.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
json vec_json(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }
// mm as um with 3 decimals; what rounds to zero prints as 0.000, never -0.000.
std::string um(double mm) { return fmt::format("{:.3f}", std::abs(mm) < 5e-7 ? 0.0 : mm * 1e3); }
// Above this many pairs the exact pair histogram takes minutes: refuse rather than hang.
constexpr double kMaxHistogramPairs = 2e10;
constexpr std::size_t kConeSamples = 3000;

// Where the configurations come from: a grid or a CSV file; and the map they give.
struct MapSource {
  std::string grid, points;
  bool no_travel_check = false;
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
}

ErrorMap build_map(const Machine& m, const ErrorModel& model, const MapSource& s) {
  if (!s.grid.empty() == !s.points.empty()) throw InputError({"--grid", 0, ""}, "expected exactly one of --grid, --points");
  if (!s.grid.empty())
    return grid_error_map(model, checked_grid(m, s.grid, !s.no_travel_check, 200'000'000), {s.threads});
  Configurations c = read_configurations(m, s.points, !s.no_travel_check);
  if (c.q.empty()) throw InputError({s.points, 0, ""}, "expected at least one configuration, found none");
  return error_map(model, std::move(c.q), c.dir, {s.threads});
}

std::vector<double> config(const ErrorMap& map, std::size_t i) {
  const auto q = map.configuration(i);
  return {q.begin(), q.end()};
}

json pair_json(const Machine& m, const ErrorMap& map, const PointPair& p) {
  return {{"from", joint_json(m, map.configuration(p.i))},
          {"to", joint_json(m, map.configuration(p.j))},
          {"error_from", vec_json(map.error[p.i])},
          {"error_to", vec_json(map.error[p.j])},
          {"difference", vec_json(map.error[p.j] - map.error[p.i])}};
}

json contributions_json(const ContributionAnalysis& c, std::size_t top) {
  json items = json::array();
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    const auto& it = c.items[k];
    items.push_back({{"error", it.error.str()}, {"effect", vec_json(it.effect)}, {"along", it.along}, {"share", it.share}});
  }
  return {{"exact", vec_json(c.exact)}, {"first_order", vec_json(c.first_order)}, {"residual", c.residual}, {"items", items}};
}

void print_contributions(const ContributionAnalysis& c, std::size_t top) {
  std::cout << fmt::format("  {:<6} {:>10} {:>10} {:>10} {:>11} {:>8}\n", "error", "dx um", "dy um", "dz um", "along um", "share");
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    const auto& it = c.items[k];
    std::cout << fmt::format("  {:<6} {:>10} {:>10} {:>10} {:>11} {:>7.1f}%\n", it.error.str(), um(it.effect.x()),
                             um(it.effect.y()), um(it.effect.z()), um(it.along), it.share * 100);
  }
  if (c.items.size() > top) std::cout << fmt::format("  ... {} more (--top)\n", c.items.size() - top);
  std::cout << fmt::format("  first-order sum {:.3f} um of exact {:.3f} um; second-order remainder {:.4f} um\n",
                           c.first_order.norm() * 1e3, c.exact.norm() * 1e3, c.residual * 1e3);
}

std::vector<ConeSample> cone_samples(const ErrorModel& model, const ErrorMap& map) {
  const std::size_t stride = std::max<std::size_t>(1, (map.size() + kConeSamples - 1) / kConeSamples);
  std::vector<ConeSample> out;
  for (std::size_t i = 0; i < map.size(); i += stride) out.push_back({config(map, i), model.nominal_pose(map.configuration(i)).t, map.error[i]});
  return out;
}

json contributions_figure(const ContributionAnalysis& c, std::size_t top) {
  json names = json::array(), along = json::array();
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    names.push_back(c.items[k].error.str());
    along.push_back(c.items[k].along * 1e3);
  }
  return {{"data", {{{"type", "bar"}, {"x", names}, {"y", along}, {"name", "contribution"}}}},
          {"layout", {{"xaxis", {{"title", {{"text", "error"}}}}},
                      {"yaxis", {{"title", {{"text", "part along the difference (µm)"}}}}}}}};
}

std::vector<std::vector<std::string>> contributions_rows(const ContributionAnalysis& c) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& it : c.items)
    rows.push_back({it.error.str(), um(it.effect.x()), um(it.effect.y()), um(it.effect.z()), um(it.along),
                    fmt::format("{:.1f}", it.share * 100)});
  return rows;
}
const std::vector<std::string> kContributionColumns{"error", "dx (µm)", "dy (µm)", "dz (µm)", "along (µm)", "share (%)"};

json histogram_json(const Distribution& d) {
  const auto& h = d.histogram;
  return {{"count", d.count},        {"mean", d.mean},          {"min", d.min},          {"max", d.max},
          {"bins", h.counts.size()}, {"bin_width", h.width},    {"lo", h.lo},            {"counts", h.counts},
          {"p50", h.quantile(0.5)},  {"p90", h.quantile(0.9)},  {"p95", h.quantile(0.95)}, {"p99", h.quantile(0.99)}};
}

json histogram_figure(const Distribution& d, const std::string& xtitle, const std::string& ytitle) {
  json centres = json::array();
  for (std::size_t b = 0; b < d.histogram.counts.size(); ++b)
    centres.push_back((d.histogram.lo + (static_cast<double>(b) + 0.5) * d.histogram.width) * 1e3);
  return {{"data", {{{"type", "bar"}, {"x", centres}, {"y", d.histogram.counts}, {"name", ytitle}}}},
          {"layout", {{"xaxis", {{"title", {{"text", xtitle}}}}}, {"yaxis", {{"title", {{"text", ytitle}}}}}, {"bargap", 0.02}}}};
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
};

std::size_t histogram_bins(const std::string& spec, double pairs) {
  if (spec == "auto") return static_cast<std::size_t>(std::clamp(std::ceil(2.0 * std::cbrt(pairs)), 10.0, 200.0));  // Rice rule
  const auto v = parse_number(spec);
  if (!v || *v < 1 || *v > 1e6 || *v != std::floor(*v))
    throw InputError({"--histogram", 0, ""}, "expected a bin count from 1 to 1e6 or 'auto', found '" + spec + "'");
  return static_cast<std::size_t>(*v);
}

int run_volumetric(const VolumetricOptions& o) {
  {
    auto inputs = model_inputs(o.model);
    inputs.push_back(o.source.points);
    check_outputs(inputs, {o.out, o.report});
  }
  if (!o.centre.empty() && o.box_scan == 0) throw InputError({"--centre", 0, ""}, "--centre goes with --box-scan");
  const Machine m = load(o.model);
  const ErrorModel model(m);
  if (!o.report.empty()) AtomicFile probe(o.report);  // refuse a bad report path before the work
  std::unique_ptr<AtomicFile> out;
  if (!o.out.empty()) out = std::make_unique<AtomicFile>(o.out);

  auto t0 = Clock::now();
  const ErrorMap map = build_map(m, model, o.source);
  const double t_map = seconds_since(t0);
  t0 = Clock::now();
  const VolumetricAccuracy va = volumetric_accuracy(map.error);
  const double t_va = seconds_since(t0);
  const ContributionAnalysis critical = contributions(m, map.configuration(va.va.j), map.direction(va.va.j),
                                                      std::optional<std::span<const double>>(map.configuration(va.va.i)),
                                                      map.direction(va.va.i));

  // Reduced volume.
  std::optional<ErrorMap> box_map;
  std::optional<VolumetricAccuracy> box_va;
  JointBox box;
  if (!o.box.empty()) {
    box = parse_box(m, o.box, "--box");
    box_map = sub_map(map, box.lo, box.hi);
    if (box_map->size() == 0) throw InputError({"--box", 0, ""}, "no configuration of the map lies inside the box");
    box_va = volumetric_accuracy(box_map->error);
  }
  std::vector<BoxVa> scan;
  if (o.box_scan > 0) {
    std::vector<double> centre(m.axes.size());
    if (!o.centre.empty()) {
      centre = parse_joint_values(m, o.centre, "--centre");
    } else {
      for (std::size_t k = 0; k < m.axes.size(); ++k) {
        double lo = INFINITY, hi = -INFINITY;
        for (std::size_t i = 0; i < map.size(); ++i) lo = std::min(lo, map.q[i * m.axes.size() + k]), hi = std::max(hi, map.q[i * m.axes.size() + k]);
        centre[k] = 0.5 * (lo + hi);
      }
    }
    std::vector<double> fractions;
    for (int k = 1; k <= o.box_scan; ++k) fractions.push_back(static_cast<double>(k) / o.box_scan);
    scan = va_versus_box_size(map, centre, fractions);
  }
  std::optional<Distribution> pairs, magnitudes;
  double t_hist = 0;
  if (!o.histogram.empty()) {
    if (va.pairs > kMaxHistogramPairs)
      throw InputError({"--histogram", 0, ""},
                       fmt::format("{:.3g} pairs would take minutes (limit {:.0e}); use a coarser grid or --box", va.pairs,
                                   kMaxHistogramPairs));
    const std::size_t bins = histogram_bins(o.histogram, va.pairs);
    t0 = Clock::now();
    pairs = pair_distribution(map.error, bins, va.va.value, o.source.threads);
    t_hist = seconds_since(t0);
    std::vector<double> mags(map.size());
    for (std::size_t i = 0; i < map.size(); ++i) mags[i] = map.error[i].norm();
    // 'auto' sizes each histogram for its own count (the errors are far fewer than their pairs).
    magnitudes = value_distribution(mags, o.histogram == "auto" ? histogram_bins("auto", static_cast<double>(map.size())) : bins);
  }
  std::optional<GroupingResult> grouping;
  GroupingOptions gopt;
  if (o.group_angle || o.group_magnitude) {
    if (o.group_angle) gopt.angle_tolerance = *o.group_angle;
    if (o.group_magnitude) gopt.magnitude_tolerance = *o.group_magnitude;
    grouping = fletcher_grouping(map.error, gopt);
  }

  const std::size_t n = m.axes.size();
  if (out) {
    std::string header;
    for (std::size_t k = 0; k < n; ++k) header += (k ? "," : "") + std::string(1, m.axes[k].letter);
    if (!map.dir.empty())
      for (std::size_t k = 0; k < n; ++k) header += std::string(",dir") + m.axes[k].letter;
    out->stream() << header << ",dx,dy,dz\n";
    fmt::memory_buffer buf;
    for (std::size_t i = 0; i < map.size(); ++i) {
      for (std::size_t k = 0; k < n; ++k) fmt::format_to(std::back_inserter(buf), "{}{:.12g}", k ? "," : "", to_user_units(m.axes[k], map.q[i * n + k]));
      for (const std::int8_t d : map.direction(i)) fmt::format_to(std::back_inserter(buf), ",{}", d);
      fmt::format_to(std::back_inserter(buf), ",{:.9e},{:.9e},{:.9e}\n", map.error[i].x(), map.error[i].y(), map.error[i].z());
      if (buf.size() > (1u << 20)) out->stream().write(buf.data(), static_cast<std::streamsize>(buf.size())), buf.clear();
    }
    out->stream().write(buf.data(), static_cast<std::streamsize>(buf.size()));
    out->commit();
  }

  if (!o.report.empty()) {
    Report r("Volumetric accuracy of " + m.name, command_line());
    r.set_machine(m);
    for (const auto& p : o.model.params) r.add_input("parameter file", p);
    if (!o.source.points.empty()) r.add_input("configurations", o.source.points);
    if (!o.source.grid.empty()) r.add_figure("grid", o.source.grid, "mm, deg");
    r.add_figure("volumetric accuracy VA", um(va.va.value), "µm (largest |e_i − e_j| over all pairs)");
    r.add_figure("VA per component x, y, z", fmt::format("{}, {}, {}", um(va.component[0].value), um(va.component[1].value), um(va.component[2].value)), "µm");
    r.add_figure("points, pairs", fmt::format("{}, {:.6g}", va.points, va.pairs), "");
    if (box_va) r.add_figure("VA of the box " + o.box, um(box_va->va.value), fmt::format("µm ({} points)", box_va->points));
    r.add_section("Critical pair");
    r.add_paragraph("The two configurations whose translational errors differ most: a feature machined at one and "
                    "another at the other carry this error between them (Fletcher 2009, 4.1). Exact: the same pair "
                    "value a comparison of every pair gives.");
    r.add_table("The critical pair and the per-component extremes (workpiece frame)",
                {"difference", "from (mm, deg)", "to (mm, deg)", "e from (µm)", "e to (µm)", "value (µm)"},
                [&] {
                  std::vector<std::vector<std::string>> rows;
                  auto row = [&](const std::string& what, const PointPair& p) {
                    const Vec3 a = map.error[p.i] * 1e3, b = map.error[p.j] * 1e3;
                    rows.push_back({what, format_joint_values(m, config(map, p.i), ", "), format_joint_values(m, config(map, p.j), ", "),
                                    fmt::format("{:.3f}, {:.3f}, {:.3f}", a.x(), a.y(), a.z()),
                                    fmt::format("{:.3f}, {:.3f}, {:.3f}", b.x(), b.y(), b.z()), um(p.value)});
                  };
                  row("|e_i − e_j| (VA)", va.va);
                  row("x", va.component[0]);
                  row("y", va.component[1]);
                  row("z", va.component[2]);
                  return rows;
                }());
    r.add_section("Error map");
    r.add_paragraph("Each cone is the translational error at the nominal tool point (workpiece frame); the red line "
                    "joins the critical pair.");
    r.add_plot(fmt::format("Translational errors (µm) over {} configurations{}", map.size(),
                           map.size() > kConeSamples ? fmt::format(", {} shown", cone_samples(model, map).size()) : ""),
               error_cone_figure(m, cone_samples(model, map),
                                 {{"from", model.nominal_pose(map.configuration(va.va.i)).t},
                                  {"to", model.nominal_pose(map.configuration(va.va.j)).t}},
                                 true));
    r.add_section("What makes the critical difference");
    r.add_paragraph("First-order contribution of each error to e(to) − e(from), projected on that difference (Fletcher "
                    "2009, 5): correct the largest first. Shares sum to 100 % up to the second-order remainder.");
    r.add_plot("Contributions to the critical difference (µm along it)", contributions_figure(critical, 20));
    r.add_table(fmt::format("Contributions (first-order sum {:.3f} µm; exact {:.3f} µm; remainder {:.4f} µm)",
                            critical.first_order.norm() * 1e3, critical.exact.norm() * 1e3, critical.residual * 1e3),
                kContributionColumns, contributions_rows(critical));
    if (pairs) {
      r.add_section("Distributions");
      r.add_paragraph(fmt::format("Every one of the {} pairs counted once. Mean {:.3f} µm; percentiles (within one bin, "
                                  "{:.3f} µm): 50 % {:.3f}, 90 % {:.3f}, 95 % {:.3f}, 99 % {:.3f} µm.",
                                  pairs->count, pairs->mean * 1e3, pairs->histogram.width * 1e3,
                                  pairs->histogram.quantile(0.5) * 1e3, pairs->histogram.quantile(0.9) * 1e3,
                                  pairs->histogram.quantile(0.95) * 1e3, pairs->histogram.quantile(0.99) * 1e3));
      r.add_plot("Differences |e_i − e_j| over all pairs", histogram_figure(*pairs, "|e_i − e_j| (µm)", "pairs"));
      r.add_plot("Errors |e_i| over all configurations", histogram_figure(*magnitudes, "|e| (µm)", "configurations"));
    }
    if (!scan.empty()) {
      r.add_section("Reduced volume");
      r.add_paragraph("VA of boxes centred on one configuration, their sides a fraction of the map's (Fletcher 2009, 4.2).");
      json f = json::array(), v = json::array();
      std::vector<std::vector<std::string>> rows;
      for (const auto& b : scan) {
        f.push_back(b.fraction);
        v.push_back(b.va.value * 1e3);
        rows.push_back({fmt::format("{:.3g}", b.fraction), format_joint_values(m, b.lo, ", "), format_joint_values(m, b.hi, ", "),
                        fmt::format("{}", b.points), um(b.va.value)});
      }
      r.add_plot("VA against box size",
                 {{"data", {{{"type", "scatter"}, {"mode", "lines+markers"}, {"x", f}, {"y", v}, {"name", "VA"}}}},
                  {"layout", {{"xaxis", {{"title", {{"text", "box side / map side"}}}}},
                              {"yaxis", {{"title", {{"text", "VA (µm)"}}}}}}}});
      r.add_table("VA of centred boxes", {"fraction", "from", "to", "points", "VA (µm)"}, rows);
    }
    if (grouping) {
      r.add_section("Fletcher's direction grouping");
      r.add_paragraph("The approximation of Fletcher 2009, 4.1 (vectors grouped by direction; those below the magnitude "
                      "tolerance of their group's largest dismissed) against the exact VA above.");
      r.add_table("Grouping", {"angle tolerance", "magnitude tolerance", "groups", "records kept", "comparisons", "VA (µm)", "exact VA (µm)", "difference (%)"},
                  {{fmt::format("{:g}", gopt.angle_tolerance), fmt::format("{:g}", gopt.magnitude_tolerance),
                    fmt::format("{}", grouping->groups), fmt::format("{} of {}", grouping->kept.size(), map.size()),
                    fmt::format("{:.6g}", grouping->comparisons), um(grouping->va.value), um(va.va.value),
                    fmt::format("{:.3f}", va.va.value > 0 ? 100 * (grouping->va.value - va.va.value) / va.va.value : 0.0)}});
    }
    r.write(o.report);
  }

  if (o.json_out) {
    json j;
    j["machine"] = m.name;
    j["points"] = va.points;
    j["pairs"] = va.pairs;
    j["va"] = va.va.value;
    j["va_x"] = va.component[0].value;
    j["va_y"] = va.component[1].value;
    j["va_z"] = va.component[2].value;
    j["critical_pair"] = pair_json(m, map, va.va);
    j["component_pairs"] = {{"x", pair_json(m, map, va.component[0])},
                            {"y", pair_json(m, map, va.component[1])},
                            {"z", pair_json(m, map, va.component[2])}};
    j["contributions"] = contributions_json(critical, critical.items.size());
    j["distance_evaluations"] = va.distance_evaluations;
    j["seconds"] = {{"map", t_map}, {"va", t_va}, {"histogram", t_hist}};
    if (box_va) {
      j["box"] = {{"lo", joint_json(m, box.lo)}, {"hi", joint_json(m, box.hi)}, {"points", box_va->points}, {"va", box_va->va.value},
                  {"va_x", box_va->component[0].value}, {"va_y", box_va->component[1].value}, {"va_z", box_va->component[2].value},
                  {"critical_pair", pair_json(m, *box_map, box_va->va)}};
      // Unnamed axes span everything: JSON has no infinity, so they are left out.
      for (auto* side : {&j["box"]["lo"], &j["box"]["hi"]})
        for (std::size_t k = 0; k < n; ++k)
          if (!box.named[k]) side->erase(std::string(1, m.axes[k].letter));
    }
    if (!scan.empty()) {
      j["box_scan"] = json::array();
      for (const auto& b : scan)
        j["box_scan"].push_back({{"fraction", b.fraction}, {"lo", joint_json(m, b.lo)}, {"hi", joint_json(m, b.hi)}, {"points", b.points}, {"va", b.va.value}});
    }
    if (pairs) {
      j["histogram"] = histogram_json(*pairs);
      j["error_distribution"] = histogram_json(*magnitudes);
    }
    if (grouping) {
      j["grouping"] = {{"angle", gopt.angle_tolerance},
                       {"magnitude", gopt.magnitude_tolerance},
                       {"groups", grouping->groups},
                       {"records", grouping->kept.size()},
                       {"comparisons", grouping->comparisons},
                       {"va", grouping->va.value},
                       {"va_exact", va.va.value},
                       {"difference_percent", va.va.value > 0 ? 100 * (grouping->va.value - va.va.value) / va.va.value : 0.0},
                       {"comparison_reduction_percent", va.pairs > 0 ? 100 * (1 - grouping->comparisons / va.pairs) : 0.0}};
    }
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("machine        {} ({})\n", m.name, m.topology.chain);
  std::cout << fmt::format("points         {} ({:.6g} pairs); map {:.3f} s, exact VA {:.4f} s ({} distances computed)\n",
                           va.points, va.pairs, t_map, t_va, va.distance_evaluations);
  std::cout << fmt::format("VA             {} um  from {}  to {}\n", um(va.va.value), format_joint_values(m, config(map, va.va.i)),
                           format_joint_values(m, config(map, va.va.j)));
  for (int c = 0; c < 3; ++c) {
    const auto& p = va.component[static_cast<std::size_t>(c)];
    std::cout << fmt::format("VA {}           {} um  from {}  to {}\n", "xyz"[c], um(p.value), format_joint_values(m, config(map, p.i)),
                             format_joint_values(m, config(map, p.j)));
  }
  std::cout << "contributions to the critical difference (first order, largest first):\n";
  print_contributions(critical, 8);
  if (box_va)
    std::cout << fmt::format("box {}: {} points, VA {} um (x {}, y {}, z {})\n", o.box, box_va->points, um(box_va->va.value),
                             um(box_va->component[0].value), um(box_va->component[1].value), um(box_va->component[2].value));
  for (const auto& b : scan)
    std::cout << fmt::format("box {:5.3f} of the map: {:>9} points, VA {} um\n", b.fraction, b.points, um(b.va.value));
  if (pairs)
    std::cout << fmt::format("pairs          mean {:.3f} um, 50% {:.3f}, 90% {:.3f}, 95% {:.3f}, 99% {:.3f} um ({} bins of {:.3f} um, {:.3f} s)\n",
                             pairs->mean * 1e3, pairs->histogram.quantile(0.5) * 1e3, pairs->histogram.quantile(0.9) * 1e3,
                             pairs->histogram.quantile(0.95) * 1e3, pairs->histogram.quantile(0.99) * 1e3,
                             pairs->histogram.counts.size(), pairs->histogram.width * 1e3, t_hist);
  if (grouping)
    std::cout << fmt::format("grouping       angle {:g}, magnitude {:g}: {} groups, {} records kept, {:.6g} comparisons "
                             "({:.1f}% fewer); VA {} um ({:+.3f}% of exact)\n",
                             gopt.angle_tolerance, gopt.magnitude_tolerance, grouping->groups, grouping->kept.size(),
                             grouping->comparisons, va.pairs > 0 ? 100 * (1 - grouping->comparisons / va.pairs) : 0.0,
                             um(grouping->va.value), va.va.value > 0 ? 100 * (grouping->va.value - va.va.value) / va.va.value : 0.0);
  if (!o.out.empty()) std::cout << "wrote          " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report         " << o.report << "\n";
  return 0;
}

// ---------------------------------------------------------------------------------------------
// mtcal contributions

struct ContributionOptions {
  ModelOptions model;
  MapSource source;
  std::string at, pair, report;
  std::size_t top = 10;
  bool json_out = false, no_what_if = false;
};

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
  std::vector<double> a, b;
  std::vector<std::int8_t> dir_a, dir_b;  // directions of motion (from --points), or empty
  std::optional<VolumetricAccuracy> va;
  struct WhatIf {
    ErrorName error;
    double va;
  };
  std::vector<WhatIf> what_if;
  std::string mode;
  if (!o.at.empty()) {
    mode = "at";
    a = parse_joint_values(m, o.at, "--at");
    check_joints(m, a, "--at", !o.source.no_travel_check);
  } else if (!o.pair.empty()) {
    mode = "pair";
    const auto semi = o.pair.find(';');
    if (semi == std::string::npos || o.pair.find(';', semi + 1) != std::string::npos)
      throw InputError({"--pair", 0, ""}, "expected two configurations separated by ';', e.g. \"X=0,Y=0;X=500,Y=400\", found '" + o.pair + "'");
    b = parse_joint_values(m, o.pair.substr(0, semi), "--pair");
    a = parse_joint_values(m, o.pair.substr(semi + 1), "--pair");
    check_joints(m, b, "--pair", !o.source.no_travel_check);
    check_joints(m, a, "--pair", !o.source.no_travel_check);
  } else {
    mode = "critical_pair";
    const ErrorMap map = build_map(m, model, o.source);
    va = volumetric_accuracy(map.error);
    b = config(map, va->va.i);
    a = config(map, va->va.j);
    dir_b.assign(map.direction(va->va.i).begin(), map.direction(va->va.i).end());
    dir_a.assign(map.direction(va->va.j).begin(), map.direction(va->va.j).end());
    // The exact answer to "which error first": the VA with that error removed, every other kept.
    if (!o.no_what_if)
      for (const auto& e : nonzero_errors(m)) {
        const ErrorModel without(without_error(m, e));
        const ErrorMap wm = error_map(without, map.q, map.dir, {o.source.threads});
        what_if.push_back({e, volumetric_accuracy(wm.error).va.value});
      }
    std::stable_sort(what_if.begin(), what_if.end(), [](const WhatIf& x, const WhatIf& y) { return x.va < y.va; });
  }
  const ContributionAnalysis c = b.empty() ? contributions(m, a, dir_a)
                                           : contributions(m, a, dir_a, std::optional<std::span<const double>>(b), dir_b);

  if (!o.report.empty()) {
    Report r("Error contributions on " + m.name, command_line());
    r.set_machine(m);
    for (const auto& p : o.model.params) r.add_input("parameter file", p);
    if (!o.source.points.empty()) r.add_input("configurations", o.source.points);
    const std::string what = b.empty() ? "e(" + format_joint_values(m, a, ", ") + ")"
                                       : "e(" + format_joint_values(m, a, ", ") + ") − e(" + format_joint_values(m, b, ", ") + ")";
    r.add_figure("exact", fmt::format("{:.3f}", c.exact.norm() * 1e3), "µm: |" + what + "|");
    r.add_figure("first-order sum", fmt::format("{:.3f}", c.first_order.norm() * 1e3), "µm");
    r.add_figure("second-order remainder", fmt::format("{:.4f}", c.residual * 1e3), "µm");
    if (va) r.add_figure("VA (critical pair)", um(va->va.value), "µm over " + o.source.grid + o.source.points);
    r.add_section("Contributions");
    r.add_paragraph("First-order effect of each error (its sensitivity on the error-free machine times its value at the "
                    "configurations), projected on the exact error; largest first (Fletcher 2009, 5).");
    r.add_plot("Contribution of each error (µm along the exact error)", contributions_figure(c, 30));
    r.add_table("Contributions", kContributionColumns, contributions_rows(c));
    if (!what_if.empty()) {
      r.add_section("Which error to correct first");
      r.add_paragraph("The exact VA of the map with one error removed and every other kept.");
      json names = json::array(), gains = json::array();
      std::vector<std::vector<std::string>> rows;
      for (const auto& w : what_if) {
        names.push_back(w.error.str());
        gains.push_back((va->va.value - w.va) * 1e3);
        rows.push_back({w.error.str(), um(w.va), um(va->va.value - w.va)});
      }
      r.add_plot("VA gained by removing each error (µm)",
                 {{"data", {{{"type", "bar"}, {"x", names}, {"y", gains}, {"name", "gain"}}}},
                  {"layout", {{"yaxis", {{"title", {{"text", "VA − VA without the error (µm)"}}}}}}}});
      r.add_table("VA without each error", {"error removed", "VA (µm)", "gain (µm)"}, rows);
    }
    r.write(o.report);
  }
  if (o.json_out) {
    json j;
    j["mode"] = mode;
    j["at"] = joint_json(m, a);
    if (!b.empty()) j["from"] = joint_json(m, b);
    if (va) j["va"] = va->va.value;
    const json cj = contributions_json(c, o.top);
    for (auto it = cj.begin(); it != cj.end(); ++it) j[it.key()] = it.value();
    if (va && !o.no_what_if) {
      j["what_if"] = json::array();
      for (const auto& w : what_if) j["what_if"].push_back({{"error", w.error.str()}, {"va_without", w.va}, {"gain", va->va.value - w.va}});
    }
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  if (b.empty())
    std::cout << fmt::format("error at {}: ({}, {}, {}) um\n", format_joint_values(m, a), um(c.exact.x()), um(c.exact.y()), um(c.exact.z()));
  else
    std::cout << fmt::format("difference e(to) - e(from), from {} to {}: ({}, {}, {}) um, |.| {} um\n", format_joint_values(m, b),
                             format_joint_values(m, a), um(c.exact.x()), um(c.exact.y()), um(c.exact.z()), um(c.exact.norm()));
  if (va) std::cout << fmt::format("VA {} um: that is the critical pair of the map\n", um(va->va.value));
  print_contributions(c, o.top);
  if (!what_if.empty()) {
    std::cout << "VA with one error removed (exact), best first:\n";
    for (std::size_t k = 0; k < what_if.size() && k < o.top; ++k)
      std::cout << fmt::format("  {:<6} VA {} um  (gain {} um)\n", what_if[k].error.str(), um(what_if[k].va), um(va->va.value - what_if[k].va));
  }
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
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

int run_diagonals(const DiagonalCommandOptions& o) {
  check_outputs(model_inputs(o.model), {o.out, o.report});
  const Machine m = load(o.model);
  const ErrorModel model(m);
  JointBox box = parse_box(m, o.box, "--box");
  for (std::size_t k = 0; k < m.axes.size(); ++k)
    if (!box.named[k]) {
      if (m.axes[k].kind == AxisKind::Linear && (m.axes[k].letter == 'X' || m.axes[k].letter == 'Y' || m.axes[k].letter == 'Z'))
        throw InputError({"--box", 0, std::string(1, m.axes[k].letter)},
                         fmt::format("expected a range lo:hi for {} (the box's linear axes), found none", m.axes[k].letter));
      box.lo[k] = box.hi[k] = 0.0;
    }
  check_joints(m, box.lo, "--box", !o.no_travel_check);
  check_joints(m, box.hi, "--box", !o.no_travel_check);
  if (!o.report.empty()) AtomicFile probe(o.report);
  std::unique_ptr<AtomicFile> out;
  if (!o.out.empty()) out = std::make_unique<AtomicFile>(o.out);
  const auto diagonals = diagonal_displacements(model, box.lo, box.hi, {o.points, !o.no_face});
  if (out) {
    out->stream() << "diagonal,position,deviation\n";
    for (const auto& d : diagonals)
      for (std::size_t i = 0; i < d.position.size(); ++i)
        out->stream() << fmt::format("{},{:.9g},{:.9e}\n", d.name, d.position[i], d.deviation[i]);
    out->commit();
  }
  if (!o.report.empty()) {
    Report r("ISO 230-6 diagonal displacements of " + m.name, command_line());
    r.set_machine(m);
    for (const auto& p : o.model.params) r.add_input("parameter file", p);
    r.add_figure("box", o.box, "mm, deg");
    const auto worst = std::max_element(diagonals.begin(), diagonals.end(), [](const auto& x, const auto& y) { return x.range < y.range; });
    r.add_figure("largest range", um(worst->range), "µm on " + worst->name);
    r.add_section("Diagonal displacement errors");
    r.add_paragraph("What a laser aligned with each diagonal would read: the tool's translational error projected on "
                    "the diagonal, relative to its start (ISO 230-6). Simulated from the model.");
    for (const bool body : {true, false}) {
      json data = json::array();
      for (const auto& d : diagonals) {
        if ((d.name.rfind("body", 0) == 0) != body) continue;
        json x = json::array(), y = json::array();
        for (std::size_t i = 0; i < d.position.size(); ++i) x.push_back(d.position[i]), y.push_back(d.deviation[i] * 1e3);
        data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"x", x}, {"y", y}, {"name", d.name}});
      }
      if (data.empty()) continue;
      r.add_plot(body ? "Body diagonals" : "Face diagonals",
                 {{"data", data},
                  {"layout", {{"xaxis", {{"title", {{"text", "position along the diagonal (mm)"}}}}},
                              {"yaxis", {{"title", {{"text", "displacement error (µm)"}}}}}}}});
    }
    std::vector<std::vector<std::string>> rows;
    for (const auto& d : diagonals)
      rows.push_back({d.name, format_joint_values(m, d.start, ", "), format_joint_values(m, d.end, ", "),
                      fmt::format("{:.1f}", d.length), um(d.range)});
    r.add_table("Diagonals", {"diagonal", "from", "to", "length (mm)", "range (µm)"}, rows);
    r.write(o.report);
  }
  if (o.json_out) {
    json j;
    j["machine"] = m.name;
    j["diagonals"] = json::array();
    for (const auto& d : diagonals)
      j["diagonals"].push_back({{"name", d.name},
                                {"from", joint_json(m, d.start)},
                                {"to", joint_json(m, d.end)},
                                {"length", d.length},
                                {"direction", vec_json(d.direction)},
                                {"range", d.range},
                                {"position", d.position},
                                {"deviation", d.deviation}});
    if (!o.out.empty()) j["out"] = o.out;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("{:<16} {:>10} {:>12} {:>12} {:>12}\n", "diagonal", "length mm", "range um", "end um", "max |d| um");
  for (const auto& d : diagonals) {
    double mx = 0;
    for (double v : d.deviation) mx = std::max(mx, std::abs(v));
    std::cout << fmt::format("{:<16} {:>10.1f} {:>12} {:>12} {:>12}\n", d.name, d.length, um(d.range), um(d.deviation.back()), um(mx));
  }
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_volumetric_commands(CLI::App& app) {
  std::vector<Command> out;
  {
    auto o = std::make_shared<VolumetricOptions>();
    auto* c = app.add_subcommand(
        "volumetric", "Volumetric accuracy (Fletcher 2009): the exact largest difference between the error vectors of "
                      "any two points of a grid or list of configurations, per component too, with the critical pair "
                      "and what makes it; optional pair histogram, reduced volumes and Fletcher's grouping");
    add_model_options(c, o->model);
    add_map_options(c, o->source);
    c->add_option("--box", o->box, "Also the VA of a sub-box of the map, e.g. \"X=0:250,Y=0:200\" (lo:hi; axes not named: all)");
    c->add_option("--box-scan", o->box_scan, "VA of N boxes centred on --centre, sides 1/N, 2/N .. 1 of the map's")
        ->check(CLI::Range(1, 1000));
    c->add_option("--centre", o->centre, "Centre of the --box-scan boxes (default: the middle of the map)");
    c->add_option("--histogram", o->histogram, "Histogram of |e_i - e_j| over all pairs and of |e_i|: a bin count or 'auto'");
    c->add_option("--group-angle", o->group_angle, "Fletcher's grouping: angle tolerance (sum of unit-vector component "
                                                   "differences; default 0.1 when only --group-magnitude is given)")
        ->check(kFinite);
    c->add_option("--group-magnitude", o->group_magnitude, "Fletcher's grouping: magnitude tolerance (default 0.9)")->check(kFinite);
    c->add_option("--out", o->out, "Write the error map as CSV: axis columns (mm, deg), dx, dy, dz (mm)");
    c->add_option("--report", o->report, "Write an HTML report: critical pair, error map, contributions, distributions");
    c->add_flag("--json", o->json_out, "Machine-readable output: points pairs va va_x va_y va_z critical_pair ... (mm)");
    out.push_back({c, [o] { return run_volumetric(*o); }});
  }
  {
    auto o = std::make_shared<ContributionOptions>();
    auto* c = app.add_subcommand(
        "contributions", "Contribution of every error (first order, ranked, um and %) to the error at a configuration, "
                         "to the difference of two, or to a map's critical pair with the exact VA gained by removing "
                         "each error (Fletcher 2009, 5)");
    add_model_options(c, o->model);
    add_map_options(c, o->source);
    c->add_option("--at", o->at, "One configuration, e.g. \"X=100,Y=50,Z=-20\" (mm, deg)");
    c->add_option("--pair", o->pair, "Two configurations FROM;TO, e.g. \"X=0,Y=0,Z=0;X=500,Y=400,Z=-300\": e(TO) - e(FROM)");
    c->add_option("--top", o->top, "Errors listed")->check(CLI::Range(1, 100000))->capture_default_str();
    c->add_flag("--no-what-if", o->no_what_if, "With --grid/--points: skip the VA with each error removed");
    c->add_option("--report", o->report, "Write an HTML report");
    c->add_flag("--json", o->json_out, "Machine-readable output: exact first_order residual items[error effect along share] (mm)");
    out.push_back({c, [o] { return run_contributions(*o); }});
  }
  {
    auto o = std::make_shared<DiagonalCommandOptions>();
    auto* c = app.add_subcommand("diagonals", "ISO 230-6 diagonal displacement tests simulated on the model: the 4 body "
                                              "diagonals and 12 face diagonals of a box, error along each and its range");
    add_model_options(c, o->model);
    c->add_option("--box", o->box, "The box, e.g. \"X=0:500,Y=0:400,Z=-300:0\" (mm; rotary axes as single values, "
                                   "default 0)")
        ->required();
    c->add_option("--points", o->points, "Targets per diagonal, ends included")->check(CLI::Range(2, 1000000))->capture_default_str();
    c->add_flag("--no-face", o->no_face, "Body diagonals only");
    c->add_flag("--no-travel-check", o->no_travel_check, "Allow a box outside the axes' travels");
    c->add_option("--out", o->out, "Write CSV: diagonal, position (mm), deviation (mm)");
    c->add_option("--report", o->report, "Write an HTML report with the deviation curves");
    c->add_flag("--json", o->json_out, "Machine-readable output: diagonals[name from to length direction range position deviation] (mm)");
    out.push_back({c, [o] { return run_diagonals(*o); }});
  }
  return out;
}

}  // namespace mtcal::cli
