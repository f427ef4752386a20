// A probing plan designed end to end (mtcal plan): candidates, the design to a budget, its time, the comparison, Monte Carlo.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/identification/planning.hpp"

namespace mtcal {

// What mtcal plan asks for (docs/planning.md).
struct PlanStudyOptions {
  IdentificationOptions model;  // estimate, scale bars, sigmas (ball, facet, scale bar)
  DesignCriterion criterion = DesignCriterion::D;
  std::size_t poses = 0;                                   // budget: exactly this many poses
  std::vector<std::pair<std::string, double>> target_u;    // budget: parameter -> u (internal units)
  double rotary_step = 0.2617993877991494;                 // candidate grid step of the rotary axes, rad (15 deg)
  ProbeReach reach;
  TimingOptions timing;
  ProbeCycle cycle;  // the probing program's cycle, which the time estimate follows
  // Choose the estimated parameters among choose->candidates (choose_parameters at every candidate
  // pose), model.estimate being kept in every subset.
  std::optional<SubsetOptions> choose;
  // Where balls may go besides the artefact's: its positions (region_balls) are candidate balls too.
  std::optional<BallRegion> ball_region;
  // Ballbar circles and laser lines offered beside the probings (candidate_configurations).
  InstrumentCandidates instruments;
  // The predicted VA over workspace (per axis values, chain order, internal units; empty: the
  // travels, 5 values an axis, travel_grid) and its uncertainty: with va, the VA's gradient
  // (va_sensitivity) enters the design; target_va_u > 0 is a budget on it (mm). The pairs within
  // va_tie of the critical one count (mm; 0: 6 x target_va_u - a pair can overtake the critical one
  // when each length is off by 3 u -, or va_options.tie_tolerance without a target).
  bool va = false;
  std::vector<std::vector<double>> workspace;
  VaOptions va_options{1e-3, 256};
  double va_tie = 0.0;
  double target_va_u = 0.0;
  std::string target_va_source = "target VA uncertainty";
  std::size_t monte_carlo = 0;  // runs of simulate -> identify on the designed plan
  std::uint64_t seed = 1;
  int threads = 0;
  // Where messages about the budget are located (the command passes its options).
  std::string poses_source = "poses", target_source = "target uncertainty", against_source = "against plan";
  std::function<void(const char* phase, std::size_t poses)> progress;
};

// How the design used a ball region: its positions, those with a candidate left after the
// constraints, those the design probes.
struct BallRegionUse {
  std::size_t positions = 0, reachable = 0, used = 0;
};

// Everything the design gives (io/json/planning_json.hpp's PlanReport shows it).
struct PlanStudy {
  IdentificationOptions model;  // the options' model, with the chosen parameters when choose was given
  std::optional<ParameterChoice> choice;
  std::optional<VaSensitivity> va;
  std::vector<std::vector<double>> workspace;  // of the VA, as used (with va)
  double target_va_u = 0.0;                    // mm (0: none)
  std::optional<double> against_va_u;          // the VA's u with the given plan (mm)
  std::optional<BallRegionUse> region;
  CandidateSet candidates;
  PlanDesign design;
  TimeEstimate time;
  // The designed plan's ballbar and laser setups: by hand, beside the probing program.
  std::vector<InstrumentSetup> by_hand;
  std::optional<PlanPrediction> against;
  std::optional<TimeEstimate> against_time;
  std::optional<PlanMonteCarlo> monte_carlo;
};

// The candidates of artefact's features (and of the ball region's positions) over the rotary grid within reach, the plan designed to
// the budget (options.poses, options.target_u, or else the predicted uncertainties of `against`,
// a given plan), its measuring time, against's prediction and time, and with monte_carlo > 0 the
// Monte Carlo check (the machine as truth, the estimated parameters zero in the prior; with va, the
// spread of the identified machines' VA too). Throws
// InputError located at options.poses_source without any budget.
PlanStudy plan_study(const Machine& m, const ProbingPlan& artefact, const std::optional<ProbingPlan>& against,
                     const PlanStudyOptions& options);

}  // namespace mtcal
