// Python bindings of probing plans and the controller's side: plan design, probe programs and logs, commanded joints.
#include <cmath>
#include <memory>
#include <numbers>

#include "common.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/identification/plan_study.hpp"
#include "mtcal/identification/sphere_locate.hpp"
#include "mtcal/io/gcode/probe_program.hpp"
#include "mtcal/io/instruments/probe_log.hpp"
#include "mtcal/io/instruments/probing_plan_file.hpp"
#include "mtcal/io/json/planning_json.hpp"
#include "mtcal/kinematics/commanded_joints.hpp"
#include "mtcal/kinematics/tool_point_coordinates.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal::python {

using namespace pybind11::literals;

namespace {

struct PlanResult {
  Machine machine;
  PlanStudy study;
  std::string against_path;
  std::string workspace;  // the VA's grid in words (PlanReport::workspace)
};

ProbeCycle cycle_of(double ball_diameter, double tip_diameter, double approach, double overtravel, double clearance,
                    int touches) {
  if (touches != 4 && touches != 5) throw py::value_error("touches: expected 4 or 5, found " + std::to_string(touches));
  for (const auto& [name, v] : {std::pair{"ball_diameter", ball_diameter}, {"tip_diameter", tip_diameter},
                                {"approach", approach}, {"overtravel", overtravel}, {"clearance", clearance}})
    if (!(v > 0) || !std::isfinite(v)) throw py::value_error(std::string(name) + ": expected a length > 0 in mm");
  ProbeCycle c;
  c.ball_diameter = ball_diameter;
  c.tip_diameter = tip_diameter;
  c.approach = approach;
  c.overtravel = overtravel;
  c.clearance = clearance;
  c.touches_per_ball = touches;
  return c;
}

// What a probing program's X Y Z mean (--program-coordinates): 'axes' or 'tool-point'.
ProbeCoordinates coordinates_of(const std::string& v) {
  if (v == "axes") return ProbeCoordinates::Axes;
  if (v == "tool-point") return ProbeCoordinates::ToolPoint;
  throw py::value_error("program_coordinates: expected 'axes' or 'tool-point', found '" + v + "'");
}

// Tool-point coordinates need a machine with a tool-centre-point world: refused before any work, as
// the command does.
void check_tool_point(const Machine& m) {
  try {
    ToolPointCoordinates check(m);
  } catch (const ModelError& e) {
    throw InputError({m.source, 0, ""}, std::string("no tool-point coordinates for this machine: ") + e.what());
  }
}

ProbeLogFormat log_format(const std::string& dialect) {
  if (dialect == "linuxcnc") return ProbeLogFormat::LinuxCNC;
  if (dialect == "iso") return ProbeLogFormat::IsoCsv;
  throw py::value_error("dialect: expected 'linuxcnc' or 'iso', found '" + dialect + "'");
}

CommandedPose pose_of(const CommandedJointSolver& s, const double* point, const double* rotary) {
  CommandedPose p;
  p.point = Vec3(point[0], point[1], point[2]);
  p.rotary.assign(rotary, rotary + s.rotary_count());
  return p;
}

}  // namespace

