// mtcal plan: the fewest probing poses that identify the requested parameters (docs/planning.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "acceptance.hpp"
#include "budget.hpp"
#include "common.hpp"
#include "planning_command.hpp"
#include "history.hpp"
#include "mtcal/identification/plan_study.hpp"
#include "mtcal/identification/sphere_locate.hpp"
#include "mtcal/io/system/files.hpp"
#include "mtcal/io/gcode/probe_program.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/json/planning_json.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/text/joints.hpp"
#include "mtcal/util/errors.hpp"
#include "mtcal/util/units.hpp"

namespace mtcal::cli {
namespace {

struct PlanOptions {
  ModelOptions model;
  std::vector<std::string> estimate, scale_bars, target_u, candidates;
  std::size_t choose = 0;
  std::string target_va_u, workspace, ball_region;
  double ball_spacing = 100.0, va_tie_um = 0.0;
  std::string artefact, against, out, criterion = "d";
  std::size_t poses = 0, monte_carlo = 0;
  std::uint64_t seed = 1;
  double sigma_um = 1.0, rotary_step_deg = 15.0;
  ProbeReach reach;
  TimingOptions timing;
  ProbeCycle cycle;
  std::string gcode, dialect = "linuxcnc", log = "mtcal-contacts.txt", program_coordinates = "axes";
  int threads = 0;
  bool json_out = false;
  bool locate = false;
  double locate_within = 3.0;
  std::string locate_at;
  InstrumentCandidates instruments;
};

// --program-coordinates tool-point needs a machine with a tool-centre-point world: refused before anything
// is designed or written.
void check_tool_point_coordinates(const Machine& m, const std::string& coordinates) {
  if (coordinates != "tool-point") return;
  try {
    ToolPointCoordinates check(m);
  } catch (const ModelError& e) {
    throw InputError({"--program-coordinates", 0, "tool-point"}, std::string(m.source) + ": " + e.what());
  }
}

const char* const kProgramCoordinatesHelp =
    "What the program's X Y Z mean: axes (the machine's axis values, a controller without tool-centre-point "
    "kinematics, LinuxCNC trivkins) or tool-point (the world of a tool-centre-point kinematics such as the module of "
    "compensate --format linuxcnc-kins: the nominal tool point in the workpiece frame and the rotary axes); the time "
    "estimate follows the program so written";

// The probing cycle's options, shared by plan --gcode and probe-log (they must be the same).
void add_cycle_options(CLI::App* c, ProbeCycle& cycle) {
  c->add_option("--ball-diameter", cycle.ball_diameter, "Reference ball diameter, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--tip-diameter", cycle.tip_diameter, "Stylus tip diameter, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--overtravel", cycle.overtravel, "Probing moves end this far beyond the expected contact, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--clearance", cycle.clearance, "Height above a ball between its touches, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
}

// "EX0C=0.5um,EXX.1=2um/m,EC0Y=1e-6": targets with a unit, or bare in the parameter's internal
// unit (mm, rad, mm/mm).
std::vector<std::pair<std::string, double>> parse_targets(const Machine& m, const std::vector<std::string>& specs) {
  std::vector<std::pair<std::string, double>> out;
  const auto params = m.parameters();
  for (const auto& s : specs) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({"--target-u", 0, s},
                       "expected PARAMETER=U (U with a unit, or in the parameter's unit), found '" + printable(s) + "'");
    const std::string name = s.substr(0, eq);
    const auto i = m.parameter_index(name);
    if (!i)
      throw InputError({"--target-u", 0, name}, "unknown parameter '" + printable(name) + "'" + name_hint(m, name) +
                                                    " (" + parameter_naming(m) + ")");
    out.emplace_back(name, parse_in_unit(s.substr(eq + 1), params[*i].unit, {"--target-u", 0, name}));
  }
  return out;
}

// "XMIN:XMAX,YMIN:YMAX,Z" (mm, workpiece frame): the rectangle where balls may go.
BallRegion parse_region(const std::string& spec, double spacing) {
  const SourceLocation where{"--ball-region", 0, spec};
  auto fail = [&] {
    return InputError(where, "expected XMIN:XMAX,YMIN:YMAX,Z (mm, workpiece frame), found '" + printable(spec) + "'");
  };
  std::vector<std::string> parts;
  for (std::size_t a = 0;;) {
    const std::size_t b = spec.find(',', a);
    parts.push_back(spec.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  if (parts.size() != 3) throw fail();
  auto number = [&](const std::string& t) {
    try {
      std::size_t used = 0;
      const double v = std::stod(t, &used);
      if (used != t.size() || !std::isfinite(v)) throw fail();
      return v;
    } catch (const std::logic_error&) {
      throw fail();
    }
  };
  auto range = [&](const std::string& t, double& lo, double& hi) {
    const auto c = t.find(':');
    if (c == std::string::npos) throw fail();
    lo = number(t.substr(0, c));
    hi = number(t.substr(c + 1));
  };
  BallRegion r;
  range(parts[0], r.x_min, r.x_max);
  range(parts[1], r.y_min, r.y_max);
  r.z = number(parts[2]);
  r.spacing = spacing;
  return r;
}

std::size_t va_points(const std::vector<std::vector<double>>& grid) {
  std::size_t n = 1;
  for (const auto& v : grid) n *= v.size();
  return n;
}

void print_prediction(const PlanPrediction& p, const PlanPrediction* against, const PlanMonteCarlo* mc) {
  std::cout << fmt::format("{:<10} {:>12} {:<7}{}{}\n", "parameter", "u", "unit", against ? "  u (against)" : "",
                           mc ? "  u (Monte Carlo)  ratio" : "");
  for (std::size_t i = 0; i < p.parameters.size(); ++i) {
    const auto& e = p.parameters[i];
    std::cout << fmt::format("{:<10} {:>12.4g} {:<7}", e.name, e.u, e.unit);
    if (against) std::cout << fmt::format(" {:>12.4g}", against->parameters[i].u);
    if (mc) std::cout << fmt::format(" {:>16.4g} {:>6.3f}", mc->stdev[i], mc->stdev[i] / e.u);
    std::cout << "\n";
  }
}

ProbeProgramOptions program_options(const PlanOptions& o) {
  ProbeProgramOptions po;
  po.dialect = o.dialect == "iso" ? ProbeDialect::Iso : ProbeDialect::LinuxCNC;
  po.probe_feed = o.timing.probe_feed;
  po.feed = o.timing.move_feed;
  po.log = o.log;
  po.coordinates = o.program_coordinates == "tool-point" ? ProbeCoordinates::ToolPoint : ProbeCoordinates::Axes;
  return po;
}

// plan --locate: the locating program of the artefact's balls at their rough positions, and its plan
// (what probe-log --locate reads the log against).
int run_locate_plan(const PlanOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.artefact);
  check_outputs(inputs, {o.out, o.gcode});
  if (o.artefact.empty())
    throw InputError({"--artefact", 0, ""}, "expected the balls' rough positions to locate: --artefact PLAN.csv");
  if (o.gcode.empty()) throw InputError({"--gcode", 0, ""}, "expected the locating program to write: --gcode FILE");
  if (o.out.empty())
    throw InputError({"--out", 0, ""}, "expected the locating plan to write (probe-log --locate --plan reads it): --out FILE");
  const Machine m = load(o.model);
  check_tool_point_coordinates(m, o.program_coordinates);
  const std::vector<double> at = o.locate_at.empty() ? std::vector<double>(m.axes.size(), 0.0)
                                                     : parse_joint_values(m, o.locate_at, "--locate-at");
  check_joints(m, at, "--locate-at", true);
  LocateOptions lo;
  lo.within = o.locate_within;
  ProbingPlan plan;
  std::vector<ProbeTouch> touches;
  std::string program;
  try {
    plan = locate_plan(m, read_probing_csv(m, o.artefact), at);
    touches = locate_touches(m, plan, o.cycle, lo);
    ProbeProgramOptions po = program_options(o);
    po.header = fmt::format("machine {}: {} ball{} located from rough positions by mtcal plan --locate", m.name,
                            plan.records.size(), plan.records.size() == 1 ? "" : "s");
    program = locate_program(m, plan, o.cycle, lo, po);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"locating distance", "--locate-within"}});
  }
  // Both appear or neither (the command's output group, main.cpp).
  write_probing_csv(o.out, m, plan,
                    fmt::format("Locating plan of mtcal plan --locate: machine {}, {} balls at their rough positions, "
                                "within {:g} mm",
                                o.model.machine, plan.records.size(), lo.within));
  write_file_atomically(o.gcode, program);
  if (o.json_out) {
    Json balls = Json::array();
    for (const auto& r : plan.records) {
      const auto& f = plan.features[r.feature];
      balls.push_back({{"id", f.id}, {"rough", {f.position.x(), f.position.y(), f.position.z()}}});
    }
    print_json(Json{{"locate", {{"balls", balls}, {"touches", touches.size()}, {"within_mm", lo.within},
                                {"at", format_joint_values(m, at)}}},
                    {"out", o.out},
                    {"gcode", o.gcode}});
    return 0;
  }
  std::cout << fmt::format("locating program: {} ball{} at {}, {} touches, each centre within {:g} mm of its rough "
                           "position\nwrote {}\nwrote {}\n",
                           plan.records.size(), plan.records.size() == 1 ? "" : "s", format_joint_values(m, at),
                           touches.size(), lo.within, o.out, o.gcode);
  return 0;
}

