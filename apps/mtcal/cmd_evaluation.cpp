// mtcal iso230-2: ISO 230-2 positioning accuracy and repeatability of a linear axis.
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/io/files.hpp"
#include "mtcal/report/report.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

using json = nlohmann::ordered_json;

struct Iso2302Options {
  std::string file, unit = "mm", report, format = "auto";
  bool json_out = false;
};

bool looks_like_dat(const std::string& path) {
  if (path.size() >= 4 && path.substr(path.size() - 4) == ".dat") return true;
  return read_text_file(path, "positioning file").find("TGT_DATA[") != std::string::npos;
}

void write_report(const Iso2302Options& o, const PositioningRuns& runs, const PositioningEvaluation& e) {
  Report r("ISO 230-2 positioning of a linear axis", command_line());
  r.add_input("measurements", o.file);
  const std::string u = e.unit;
  r.add_figure("accuracy A", fmt::format("{:.4f}", e.A), u);
  r.add_figure("repeatability R", fmt::format("{:.4f}", e.R), u);
  r.add_figure("reversal value B", fmt::format("{:.4f}", e.B), u);
  r.add_figure("systematic positioning error E", fmt::format("{:.4f}", e.E), u);
  r.add_figure("mean positioning error M", fmt::format("{:.4f}", e.M), u);
  r.add_figure("targets x runs", fmt::format("{} x {}", e.targets.size(), e.runs), "per direction");
  if (e.runs < 5) r.add_warning(fmt::format("ISO 230-2 asks for 5 runs per direction; this has {}.", e.runs));

  r.add_section("Deviations");
  r.add_paragraph("Mean positional deviation per target and direction (x̄↑ up, x̄↓ down) with the ±2s bands that "
                  "define the accuracy A, and every run's deviation as a point.");
  json x = json::array(), up = x, dn = x, up_hi = x, up_lo = x, dn_hi = x, dn_lo = x, mean = x;
  json rx_up = x, ry_up = x, rx_dn = x, ry_dn = x;
  for (std::size_t i = 0; i < e.targets.size(); ++i) {
    const auto& t = e.targets[i];
    x.push_back(t.target);
    up.push_back(t.mean_up);
    dn.push_back(t.mean_down);
    mean.push_back(t.mean);
    up_hi.push_back(t.mean_up + 2 * t.s_up);
    up_lo.push_back(t.mean_up - 2 * t.s_up);
    dn_hi.push_back(t.mean_down + 2 * t.s_down);
    dn_lo.push_back(t.mean_down - 2 * t.s_down);
    for (double v : runs.up[i]) rx_up.push_back(t.target), ry_up.push_back(v - t.target);
    for (double v : runs.down[i]) rx_dn.push_back(t.target), ry_dn.push_back(v - t.target);
  }
  auto band = [&](const json& lo, const json& hi, const char* colour, const char* name) {
    return json::array({json{{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", lo}, {"line", {{"width", 0}}},
                             {"showlegend", false}, {"hoverinfo", "skip"}},
                        json{{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", hi}, {"fill", "tonexty"},
                             {"fillcolor", colour}, {"line", {{"width", 0}}}, {"name", name}}});
  };
  json data = json::array();
  for (auto& t : band(up_lo, up_hi, "rgba(31,119,180,0.2)", "x̄↑ ± 2s↑")) data.push_back(t);
  for (auto& t : band(dn_lo, dn_hi, "rgba(214,39,40,0.2)", "x̄↓ ± 2s↓")) data.push_back(t);
  data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"x", x}, {"y", up}, {"name", "x̄↑ (up)"},
                  {"line", {{"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "lines+markers"}, {"x", x}, {"y", dn}, {"name", "x̄↓ (down)"},
                  {"line", {{"color", "rgb(214,39,40)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "lines"}, {"x", x}, {"y", mean}, {"name", "x̄ (bidirectional)"},
                  {"line", {{"color", "black"}, {"dash", "dot"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "markers"}, {"x", rx_up}, {"y", ry_up}, {"name", "runs up"},
                  {"marker", {{"size", 4}, {"color", "rgb(31,119,180)"}}}});
  data.push_back({{"type", "scatter"}, {"mode", "markers"}, {"x", rx_dn}, {"y", ry_dn}, {"name", "runs down"},
                  {"marker", {{"size", 4}, {"color", "rgb(214,39,40)"}}}});
  r.add_plot("Positional deviation x = measured − target (" + u + ") against the target position (" + u + ")",
             {{"data", data},
              {"layout", {{"xaxis", {{"title", {{"text", "target (" + u + ")"}}}}},
                          {"yaxis", {{"title", {{"text", "deviation (" + u + ")"}}}}}}}});

  r.add_section("Per target");
  std::vector<std::vector<std::string>> rows;
  for (const auto& t : e.targets)
    rows.push_back({fmt::format("{:g}", t.target), fmt::format("{:.5f}", t.mean_up), fmt::format("{:.5f}", t.mean_down),
                    fmt::format("{:.5f}", t.mean), fmt::format("{:.5f}", t.reversal), fmt::format("{:.5f}", t.s_up),
                    fmt::format("{:.5f}", t.s_down), fmt::format("{:.5f}", t.R_up), fmt::format("{:.5f}", t.R_down),
                    fmt::format("{:.5f}", t.R)});
  r.add_table("ISO 230-2 quantities per target (" + u + ")",
              {"target", "x̄↑", "x̄↓", "x̄", "B_i", "s↑", "s↓", "R↑", "R↓", "R_i"}, rows);
  r.add_table("Axis (" + u + ")", {"A", "A↑", "A↓", "B", "B̄", "R", "R↑", "R↓", "E", "E↑", "E↓", "M"},
              {{fmt::format("{:.5f}", e.A), fmt::format("{:.5f}", e.A_up), fmt::format("{:.5f}", e.A_down),
                fmt::format("{:.5f}", e.B), fmt::format("{:.5f}", e.B_mean), fmt::format("{:.5f}", e.R),
                fmt::format("{:.5f}", e.R_up), fmt::format("{:.5f}", e.R_down), fmt::format("{:.5f}", e.E),
                fmt::format("{:.5f}", e.E_up), fmt::format("{:.5f}", e.E_down), fmt::format("{:.5f}", e.M)}});
  r.write(o.report);
}

int run_iso230_2(const Iso2302Options& o) {
  check_outputs({o.file}, {o.report});
  const bool dat = o.format == "dat" || (o.format == "auto" && looks_like_dat(o.file));
  const PositioningRuns runs = dat ? read_positioning_dat(o.file) : read_positioning_csv(o.file, o.unit);
  const PositioningEvaluation e = evaluate_positioning(runs, o.file);
  if (!o.report.empty()) write_report(o, runs, e);
  if (o.json_out) {
    json j;
    for (const auto& [k, v] : std::initializer_list<std::pair<const char*, double>>{
             {"A", e.A}, {"A_up", e.A_up}, {"A_down", e.A_down}, {"B", e.B}, {"B_mean", e.B_mean}, {"R", e.R},
             {"R_up", e.R_up}, {"R_down", e.R_down}, {"E", e.E}, {"E_up", e.E_up}, {"E_down", e.E_down}, {"M", e.M}})
      j[k] = v;
    j["unit"] = e.unit;
    j["runs"] = e.runs;
    json ts = json::array();
    for (const auto& t : e.targets)
      ts.push_back({{"target", t.target}, {"mean_up", t.mean_up}, {"mean_down", t.mean_down}, {"mean", t.mean},
                    {"B", t.reversal}, {"s_up", t.s_up}, {"s_down", t.s_down}, {"R_up", t.R_up},
                    {"R_down", t.R_down}, {"R", t.R}});
    j["targets"] = ts;
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  std::cout << fmt::format("ISO 230-2: {} targets x {} runs per direction, unit {}\n", e.targets.size(), e.runs, e.unit);
  std::cout << fmt::format("{:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "target", "mean_up",
                           "mean_down", "B_i", "s_up", "s_down", "R_i", "mean");
  for (const auto& t : e.targets)
    std::cout << fmt::format("{:>10g} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f} {:>10.5f}\n", t.target,
                             t.mean_up, t.mean_down, t.reversal, t.s_up, t.s_down, t.R, t.mean);
  std::cout << fmt::format("A {:.5f} (up {:.5f}, down {:.5f})   R {:.5f} (up {:.5f}, down {:.5f})\n", e.A, e.A_up,
                           e.A_down, e.R, e.R_up, e.R_down);
  std::cout << fmt::format("B {:.5f} (mean {:.5f})   E {:.5f} (up {:.5f}, down {:.5f})   M {:.5f}   [{}]\n", e.B,
                           e.B_mean, e.E, e.E_up, e.E_down, e.M, e.unit);
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_evaluation_commands(CLI::App& app) {
  auto o = std::make_shared<Iso2302Options>();
  auto* c = app.add_subcommand("iso230-2", "ISO 230-2 linear positioning: accuracy A, repeatability R, reversal B, "
                                           "systematic and mean positioning errors E and M, per target and per axis");
  c->add_option("file", o->file, "Measurements: CSV target,run,direction,measured (direction up/down or +/-), or "
                                 "the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT)")
      ->required();
  c->add_option("--unit", o->unit, "Unit of a CSV's values (a .dat file says its own)")->capture_default_str();
  c->add_option("--format", o->format, "Input format: auto (by .dat extension or content), csv or dat")
      ->check(CLI::IsMember({"auto", "csv", "dat"}))
      ->capture_default_str();
  c->add_flag("--json", o->json_out, "Machine-readable output: A A_up A_down B B_mean R R_up R_down E E_up E_down M at "
                                     "the top level (input unit), per-target values under targets");
  c->add_option("--report", o->report, "Write an HTML report: deviations with ±2s bands per direction, tables");
  return {{c, [o] { return run_iso230_2(*o); }}};
}

}  // namespace mtcal::cli
