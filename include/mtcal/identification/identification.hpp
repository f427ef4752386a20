// Indirect calibration from probing (Viprey 2015; Mohammed 2019 SAMBA/TANGO): virtual machine,
// nonlinear least squares, identifiability, combinatorial subset analysis, Monte Carlo uncertainty.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mtcal/identification/probing_plan.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// The artefact's unknowns: true ball centres and the offsets n . p of the touched facet planes
// (per feature index; the entry of the other kind is unused).
struct ArtefactState {
  std::vector<Vec3> ball;
  std::vector<double> offset;
};
// The nominal state: ball centres as given, offsets of the planes through the given points.
ArtefactState nominal_artefact(const ProbingPlan& plan);

// Two balls at a calibrated distance (mm): fixes the scale that uncalibrated balls leave free.
struct ScaleBar {
  std::string ball_a, ball_b;
  double length = 0.0;
  // Where the bar was given (the location of messages about it: a file, a command-line option).
  std::string source = "scale bar";
};
// The text form "1:2:304.8" is read by the formats layer (parse_scale_bar).

// ---- Virtual machine (Viprey 2015 figure 4) ----

struct SimulationOptions {
  double noise = 0.0;           // standard deviation of each reading, mm
  double artefact_error = 0.0;  // standard deviation of each feature's true position about its nominal one, mm
  std::uint64_t seed = 1;
  std::vector<ScaleBar> scale_bars;  // true ball pairs are set to these lengths (ball_b moved along the bar)
};
struct Simulation {
  ProbingPlan measurements;  // the plan with readings
  ArtefactState truth;
};
// The nominal targets of a plan: linear axis values that put the nominal tool point on each
// feature's nominal position at the record's indexation (exact: the nominal chain is affine in
// the linear axes at fixed rotary values).
ProbingPlan plan_targets(const Machine& m, const ProbingPlan& plan);
// What machine `truth` reads: for a ball, the linear axes that put the actual tool point on the
// true centre; for a facet, the probing axis (the linear axis most nearly along its normal) moved
// from the nominal target until the actual tool point is on the true plane, its direction of
// motion set to the approach (against the normal); other axes keep the plan's directions. Then
// Gaussian noise on the readings (balls: X, Y, Z; facets: the probing axis). Throws ModelError if
// a reading does not converge.
Simulation simulate_probing(const Machine& truth, const ProbingPlan& plan, const SimulationOptions& options);

// ---- Identification ----

struct IdentificationOptions {
  // Parameters (EXX.1, EX0C, EXX.b) or errors (EXX: every coefficient) of the machine to estimate;
  // every other parameter keeps the machine's value. The artefact's unknowns are always estimated.
  std::vector<std::string> estimate;
  std::vector<ScaleBar> scale_bars;
  bool estimate_pretravel = false;  // one probe pre-travel for all facet touches (mm)
  // Standard deviations that weight the residuals (mm).
  double sigma_ball = 1e-3, sigma_facet = 1e-3, sigma_scale_bar = 1e-3;
  double sigma_ballbar = 1e-3, sigma_laser = 1e-3;  // a ballbar's length reading, a laser's displacement
  enum class Loss { None, Huber, Cauchy };
  Loss loss = Loss::None;
  double loss_scale = 3.0;  // in units of sigma
  int max_iterations = 100;
  double function_tolerance = 1e-14, parameter_tolerance = 1e-14, gradient_tolerance = 1e-16;
  // A scaled Jacobian direction whose singular value is below this fraction of the largest is
  // unidentifiable.
  double rank_tolerance = 1e-8;
  // Where the names in estimate came from: the location of messages about them (a file, a
  // command-line option).
  std::string estimate_source = "estimated parameters";
};

struct EstimatedParameter {
  std::string name;
  double value = 0.0;
  double u = 0.0;  // standard uncertainty: sqrt of the covariance's diagonal (residual variance); NaN if rank deficient
  std::string unit;
};

// Identifiability of a set of unknowns at a plan: SVD of the Jacobian with unit-norm columns.
struct Identifiability {
  std::vector<std::string> columns;  // machine parameters, then artefact unknowns ("ball 3 x", "facet 7"), pre-travel
  std::size_t rank = 0;
  std::vector<double> singular_values;                    // of the scaled Jacobian, largest first
  double condition = 0.0;                                 // largest / smallest (infinity when rank deficient)
  double condition_identifiable = 0.0;                    // the same over the identifiable unknowns only
  std::vector<std::string> identifiable, unidentifiable;  // requested machine parameters, split
  // For each excluded unknown, the combination of kept ones it cannot be told apart from:
  // "EXw = -1 ball 3 x - 1 ball 4 x ..." (natural units: moving the left side by 1 is the same as
  // moving the right-hand unknowns by these amounts).
  std::vector<std::string> null_directions;
};