int run_plan(const PlanOptions& o) {
  if (o.locate) return run_locate_plan(o);
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.artefact);
  inputs.push_back(o.against);
  check_outputs(inputs, {o.out});
  const Machine m = load(o.model);
  check_tool_point_coordinates(m, o.program_coordinates);
  const bool instruments = !o.instruments.ballbar_radii.empty() || !o.instruments.laser_axes.empty();
  if (o.artefact.empty() && o.against.empty() && o.ball_region.empty() && !instruments)
    throw InputError({"--artefact", 0, ""},
                     "expected the artefact's balls and facets: --artefact PLAN.csv, --against PLAN.csv or --ball-region "
                     "(or --ballbar, --laser)");
  if (o.estimate.empty() && o.candidates.empty())
    throw InputError({"--estimate", 0, ""}, "expected the parameters to identify: --estimate, or --candidates with --choose");
  if (!o.candidates.empty() && o.choose == 0) throw InputError({"--candidates", 0, ""}, "--candidates needs --choose K");
  std::optional<ProbingPlan> against;
  if (!o.against.empty()) against = read_probing_csv(m, o.against);
  ProbingPlan artefact;
  if (!o.artefact.empty())
    artefact = read_probing_csv(m, o.artefact);
  else if (against)
    artefact = *against;
  PlanStudyOptions so;
  if (!o.ball_region.empty()) so.ball_region = parse_region(o.ball_region, o.ball_spacing);
  so.instruments = o.instruments;
  so.instruments.ballbar_source = "--ballbar";
  so.instruments.laser_source = "--laser";
  so.model.estimate = o.estimate;
  so.model.estimate_source = "--estimate";
  for (const auto& s : o.scale_bars) so.model.scale_bars.push_back(parse_scale_bar(s, "--scale-bar"));
  so.model.sigma_ball = so.model.sigma_facet = so.model.sigma_scale_bar = so.model.sigma_ballbar = so.model.sigma_laser =
      o.sigma_um * 1e-3;
  // --candidates: the best conditioned full-rank subset at every candidate pose (identifiability --choose).
  if (!o.candidates.empty()) {
    SubsetOptions c;
    c.candidates = o.candidates;
    c.always = o.estimate;
    c.choose = o.choose;
    c.threads = o.threads;
    c.keep = 1;
    c.candidates_source = "--candidates";
    c.always_source = "--estimate";
    c.choose_source = "--choose";
    c.max_subsets = 10'000'000;  // about a minute on 2 cores (identifiability --choose: 1.5e5 a second a thread)
    so.choose = c;
  }
  // The predicted VA over the workspace, with its gradient (when asked for).
  so.va = !o.target_va_u.empty() || !o.workspace.empty() || o.criterion == "va";
  const std::string va_option = o.workspace.empty() ? "--target-va-u" : "--workspace";
  if (so.va) {
    try {
      if (!o.workspace.empty()) so.workspace = checked_grid(m, o.workspace, false, 1'000'000);
      if (!o.target_va_u.empty()) so.target_va_u = parse_in_unit(o.target_va_u, "mm", {"--target-va-u", 0, ""});
    } catch (const InputError& e) {
      rethrow_for_options(e, {{"--grid", "--workspace"}, {"workspace", va_option}});
    }
    so.va_tie = o.va_tie_um * 1e-3;
  }
  so.criterion = o.criterion == "a"       ? DesignCriterion::A
                 : o.criterion == "max-u" ? DesignCriterion::MaxU
                 : o.criterion == "va"    ? DesignCriterion::Va
                                          : DesignCriterion::D;
  so.poses = o.poses;
  so.target_u = parse_targets(m, o.target_u);
  so.rotary_step = o.rotary_step_deg * std::numbers::pi / 180;
  so.reach = o.reach;
  so.timing = o.timing;
  so.timing.tool_point = o.program_coordinates == "tool-point";  // the time of the program written
  so.cycle = o.cycle;
  so.monte_carlo = o.monte_carlo;
  so.seed = o.seed;
  so.threads = o.threads;
  so.poses_source = "--poses";
  so.target_source = "--target-u";
  so.target_va_source = "--target-va-u";
  so.against_source = "--against " + o.against;
  if (so.poses == 0 && so.target_u.empty() && so.target_va_u == 0 && !against)
    throw InputError({"--poses", 0, ""},
                     "expected a budget: --poses N, --target-u PARAM=U, --target-va-u U or --against PLAN.csv");
  for (const auto* path : {&o.out, &o.gcode})
    if (!path->empty()) AtomicFile check(*path);
  Progress progress("plan: poses", 0);
  if (progress.active()) so.progress = [&](const char*, std::size_t n) { progress.update(n, n); };
  std::optional<PlanStudy> studied;
  try {
    studied = plan_study(m, artefact, against, so);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"workspace", va_option}, {"ball region", "--ball-region"}});
  }
  const PlanStudy& study = *studied;
  const CandidateSet& cands = study.candidates;
  const PlanDesign& design = study.design;
  const std::optional<PlanPrediction>& against_pred = study.against;
  const std::optional<TimeEstimate>& against_time = study.against_time;
  PlanReport report = plan_report(study);
  report.against_path = o.against;
  if (study.va) report.workspace = o.workspace.empty() ? kPlanTravelWorkspace : o.workspace;
  if (!o.out.empty()) {
    report.out = o.out;
    write_probing_csv(o.out, m, design.plan,
                      fmt::format("Designed by mtcal plan: machine {}, {} poses, criterion {}, {} candidates{}",
                                  o.model.machine, design.poses, design.criterion, plan_poses(cands.plan),
                                  study.by_hand.empty()
                                      ? ""
                                      : fmt::format(" ({} ballbar circles and laser lines, by hand)", study.by_hand.size())));
  }
  if (!o.gcode.empty()) {
    report.gcode = o.gcode;
    ProbeProgramOptions po = program_options(o);
    const ProbingPlan probing = probing_part(design.plan);
    po.header = fmt::format("machine {}: {} poses designed by mtcal plan", m.name, design.poses);
    // The circles and lines are not in the program: it says which remain to be done by hand.
    if (!study.by_hand.empty()) {
      po.notes.push_back(fmt::format("This program probes {} of the plan's {} poses; by hand, beside it (ISO 230-4 "
                                     "ballbar, ISO 230-2 laser; their readings go into the measurement file's "
                                     "reading column):",
                                     probing.records.size(), design.poses));
      for (const auto& setup : study.by_hand) po.notes.push_back("  " + describe_setup(setup));
    }
    write_probe_program(o.gcode, m, probing, o.cycle, po);
  }
  if ((o.json_out || recording()) && emit_json(to_json(report), o.json_out)) return 0;

  const std::optional<ParameterChoice>& choice = study.choice;
  const std::optional<VaSensitivity>& va = study.va;
  if (choice)
    std::cout << fmt::format("parameters: {} chosen of --candidates ({} of {} subsets of {} full rank at every "
                             "candidate; condition {:.4g}): {}\n",
                             fmt::join(choice->chosen, ","), choice->full_rank, choice->examined, o.choose,
                             choice->condition, fmt::join(choice->estimate, ","));
  std::cout << fmt::format("candidates: {} considered, {} kept;", cands.considered, plan_poses(cands.plan));
  for (const auto& [name, n] : cands.removed) std::cout << fmt::format(" {} removed by {}", n, name) << ";";
  std::cout << "\n";
  if (report.region.positions > 0)
    std::cout << fmt::format("ball region: {} positions, {} with a candidate left, {} used by the design\n",
                             report.region.positions, report.region.reachable, report.region.used);
  std::cout << fmt::format("designed plan: {} poses at {} indexations (criterion {}, {} after elimination, {} exchanges in {} passes){}\n",
                           design.poses, report.time.indexations, design.criterion, design.greedy_poses,
                           design.exchanges, design.passes, design.target_met ? "" : "; TARGET NOT MET");
  std::cout << fmt::format("estimated time: {:.0f} s (moves {:.0f} s, probing {:.0f} s, indexing {:.0f} s; {} touches{})\n",
                           report.time.total, report.time.moves, report.time.probing, report.time.indexing,
                           report.time.touches,
                           report.time.circles + report.time.lines > 0
                               ? fmt::format("; ballbar circles and laser lines {:.0f} s", report.time.instruments)
                               : "");
  for (const auto& setup : study.by_hand) std::cout << "by hand: " << describe_setup(setup) << "\n";
  if (against_pred)
    std::cout << fmt::format("against {}: {} poses, {:.0f} s; the designed plan has {:.0f} % fewer poses\n", o.against,
                             against_pred->poses, against_time->total,
                             100.0 * (static_cast<double>(against_pred->poses) - static_cast<double>(design.poses)) /
                                 static_cast<double>(against_pred->poses));
  print_prediction(design.prediction, against_pred ? &*against_pred : nullptr,
                   report.monte_carlo ? &*report.monte_carlo : nullptr);
  if (va) {
    std::cout << fmt::format("VA over {} ({} configurations): {:.3f} um; its predicted u {:.4g} um (best reachable "
                             "{:.4g} um{}{}; {} pair{} within {:.4g} um of the critical one)\n",
                             report.workspace, va_points(study.workspace), va->va * 1e3, design.va_u * 1e3,
                             design.va_u_best * 1e3, so.target_va_u > 0 ? fmt::format(", target {:.4g} um", so.target_va_u * 1e3) : "",
                             report.against_va_u ? fmt::format(", against {:.4g} um", *report.against_va_u * 1e3) : "",
                             va->pair_lengths.size(), va->pair_lengths.size() == 1 ? "" : "s", va->tie_tolerance * 1e3);
    if (report.monte_carlo && report.monte_carlo->va)
      std::cout << fmt::format("VA Monte Carlo: mean {:.3f} um, spread {:.4g} um, ratio {:.3f}\n",
                               report.monte_carlo->va_mean * 1e3, report.monte_carlo->va_stdev * 1e3,
                               report.monte_carlo->va_stdev / design.va_u);
  }
  if (report.monte_carlo)
    std::cout << fmt::format("Monte Carlo: {} runs of simulate -> identify ({} failed), seed {}\n", report.monte_carlo->runs,
                             report.monte_carlo->failed, o.seed);
  if (!o.out.empty()) std::cout << "wrote " << o.out << "\n";
  if (!o.gcode.empty()) std::cout << "wrote " << o.gcode << "\n";
  return 0;
}

