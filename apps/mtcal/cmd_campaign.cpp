// mtcal pose-check, campaign: a calibration campaign judged (docs/campaign.md); the truth is drawn by errors --draw.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "common.hpp"
#include "history.hpp"
#include "mtcal/evaluation/pose_check.hpp"
#include "mtcal/identification/campaign.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/json/campaign_json.hpp"
#include "mtcal/io/model/identification_result_file.hpp"
#include "mtcal/io/model/machine_file.hpp"
#include "mtcal/io/points/reached_poses_file.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/report/campaign.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::cli {
namespace {

struct PoseCheckCliOptions {
  ModelOptions model;
  std::string poses;
  bool json_out = false, per_pose = false;
};

void print_pose_check(const PoseCheck& c, const std::string& source) {
  std::cout << fmt::format("{} poses of {} (tool length {:g} mm)\n", c.poses.size(), source, c.tool_length);
  std::cout << fmt::format("max |e| {:.3f} um (pose {}), RMS |e| {:.3f} um, VA {:.3f} um, max direction error {:.3f} urad\n",
                           c.max_error * 1e3, c.max_index, c.rms_error * 1e3, c.va.va.value * 1e3,
                           c.max_direction_error * 1e6);
}

int run_pose_check(const PoseCheckCliOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.poses);
  check_outputs(inputs, {});
  const Machine m = load(o.model);
  const auto poses = read_reached_poses(m, o.poses);
  const PoseCheck c = check_reached_poses(m, poses, {}, o.poses);
  if (o.json_out || recording()) {
    Json j = to_json(c, poses, o.per_pose);
    j["machine"] = m.name;
    if (emit_json(std::move(j), o.json_out)) return 0;
  }
  print_pose_check(c, o.poses);
  return 0;
}

struct CampaignCliOptions {
  ModelOptions model;
  std::string before, after, identified, truth, poses_before, poses_after, report, reference = "nominal";
  double noise_um = 0.0;
  bool json_out = false;
};

int run_campaign(const CampaignCliOptions& o) {
  auto inputs = model_inputs(o.model);
  for (const auto* p : {&o.before, &o.after, &o.identified, &o.truth, &o.poses_before, &o.poses_after})
    inputs.push_back(*p);
  check_outputs(inputs, {o.report});
  if ((!o.poses_before.empty() || !o.poses_after.empty()) && o.truth.empty())
    throw InputError({o.poses_before.empty() ? "--poses-after" : "--poses-before", 0, ""},
                     "the reached poses are evaluated on the truth: give --truth");
  if (o.reference == "identified" && o.identified.empty())
    throw InputError({"--reference", 0, ""}, "--reference identified takes the centres from --identified: give it");
  if (!o.report.empty()) AtomicFile check(o.report);
  const Machine m = load(o.model);
  const ProbingPlan before = read_probing_csv(m, o.before);
  const ProbingPlan after = read_probing_csv(m, o.after);
  std::optional<IdentifiedSummary> identified;
  if (!o.identified.empty()) identified = read_identification_json(o.identified);
  std::optional<Machine> truth;
  if (!o.truth.empty()) {
    truth = m;
    load_parameters(*truth, o.truth);
  }
  std::optional<PoseCheck> pb, pa;
  if (!o.poses_before.empty()) pb = check_reached_poses(*truth, read_reached_poses(*truth, o.poses_before), {}, o.poses_before);
  if (!o.poses_after.empty()) pa = check_reached_poses(*truth, read_reached_poses(*truth, o.poses_after), {}, o.poses_after);
  CampaignOptions co;
  co.reference = o.reference == "identified" ? BallReference::Identified
                 : o.reference == "mean"     ? BallReference::Mean
                                             : BallReference::Nominal;
  co.probing_noise = o.noise_um * 1e-3;
  co.before_source = o.before;
  co.after_source = o.after;
  const CampaignResult r = campaign_report(m, before, after, identified ? &*identified : nullptr,
                                           truth ? &*truth : nullptr, pb ? &*pb : nullptr, pa ? &*pa : nullptr, co);
  if (!o.report.empty())
    campaign_report_page(m, r,
                         {model_inputs(o.model), o.before, o.after, o.identified, o.truth, o.poses_before,
                          o.poses_after},
                         command_line())
        .write(o.report);
  if (o.json_out || recording()) {
    Json j = to_json(r, m);
    if (!o.report.empty()) j["report"] = o.report;
    if (emit_json(std::move(j), o.json_out)) return 0;
  }
  std::cout << fmt::format("probed centres ({} ball records, deviations from the {} centres): before max {:.3f} um, "
                           "RMS {:.3f} um; after max {:.3f} um, RMS {:.3f} um (per coordinate {:.3f} um)\n",
                           r.probed.size(), o.reference, r.before.max * 1e3, r.before.rms * 1e3, r.after.max * 1e3,
                           r.after.rms * 1e3, r.after.rms_coordinate * 1e3);
  if (r.identification)
    std::cout << fmt::format("identification {}: residual RMS balls {:.3f} um, sigma0 {:.3g}{}\n",
                             r.identification->source, r.identification->rms_ball * 1e3, r.identification->sigma0,
                             r.identification->converged ? "" : ", NOT converged");
  if (!r.parameters.empty()) {
    std::cout << fmt::format("{:<10} {:>14} {:>12} {:>14} {:>8}\n", "parameter", "value", "u", "truth", "|d|/u");
    for (const auto& p : r.parameters)
      std::cout << fmt::format("{:<10} {:>14.6g} {:>12.3g} {:>14} {:>8}\n", p.name, p.value, p.u,
                               p.truth ? fmt::format("{:.6g}", *p.truth) : "-",
                               std::isfinite(p.ratio) ? fmt::format("{:.2f}", p.ratio) : "-");
    std::cout << fmt::format("{} of {} within 3 u (largest |d|/u {:.3g})\n", r.parameters.size() - r.beyond_3u,
                             r.parameters.size(), r.max_ratio);
  }
  for (const auto& [name, v] : r.not_estimated)
    std::cout << fmt::format("not estimated, non-zero in the truth: {} = {:.6g}\n", name, v);
  for (const auto& [label, c] : {std::pair<const char*, const std::optional<PoseCheck>*>{"before", &r.poses_before},
                                 {"after", &r.poses_after}})
    if (*c)
      std::cout << fmt::format("reached poses {}: {} poses, max |e| {:.3f} um, VA {:.3f} um\n", label,
                               (*c)->poses.size(), (*c)->max_error * 1e3, (*c)->va.va.value * 1e3);
  if (r.residual_goal)
    std::cout << fmt::format("goal RMS per coordinate after <= 2 x noise ({:.3f} um): {}\n", 2 * r.probing_noise * 1e3,
                             *r.residual_goal ? "met" : "NOT met");
  if (r.parameter_goal) std::cout << fmt::format("goal parameters within 3 u: {}\n", *r.parameter_goal ? "met" : "NOT met");
  if (!o.report.empty()) std::cout << "report " << o.report << "\n";
  return 0;
}

}  // namespace