struct IdentificationResult {
  std::string termination;  // Ceres' termination type and message
  bool converged = false;
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;  // 1/2 sum of squared weighted residuals
  std::size_t residuals = 0, unknowns = 0;
  double sigma0 = 0.0;  // a posteriori standard deviation of unit weight: sqrt(2 cost / (m - n))
  double rms_ball = 0.0, rms_facet = 0.0, rms_scale_bar = 0.0;  // unweighted residual RMS, mm
  double rms_ballbar = 0.0, rms_laser = 0.0;                    // the same of the ballbar and laser readings
  Identifiability identifiability;                              // at the solution, over the estimated unknowns
  std::vector<EstimatedParameter> parameters;                   // estimated machine parameters
  Eigen::MatrixXd correlation;                                  // among them
  // Their covariance sigma0^2 (J^T J)^-1 (the machine-parameter block; u is the root of its
  // diagonal); NaN where rank deficient.
  Eigen::MatrixXd covariance;
  ArtefactState artefact;
  double pretravel = 0.0, pretravel_u = 0.0;
  bool pretravel_estimated = false;  // requested and identifiable
  Machine machine;                   // the prior machine with the estimates
};

// Nonlinear least squares (Ceres, Levenberg-Marquardt, dense QR) on the exact model with its
// analytic Jacobian. Requested parameters that are not identifiable at the start are excluded
// (reported, never given values). Throws InputError for unknown names, too few residuals, or an
// unknown scale-bar ball.
IdentificationResult identify(const Machine& prior, const ProbingPlan& measurements,
                              const IdentificationOptions& options);

// Structural identifiability of options.estimate at a plan or measurements (plans are first given
// their nominal targets): at the error-free machine and nominal artefact, where equivalences
// between errors are exact. Unknowns are taken in order (artefact, then the requested parameters,
// then pre-travel) and kept while they add rank.
Identifiability identifiability(const Machine& m, const ProbingPlan& plan, const IdentificationOptions& options);

// ---- Combinatorial analysis (Viprey 2015, section 4) ----

struct SubsetOptions {
  std::vector<std::string> candidates;  // machine parameter names
  std::vector<std::string> always;      // machine parameters in every subset (the artefact's unknowns always are)
  std::size_t choose = 1;               // subset size, from the candidates
  // Relative singular value below which a subset is deficient. The test runs on the normal
  // matrix, whose rounding (1e-16) limits it to about 1e-8: at least 1e-7 is required.
  double rank_tolerance = 1e-6;
  int threads = 0;
  std::size_t keep = 1000;  // subsets listed (best first); count covers all
  bool by_residue = false;  // rank by the residue of estimation (measurements) instead of the condition number
  // Where each input came from: the locations of messages about them (a file, a command-line
  // option). The always-parameters' source is also named in the text of messages.
  std::string candidates_source = "candidates", always_source = "parameters in every subset",
              choose_source = "subset size", by_residue_source = "ranking by residue",
              rank_tolerance_source = "rank tolerance";
  // Refuse (LimitError, Limit::Time, located in choose_source) more than this many subsets C(n, k)
  // before starting; 0: no limit. The search prunes, so this bounds the work from above.
  std::uint64_t max_subsets = 0;
  // Called from the workers after each leading member's subsets with the ones finished and the
  // total (may be empty).
  std::function<void(std::size_t done, std::size_t total)> progress;
};
struct ParameterSubset {
  std::vector<std::size_t> members;  // indices into candidates, ascending
  double condition = 0.0;            // of the scaled Jacobian with always + members + artefact
  double residue = 0.0;              // Viprey eq. 5 at first order: |r| after fitting (measurements only; else NaN)
};
struct SubsetAnalysis {
  std::uint64_t examined = 0;  // C(n, k)
  std::uint64_t full_rank = 0;
  std::uint64_t pruned = 0;              // deficient subsets or prefixes (a prefix's supersets are never formed)
  std::vector<std::string> candidates;   // the candidates' parameter names, as members index them
  std::vector<ParameterSubset> subsets;  // best conditioned (or smallest residue) first, at most keep
};
// Every k-subset of the candidates whose model (with the always-parameters, the artefact unknowns
// and the scale bars) has full rank. Depth-first over subsets with an incremental Cholesky
// factorisation of the scaled normal matrix: a prefix that is already deficient is pruned with
// all its supersets. Split over threads by leading member. With measurements, each subset's
// first-order residue is computed too.
SubsetAnalysis full_rank_subsets(const Machine& m, const ProbingPlan& plan, const SubsetOptions& options,
                                 const IdentificationOptions& model_options = {});