struct ProbeLogOptions {
  ModelOptions model;
  std::string plan, log, dialect = "linuxcnc", out, program_coordinates = "axes";
  ProbeCycle cycle;
  double approach = 3.0;
  int touches = 5;
  bool json_out = false;
  bool locate = false;
  double locate_within = 3.0;
};

// probe-log --locate: the spheres of the locating program's log, written as the artefact plan takes.
int run_locate_log(const ProbeLogOptions& o, const Machine& m, const std::vector<LoggedContact>& contacts) {
  ProbeCycle cycle = o.cycle;
  cycle.approach = o.approach;
  LocateOptions lo;
  lo.within = o.locate_within;
  std::optional<LocateResult> found;
  try {
    found = locate_spheres(m, plan_targets(m, read_probing_csv(m, o.plan)), cycle, lo, contacts, o.log);
  } catch (const InputError& e) {
    rethrow_for_options(e, {{"locating distance", "--locate-within"}});
  }
  std::string comment = "Located by mtcal probe-log --locate (plan " + o.plan + ", log " + o.log + "):";
  for (const auto& s : found->spheres)
    comment += fmt::format(" ball {} diameter {:.4f} mm, RMS {:.2f} um;", s.id, s.ball_diameter, s.rms * 1e3);
  write_probing_csv(o.out, m, found->artefact, comment);
  if (o.json_out) {
    Json j = to_json(*found);
    j["contacts"] = contacts.size();
    j["within_mm"] = lo.within;
    j["out"] = o.out;
    print_json(j);
    return 0;
  }
  for (const auto& s : found->spheres) {
    std::cout << fmt::format("ball {}: centre {:.4f} {:.4f} {:.4f} mm, {:.3f} mm from its rough position; diameter "
                             "{:.4f} mm; RMS {:.2f} um over {} contacts\n",
                             s.id, s.centre.x(), s.centre.y(), s.centre.z(), s.offset, s.ball_diameter, s.rms * 1e3,
                             s.contacts);
    if (s.beyond)
      std::cout << fmt::format("note         ball {} lies farther than --locate-within ({:g} mm) from its rough "
                               "position: its touches were laid out for less; locate it again from the centre found\n",
                               s.id, lo.within);
  }
  std::cout << fmt::format("wrote {} (plan --artefact)\n", o.out);
  return 0;
}

