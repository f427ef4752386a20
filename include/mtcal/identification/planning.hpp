// Planning a probing measurement (docs/planning.md): candidate configurations within reach, an optimal design, predicted uncertainties, measuring time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mtcal/identification/identification.hpp"
#include "mtcal/identification/probing_plan.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// ---- The instrument and its reach ----

// A touch probe on balls on stems and on facets, all fixed to the workpiece side. The tool axis a
// is the unit vector from the probe's tip to the spindle, in the workpiece frame, at a
// configuration's nominal pose.
struct ProbeReach {
  // Stem direction of every ball, from its centre into the stem (workpiece frame): down to the table.
  Vec3 stem = Vec3(0, 0, -1);
  // Largest angle between a and -stem (deg): 90 lets the probe come horizontally, never from the
  // stem's side (the stylus would reach into the stem).
  double max_tilt_deg = 90.0;
  // Stylus length from the tip centre to the holder (mm) and the holder's radius (mm): the holder,
  // a disc of that radius at that distance along a, must stay above the table plane.
  double stylus_length = 50.0, holder_radius = 20.0;
  double table_z = 0.0;  // the table plane, z in the workpiece frame (mm)
};

// Candidate configurations: every feature at every indexation of a grid over the rotary axes.
struct CandidateGrid {
  // Per rotary axis of the machine (chain order among the rotary axes): the values (rad).
  std::vector<std::vector<double>> rotary;
};
// The rotary grid of step `step` (rad) over each rotary axis' travel (or [-pi, pi) without one);
// a travel of a full turn or more is sampled over one turn only (the same poses again otherwise).
CandidateGrid rotary_grid(const Machine& m, double step);

struct CandidateSet {
  ProbingPlan plan;  // the features and one record per surviving candidate (nominal targets)
  std::size_t considered = 0;
  // Per constraint, in the order applied: name and the number of candidates it removed.
  std::vector<std::pair<std::string, std::size_t>> removed;
};
// Where balls may go: a rectangle of the table (workpiece frame, mm) sampled every `spacing` from
// its min corner (both ends included when the side is a multiple of it), ball centres at height z.
struct BallRegion {
  double x_min = 0.0, x_max = 0.0, y_min = 0.0, y_max = 0.0, z = 0.0;
  double spacing = 100.0;
  std::string id_prefix = "R";  // ids R1, R2 ... (x fastest)
};
// The candidate balls of a region (ids not among `taken`, which are the given features' ids).
// Throws InputError for a region whose min exceeds its max, a spacing that is not > 0, more than
// 10,000 positions, or an id already taken.
std::vector<ProbeFeature> region_balls(const BallRegion& region, const std::vector<ProbeFeature>& taken = {});

// Ballbar circles (ISO 230-4) and laser lines (ISO 230-2) offered to the design beside the
// probings (docs/planning.md, "Ballbar circles and laser lines"). Each circle and each line is one
// candidate: its readings are chosen together (one pose of the budget), and its own feature, so
// that its unknowns (the pivot's centre in the plane and the bar's length offset; the laser's
// offset) are nuisance columns of that candidate only. Both are taken with the rotary axes at the
// value nearest 0 within their travel.
struct InstrumentCandidates {
  // A circle of each radius (mm) in each of the XY, YZ and ZX planes whose two axes leave 2 R of
  // the tool point's travel, about pivots on a grid of pivots_per_axis values per in-plane axis
  // (from min + R to max - R of the tool point's travel box; the middle alone when 1), the
  // pivot's coordinate along the normal at the middle of the box. ballbar_points readings a
  // circle, evenly in angle from the plane's first axis.
  std::vector<double> ballbar_radii;
  std::size_t ballbar_points = 36;
  std::size_t pivots_per_axis = 3;
  // A line along each of these linear axes (letters of the machine), through the middle of the
  // tool point's travel box, laser_points targets evenly over the axis' travel.
  std::vector<std::string> laser_axes;
  std::size_t laser_points = 11;
  // Where messages about them are located (the command passes its options).
  std::string ballbar_source = "ballbar radius", laser_source = "laser axis";
};

