// Common ground of every compensation target: what its numbers are, what it leaves, and the residual it predicts.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "mtcal/compensation/tables.hpp"
#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// What the numbers of a written table are. mtcal's rule (PRODUCT.md, ISO 230-1 3.4, ISO 230-2
// 2.11): an error is e = actual - nominal, a correction is c = -e; a controller that wants the
// position actually reached gets nominal + e. Every target states which one it writes and where
// its controller's documentation says so.
enum class TableQuantity { Error, Correction, ActualPosition };
const char* to_string(TableQuantity q);

// Piecewise-linear interpolation of a table at x, holding the end values outside it: the rule of
// LinuxCNC's compensation tables (and of most controllers' pitch-error tables).
// positions strictly increasing, values.size() == positions.size() >= 1.
double interpolate_held(std::span<const double> positions, std::span<const double> values, double x);

// What a controller adds, at one configuration, once it has loaded the tables: to the commanded
// joint values (internal units, chain order; empty = nothing) and to the tool position
// (machine x y z, mm), as a volumetric compensation does.
struct AppliedCorrection {
  std::vector<double> joint;
  Vec3 cartesian = Vec3::Zero();
};
// The target's own rule (interpolation, held ends, direction of motion) as a function of the
// nominal configuration q (internal units) and each axis's direction of motion.
using CorrectionRule = std::function<AppliedCorrection(std::span<const double> q, std::span<const std::int8_t> dir)>;

// A table as a controller holds it, with the rule it applies it by: the value at a position is
// interpolated linearly between the nodes and held beyond the ends (interpolate_held: LinuxCNC's
// compute_screw_comp(), SINUMERIK EEC and CEC, HEIDENHAIN *.COM, FANUC pitch error compensation),
// read from the column of the input joint's direction of motion (reverse while it moves -, forward
// otherwise; one column for both when reverse is empty), and moves the output joint by
// sign x value. The values are in the quantity the controller reads (TableQuantity); the sign says
// what it does with them (-1: it moves the axis by minus an error).
struct ControllerTable {
  std::size_t input = 0;                 // joint whose position indexes the table (chain order)
  std::size_t output = 0;                // joint whose command the value changes
  std::vector<double> position{};            // nodes, strictly increasing, in the table's unit of the input
  std::vector<double> forward{}, reverse{};  // values at the nodes, in the table's unit of the output
  double sign = +1.0;
  double unit = 1.0;  // internal units per table unit, of position and value alike (deg -> rad: pi/180)
  bool wrap_turn = false;  // a rotary input is taken modulo 360 deg into [0, 360) first (FANUC)
  // The change of the output joint's command (internal units) at the input's position q (internal units).
  double value_at(double q, std::int8_t dir) const;
};

// The rule of a set of tables on a machine of `joints` axes: each table adds its value_at to its
// output joint, tables on the same joint summed (SINUMERIK K3 4.4.3; one table per joint elsewhere).
CorrectionRule table_rule(std::vector<ControllerTable> tables, std::size_t joints);

// Something of the model a target cannot hold, and the largest error it leaves over the
// sampled travel (mm for a translation, rad for a rotation, as `unit` says).
struct NotCompensated {
  std::string what;  // "EYX (straightness of X in Y): a per-joint table holds X's positioning only"
  double max_error = 0.0;
  std::string unit;
};

// The tool point's error before and after compensation over a grid of configurations, each
// evaluated moving forward (+) and in reverse (-) on every axis.
struct ResidualSummary {
  std::size_t configurations = 0;      // grid points (each counted once, both approaches evaluated)
  std::array<double, 3> max_before{};  // max |e_x|, |e_y|, |e_z| (mm)
  std::array<double, 3> max_after{};
  double max_norm_before = 0.0;  // max |e| (mm)
  double max_norm_after = 0.0;
  double va_before = 0.0;  // Fletcher's volumetric accuracy, max |e_i - e_j| (mm)
  double va_after = 0.0;
};