int run_probe_log(const ProbeLogOptions& o) {
  auto inputs = model_inputs(o.model);
  inputs.push_back(o.plan);
  inputs.push_back(o.log);
  check_outputs(inputs, {o.out});
  const Machine m = load(o.model);
  check_tool_point_coordinates(m, o.program_coordinates);
  auto contacts = read_probe_log(m, o.log, o.dialect == "iso" ? ProbeLogFormat::IsoCsv : ProbeLogFormat::LinuxCNC);
  if (o.program_coordinates == "tool-point") contacts = contacts_from_tool_points(m, std::move(contacts));
  if (o.locate) return run_locate_log(o, m, contacts);
  ProbeCycle cycle = o.cycle;
  cycle.approach = o.approach;
  cycle.touches_per_ball = o.touches;
  // A plan's ballbar and laser records are not in its program (plan --gcode): the log holds the
  // probing records' contacts, their readings are taken by hand.
  const ProbingPlan whole = read_probing_csv(m, o.plan);
  const ProbingPlan probing = probing_part(whole);
  const std::size_t by_hand = whole.records.size() - probing.records.size();
  const ProbingPlan meas = measurements_from_contacts(m, plan_targets(m, probing), cycle, contacts, o.log);
  write_probing_csv(o.out, m, meas,
                    fmt::format("Measured: plan {}, probe log {} ({} contacts){}", o.plan, o.log, contacts.size(),
                                by_hand > 0 ? fmt::format("; the plan's {} ballbar and laser records are not in it "
                                                          "(by hand)",
                                                          by_hand)
                                            : ""));
  if (o.json_out) {
    print_json(Json{{"records", meas.records.size()}, {"contacts", contacts.size()}, {"by_hand_records", by_hand},
                    {"out", o.out}});
    return 0;
  }
  std::cout << fmt::format("{} contacts of {} -> {} measurement records; wrote {}\n", contacts.size(), o.log,
                           meas.records.size(), o.out);
  if (by_hand > 0)
    std::cout << fmt::format("note: the plan's {} ballbar and laser records are not in the probing program: their "
                             "readings are taken by hand (ISO 230-4, ISO 230-2) and added to {} (column reading)\n",
                             by_hand, o.out);
  return 0;
}

}  // namespace

