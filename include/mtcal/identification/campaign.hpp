// A calibration campaign judged: probed sphere centres before and after compensation, identified parameters against a truth, reached poses.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/evaluation/pose_check.hpp"
#include "mtcal/identification/identification.hpp"
#include "mtcal/identification/probing_plan.hpp"

namespace mtcal {

// What an identification reported (identify --json, read back by the formats layer): the
// estimates with their standard uncertainties, the fit's residual and the artefact's estimate.
struct IdentifiedSummary {
  std::string source;
  bool converged = false;
  std::size_t residuals = 0, unknowns = 0, rank = 0;
  double rms_ball = 0.0, rms_facet = 0.0, sigma0 = 0.0;  // mm (sigma0 has no unit)
  std::vector<EstimatedParameter> parameters;
  std::vector<std::string> unidentifiable;
  std::map<std::string, Vec3> balls;  // estimated ball centres by feature id (workpiece frame, mm)
};

// Where a probed ball centre's deviation is measured from.
enum class BallReference {
  Nominal,     // the plan's nominal centre (the artefact where the plan says it is)
  Identified,  // the identification's estimate of the centre (the artefact's own set-up error removed)
  Mean,        // the mean of the ball's probed centres in the same measurement (its set-up taken out:
               // what a compensation can remove; a constant offset of the machine goes with it)
};

struct CampaignOptions {
  BallReference reference = BallReference::Nominal;
  double probing_noise = 0.0;  // standard deviation of a reading, mm; 0: not stated (no goal checked)
  std::string before_source = "before", after_source = "after";
};

// One probed ball record: the nominal tool point at the readings (the linear axes where the
// controller saw the centre) minus the reference centre, before and after (mm, workpiece frame).
struct ProbedDeviation {
  std::size_t record = 0;  // index in the measurements
  int indexation = 0;
  std::string feature;
  std::vector<double> rotary;  // the record's rotary values, chain order (rad)
  int line_before = 0, line_after = 0;
  Vec3 before = Vec3::Zero(), after = Vec3::Zero();
};

struct DeviationSummary {
  std::size_t count = 0;
  double max = 0.0;  // largest |d|, mm
  std::size_t max_index = 0;  // into probed
  double rms = 0.0;           // sqrt(mean |d|^2), mm
  double rms_coordinate = 0.0;  // sqrt(mean of dx^2, dy^2, dz^2) = rms / sqrt(3), mm: against a reading's sigma
};

// An estimate against the truth: d = value - truth, ratio |d| / u (NaN where u is not known).
struct ParameterCheck {
  std::string name, unit;
  double value = 0.0, u = 0.0;
  std::optional<double> truth;  // none: the truth machine has no parameter of this name
  double deviation = 0.0, ratio = 0.0;
};

struct CampaignResult {
  std::vector<ProbedDeviation> probed;
  std::size_t facets = 0;  // facet records, not compared (their offsets hold the stylus' radius)
  DeviationSummary before, after;
  BallReference reference = BallReference::Nominal;
  std::optional<IdentifiedSummary> identification;
  std::vector<ParameterCheck> parameters;  // with a truth and an identification
  // Parameters of the truth that are not zero and were not estimated: each biases the
  // identification (the model cannot reach the truth).
  std::vector<std::pair<std::string, double>> not_estimated;
  double max_ratio = 0.0;
  std::size_t beyond_3u = 0;
  std::optional<PoseCheck> poses_before, poses_after;
  double probing_noise = 0.0;
  // The goals, where their inputs are there: the RMS per coordinate of d after within
  // 2 x the probing noise (a reading's standard deviation, per coordinate); every identified
  // parameter within 3 u of the truth.
  std::optional<bool> residual_goal, parameter_goal;
};

// The campaign: before and after must be measurements of the same plan (the same records: feature,
// indexation and rotary values, in the same order; InputError naming the after file's line
// otherwise). truth: the machine the measurements came from, when known (a rehearsal); identified:
// the identification; poses: the reached-pose checks before and after (check_reached_poses), when
// made. Throws InputError when a reference centre is missing (an identified ball not in the
// identification's artefact) or there is no ball record.
CampaignResult campaign_report(const Machine& nominal, const ProbingPlan& before, const ProbingPlan& after,
                               const IdentifiedSummary* identified, const Machine* truth,
                               const PoseCheck* poses_before, const PoseCheck* poses_after,
                               const CampaignOptions& options = {});

}  // namespace mtcal