// Every feature of `features` at every grid indexation (facets: each pre-move pattern of the linear
// axes other than the probing one), then the constraints: "travel" (a linear target outside its
// axis' travel), "stem" (a ball approached beyond max_tilt_deg), "facet side" (the probe behind a
// facet's plane: a . n < 0), "table" (at a ball, the holder below the table plane); then the
// instruments' circles and lines (features BB<R><plane><n> and L<axis>, records after the
// probings' at one further indexation), a circle or line removed by "travel" when one of its
// readings is outside it. `considered` and `removed` count candidates (a circle or line is one).
// Throws InputError when no candidate is left, naming how many each constraint removed; for a
// ballbar radius that no plane's travel holds (2 R against the tool point's travel, located at
// ballbar_source with the radius), an unknown or non-linear laser axis (at laser_source with the
// value), fewer than 4 readings a circle or 2 targets a line, or an instrument id already taken.
CandidateSet candidate_configurations(const Machine& m, const std::vector<ProbeFeature>& features,
                                      const CandidateGrid& grid, const ProbeReach& reach,
                                      const InstrumentCandidates& instruments = {});

// The poses of a plan: a pose per probing record (ball, facet), and per ballbar or laser feature
// with records one (a circle, a line: one setup, its readings taken together).
std::size_t plan_poses(const ProbingPlan& plan);
// The plan with its probing records only (balls, facets): what a probing program takes.
ProbingPlan probing_part(const ProbingPlan& plan);
// The ballbar and laser setups of a plan, in the order of their first record: what remains to be
// done by hand beside the probing program.
struct InstrumentSetup {
  std::string id;
  ProbeFeature::Kind kind = ProbeFeature::Kind::Ballbar;
  std::string plane;            // ballbar: "XY", "YZ" or "ZX"
  Vec3 position = Vec3::Zero();  // ballbar: the pivot; laser: the beam's point (at = 0)
  Vec3 direction = Vec3::Zero();  // laser: the beam
  double radius = 0.0;          // ballbar, mm
  double from = 0.0, to = 0.0;  // laser: the targets' range along the beam, mm
  std::vector<double> rotary;   // the rotary axes' values (chain order among them, rad)
  std::size_t readings = 0;
};
std::vector<InstrumentSetup> instrument_setups(const Machine& m, const ProbingPlan& plan);
// One line of words for a setup (the program's header, the command's output): "ballbar BB150XY1:
// XY plane, pivot 0 0 -250 mm, radius 150 mm, 36 readings" / "laser LX: beam 1 0 0 from -400 0
// -250 mm, 0 to 800 mm, 11 targets".
std::string describe_setup(const InstrumentSetup& s);
// The constraint (name as above) that rejects record r of a plan (with nominal targets), or "".
std::string reach_violation(const Machine& m, const ProbingPlan& plan, const ProbingRecord& r, const ProbeReach& reach);

// ---- The parameters to identify, chosen ----

struct ParameterChoice {
  std::vector<std::string> chosen;    // the best subset's members (resolved names: EXX -> EXX.0, EXX.1 ...)
  std::vector<std::string> estimate;  // options.always, then chosen: what the design estimates
  double condition = 0.0;             // of the scaled Jacobian at every candidate
  std::uint64_t examined = 0, full_rank = 0;
};
// The rank-safe subset search (full_rank_subsets, Viprey 2015 section 4) on every candidate
// configuration at once - what the instrument can identify whatever the poses - and its best
// conditioned subset. Throws InputError when no subset of options.choose has full rank, naming
// the null-space combinations of the always-parameters and all candidates (identifiability).
ParameterChoice choose_parameters(const Machine& m, const ProbingPlan& candidates, const SubsetOptions& options,
                                  const IdentificationOptions& model);

// ---- Predicted uncertainty ----

struct PredictedParameter {
  std::string name, unit;
  double u = 0.0;       // predicted standard uncertainty (internal units)
  double target = 0.0;  // the budget's target (0: none)
};
struct PlanPrediction {
  std::size_t poses = 0, residuals = 0, unknowns = 0, rank = 0;
  double condition = 0.0;  // of the column-equilibrated Jacobian (analyse_jacobian)
  std::vector<PredictedParameter> parameters;
  Eigen::MatrixXd covariance;  // of the machine parameters, internal units
};
// sigma^2 (J^T J)^-1 of the machine parameters of options.estimate at the plan's nominal targets,
// the error-free machine and the nominal artefact (the weights 1/sigma of the options), through
// analyse_jacobian (fitting/least_squares.hpp). Throws InputError naming the null-space
// combination (as identifiability does) when a requested parameter is not identifiable.
PlanPrediction predict_plan(const Machine& m, const ProbingPlan& plan, const IdentificationOptions& options);

// ---- The predicted VA and its uncertainty ----

