#include "mtcal/report/volumetric.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/io/text/joints.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {
namespace {

using json = nlohmann::ordered_json;

constexpr std::size_t kConeSamples = kMapSamples;

// mm as um with 3 decimals; what rounds to zero prints as 0.000, never -0.000.
std::string um(double mm) { return fmt::format("{:.3f}", std::abs(mm) < 5e-7 ? 0.0 : mm * 1e3); }

std::vector<double> config(const ErrorMap& map, std::size_t i) {
  const auto q = map.configuration(i);
  return {q.begin(), q.end()};
}

// A streamed study's map holds its samples first (VolumetricStudy::sample_points).
std::vector<ConeSample> cone_samples(const ErrorModel& model, const ErrorMap& map, const VolumetricStudy& s) {
  const std::size_t stride =
      s.map_points ? 1 : std::max<std::size_t>(1, (map.size() + kConeSamples - 1) / kConeSamples);
  const std::size_t end = s.map_points ? s.sample_points : map.size();
  std::vector<ConeSample> out;
  for (std::size_t i = 0; i < end; i += stride)
    out.push_back({config(map, i), model.nominal_pose(map.configuration(i)).t, map.error[i]});
  return out;
}

json contributions_figure(const ContributionAnalysis& c, std::size_t top) {
  json names = json::array(), along = json::array();
  for (std::size_t k = 0; k < c.items.size() && k < top; ++k) {
    names.push_back(c.items[k].error.str());
    along.push_back(c.items[k].along * 1e3);
  }
  return {{"data", {{{"type", "bar"}, {"x", names}, {"y", along}, {"name", "contribution"}}}},
          {"layout",
           {{"xaxis", {{"title", {{"text", "error"}}}}},
            {"yaxis", {{"title", {{"text", "part along the difference (µm)"}}}}}}}};
}

std::vector<std::vector<std::string>> contributions_rows(const ContributionAnalysis& c) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& it : c.items)
    rows.push_back({it.error.str(), um(it.effect.x()), um(it.effect.y()), um(it.effect.z()), um(it.along),
                    fmt::format("{:.1f}", it.share * 100)});
  return rows;
}
const std::vector<std::string> kContributionColumns{"error",   "dx (µm)",    "dy (µm)",
                                                    "dz (µm)", "along (µm)", "share (%)"};

json histogram_figure(const Distribution& d, const std::string& xtitle, const std::string& ytitle) {
  json centres = json::array();
  for (std::size_t b = 0; b < d.histogram.counts.size(); ++b)
    centres.push_back((d.histogram.lo + (static_cast<double>(b) + 0.5) * d.histogram.width) * 1e3);
  return {{"data", {{{"type", "bar"}, {"x", centres}, {"y", d.histogram.counts}, {"name", ytitle}}}},
          {"layout",
           {{"xaxis", {{"title", {{"text", xtitle}}}}}, {"yaxis", {{"title", {{"text", ytitle}}}}}, {"bargap", 0.02}}}};
}

}  // namespace

