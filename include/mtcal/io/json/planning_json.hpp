// JSON of a designed probing plan (mtcal plan --json, docs/planning.md): predicted uncertainties, time, the comparison.
#pragma once

#include <optional>
#include <string>

#include "mtcal/identification/plan_study.hpp"
#include "mtcal/identification/planning.hpp"
#include "mtcal/identification/sphere_locate.hpp"
#include "mtcal/io/json/json.hpp"

namespace mtcal {

Json to_json(const PlanPrediction& p);
Json to_json(const TimeEstimate& t);
Json to_json(const CandidateSet& c);
// A ballbar or laser setup: id, kind, ballbar {plane, pivot [x y z], radius_mm} or laser {beam
// [x y z], point [x y z], from_mm, to_mm}, rotary (rad), readings, text (describe_setup).
Json to_json(const InstrumentSetup& s);
Json to_json(const PlanMonteCarlo& mc, const PlanPrediction& predicted);

// What mtcal plan reports, keys in this order: criterion, criterion_value, candidates {considered,
// kept, removed {constraint: count}}, poses, greedy_poses, exchanges, passes, target_met,
// predicted (to_json(PlanPrediction)), best_reachable, time, [against {plan, poses, predicted,
// time, fewer_poses_percent}], [monte_carlo], out, gcode; [parameters_chosen {chosen, estimate,
// condition, full_rank, examined}], [va {value, u, u_best, [target], [u_against], workspace,
// pairs} (mm)], [ball_region {positions, reachable, used}], [by_hand [setup]: the designed
// plan's ballbar circles and laser lines, not in the probing program]; monte_carlo has [va {mean,
// u_monte_carlo, ratio}]. poses counts a circle or a line as one (plan_poses); time has
// instruments_s, ballbar_circles, laser_lines.
struct PlanReport {
  const CandidateSet* candidates = nullptr;
  const PlanDesign* design = nullptr;
  TimeEstimate time;
  std::optional<PlanPrediction> against;
  std::optional<TimeEstimate> against_time;
  std::string against_path;
  std::optional<PlanMonteCarlo> monte_carlo;
  std::string out, gcode;
  const ParameterChoice* choice = nullptr;  // --candidates
  const VaSensitivity* va = nullptr;        // the predicted VA over the workspace
  std::string workspace;
  double target_va_u = 0.0;
  std::optional<double> against_va_u;
  struct Region {
    std::size_t positions = 0, reachable = 0, used = 0;
  } region;  // --ball-region (positions 0: none)
  std::vector<InstrumentSetup> by_hand;
};
Json to_json(const PlanReport& r);
// The report of a study (pointers into it: it must outlive the report); against_path, workspace
// (the VA's grid in words), out and gcode are the caller's.
PlanReport plan_report(const PlanStudy& s);
// The words of PlanReport::workspace for the default workspace (travel_grid, 5 values an axis).
inline constexpr const char* kPlanTravelWorkspace = "the travels, 5 values an axis";

// The located spheres (probe-log --locate --json): spheres [{id, centre [x y z], rough [x y z],
// offset_mm, beyond, ball_diameter_mm, contact_radius_mm, rms_um, contacts}] (mm, workpiece frame).
Json to_json(const LocateResult& r);

}  // namespace mtcal