// A workspace grid over the travels: per_axis values evenly from each axis' travel min to max; a
// rotary axis of a full turn or more, or without a travel, per_axis values over one turn
// ([-180, 180) deg). Per axis values, chain order, internal units (as parse_grid gives them).
// Throws InputError for per_axis < 2.
std::vector<std::vector<double>> travel_grid(const Machine& m, std::size_t per_axis);

// Fletcher's VA (evaluation/volumetric.hpp: the largest |e_j - e_i| over the workspace's
// configurations, translational, no directions of motion) of the machine m, and its gradient
// with respect to the parameters of options.estimate at m's values. The VA is a maximum over
// pairs; where one pair (i, j) attains it, it is differentiable and its gradient is that pair's
// (Danskin's theorem): dVA/dtheta = d^T (de_j/dtheta - de_i/dtheta), d the unit vector of
// e_j - e_i, de/dtheta ErrorModel::jacobian (analytic). Pairs within tie_tolerance of the
// maximum can become the critical one under the estimates' errors (the VA has a kink where two
// tie): their gradients are kept too (at most max_pairs, longest first), and the uncertainty is
// the largest over them. Throws InputError for a VA of zero (no gradient: the errors of m must
// not all vanish on the workspace).
struct VaOptions {
  double tie_tolerance = 1e-3;  // mm
  std::size_t max_pairs = 32;
};
struct VaSensitivity {
  double va = 0.0;                      // mm
  std::vector<double> from, to;         // the critical pair's configurations (internal units)
  std::vector<std::string> parameters;  // the estimated parameters, in the gradients' order
  Eigen::VectorXd gradient;             // of the critical pair: mm per internal unit of each parameter
  // Per pair within the tolerance (the critical one first): its length (mm) and gradient (a column).
  std::vector<double> pair_lengths;
  Eigen::MatrixXd gradients;
  double tie_tolerance = 0.0;  // mm, as used
  bool pairs_capped = false;   // more pairs were within it than max_pairs
};
VaSensitivity va_sensitivity(const Machine& m, const std::vector<std::vector<double>>& workspace,
                             const IdentificationOptions& options, const VaOptions& va_options = {});
// The VA's standard uncertainty to first order: sqrt(g^T C g) (JCGM 100:2008, GUM eq. 13), C the
// parameters' covariance (PlanPrediction::covariance, internal units), the largest over the
// pairs of s.gradients; mm.
double va_uncertainty(const VaSensitivity& s, const Eigen::MatrixXd& covariance);

// ---- Optimal design ----

enum class DesignCriterion {
  D,     // maximise det of the parameters' information (Ds: the artefact's unknowns are nuisance)
  A,     // minimise the sum of the parameters' relative variances
  MaxU,  // minimise the largest relative standard uncertainty (u / target; the VA's too, with its target)
  Va,    // minimise the variance of the predicted VA, g^T C g (c-optimality); needs va_gradients
};

struct DesignOptions {
  IdentificationOptions model;  // estimate, scale bars, sigmas (ball, facet, scale bar)
  DesignCriterion criterion = DesignCriterion::D;
  // Budget: exactly this many poses, or (when 0) the fewest poses that meet target_u.
  std::size_t poses = 0;
  // Per requested parameter name: the standard uncertainty to reach (internal units).
  std::vector<std::pair<std::string, double>> target_u;
  std::string target_source = "target uncertainty";  // location of messages about the targets
  // The predicted VA's gradients with respect to the estimated parameters (VaSensitivity::gradients,
  // a column per near-critical pair; empty: none) and a target on its standard uncertainty, the
  // largest sqrt(g^T C g) over the columns (mm; 0: none). With poses == 0 the fewest poses meet
  // it together with target_u.
  Eigen::MatrixXd va_gradients;
  double target_va_u = 0.0;
  std::string target_va_source = "target VA uncertainty";
  std::string poses_source = "poses";
  int max_passes = 30;  // Fedorov exchange passes (each tries every selected pose)
  int threads = 0;
  // Called with a phase ("eliminate", "exchange") and the current number of poses.
  std::function<void(const char* phase, std::size_t poses)> progress;
};