void write_volumetric_report(const std::string& path, const ErrorModel& model, const ErrorMap& map,
                             const VolumetricStudy& s, const std::string& box_text, const ReportSources& sources,
                             const ToleranceVerdict& verdict) {
  const Machine& m = model.machine();
  const VolumetricAccuracy& va = s.va;
  Report r("Volumetric accuracy of " + m.name, sources.command);
  r.set_verdict(verdict);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  if (!sources.points_file.empty()) r.add_input("configurations", sources.points_file);
  if (!sources.grid.empty()) r.add_figure("grid", sources.grid, "mm, deg");
  r.add_figure("volumetric accuracy VA", um(va.va.value), "µm (largest |e_i − e_j| over all pairs)");
  r.add_figure("VA per component x, y, z",
               fmt::format("{}, {}, {}", um(va.component[0].value), um(va.component[1].value),
                           um(va.component[2].value)),
               "µm");
  r.add_figure("points, pairs", fmt::format("{}, {:.6g}", va.points, va.pairs), "");
  if (s.box_va)
    r.add_figure("VA of the box " + box_text, um(s.box_va->va.value), fmt::format("µm ({} points)", s.box_va->points));
  r.add_section("Critical pair");
  r.add_paragraph(
      "The two configurations whose translational errors differ most: a feature machined at one and "
      "another at the other carry this error between them (Fletcher 2009, 4.1). Exact: the same pair "
      "value a comparison of every pair gives.");
  r.add_table("The critical pair and the per-component extremes (workpiece frame)",
              {"difference", "from (mm, deg)", "to (mm, deg)", "e from (µm)", "e to (µm)", "value (µm)"}, [&] {
                std::vector<std::vector<std::string>> rows;
                auto row = [&](const std::string& what, const PointPair& p) {
                  const Vec3 a = map.error[p.i] * 1e3, b = map.error[p.j] * 1e3;
                  rows.push_back({what, format_joint_values(m, config(map, p.i), ", "),
                                  format_joint_values(m, config(map, p.j), ", "),
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
  r.add_paragraph(
      "Each cone is the translational error at the nominal tool point (workpiece frame); the red line "
      "joins the critical pair.");
  const std::size_t points = s.map_points ? s.map_points : map.size();
  r.add_plot(fmt::format("Translational errors (µm) over {} configurations{}", points,
                         points > kConeSamples ? fmt::format(", {} shown", cone_samples(model, map, s).size()) : ""),
             error_cone_figure(m, cone_samples(model, map, s),
                               {{"from", model.nominal_pose(map.configuration(va.va.i)).t},
                                {"to", model.nominal_pose(map.configuration(va.va.j)).t}},
                               true));
  r.add_section("What makes the critical difference");
  r.add_paragraph(
      "First-order contribution of each error to e(to) − e(from), projected on that difference (Fletcher "
      "2009, 5): correct the largest first. Shares sum to 100 % up to the second-order remainder.");
  r.add_plot("Contributions to the critical difference (µm along it)", contributions_figure(s.critical, 20));
  r.add_table(fmt::format("Contributions (first-order sum {:.3f} µm; exact {:.3f} µm; remainder {:.4f} µm)",
                          s.critical.first_order.norm() * 1e3, s.critical.exact.norm() * 1e3,
                          s.critical.residual * 1e3),
              kContributionColumns, contributions_rows(s.critical));
  if (s.pairs) {
    r.add_section("Distributions");
    r.add_paragraph(
        fmt::format("Every one of the {} pairs counted once. Mean {:.3f} µm; percentiles (within one bin, "
                    "{:.3f} µm): 50 % {:.3f}, 90 % {:.3f}, 95 % {:.3f}, 99 % {:.3f} µm.",
                    s.pairs->count, s.pairs->mean * 1e3, s.pairs->histogram.width * 1e3,
                    s.pairs->histogram.quantile(0.5) * 1e3, s.pairs->histogram.quantile(0.9) * 1e3,
                    s.pairs->histogram.quantile(0.95) * 1e3, s.pairs->histogram.quantile(0.99) * 1e3));
    r.add_plot("Differences |e_i − e_j| over all pairs", histogram_figure(*s.pairs, "|e_i − e_j| (µm)", "pairs"));
    r.add_plot("Errors |e_i| over all configurations", histogram_figure(*s.magnitudes, "|e| (µm)", "configurations"));
  }
  if (!s.scan.empty()) {
    r.add_section("Reduced volume");
    r.add_paragraph(
        "VA of boxes centred on one configuration, their sides a fraction of the map's (Fletcher 2009, 4.2).");
    json f = json::array(), v = json::array();
    std::vector<std::vector<std::string>> rows;
    for (const auto& b : s.scan) {
      f.push_back(b.fraction);
      v.push_back(b.va.value * 1e3);
      rows.push_back({fmt::format("{:.3g}", b.fraction), format_joint_values(m, b.lo, ", "),
                      format_joint_values(m, b.hi, ", "), fmt::format("{}", b.points), um(b.va.value)});
    }
    r.add_plot("VA against box size",
               {{"data", {{{"type", "scatter"}, {"mode", "lines+markers"}, {"x", f}, {"y", v}, {"name", "VA"}}}},
                {"layout",
                 {{"xaxis", {{"title", {{"text", "box side / map side"}}}}},
                  {"yaxis", {{"title", {{"text", "VA (µm)"}}}}}}}});
    r.add_table("VA of centred boxes", {"fraction", "from", "to", "points", "VA (µm)"}, rows);
  }
  if (s.grouping) {
    const GroupingComparison& g = *s.grouping;
    r.add_section("Fletcher's direction grouping");
    r.add_paragraph(
        "The approximation of Fletcher 2009, 4.1 (vectors grouped by direction; those below the magnitude "
        "tolerance of their group's largest dismissed) against the exact VA above.");
    r.add_table("Grouping",
                {"angle tolerance", "magnitude tolerance", "groups", "records kept", "comparisons", "VA (µm)",
                 "exact VA (µm)", "difference (%)"},
                {{fmt::format("{:g}", g.options.angle_tolerance), fmt::format("{:g}", g.options.magnitude_tolerance),
                  fmt::format("{}", g.result.groups), fmt::format("{} of {}", g.result.kept.size(), points),
                  fmt::format("{:.6g}", g.result.comparisons), um(g.result.va.value), um(va.va.value),
                  fmt::format("{:.3f}", g.difference_percent)}});
  }
  r.write(path);
}

// "EC0Y (7.500 µm against it), EXX (6.528), EXZ (4.500)": the first three errors it cancelled.
static std::string cancelled_list(const WhatIf& w) {
  std::string out;
  for (std::size_t k = 0; k < w.cancelled.size() && k < 3; ++k)
    out += fmt::format("{}{} ({}{})", k ? ", " : "", w.cancelled[k].first.str(), um(w.cancelled[k].second),
                       k ? "" : " µm against it");
  return out;
}

void write_contributions_report(const std::string& path, const Machine& m, const ContributionStudy& s,
                                const ReportSources& sources) {
  Report r("Error contributions on " + m.name, sources.command);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  if (!sources.points_file.empty()) r.add_input("configurations", sources.points_file);
  const std::string what =
      s.b.empty() ? "e(" + format_joint_values(m, s.a, ", ") + ")"
                  : "e(" + format_joint_values(m, s.a, ", ") + ") − e(" + format_joint_values(m, s.b, ", ") + ")";
  r.add_figure("exact", fmt::format("{:.3f}", s.analysis.exact.norm() * 1e3), "µm: |" + what + "|");
  r.add_figure("first-order sum", fmt::format("{:.3f}", s.analysis.first_order.norm() * 1e3), "µm");
  r.add_figure("second-order remainder", fmt::format("{:.4f}", s.analysis.residual * 1e3), "µm");
  if (s.va) r.add_figure("VA (critical pair)", um(s.va->va.value), "µm over " + sources.grid + sources.points_file);
  r.add_section("Contributions");
  r.add_paragraph(
      "First-order effect of each error (its sensitivity on the error-free machine times its value at the "
      "configurations), projected on the exact error; largest first (Fletcher 2009, 5).");
  r.add_plot("Contribution of each error (µm along the exact error)", contributions_figure(s.analysis, 30));
  r.add_table("Contributions", kContributionColumns, contributions_rows(s.analysis));
  if (!s.what_if.empty()) {
    r.add_section("Which error to correct first");
    r.add_paragraph("The exact VA of the map with one error removed and every other kept.");
    json names = json::array(), gains = json::array();
    std::vector<std::vector<std::string>> rows;
    for (const auto& w : s.what_if) {
      names.push_back(w.error.str());
      gains.push_back((s.va->va.value - w.va) * 1e3);
      rows.push_back({w.error.str(), um(w.va), um(s.va->va.value - w.va)});
    }
    r.add_plot("VA gained by removing each error (µm)",
               {{"data", {{{"type", "bar"}, {"x", names}, {"y", gains}, {"name", "gain"}}}},
                {"layout", {{"yaxis", {{"title", {{"text", "VA − VA without the error (µm)"}}}}}}}});
    r.add_table("VA without each error", {"error removed", "VA (µm)", "gain (µm)"}, rows);
    for (const auto& w : s.what_if)
      if (w.disagrees)
        r.add_paragraph(fmt::format(
            "{} has a first-order share of {:.1f}% of the critical difference, yet removing it {} the VA from {} "
            "to {} µm: without it the pair from {} to {} is critical{}.",
            w.error.str(), 100 * w.share, w.va > s.va->va.value ? "raises" : "lowers", um(s.va->va.value), um(w.va),
            format_joint_values(m, w.from, ", "), format_joint_values(m, w.to, ", "),
            w.along_there < 0 && !w.cancelled.empty() ? fmt::format(", where {} ({} µm along it) was cancelling {}",
                                                                    w.error.str(), um(w.along_there), cancelled_list(w))
                                                      : std::string()));
  }
  if (s.sequence) {
    const auto& q = *s.sequence;
    r.add_section("Errors to correct to reach the target VA");
    r.add_paragraph(
        fmt::format("Greedy sequence: at each step the error whose removal gives the smallest exact VA over the map is "
                    "removed, until the VA is at most {} µm{}.",
                    um(q.target), q.reached ? "" : " (not reached: every error removed)"));
    std::vector<std::vector<std::string>> rows{{"0", "(none)", um(q.start)}};
    for (std::size_t k = 0; k < q.steps.size(); ++k)
      rows.push_back({std::to_string(k + 1), q.steps[k].error.str(), um(q.steps[k].va)});
    r.add_table("Correction sequence", {"step", "error corrected", "VA after (µm)"}, rows);
  }
  r.write(path);
}

void write_diagonals_report(const std::string& path, const Machine& m, const std::vector<DiagonalProfile>& diagonals,
                            const std::string& box_text, const ReportSources& sources) {
  Report r("ISO 230-6 diagonal displacements of " + m.name, sources.command);
  r.set_machine(m);
  for (const auto& p : sources.parameter_files) r.add_input("parameter file", p);
  r.add_figure("box", box_text, "mm, deg");
  const auto worst = std::max_element(diagonals.begin(), diagonals.end(),
                                      [](const auto& x, const auto& y) { return x.range < y.range; });
  r.add_figure("largest range", um(worst->range), "µm on " + worst->name);
  r.add_section("Diagonal displacement errors");
  r.add_paragraph(
      "What a laser aligned with each diagonal would read: the tool's translational error projected on "
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
                {"layout",
                 {{"xaxis", {{"title", {{"text", "position along the diagonal (mm)"}}}}},
                  {"yaxis", {{"title", {{"text", "displacement error (µm)"}}}}}}}});
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& d : diagonals)
    rows.push_back({d.name, format_joint_values(m, d.start, ", "), format_joint_values(m, d.end, ", "),
                    fmt::format("{:.1f}", d.length), um(d.range)});
  r.add_table("Diagonals", {"diagonal", "from", "to", "length (mm)", "range (µm)"}, rows);
  r.write(path);
}

}  // namespace mtcal