// ---- Uncertainty by Monte Carlo ----

struct MonteCarloOptions {
  std::size_t runs = 100;
  std::uint64_t seed = 1;
  int threads = 0;
  // Reading noise (mm): 0 means sigma0 times the identification's sigma of each kind.
  double noise = 0.0;
  // Workspace grid (per axis values, chain order, internal units) for the VA of each run's model;
  // empty: none.
  std::vector<std::vector<double>> workspace;
  // Called from the workers after each run with the runs finished and the total (may be empty).
  std::function<void(std::size_t done, std::size_t total)> progress;
};
struct MonteCarloResult {
  std::size_t runs = 0, failed = 0;          // failed: the solver did not converge, or threw
  std::vector<double> mean, stdev;           // per estimated parameter (order of result.parameters)
  std::vector<std::vector<double>> samples;  // runs x parameters
  double va_mean = 0.0, va_stdev = 0.0;      // over the workspace grid
  double va_identified = 0.0;                // VA of the identified machine itself
  double map_stdev_max = 0.0;                // largest standard deviation of an error component over the workspace, mm
};
// Re-draws the readings from the identified machine and artefact with noise, identifies again
// (starting from the identification), and collects the estimates: the spread is the uncertainty.
MonteCarloResult monte_carlo(const Machine& prior, const ProbingPlan& measurements,
                             const IdentificationOptions& options, const IdentificationResult& result,
                             const MonteCarloOptions& mc);

// Viprey 2015 eq. 2: the identified model against the imposed one over a workspace grid:
// max and RMS of |e_identified - e_true| (translational, mm).
struct ModelDeviation {
  double max = 0.0, rms = 0.0;
};
ModelDeviation model_deviation(const Machine& identified, const Machine& truth,
                               const std::vector<std::vector<double>>& workspace);

// ---- Identification with its assessment (what mtcal identify reports) ----

struct AssessmentOptions {
  std::size_t monte_carlo_runs = 0;  // 0: no Monte Carlo
  std::uint64_t seed = 1;
  int threads = 0;
  // Workspace grid (per axis values, chain order, internal units) for the identified model's VA,
  // the Monte Carlo spread and the comparison with truth; empty: none.
  std::vector<std::vector<double>> workspace;
  const Machine* truth = nullptr;  // the imposed machine (simulations), or none
  std::function<void(std::size_t done, std::size_t total)> monte_carlo_progress;  // MonteCarloOptions::progress
};
struct IdentificationRun {
  IdentificationResult result;
  double seconds = 0;                  // wall time of the identification
  std::vector<ProbeFeature> features;  // the measurements' features (ball/facet ids of result.artefact)
  std::optional<MonteCarloResult> monte_carlo;
  double monte_carlo_seconds = 0;
  std::uint64_t seed = 1;                   // of the Monte Carlo runs
  bool workspace = false;                   // a workspace grid was given
  std::optional<double> va;                 // VA of the identified model over the workspace (mm)
  std::optional<ModelDeviation> deviation;  // against the imposed machine (with truth)
  std::vector<double> imposed;              // per estimated parameter: the imposed machine's value (with truth)
};
// identify, then Monte Carlo (when runs > 0), the deviation from truth (when given) and the VA
// (when a workspace is given). The machine file's parameters the result changes are in
// identified_errors.
IdentificationRun identify_and_assess(const Machine& prior, const ProbingPlan& measurements,
                                      const IdentificationOptions& options, const AssessmentOptions& assessment);
// The errors (in the prior's order of first estimate) whose parameters identification estimated:
// what an identified parameter file holds.
std::vector<ErrorName> identified_errors(const Machine& prior, const IdentificationResult& result);

}  // namespace mtcal