struct PlanDesign {
  ProbingPlan plan;                    // the selected candidates, grouped by indexation
  std::vector<std::size_t> selected;   // indices into the candidates' records (plan order)
  std::size_t poses = 0;               // plan_poses(plan): a circle or a line is one
  PlanPrediction prediction;           // predict_plan of the selected plan
  PlanPrediction all_candidates;       // with every candidate: the best reachable
  std::string criterion;               // "D", "A", "max-u"
  double criterion_value = 0.0;        // log det Cov (D), sum (u/ref)^2 (A), max u/ref (max-u)
  std::size_t greedy_poses = 0;        // poses after the first backward elimination
  std::size_t exchanges = 0, passes = 0;
  bool target_met = true;
  // With va_gradients: the predicted VA's standard uncertainty of the design and with every
  // candidate (mm).
  double va_u = 0.0, va_u_best = 0.0;
};
// Exchange design over the candidates (Fedorov 1972, Theory of Optimal Experiments ch. 3;
// Atkinson, Donev & Tobias 2007, Optimum Experimental Designs, ch. 12; Cook & Nachtsheim 1980):
// backward elimination from every candidate (each step removes the pose whose loss hurts the
// criterion least) down to `poses`, then exchange passes (each selected pose removed in turn and
// the best candidate put in its place, while that improves the criterion). With target_u: remove
// while the targets stay met, exchange, and remove again while possible. (A forward build-up is
// myopic where two poses are needed together: a scale bar's two balls.) Each pose is used once.
// A pose is a probing record, or all the records of one ballbar or laser feature (a circle, a
// line: plan_poses), whose rows enter and leave the information together.
// Information matrices of columns scaled to unit RMS per candidate, with a 1e-10 ridge so that
// undetermined unknowns have a large finite variance; the result is re-predicted exactly by
// predict_plan. Throws InputError for a budget that cannot be met (with the best reachable
// uncertainty), parameters no candidate set identifies (the null-space combination), more poses
// than candidates, or a target for a parameter not estimated.
PlanDesign design_plan(const Machine& m, const ProbingPlan& candidates, const DesignOptions& options);

// ---- The prediction checked by simulation ----

struct PlanMonteCarlo {
  std::size_t runs = 0, failed = 0;  // failed: the solver did not converge, or threw
  std::vector<double> stdev, mean;   // per estimated parameter (order of predict_plan's parameters)
  bool va = false;                   // a workspace was given: the identified machines' VA over it
  double va_mean = 0.0, va_stdev = 0.0;  // mm
};
// runs x (simulate_probing of `truth` with noise options.sigma_ball (balls) and the plan, seeds
// seed, seed+1, ...; then identify from `prior`): the spread of the estimates, to set beside
// predict_plan. Scale bars of options whose two balls the plan probes are imposed in the simulation
// and used in the identification (the others left out, as design_plan predicts). Independent of threads.
// With a workspace (non-empty), also the spread of the identified machines' VA over it (to set
// beside va_uncertainty).
PlanMonteCarlo plan_monte_carlo(const Machine& truth, const Machine& prior, const ProbingPlan& plan,
                                const IdentificationOptions& options, std::size_t runs, std::uint64_t seed,
                                int threads = 0, const std::vector<std::vector<double>>& workspace = {});

// ---- The probing program's touches, and the contacts back as measurements ----

// Geometry of the probing cycle (mm). Positions are the machine's axis values (mm, rad) in chain
// order, as the plan's nominal targets are: the probe tip's centre is on a ball's centre at the
// record's target, and on a facet's plane at its target.
struct ProbeCycle {
  double ball_diameter = 25.4, tip_diameter = 3.0;
  double approach = 3.0;    // start this far from the expected contact
  double overtravel = 2.0;  // and probe up to this far beyond it
  double clearance = 10.0;  // above a ball (along the tool axis) between its touches
  int touches_per_ball = 5;  // the pole, then 4 on the equator (tool frame); 5 or 4+1 only
};
// One probing move: from start to end (both full configurations, the rotary axes at the record's
// indexation), expected to trip at expected.
struct ProbeTouch {
  std::size_t record = 0;
  std::vector<double> start, end, expected;
};
// Per ball record touches_per_ball touches around the target (first along the tool axis, from
// above; then along the other two linear axes, both ways), per facet record one along its probing
// axis in its approach direction. Throws InputError for a cycle geometry that is not positive.
std::vector<ProbeTouch> probe_touches(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle);