// Where a target lets the machine be commanded, for a target that chooses it (linuxcnc-kins: the
// commanded travel of its kinematics module, inside each joint's travel by the room its corrections
// need there). Positions in the axis's user unit (mm, deg).
struct CommandedRange {
  char axis = 'X';
  double lo = 0.0, hi = 0.0;
  std::string unit;                 // "mm" or "deg"
  bool given = false;               // the caller's range (CompensationOptions::sampling), not computed
  double margin = 0.0;              // room left inside the travel, the larger of both ends
  double largest_correction = 0.0;  // max |corrected - commanded joint| over the grid the margin came from
  std::string why;                  // how the range was found, in words
};

// What every target reports besides its files: the quantity its numbers are, where that rule is
// documented, what it leaves, and the residual it predicts.
struct CompensationSummary {
  std::string target;  // "linuxcnc", "siemens", "isg" ... as --format names it
  TableQuantity quantity = TableQuantity::Correction;
  std::string sign_source;  // the controller document (manual, page or source file) that says so
  std::vector<NotCompensated> not_compensated;
  std::vector<std::string> warnings;
  ResidualSummary residual;
  std::vector<CommandedRange> commanded;  // chain order; empty for a target that does not choose one
};

// What the caller asks of every target. Empty sampling: each axis over its travel
// (default_sampling) at `points` positions, or at the target's own default/maximum when 0.
struct CompensationOptions {
  std::vector<AxisSampling> sampling;  // per axis to compensate; the others at reference
  std::size_t points = 0;
  std::vector<double> reference;     // internal units, chain order; empty = all zero
  std::size_t residual_points = 11;  // per axis, for the residual grid over the sampled ranges
  int threads = 0;
  int comp_file_type = 1;                // LinuxCNC COMP_FILE_TYPE: 0 columns are actual positions, 1 corrections
  double skew_reference_length = 100.0;  // mm: RepRapFirmware M556 S, FluidNC Skewed distance_mm
  double detection_unit = 0.001;         // FANUC: mm (linear) and deg (rotary) per count of a pitch error value
};

// The sampling of every axis: the caller's where given (by axis letter), the travel elsewhere
// (default_sampling), with `points` (or default_points when 0) positions each.
std::vector<AxisSampling> resolve_sampling(const Machine& m, const CompensationOptions& o, std::size_t default_points,
                                           std::size_t max_points, const std::string& target);

// The residual grid: per axis, residual_points values over its sampling (internal units).
std::vector<std::vector<double>> residual_grid(const Machine& m, const std::vector<AxisSampling>& sampling,
                                               std::size_t points_per_axis);

// The error of the tool point along a linear axis's own direction when that axis alone moves
// (the others at `reference`), forward and reverse: what a per-axis table holds (mm, user positions).
struct PositioningTable {
  char axis = 'X';
  std::vector<double> position, forward, reverse;
};
// The machine with only the errors of its linear axes (their motion and location errors): what the
// per-axis tables of the linear axes are sampled on, so that a rotary axis's or a set-up error's
// effect at the reference configuration (right at one angle only) does not enter them as a constant.
Machine linear_axis_errors(const Machine& m);

// One table per linear axis whose errors are not all zero, in chain order.
std::vector<PositioningTable> positioning_tables(const ErrorModel& model, const std::vector<AxisSampling>& sampling,
                                                 std::span<const double> reference, const std::string& where);

// The error before on `machine` (no correction) and after on `compensated` (the model the
// controller's rule sees, e.g. less what kinematics pins hold) with `rule`, over one grid.
ResidualSummary residual_before_after(const ErrorModel& machine, const ErrorModel& compensated,
                                      const std::vector<std::vector<double>>& grid, const CorrectionRule& rule,
                                      int threads);

// For each error of the model that is not zero and that `held(name)` says the target cannot hold:
// its name and the largest tool-point error it alone causes over `grid` (mm).
std::vector<NotCompensated> errors_not_held(const Machine& m, const std::vector<std::vector<double>>& grid,
                                            const std::function<bool(const ErrorName&)>& held, int threads);

// Error after = actual(q + c_joint(q)) - nominal(q) + c_cartesian(q): the machine is commanded
// to the corrected joints while the program asked for q. `axis_values`: per axis (chain order)
// the joint values of the grid, internal units (an axis with one value stays there).
ResidualSummary predict_residual(const ErrorModel& model, const std::vector<std::vector<double>>& axis_values,
                                 const CorrectionRule& rule, int threads = 0);

}  // namespace mtcal