void bind_planning(py::module_& m) {
  // ---------------------------------------------------------------- plan design (mtcal plan)
  py::class_<PlanResult>(m, "PlanResult", "A designed probing plan: the poses, predicted uncertainties, time.")
      .def_property_readonly("plan", [](const PlanResult& r) { return r.study.design.plan; },
                             "ProbingPlan of the selected poses (write_probing_csv writes it)")
      .def_property_readonly("poses", [](const PlanResult& r) { return r.study.design.poses; },
                             "Poses of the design (a ballbar circle or a laser line is one)")
      .def_property_readonly("criterion", [](const PlanResult& r) { return r.study.design.criterion; })
      .def_property_readonly("target_met", [](const PlanResult& r) { return r.study.design.target_met; })
      .def_property_readonly(
          "uncertainties",
          [](const PlanResult& r) {
            py::dict d;
            for (const auto& p : r.study.design.prediction.parameters) d[py::str(p.name)] = p.u;
            return d;
          },
          "Predicted standard uncertainty per estimated parameter (internal units)")
      .def_property_readonly(
          "estimate", [](const PlanResult& r) { return r.study.model.estimate; },
          "The estimated parameters: estimate, then those chosen among candidates (with choose)")
      .def_property_readonly(
          "va_u", [](const PlanResult& r) -> py::object { return r.study.va ? py::cast(r.study.design.va_u) : py::none(); },
          "The predicted VA's standard uncertainty of the design (mm), or None without the VA")
      .def_property_readonly("time", [](const PlanResult& r) { return r.study.time.total; }, "Estimated seconds")
      .def(
          "to_dict",
          [](const PlanResult& r, const std::string& out, const std::string& gcode) {
            PlanReport rep = plan_report(r.study);
            rep.against_path = r.against_path;
            if (r.study.va) rep.workspace = r.workspace;
            rep.out = out;
            rep.gcode = gcode;
            return to_py(to_json(rep));
          },
          "out"_a = "", "gcode"_a = "", "As `mtcal plan --json` (out, gcode: the files named, as --out, --gcode).");
  m.def(
      "design_plan",
      [](const Machine& mm, py::handle artefact, py::handle against, const std::vector<std::string>& estimate,
         const std::vector<std::string>& candidates, std::size_t choose, const std::vector<std::string>& scale_bars,
         double sigma, std::size_t poses, py::handle target_u, double target_va_u, py::handle workspace,
         double va_tie, const std::string& criterion, py::handle ball_region, double ball_spacing,
         double rotary_step, double max_tilt_deg, double stylus_length, double holder_radius, double table_z,
         double rapid, double rotary_speed, double probe_feed, double move_feed, double approach, int touches,
         double ball_diameter, double tip_diameter, double overtravel, double clearance, std::size_t monte_carlo,
         std::uint64_t seed, int threads, const std::string& program_coordinates,
         const std::vector<double>& ballbar, std::size_t ballbar_points, double ballbar_feed, double ballbar_setup,
         const std::vector<std::string>& laser, std::size_t laser_points, double laser_setup, double laser_dwell) {
        const ProbeCoordinates coordinates = coordinates_of(program_coordinates);
        if (artefact.is_none() && against.is_none() && ball_region.is_none() && ballbar.empty() && laser.empty())
          throw py::value_error(
              "artefact: expected the artefact's balls and facets (a ProbingPlan), against, ball_region, ballbar or "
              "laser");
        if (estimate.empty() && candidates.empty())
          throw py::value_error("estimate: expected the parameters to identify, or candidates with choose");
        if (!candidates.empty() && choose == 0) throw py::value_error("choose: candidates needs choose (how many)");
        if (candidates.empty() && choose != 0) throw py::value_error("choose: needs candidates");
        if (!(sigma > 0)) throw py::value_error("sigma: expected a standard deviation > 0 in mm");
        if (!(target_va_u >= 0) || !std::isfinite(target_va_u))
          throw py::value_error("target_va_u: expected a standard uncertainty >= 0 in mm (0: none)");
        if (!(va_tie >= 0) || !std::isfinite(va_tie)) throw py::value_error("va_tie: expected a length >= 0 in mm");
        if (!(move_feed > 0) || !std::isfinite(move_feed)) throw py::value_error("move_feed: expected a feed > 0 mm/min");
        PlanStudyOptions o;
        o.model.estimate = estimate;
        o.model.estimate_source = "estimate";
        for (const auto& s : scale_bars) o.model.scale_bars.push_back(parse_scale_bar(s, "scale_bars"));
        o.model.sigma_ball = o.model.sigma_facet = o.model.sigma_scale_bar = o.model.sigma_ballbar = o.model.sigma_laser =
            sigma;
        if (criterion == "d")
          o.criterion = DesignCriterion::D;
        else if (criterion == "a")
          o.criterion = DesignCriterion::A;
        else if (criterion == "max-u")
          o.criterion = DesignCriterion::MaxU;
        else if (criterion == "va")
          o.criterion = DesignCriterion::Va;
        else
          throw py::value_error("criterion: expected 'd', 'a', 'max-u' or 'va', found '" + criterion + "'");
        // As mtcal plan --candidates: the best conditioned full-rank subset at every candidate pose.
        if (!candidates.empty()) {
          SubsetOptions c;
          c.candidates = candidates;
          c.always = estimate;
          c.choose = choose;
          c.threads = threads;
          c.keep = 1;
          c.candidates_source = "candidates";
          c.always_source = "estimate";
          c.choose_source = "choose";
          c.max_subsets = 10'000'000;
          o.choose = c;
        }
        o.poses = poses;
        if (!target_u.is_none())
          for (auto item : target_u.cast<py::dict>())
            o.target_u.emplace_back(py::str(item.first).cast<std::string>(), item.second.cast<double>());
        o.va = target_va_u > 0 || !workspace.is_none() || criterion == "va";
        std::string workspace_text = kPlanTravelWorkspace;
        if (!workspace.is_none()) {
          o.workspace = grid_values(mm, workspace, "workspace");
          check_grid(mm, o.workspace, "workspace", false, 1'000'000);
          workspace_text = py::isinstance<py::str>(workspace) ? workspace.cast<std::string>() : std::string("given");
        }
        o.target_va_u = target_va_u;
        o.va_tie = va_tie;
        o.target_va_source = "target_va_u";
        if (!ball_region.is_none()) {
          const auto v = ball_region.cast<std::vector<double>>();
          if (v.size() != 5)
            throw py::value_error("ball_region: expected (x_min, x_max, y_min, y_max, z) in mm, found " +
                                  std::to_string(v.size()) + " values");
          BallRegion br;
          br.x_min = v[0];
          br.x_max = v[1];
          br.y_min = v[2];
          br.y_max = v[3];
          br.z = v[4];
          br.spacing = ball_spacing;
          o.ball_region = br;
        }
        o.rotary_step = rotary_step;
        o.reach.max_tilt_deg = max_tilt_deg;
        o.reach.stylus_length = stylus_length;
        o.reach.holder_radius = holder_radius;
        o.reach.table_z = table_z;
        o.timing.rapid = rapid;
        o.timing.rotary_speed = rotary_speed;
        o.timing.probe_feed = probe_feed;
        o.timing.move_feed = move_feed;
        o.timing.tool_point = coordinates == ProbeCoordinates::ToolPoint;  // the time of that program
        o.instruments.ballbar_radii = ballbar;
        o.instruments.ballbar_points = ballbar_points;
        o.instruments.laser_axes = laser;
        o.instruments.laser_points = laser_points;
        o.instruments.ballbar_source = "ballbar";
        o.instruments.laser_source = "laser";
        o.timing.ballbar_feed = ballbar_feed;
        o.timing.ballbar_setup = ballbar_setup;
        o.timing.laser_setup = laser_setup;
        o.timing.laser_dwell = laser_dwell;
        o.cycle = cycle_of(ball_diameter, tip_diameter, approach, overtravel, clearance, touches);
        o.monte_carlo = monte_carlo;
        o.seed = seed;
        o.threads = threads;
        o.target_source = "target_u";
        o.against_source = "against";
        std::optional<ProbingPlan> given;
        if (!against.is_none()) given = against.cast<ProbingPlan>();
        const ProbingPlan art = !artefact.is_none() ? artefact.cast<ProbingPlan>() : given ? *given : ProbingPlan{};
        if (o.timing.tool_point) check_tool_point(mm);
        PlanResult r{mm, {}, given ? given->source : std::string(), workspace_text};
        LongCall release;  // without the GIL, stoppable with Ctrl-C
        r.study = plan_study(mm, art, given, o);
        return r;
      },
      "machine"_a, "artefact"_a = py::none(), py::kw_only(), "against"_a = py::none(),
      "estimate"_a = std::vector<std::string>{}, "candidates"_a = std::vector<std::string>{},
      "choose"_a = std::size_t{0}, "scale_bars"_a = std::vector<std::string>{}, "sigma"_a = 1e-3,
      "poses"_a = std::size_t{0}, "target_u"_a = py::none(), "target_va_u"_a = 0.0, "workspace"_a = py::none(),
      "va_tie"_a = 0.0, "criterion"_a = "d", "ball_region"_a = py::none(), "ball_spacing"_a = 100.0,
      "rotary_step"_a = 15 * std::numbers::pi / 180, "max_tilt_deg"_a = 90.0, "stylus_length"_a = 50.0,
      "holder_radius"_a = 20.0, "table_z"_a = 0.0, "rapid"_a = 10000.0, "rotary_speed"_a = 5400.0,
      "probe_feed"_a = 200.0, "move_feed"_a = 2000.0, "approach"_a = 3.0, "touches"_a = 5,
      "ball_diameter"_a = 25.4, "tip_diameter"_a = 3.0, "overtravel"_a = 2.0, "clearance"_a = 10.0,
      "monte_carlo"_a = std::size_t{0}, "seed"_a = std::uint64_t{1}, "threads"_a = 0, "program_coordinates"_a = "axes",
      "ballbar"_a = std::vector<double>{}, "ballbar_points"_a = std::size_t{36}, "ballbar_feed"_a = 1000.0,
      "ballbar_setup"_a = 300.0, "laser"_a = std::vector<std::string>{}, "laser_points"_a = std::size_t{11},
      "laser_setup"_a = 900.0, "laser_dwell"_a = 4.0,
      R"(Designs a probing plan, as `mtcal plan` (docs/planning.md): the fewest poses (indexations x
balls and facets of artefact, a ProbingPlan, and of ball_region) that identify `estimate` (and,
with candidates and choose, the best conditioned full-rank subset of choose of the candidates) to
a budget: poses (exactly N, with criterion 'd', 'a', 'max-u' or 'va'), target_u {parameter: u in
internal units}, target_va_u (mm: the predicted VA's standard uncertainty over workspace, a grid
spec or dict as identify takes it, default the travels at 5 values an axis; va_tie: pairs within
it of the critical one count, mm, 0: 6 x target_va_u or 1 um), or the predicted uncertainties of
`against` (a given ProbingPlan). ball_region: (x_min, x_max, y_min, y_max, z) mm, workpiece
frame, ball positions every ball_spacing. sigma: standard deviation of a reading (mm);
rotary_step: candidate grid step (rad); the reach (max_tilt_deg, stylus_length, holder_radius,
table_z in mm); the time of the program (rapid, probe_feed, move_feed mm/min, rotary_speed
deg/min) with its cycle (approach, ball_diameter, tip_diameter, overtravel, clearance mm,
touches) in program_coordinates 'axes' or 'tool-point' (as probe_program writes it). ballbar: radii (mm)
of candidate ballbar circles (--ballbar; ballbar_points readings each, timed at ballbar_feed mm/min
both ways plus ballbar_setup s), laser: linear axis letters of candidate laser lines (--laser;
laser_points targets each, timed as laser_setup s plus per target the step at rapid and
laser_dwell s); each circle or line is one pose, done by hand (to_dict()['by_hand']). Returns
PlanResult (plan, poses, uncertainties, estimate, va_u, time, to_dict()).)");

  // ---------------------------------------------------------------- probe programs and logs (mtcal plan --gcode, probe-log)
  m.def("probing_part", &probing_part, "plan"_a,
        "The plan with its probing records only (balls, facets): what probe_program takes, as plan --gcode "
        "writes it (a design's ballbar circles and laser lines are done by hand).");
  m.def(
      "probe_program",
      [](const Machine& mm, const ProbingPlan& plan, const std::string& dialect, double probe_feed, double move_feed,
         const std::string& log, const std::string& header, double ball_diameter, double tip_diameter,
         double approach, double overtravel, double clearance, int touches, const std::string& program_coordinates) {
        ProbeProgramOptions po;
        po.coordinates = coordinates_of(program_coordinates);
        if (po.coordinates == ProbeCoordinates::ToolPoint) check_tool_point(mm);
        po.dialect = log_format(dialect) == ProbeLogFormat::IsoCsv ? ProbeDialect::Iso : ProbeDialect::LinuxCNC;
        po.probe_feed = probe_feed;
        po.feed = move_feed;
        po.log = log;
        po.header = header;
        return probe_program(mm, plan, cycle_of(ball_diameter, tip_diameter, approach, overtravel, clearance, touches),
                             po);
      },
      "machine"_a, "plan"_a, py::kw_only(), "dialect"_a = "linuxcnc", "probe_feed"_a = 200.0,
      "move_feed"_a = 2000.0, "log"_a = "mtcal-contacts.txt", "header"_a = "", "ball_diameter"_a = 25.4, "tip_diameter"_a = 3.0,
      "approach"_a = 3.0, "overtravel"_a = 2.0, "clearance"_a = 10.0, "touches"_a = 5,
      "program_coordinates"_a = "axes",
      "The probing program of a plan (mtcal plan --gcode): 'linuxcnc' (G38.2 with a PROBEOPEN log named log) or "
      "'iso' (G31, #5061 CSV); probe_feed: the probing moves', move_feed: the G1 moves' feed (mm/min); "
      "program_coordinates (--program-coordinates): 'axes' (the machine's axis values) or 'tool-point' (the world "
      "of a tool-centre-point kinematics). Balls and facets only: a plan's ballbar and laser records are refused "
      "(design_plan's plan: probing_part(plan) first). Text.");
  m.def(
      "read_probe_log",
      [](const Machine& mm, const std::string& path, const std::string& dialect) {
        const auto contacts = read_probe_log(mm, path, log_format(dialect));
        const std::size_t k = mm.axes.size();
        std::vector<double> q;
        q.reserve(contacts.size() * k);
        for (const auto& c : contacts) q.insert(q.end(), c.q.begin(), c.q.end());
        return to_array(q, k);
      },
      "machine"_a, "path"_a, py::kw_only(), "dialect"_a = "linuxcnc",
      "The contacts a probing program logged: 'linuxcnc' (PROBEOPEN: 9 numbers a line, X Y Z A B C U V W) or "
      "'iso' (#5061,#5062,#5063[,...] CSV). (N, k) joint values, internal units (NaN for an axis the log does "
      "not carry).");
  m.def(
      "measurements_from_contacts",
      [](const Machine& mm, const ProbingPlan& plan, const std::string& log, const std::string& dialect,
         double ball_diameter, double tip_diameter, double approach, double overtravel, double clearance,
         int touches, const std::string& program_coordinates) {
        const bool tcp = coordinates_of(program_coordinates) == ProbeCoordinates::ToolPoint;
        if (tcp) check_tool_point(mm);
        const ProbeCycle cycle = cycle_of(ball_diameter, tip_diameter, approach, overtravel, clearance, touches);
        auto contacts = read_probe_log(mm, log, log_format(dialect));
        if (tcp) contacts = contacts_from_tool_points(mm, std::move(contacts));
        return measurements_from_contacts(mm, plan_targets(mm, plan), cycle, contacts);
      },
      "machine"_a, "plan"_a, "log"_a, py::kw_only(), "dialect"_a = "linuxcnc", "ball_diameter"_a = 25.4,
      "tip_diameter"_a = 3.0, "approach"_a = 3.0, "overtravel"_a = 2.0, "clearance"_a = 10.0, "touches"_a = 5,
      "program_coordinates"_a = "axes",
      "The probe log of a plan's program (path) as measurements, as `mtcal probe-log`: a measured ProbingPlan "
      "for identify (write_probing_csv writes the command's --out). The cycle and program_coordinates ('axes' or "
      "'tool-point', --program-coordinates) as given to the program.");

  // ---------------------------------------------------------------- the first coarse touch (plan --locate, probe-log --locate)
  py::class_<LocateResult>(m, "LocateResult", "Spheres located by the first coarse touch (mtcal probe-log --locate).")
      .def_readonly("artefact", &LocateResult::artefact,
                    "The artefact with its balls at their located centres (one record each at the locating "
                    "configuration): what design_plan takes as its artefact")
      .def(
          "to_dict", [](const LocateResult& r) { return to_py(to_json(r)); },
          "As `mtcal probe-log --locate --json`: spheres [{id centre rough offset_mm beyond ball_diameter_mm "
          "contact_radius_mm rms_um contacts}] (mm, workpiece frame)")
      .def(
          "write",
          [](const LocateResult& r, const Machine& mm, const std::string& path) {
            write_probing_csv(path, mm, r.artefact, "Located by mtcal locate_spheres");
          },
          "machine"_a, "path"_a, "Writes the located artefact as probe-log --locate --out (complete or not at all).");
  m.def(
      "locate_plan",
      [](const Machine& mm, const ProbingPlan& artefact, py::handle at) {
        const std::vector<double> q =
            at.is_none() ? std::vector<double>(mm.axes.size(), 0.0) : configuration(mm, at, "at");
        return locate_plan(mm, artefact, q);
      },
      "machine"_a, "artefact"_a, py::kw_only(), "at"_a = py::none(),
      "The locating plan of an artefact's balls at their rough positions, as `mtcal plan --locate --out`: one "
      "record per ball at the configuration `at` (k joint values, internal units; the rotary ones are used; "
      "default all 0).");
  m.def(
      "locate_program",
      [](const Machine& mm, const ProbingPlan& plan, double within, const std::string& dialect, double probe_feed,
         double move_feed, const std::string& log, const std::string& header, const std::string& program_coordinates,
         double ball_diameter, double tip_diameter, double approach, double overtravel, double clearance) {
        ProbeProgramOptions po;
        po.dialect = log_format(dialect) == ProbeLogFormat::IsoCsv ? ProbeDialect::Iso : ProbeDialect::LinuxCNC;
        po.probe_feed = probe_feed;
        po.feed = move_feed;
        po.log = log;
        po.header = header;
        po.coordinates = coordinates_of(program_coordinates);
        LocateOptions lo;
        lo.within = within;
        return locate_program(mm, plan, cycle_of(ball_diameter, tip_diameter, approach, overtravel, clearance, 5), lo,
                              po);
      },
      "machine"_a, "plan"_a, py::kw_only(), "within"_a = 3.0, "dialect"_a = "linuxcnc", "probe_feed"_a = 200.0,
      "move_feed"_a = 2000.0, "log"_a = "mtcal-contacts.txt", "header"_a = "", "program_coordinates"_a = "axes",
      "ball_diameter"_a = 25.4, "tip_diameter"_a = 3.0, "approach"_a = 3.0, "overtravel"_a = 2.0, "clearance"_a = 10.0,
      "The locating program of a locate_plan, as `mtcal plan --locate --gcode`: 9 touches a ball laid out for a "
      "centre within `within` mm of its rough position; program_coordinates 'axes' or 'tool-point'. Text.");
  m.def(
      "locate_spheres",
      [](const Machine& mm, const ProbingPlan& plan, const std::string& log, double within, const std::string& dialect,
         const std::string& program_coordinates, double ball_diameter, double tip_diameter, double approach,
         double overtravel, double clearance) {
        auto contacts = read_probe_log(mm, log, log_format(dialect));
        if (coordinates_of(program_coordinates) == ProbeCoordinates::ToolPoint)
          contacts = contacts_from_tool_points(mm, std::move(contacts));
        LocateOptions lo;
        lo.within = within;
        return locate_spheres(mm, plan_targets(mm, plan),
                              cycle_of(ball_diameter, tip_diameter, approach, overtravel, clearance, 5), lo, contacts,
                              log);
      },
      "machine"_a, "plan"_a, "log"_a, py::kw_only(), "within"_a = 3.0, "dialect"_a = "linuxcnc",
      "program_coordinates"_a = "axes", "ball_diameter"_a = 25.4, "tip_diameter"_a = 3.0, "approach"_a = 3.0,
      "overtravel"_a = 2.0, "clearance"_a = 10.0,
      "The spheres the locating program's log (path) gives, as `mtcal probe-log --locate`: LocateResult "
      "(artefact, to_dict(), write()). The cycle and `within` as given to the program.");

  // ---------------------------------------------------------------- commanded joints (the inverse with errors)
  py::class_<CommandedJointSolver>(m, "CommandedJointSolver", R"(Inverse kinematics with the full error model
(kinematics/commanded_joints.hpp; what compensate --format linuxcnc-kins runs in the controller):
the joints that put the actual tool point on a commanded one, in LinuxCNC's tool-centre-point
convention (tool point in the workpiece frame, mm; rotary coordinates, rad). Three linear axes and
at most two rotary axes; directions of motion are not used (the model at dir = 0).)")
      .def(py::init([](const Machine& mm, int max_iterations, double point_tolerance, double orientation_tolerance,
                       double orientation_damping) {
             CommandedJointOptions o;
             o.max_iterations = max_iterations;
             o.point_tolerance = point_tolerance;
             o.orientation_tolerance = orientation_tolerance;
             o.orientation_damping = orientation_damping;
             return std::make_unique<CommandedJointSolver>(mm, o);
           }),
           "machine"_a, py::kw_only(), "max_iterations"_a = 12, "point_tolerance"_a = 1e-11,
           "orientation_tolerance"_a = 1e-13, "orientation_damping"_a = 0.02)
      .def_static("unsupported", &CommandedJointSolver::unsupported, "machine"_a,
                  "Why a machine cannot be solved for, or None when it can.")
      .def_property_readonly("rotary_count", &CommandedJointSolver::rotary_count)
      .def_property_readonly("linear_axes", &CommandedJointSolver::linear_axes, "Indices (chain order)")
      .def_property_readonly("rotary_axes", &CommandedJointSolver::rotary_axes, "Indices (chain order)")
      .def(
          "inverse",
          [](const CommandedJointSolver& s, py::handle points, py::handle rotary, double tool_length) {
            const std::size_t r = s.rotary_count();
            const Rows p = as_rows(points, "points", 3, true);
            Rows a;
            if (r > 0) {
              if (rotary.is_none()) throw py::value_error("rotary: expected the rotary coordinates (rad)");
              a = as_rows(rotary, "rotary", r, true);
              if (a.rows != p.rows)
                throw py::value_error("rotary: expected " + std::to_string(p.rows) + " rows like points, found " +
                                      std::to_string(a.rows));
            }
            const std::size_t k = s.model().machine().axes.size();
            std::vector<double> q(p.rows * k), point_res(p.rows), dir_err(p.rows), orient_res(p.rows);
            std::vector<int> iters(p.rows);
            std::vector<bool> conv(p.rows);
            {
              LongCall release;
              for (std::size_t i = 0; i < p.rows; ++i) {
                const auto res = s.inverse(pose_of(s, p.data + 3 * i, r ? a.data + r * i : nullptr), tool_length);
                std::copy(res.q.begin(), res.q.end(), q.begin() + static_cast<std::ptrdiff_t>(i * k));
                point_res[i] = res.point_residual;
                orient_res[i] = res.orientation_residual;
                dir_err[i] = res.direction_error;
                iters[i] = res.iterations;
                conv[i] = res.converged;
              }
            }
            py::dict d;
            d["q"] = p.single ? to_array(q) : to_array(q, k);
            d["converged"] = p.single ? py::object(py::bool_(conv[0])) : py::cast(conv);
            d["iterations"] = p.single ? py::object(py::int_(iters[0])) : py::cast(iters);
            d["point_residual"] = p.single ? py::object(py::float_(point_res[0])) : to_array(point_res);
            d["orientation_residual"] = p.single ? py::object(py::float_(orient_res[0])) : to_array(orient_res);
            d["direction_error"] = p.single ? py::object(py::float_(dir_err[0])) : to_array(dir_err);
            return d;
          },
          "points"_a, "rotary"_a = py::none(), py::kw_only(), "tool_length"_a,
          R"(Joints for commanded tool points (N, 3) or (3,) (mm, workpiece frame) and rotary coordinates
(N, r) or (r,) (rad): {q (N, k) chain order, converged, iterations, point_residual (mm),
orientation_residual, direction_error (rad)}. tool_length: mm (LinuxCNC's tool offset).)")
      .def(
          "forward",
          [](const CommandedJointSolver& s, py::handle configs, double tool_length) {
            const std::size_t k = s.model().machine().axes.size(), r = s.rotary_count();
            const Rows q = as_rows(configs, "configs", k, true);
            std::vector<double> pts(q.rows * 3), rot(q.rows * r);
            for (std::size_t i = 0; i < q.rows; ++i) {
              const auto f = s.forward(std::span<const double>(q.data + k * i, k), tool_length);
              for (int c = 0; c < 3; ++c) pts[3 * i + static_cast<std::size_t>(c)] = f.pose.point[c];
              std::copy(f.pose.rotary.begin(), f.pose.rotary.end(), rot.begin() + static_cast<std::ptrdiff_t>(r * i));
            }
            py::array_t<double> rotary = q.single ? to_array(rot)
                                         : r == 0 ? new_array({static_cast<py::ssize_t>(q.rows), 0})
                                                  : to_array(rot, r);
            return py::make_tuple(q.single ? to_array(pts) : to_array(pts, 3), rotary);
          },
          "configs"_a, py::kw_only(), "tool_length"_a,
          "The actual tool points (N, 3) and the rotary coordinates (N, r) that inverse maps to the joints.")
      .def(
          "nominal_inverse",
          [](const CommandedJointSolver& s, py::handle point, py::handle rotary, double tool_length) {
            const auto p = as_std_vector(point, "point", 3);
            std::vector<double> a;
            if (s.rotary_count()) a = as_std_vector(rotary, "rotary", s.rotary_count());
            return to_array(s.nominal_inverse(pose_of(s, p.data(), a.data()), tool_length));
          },
          "point"_a, "rotary"_a = py::none(), py::kw_only(), "tool_length"_a,
          "The nominal topology's joints for one commanded tool point and rotary coordinates (no errors).");
}

}  // namespace mtcal::python