std::vector<Command> add_planning_commands(CLI::App& app) {
  auto o = std::make_shared<PlanOptions>();
  auto* c = app.add_subcommand("plan",
                               "Design a probing plan: the fewest poses (indexations x balls and facets) that identify "
                               "the requested parameters to a budget; predicted uncertainties, measuring time");
  add_model_options(c, o->model);
  c->add_option("--estimate", o->estimate,
                "Parameters or errors to identify (as mtcal identify --estimate); with --candidates, those in every subset")
      ->delimiter(',');
  auto* choose = c->add_option("--choose", o->choose,
                               "With --candidates: how many of them to identify (the best conditioned full-rank subset)")
                     ->check(CLI::Range(1, 64));
  c->add_option("--candidates", o->candidates,
                "Candidate parameters: the subset of --choose of them that is full rank at every candidate pose and "
                "best conditioned is identified (as identifiability --choose), beside --estimate")
      ->delimiter(',')
      ->needs(choose);
  c->add_option("--scale-bar", o->scale_bars, "Calibrated distance between two balls: BALL:BALL:LENGTH (mm)");
  c->add_option("--sigma-um", o->sigma_um, "Standard deviation of a reading (ball centre coordinate, facet touch), um")
      ->transform(length_in(1e-3, "LENGTH"))
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--artefact", o->artefact, "Plan or measurement CSV whose balls and facets are used (its rows are not)");
  c->add_option("--against", o->against,
                "A given plan: its predicted uncertainties are the budget unless --poses or --target-u is given");
  auto* poses = c->add_option("--poses", o->poses, "Budget: exactly this many poses")->check(CLI::Range(1, 100000));
  c->add_option("--target-u", o->target_u,
                "Budget: PARAMETER=U, a standard uncertainty (0.5um, 2urad, 1um/m; bare: the parameter's unit "
                "mm, rad, mm/mm); the fewest poses that reach every target")
      ->delimiter(',')
      ->excludes(poses);
  c->add_option("--target-va-u", o->target_va_u,
                "Budget: the standard uncertainty of the predicted VA over --workspace (2um; bare: mm); the fewest "
                "poses that reach it (and --target-u, when given)")
      ->excludes(poses);
  c->add_option("--workspace", o->workspace,
                "Grid of the VA (as identify --workspace), e.g. \"X=-300:300:5,Y=-250:250:5,Z=-300:300:5\"; default: "
                "5 values an axis over the travels");
  c->add_option("--va-tie-um", o->va_tie_um,
                "Pairs within this of the VA count as critical too (the largest u among them is the VA's), um; "
                "default: 6 x --target-va-u, or 1 um")
      ->check(CLI::NonNegativeNumber & kFinite);
  c->add_option("--criterion", o->criterion,
                "d (D-optimal), a (A-optimal), max-u (largest relative u) or va (smallest u of the VA); with --poses")
      ->check(CLI::IsMember({"d", "a", "max-u", "va"}))
      ->capture_default_str();
  c->add_option("--ball-region", o->ball_region,
                "Where balls may go besides the artefact's: XMIN:XMAX,YMIN:YMAX,Z (mm, workpiece frame; Z the centres' "
                "height), candidate positions every --ball-spacing");
  c->add_option("--ball-spacing", o->ball_spacing, "Spacing of the --ball-region positions, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--ballbar", o->instruments.ballbar_radii,
                "Offer ballbar circles (ISO 230-4) of these radii, mm: in the XY, YZ and ZX planes that hold them, "
                "pivots on a 3 x 3 grid within the tool point's travel, the rotary axes at 0; each circle one pose "
                "(its pivot and length offset its own unknowns); done by hand, not in --gcode")
      ->delimiter(',')
      ->check(CLI::PositiveNumber & kFinite);
  c->add_option("--ballbar-points", o->instruments.ballbar_points, "Readings of a --ballbar circle, evenly in angle")
      ->check(CLI::Range(4, 3600))
      ->capture_default_str();
  c->add_option("--ballbar-feed", o->timing.ballbar_feed, "Feed of a --ballbar circle (the time: 2 x 2 pi R a circle), mm/min")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--ballbar-setup-s", o->timing.ballbar_setup, "Setup time of a --ballbar circle (pivot, bar, centring), s")
      ->check(CLI::NonNegativeNumber & kFinite)
      ->capture_default_str();
  c->add_option("--laser", o->instruments.laser_axes,
                "Offer laser lines (ISO 230-2) along these linear axes, e.g. X,Y: through the middle of the tool "
                "point's travel, the rotary axes at 0; each line one pose (its offset its own unknown); done by hand, "
                "not in --gcode")
      ->delimiter(',');
  c->add_option("--laser-points", o->instruments.laser_points, "Targets of a --laser line, evenly over the axis' travel")
      ->check(CLI::Range(2, 1000))
      ->capture_default_str();
  c->add_option("--laser-setup-s", o->timing.laser_setup, "Setup time of a --laser line (aligning the beam), s")
      ->check(CLI::NonNegativeNumber & kFinite)
      ->capture_default_str();
  c->add_option("--laser-dwell-s", o->timing.laser_dwell,
                "Dwell at each --laser target (the time: per target the step at --rapid and the dwell), s")
      ->check(CLI::NonNegativeNumber & kFinite)
      ->capture_default_str();
  c->add_option("--rotary-step-deg", o->rotary_step_deg, "Candidate grid step of every rotary axis over its travel, deg")
      ->check(CLI::Range(0.01, 360.0))
      ->capture_default_str();
  c->add_option("--max-tilt-deg", o->reach.max_tilt_deg, "Largest angle of the probe from the balls' stems' opposite, deg")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  c->add_option("--stylus-length", o->reach.stylus_length, "Stylus length, tip centre to holder, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--holder-radius", o->reach.holder_radius, "Probe holder radius, mm")
      ->check(CLI::NonNegativeNumber & kFinite)
      ->capture_default_str();
  c->add_option("--table-z", o->reach.table_z, "Table plane, z in the workpiece frame, mm")
      ->check(kFinite)
      ->capture_default_str();
  c->add_option("--rapid", o->timing.rapid, "Rapid feed, mm/min")->check(CLI::PositiveNumber & kFinite)->capture_default_str();
  c->add_option("--rotary-speed", o->timing.rotary_speed, "Indexing speed, deg/min")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--probe-feed", o->timing.probe_feed, "Probing feed, mm/min")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--approach", o->cycle.approach, "Probing distance before the expected contact, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--touches", o->cycle.touches_per_ball, "Touches per ball centre (the program: 4 or 5)")
      ->check(CLI::Range(4, 5))
      ->capture_default_str();
  c->add_option("--monte-carlo", o->monte_carlo,
                "Check the prediction: runs of simulate (the machine as truth) -> identify on the designed plan")
      ->check(CLI::Range(0, 100000));
  c->add_option("--seed", o->seed, "First seed of the Monte Carlo runs")->capture_default_str();
  c->add_option("--threads", o->threads, "Threads (0: all cores)")->check(CLI::Range(0, 1024));
  c->add_option("--out", o->out, "Plan CSV to write (mtcal simulate --plan, identifiability --plan)");
  c->add_option("--gcode", o->gcode, "Probing program to write for the designed plan (--dialect)");
  c->add_option("--move-feed", o->timing.move_feed,
                "The program's feed (G1) of the moves near the artefact: down to each touch, its retract, between a "
                "ball's touches; mm/min (the time estimate uses it)")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str();
  c->add_option("--dialect", o->dialect, "G-code dialect: linuxcnc (G38.2, PROBEOPEN log) or iso (G31, #5061 CSV)")
      ->check(CLI::IsMember({"linuxcnc", "iso"}))
      ->capture_default_str();
  // A name on the controller's machine, written into a G-code comment: any path there, but a comment
  // ends at ')' and at the line's end, so those (and an empty name) are refused.
  c->add_option("--log-name", o->log, "LinuxCNC: the file (PROBEOPEN ...) writes the contacts to")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](std::string& s) -> std::string {
            if (s.empty() || s.find_first_of("()\r\n") != std::string::npos)
              return "expected a file name for PROBEOPEN without '(', ')' or a line break, found '" + s + "'";
            return {};
          },
          "NAME"));
  c->add_option("--program-coordinates", o->program_coordinates, kProgramCoordinatesHelp)
      ->check(CLI::IsMember({"axes", "tool-point"}))
      ->capture_default_str();
  add_cycle_options(c, o->cycle);
  auto* locate = c->add_flag("--locate", o->locate,
                             "Write the locating program instead (--gcode) and its plan (--out): a first coarse touch "
                             "of each --artefact ball from its rough position (9 touches); LinuxCNC runs it, then "
                             "probe-log --locate writes the located balls for --artefact");
  c->add_option("--locate-within", o->locate_within,
                "--locate, probe-log --locate: each ball's centre lies within this distance of its rough position, mm "
                "(at most (ball + tip) / 4)")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str()
      ->needs(locate);
  c->add_option("--locate-at", o->locate_at,
                "--locate: the rotary axes' values where the balls are located, e.g. \"A=0,C=90\" (deg; default 0)")
      ->needs(locate);
  for (const char* design : {"--estimate", "--candidates", "--against", "--poses", "--target-u", "--target-va-u",
                             "--ball-region", "--monte-carlo", "--ballbar", "--laser"})
    locate->excludes(c->get_option(design));
  c->add_flag("--json", o->json_out, "Machine-readable output: poses predicted{parameters{u}} time against ...");
  c->footer(
      "Examples:\n"
      "  mtcal plan -m examples/machines/hu40t-wCBXfYZt.yaml --estimate EC0Y,EB0Z,EA0Z,EX0C,EY0C \\\n"
      "      --scale-bar 1:2:304.8 --against examples/plans/hu40t-samba-tango.csv --out plan.csv\n"
      "  mtcal plan -m examples/machines/rrttt-table-table.yaml --artefact examples/plans/rrttt-viprey-sphere.csv \\\n"
      "      --estimate EY0C,EZ0A --poses 12 --criterion d --json\n"
      "  mtcal plan -m examples/machines/hu40t-wCBXfYZt.yaml --estimate EC0Y,EB0Z,EA0Z,EX0C,EY0C,EA0C,EB0C,EXX.1,EYY.1,EZZ.1 \\\n"
      "      --scale-bar 1:2:304.8 --artefact examples/plans/hu40t-samba-tango.csv --rotary-step-deg 45 --target-va-u 3um\n"
      "  mtcal plan -m examples/machines/rrttt-table-table.yaml --artefact examples/plans/rrttt-viprey-sphere.csv \\\n"
      "      --estimate EX0C,EY0C --candidates EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A --choose 4 --poses 20\n"
      "  mtcal plan -m examples/machines/rrttt-table-table.yaml --ball-region -100:100,-100:100,50 --ball-spacing 100 \\\n"
      "      --estimate EX0C,EY0C,EA0C,EB0C,EY0A,EZ0A,EB0A,EC0A --poses 20 --rotary-step-deg 30\n"
      "  mtcal plan -m examples/loop/rrttt-nominal.yaml --artefact examples/plans/rrttt-viprey-sphere.csv \\\n"
      "      --estimate EX0C,EY0C,EY0A,EZ0A --poses 8 --gcode probe.ngc --program-coordinates tool-point\n"
      "  mtcal plan -m examples/machines/vmc-3axis.yaml --estimate EC0Y,EA0Z,EB0Z,EXX.1,EZZ.1 --ballbar 150 \\\n"
      "      --laser X,Z --poses 5 --out plan.csv   # circles and lines by hand\n"
      "  mtcal plan -m examples/loop/rrttt-nominal.yaml --artefact examples/plans/rrttt-viprey-sphere.csv --locate \\\n"
      "      --locate-within 3 --program-coordinates tool-point \\\n"
      "      --out locate-plan.csv --gcode locate.ngc   # then LinuxCNC, then probe-log --locate\n");
  std::vector<Command> out{{c, [o] { return run_plan(*o); }}};
  auto l = std::make_shared<ProbeLogOptions>();
  auto* lc = app.add_subcommand("probe-log",
                                "Read the contacts a probing program of mtcal plan logged (LinuxCNC PROBEOPEN or the "
                                "ISO #5061 CSV) into a measurement CSV for mtcal identify --measurements");
  add_model_options(lc, l->model);
  lc->add_option("--plan", l->plan, "The plan the program was written for (mtcal plan --out)")->required();
  lc->add_option("--log", l->log, "The probe log")->required();
  lc->add_option("--dialect", l->dialect, "linuxcnc (9 numbers a line) or iso (#5061,#5062,#5063[,...] CSV)")
      ->check(CLI::IsMember({"linuxcnc", "iso"}))
      ->capture_default_str();
  lc->add_option("--approach", l->approach, "As given to mtcal plan, mm")->check(CLI::PositiveNumber & kFinite)->capture_default_str();
  lc->add_option("--touches", l->touches, "As given to mtcal plan")->check(CLI::Range(4, 5))->capture_default_str();
  lc->add_option("--program-coordinates", l->program_coordinates,
                 "As given to mtcal plan: axes, or tool-point (the log holds world positions of a tool-centre-point "
                 "kinematics, turned back into axis values by the nominal chain)")
      ->check(CLI::IsMember({"axes", "tool-point"}))
      ->capture_default_str();
  add_cycle_options(lc, l->cycle);
  auto* locate_log = lc->add_flag(
      "--locate", l->locate,
      "The log of plan --locate's program (--plan: its --out): the located balls, written for plan --artefact");
  lc->add_option("--locate-within", l->locate_within, "As given to plan --locate, mm")
      ->check(CLI::PositiveNumber & kFinite)
      ->capture_default_str()
      ->needs(locate_log);
  lc->add_option("--out", l->out,
                 "Measurement CSV to write (mtcal identify --measurements); with --locate the located balls (plan "
                 "--artefact)")
      ->required();
  lc->add_flag("--json", l->json_out,
               "Machine-readable output: records contacts out; with --locate spheres{id centre rough offset_mm "
               "ball_diameter_mm rms_um} out");
  lc->footer(
      "Examples:\n"
      "  mtcal probe-log -m examples/machines/hu40t-wCBXfYZt.yaml --plan plan.csv --log mtcal-contacts.txt \\\n"
      "      --out measured.csv && mtcal identify -m ... --measurements measured.csv --estimate ...\n"
      "  mtcal probe-log -m examples/loop/rrttt-nominal.yaml --locate --plan locate-plan.csv --log mtcal-contacts.txt \\\n"
      "      --out located-sphere.csv && mtcal plan ... --artefact located-sphere.csv ...\n");
  out.push_back({lc, [l] { return run_probe_log(*l); }});
  return out;
}

}  // namespace mtcal::cli
