// HTML report of a calibration campaign (report/campaign.hpp).
#include "mtcal/report/campaign.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mtcal/util/units.hpp"

namespace mtcal {
namespace {

using nlohmann::json;

std::string um(double mm) { return fmt::format("{:.3f}", mm * 1e3); }

// A parameter's value in a unit people read: um, urad, um/m ... (internal mm, rad, mm/mm).
std::pair<double, std::string> display(const std::string& unit) {
  if (unit == "mm") return {1e3, "µm"};
  if (unit == "rad") return {1e6, "µrad"};
  return {1.0, unit};
}

std::string cell(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : std::string("–"); }

}  // namespace

Report campaign_report_page(const Machine& m, const CampaignResult& r, const CampaignReportInputs& in,
                            const std::string& command) {
  Report rep("Calibration campaign", command);
  rep.set_machine(m);
  for (const auto& f : in.machine_files)
    if (!f.empty()) rep.add_input("machine", f);
  rep.add_input("probed before", in.before);
  rep.add_input("probed after", in.after);
  if (!in.identified.empty()) rep.add_input("identification", in.identified);
  if (!in.truth.empty()) rep.add_input("truth", in.truth);
  if (!in.poses_before.empty()) rep.add_input("reached poses before", in.poses_before);
  if (!in.poses_after.empty()) rep.add_input("reached poses after", in.poses_after);
  const char* ref = r.reference == BallReference::Nominal      ? "from the nominal centres"
                    : r.reference == BallReference::Identified ? "from the identified centres"
                                                               : "about each ball's mean";
  rep.add_figure("probed centres before", fmt::format("max {} / RMS {}", um(r.before.max), um(r.before.rms)),
                 std::string("µm, ") + ref);
  rep.add_figure("probed centres after", fmt::format("max {} / RMS {}", um(r.after.max), um(r.after.rms)),
                 std::string("µm, ") + ref);
  if (r.after.rms > 0)
    rep.add_figure("improvement", fmt::format("{:.3g}", r.before.rms / r.after.rms), "× (RMS before / RMS after)");
  if (r.identification)
    rep.add_figure("fit residual", fmt::format("{:.3f}", r.identification->rms_ball * 1e3),
                   fmt::format("µm RMS (ball centres), sigma0 {:.3g}", r.identification->sigma0));
  if (!r.parameters.empty())
    rep.add_figure("parameters against the truth", fmt::format("{} of {} within 3 u", r.parameters.size() - r.beyond_3u,
                                                               r.parameters.size()),
                   fmt::format("largest |d|/u {:.3g}", r.max_ratio));
  if (r.poses_before)
    rep.add_figure("reached poses before", fmt::format("max |e| {} / VA {}", um(r.poses_before->max_error),
                                                       um(r.poses_before->va.va.value)),
                   fmt::format("µm, {} poses", r.poses_before->poses.size()));
  if (r.poses_after)
    rep.add_figure("reached poses after", fmt::format("max |e| {} / VA {}", um(r.poses_after->max_error),
                                                      um(r.poses_after->va.va.value)),
                   fmt::format("µm, {} poses", r.poses_after->poses.size()));
  if (r.residual_goal && !*r.residual_goal)
    rep.add_warning(fmt::format("The probed centres after compensation: RMS per coordinate {} µm, above 2 × the "
                                "probing noise ({} µm).",
                                um(r.after.rms_coordinate), um(2 * r.probing_noise)));
  if (r.parameter_goal && !*r.parameter_goal)
    rep.add_warning(fmt::format("{} identified parameters are more than 3 u from the truth (or have no u or no truth).",
                                r.beyond_3u));
  if (!r.not_estimated.empty())
    rep.add_warning(fmt::format("{} parameters of the truth are not zero and were not estimated: the model cannot reach "
                                "the truth, and the estimates are biased.",
                                r.not_estimated.size()));
  if (r.identification && !r.identification->converged) rep.add_warning("The identification did not converge.");

  rep.add_section("Probed sphere centres");
  rep.add_paragraph(fmt::format(
      "Each ball record: the nominal tool point at the linear axes' readings (where the controller saw the centre) "
      "minus the ball's centre ({}), in the workpiece frame. {} ball records{}.",
      r.reference == BallReference::Nominal      ? "the plan's nominal centre"
      : r.reference == BallReference::Identified ? "the identification's estimate"
                                                 : "the mean of the ball's centres in the same measurement",
      r.probed.size(), r.facets ? fmt::format("; {} facet records not compared", r.facets) : std::string()));
  json x = json::array(), yb = json::array(), ya = json::array(), text = json::array();
  std::vector<std::vector<std::string>> rows;
  std::vector<char> rotary;
  for (const auto& ax : m.axes)
    if (ax.kind == AxisKind::Rotary) rotary.push_back(ax.letter);
  for (const auto& d : r.probed) {
    std::string at;
    for (std::size_t k = 0; k < d.rotary.size() && k < rotary.size(); ++k)
      at += fmt::format("{}{}={:g}", at.empty() ? "" : ",", rotary[k], d.rotary[k] / kRadPerDeg);
    x.push_back(d.record);
    yb.push_back(d.before.norm() * 1e3);
    ya.push_back(d.after.norm() * 1e3);
    text.push_back(fmt::format("ball {} at {}", d.feature, at));
    rows.push_back({std::to_string(d.record), std::to_string(d.indexation), d.feature, at, um(d.before.x()),
                    um(d.before.y()), um(d.before.z()), um(d.before.norm()), um(d.after.x()), um(d.after.y()),
                    um(d.after.z()), um(d.after.norm())});
  }
  rep.add_plot("|deviation| of each probed centre before and after (µm)",
               {{"data",
                 {{{"type", "bar"}, {"x", x}, {"y", yb}, {"text", text}, {"name", "before"}},
                  {{"type", "bar"}, {"x", x}, {"y", ya}, {"text", text}, {"name", "after"}}}},
                {"layout",
                 {{"barmode", "group"},
                  {"xaxis", {{"title", {{"text", "record"}}}}},
                  {"yaxis", {{"title", {{"text", "µm"}}}}}}}});
  rep.add_table("Deviations (µm)",
                {"record", "indexation", "ball", "rotary (deg)", "dx before", "dy before", "dz before", "|d| before",
                 "dx after", "dy after", "dz after", "|d| after"},
                rows);

  if (r.identification) {
    const auto& id = *r.identification;
    rep.add_section("Identification");
    rep.add_paragraph(fmt::format("{}: {}, {} residuals, {} unknowns, rank {}; residual RMS balls {:.3f} µm, facets "
                                  "{:.3f} µm; sigma0 {:.3g}.",
                                  id.source, id.converged ? "converged" : "NOT converged", id.residuals, id.unknowns,
                                  id.rank, id.rms_ball * 1e3, id.rms_facet * 1e3, id.sigma0));
    std::vector<std::vector<std::string>> prow;
    json names = json::array(), ratios = json::array();
    if (!r.parameters.empty()) {
      for (const auto& p : r.parameters) {
        const auto [f, u] = display(p.unit);
        prow.push_back({p.name, u, cell(p.value * f), cell(p.u * f), p.truth ? cell(*p.truth * f) : "–",
                        p.truth ? cell(p.deviation * f) : "–", cell(p.ratio)});
        names.push_back(p.name);
        ratios.push_back(std::isfinite(p.ratio) ? json(p.ratio) : json(nullptr));
      }
      rep.add_table("Identified parameters against the truth (u: standard uncertainty; d = value − truth)",
                    {"parameter", "unit", "value", "u", "truth", "d", "|d|/u"}, prow);
      rep.add_plot("|d|/u of each identified parameter (goal: within 3)",
                   {{"data", {{{"type", "bar"}, {"x", names}, {"y", ratios}, {"name", "|d|/u"}}}},
                    {"layout",
                     {{"yaxis", {{"title", {{"text", "|d|/u"}}}}},
                      {"shapes",
                       {{{"type", "line"},
                         {"xref", "paper"},
                         {"x0", 0},
                         {"x1", 1},
                         {"y0", 3},
                         {"y1", 3},
                         {"line", {{"color", "red"}}}}}}}}});
    } else {
      for (const auto& p : id.parameters) {
        const auto [f, u] = display(p.unit);
        prow.push_back({p.name, u, cell(p.value * f), cell(p.u * f)});
      }
      rep.add_table("Identified parameters (u: standard uncertainty)", {"parameter", "unit", "value", "u"}, prow);
    }
    if (!r.not_estimated.empty()) {
      std::vector<std::vector<std::string>> nrow;
      for (const auto& [name, v] : r.not_estimated) nrow.push_back({name, cell(v)});
      rep.add_table("Parameters of the truth not estimated (internal units mm, rad)", {"parameter", "truth"}, nrow);
    }
  }

  if (r.poses_before || r.poses_after) {
    rep.add_section("Reached poses");
    rep.add_paragraph(
        "Each commanded pose: the truth machine's actual tool point at the joints the controller reached, minus the "
        "commanded point; VA is the largest |e_i − e_j| over the poses (Fletcher 2009).");
    std::vector<std::vector<std::string>> prow;
    json data = json::array();
    for (const auto& [label, c] : {std::pair<const char*, const std::optional<PoseCheck>*>{"before", &r.poses_before},
                                   {"after", &r.poses_after}}) {
      if (!*c) continue;
      const PoseCheck& pc = **c;
      prow.push_back({label, std::to_string(pc.poses.size()), um(pc.max_error), um(pc.rms_error), um(pc.va.va.value),
                      fmt::format("{:.3f}", pc.max_direction_error * 1e6)});
      json ys = json::array();
      for (const auto& d : pc.poses) ys.push_back(d.error.norm() * 1e3);
      data.push_back({{"type", "histogram"}, {"x", ys}, {"name", label}, {"opacity", 0.6}});
    }
    rep.add_table("Tool point at the reached poses (µm; direction in µrad)",
                  {"", "poses", "max |e|", "RMS |e|", "VA", "max direction error"}, prow);
    rep.add_plot("Distribution of |e| over the reached poses (µm)",
                 {{"data", data},
                  {"layout",
                   {{"barmode", "overlay"},
                    {"xaxis", {{"title", {{"text", "|e| (µm)"}}}}},
                    {"yaxis", {{"title", {{"text", "poses"}}}}}}}});
  }
  return rep;
}

}  // namespace mtcal