std::vector<Command> add_campaign_commands(CLI::App& app) {
  std::vector<Command> out;
  {
    auto o = std::make_shared<PoseCheckCliOptions>();
    auto* c = app.add_subcommand(
        "pose-check",
        "The tool point a controller reached: commanded world poses and the joints it computed for them, evaluated on "
        "the machine (the truth): per pose actual - commanded, max |e|, VA");
    add_model_options(c, o->model);
    c->add_option("--poses", o->poses,
                  "CSV of reached poses: X,Y,Z and the rotary letters (commanded world pose, mm and deg) and "
                  "qX,qY,qZ,q<rotary> (the joints reached, mm and deg); docs/campaign.md")
        ->required();
    c->add_flag("--per-pose", o->per_pose, "With --json: every pose's error (errors[line dx_um dy_um dz_um ...])");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: poses tool_length max_um max_pose rms_um va_um va_pair max_direction_urad");
    c->footer(
        "Examples:\n"
        "  mtcal pose-check -m examples/machines/hu40t-wCBXfYZt.yaml --params truth.yaml \\\n"
        "      --poses examples/campaign/hu40t-reached-nominal.csv --json\n"
        "  mtcal pose-check -m examples/machines/hu40t-wCBXfYZt.yaml --params truth.yaml \\\n"
        "      --poses examples/campaign/hu40t-reached-nominal.csv --record=sqlite:history.db   # max_um rms_um va_um\n");
    out.push_back({c, [o] { return run_pose_check(*o); }});
  }
  {
    auto o = std::make_shared<CampaignCliOptions>();
    auto* c = app.add_subcommand(
        "campaign",
        "A calibration campaign judged: the probed sphere centres before and after compensation (the same plan), the "
        "identified parameters with u against the truth, the fit residual, the reached poses' max |e| and VA");
    add_model_options(c, o->model);
    c->add_option("--before", o->before, "Measurement CSV of the plan before compensation (mtcal probe-log --out)")
        ->required();
    c->add_option("--after", o->after, "Measurement CSV of the same plan after compensation")->required();
    c->add_option("--identified", o->identified, "What mtcal identify --json printed (saved to a file)");
    c->add_option("--truth", o->truth,
                  "Parameter file of the true errors, applied to the machine (mtcal errors --draw --out): a rehearsal");
    c->add_option("--poses-before", o->poses_before, "Reached poses without compensation (as pose-check --poses)");
    c->add_option("--poses-after", o->poses_after, "Reached poses with compensation (as pose-check --poses)");
    c->add_option("--reference", o->reference,
                  "The centres deviations are taken from: nominal (the plan's), identified (--identified's "
                  "artefact estimate) or mean (each ball's mean in the same measurement): the last two take the "
                  "balls' own set-up out")
        ->check(CLI::IsMember({"nominal", "identified", "mean"}))
        ->capture_default_str();
    c->add_option("--noise-um", o->noise_um, "Standard deviation of a probing reading, um: the goal is the RMS per coordinate after <= 2 x it")
        ->check(CLI::NonNegativeNumber & kFinite);
    c->add_option("--report", o->report, "Write an HTML report");
    c->add_flag("--json", o->json_out,
                "Machine-readable output: before{max_um rms_um} after{...} probed[...] parameters[name value u truth "
                "ratio] random_poses{before after} goals ...");
    c->footer(
        "Examples:\n"
        "  mtcal campaign -m examples/machines/hu40t-wCBXfYZt.yaml --before before.csv --after after.csv \\\n"
        "      --identified identified.json --truth truth.yaml --noise-um 0.5 --report campaign.html\n"
        "  mtcal campaign -m examples/machines/hu40t-wCBXfYZt.yaml --before before.csv --after after.csv \\\n"
        "      --identified identified.json --truth truth.yaml --noise-um 0.5 --json --record=sqlite:history.db\n");
    out.push_back({c, [o] { return run_campaign(*o); }});
  }
  return out;
}

}  // namespace mtcal::cli