// A probed position as a controller logs it: axis values (chain order, internal units; NaN for
// an axis the log does not have) and where it was read.
struct LoggedContact {
  std::vector<double> q;
  std::string source;
  int line = 0;
};
// The measurements of a plan from the logged contacts of its program, in order: a ball's centre is
// the sphere fitted to its touches (radius free), a facet's reading the contact. Throws InputError
// located at the log's line for a count other than the touches', a contact at other rotary values
// than its record's (1e-6 rad) or farther than approach + overtravel from the expected trip point;
// a short log names the first contact missing (its touch and record). log_source: the log's name
// for messages when it holds no contact.
ProbingPlan measurements_from_contacts(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                                       const std::vector<LoggedContact>& contacts,
                                       const std::string& log_source = "probe log");

// ---- Measuring time ----

struct TimingOptions {
  double rapid = 10000.0;        // mm/min, G0 of the linear axes (the slowest axis sets the time)
  double rotary_speed = 5400.0;  // deg/min, indexing (rotary axes move together)
  double probe_feed = 200.0;     // mm/min, the probing move (G38.2 / G31)
  double move_feed = 2000.0;     // mm/min, the program's G1 moves near the artefact (ProbeProgramOptions::feed)
  double settle = 0.5;           // s, dwell after each indexing (clamping)
  // The program's coordinates (ProbeProgramOptions::coordinates): false the machine's axis values,
  // true the world of a tool-centre-point kinematics, where the controller plans every move in
  // world X Y Z and an indexation is written as blocks of at most index_step (rad) with the linear
  // axes held at the safe level.
  bool tool_point = false;
  double index_step = 5.0 * 3.14159265358979323846 / 180.0;
  // The instruments, done by hand beside the program: a ballbar circle is its setup (pivot, bar,
  // centring) and the circle run both ways at ballbar_feed (ISO 230-4: 2 x 2 pi R, the overshoot
  // arcs not counted); a laser line its setup (aligning the beam) and per target the move from
  // the previous one at `rapid` and the dwell (ISO 230-2's reading at rest; one run).
  double ballbar_feed = 1000.0;  // mm/min
  double ballbar_setup = 300.0;  // s per circle
  double laser_setup = 900.0;    // s per line
  double laser_dwell = 4.0;      // s per target
};
struct TimeEstimate {
  double total = 0.0, moves = 0.0, probing = 0.0, indexing = 0.0;  // s
  double instruments = 0.0;  // s: the ballbar circles and laser lines (TimingOptions)
  std::size_t indexations = 0, touches = 0, circles = 0, lines = 0;
};
// The time of the probing program of the plan (io/gcode/probe_program.hpp) with the cycle, move
// by move as the program makes them: per record a G0 retract of the tool-axis linear axis to its
// safe travel end, the indexing when the rotary values change (axis values: one G0 of the largest
// rotary change at rotary_speed; tool-point: the blocks of at most index_step, each a G0 whose time
// is the largest of its world X Y Z changes at rapid and its rotary change at rotary_speed; plus
// settle), a G0 over the first touch's start at the safe level and a G0 down to the clearance level
// (probe_clearance_level), then per touch (probe_touches) the G1 moves at move_feed (down to the
// start; between a ball's touches up to the clearance level, over and down: path length over the
// feed), the probing move from the start to the expected contact at probe_feed and the G1 retract
// to the start at move_feed; at the end the G0 retract. Lengths in the program's coordinates.
// "probing" is the probing moves and their retracts, "indexing" the rotary moves and settles,
// "moves" the rest. The moves before the first record's G0 down (from wherever the machine is)
// are not counted, nor accelerations. Ballbar and laser records are timed apart ("instruments",
// TimingOptions), the probing program being that of probing_part(plan). Throws InputError for a
// speed that is not > 0, a cycle that probe_touches refuses, or (tool_point) a machine without
// tool-point coordinates.
TimeEstimate estimate_time(const Machine& m, const ProbingPlan& plan, const ProbeCycle& cycle,
                           const TimingOptions& options);
// Where the program's G0 down before a record's first touch ends, on the tool-axis linear axis:
// above a ball the clearance level of its touches (centre + ball and tip radii + clearance), at a
// facet clearance above the start; never beyond the safe end nor below the start. From there the
// last of the approach is a G1 at the move feed.
double probe_clearance_level(const Machine& m, const ProbingPlan& plan, const ProbingRecord& r, const ProbeTouch& first,
                             const ProbeCycle& cycle);
// The probing program's safe retract: the linear axis along the tool (chain index) and its travel
// end where the tool is farthest from the workpiece. Throws InputError when that axis has no travel.
std::pair<std::size_t, double> probe_safe_retract(const Machine& m);

}  // namespace mtcal
