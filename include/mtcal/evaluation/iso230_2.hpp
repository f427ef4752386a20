// ISO 230-2 evaluation of positioning: accuracy, repeatability, reversal, systematic deviation.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mtcal {

// Measured positions of one axis: target i, run j, approached in the positive (up) or negative
// (down) direction. A unidirectional test leaves one direction empty at every target.
struct PositioningRuns {
  std::string source = "input";  // where the runs came from (a file name), for messages
  std::string unit = "mm";       // of the values in up and down
  // deviations: up and down hold the positional deviations x_ij = measured - target in `unit`,
  // the targets being in target_unit (a laser file gives targets in mm, deviations in um).
  // Otherwise they hold measured positions in `unit`, the targets' unit too.
  bool deviations = false;
  std::string target_unit;  // empty: `unit`
  std::vector<double> targets;
  std::vector<std::vector<double>> up;    // [target][run]
  std::vector<std::vector<double>> down;  // [target][run]
  // What the file says beside the runs (machine, serial number, date, environment, keys the
  // reader does not use), in file order, for reports and JSON; and what the reader set aside.
  std::vector<std::pair<std::string, std::string>> metadata;
  std::vector<std::string> warnings;
};

// Per target, with x_ij = measured - target (ISO 230-2:2014 clause 2; ../shared/docs/PRODUCT.md).
// A value the test does not define (a direction not measured, s with one run) is NaN.
struct TargetEvaluation {
  double target = 0;
  std::size_t n_up = 0, n_down = 0;             // runs per direction at this target
  double mean_up = 0, mean_down = 0, mean = 0;  // x̄↑, x̄↓, x̄ = (x̄↑ + x̄↓)/2
  double reversal = 0;                          // B_i = x̄↑ − x̄↓
  double s_up = 0, s_down = 0;                  // sample standard deviations (n − 1)
  double R_up = 0, R_down = 0;                  // 4 s
  double R = 0;                                 // max(2 s↑ + 2 s↓ + |B_i|, R↑, R↓)
};

// Which directions a test measured.
enum class TestDirections { Both, UpOnly, DownOnly };

struct PositioningEvaluation {
  std::string unit;
  std::string target_unit;  // unit of the targets (the values' unit unless the file said otherwise)
  std::size_t runs = 0;     // the smallest number of runs per direction at any target
  TestDirections directions = TestDirections::Both;
  std::vector<TargetEvaluation> targets;
  // Quantities the test does not define are NaN: B, B_mean, M, E, R, A without both directions;
  // every R and A with a single run (no standard deviation).
  double A = 0, A_up = 0, A_down = 0;  // accuracy: max(x̄ + 2s) − min(x̄ − 2s)
  double B = 0, B_mean = 0;            // reversal value max |B_i|, mean reversal (mean B_i)
  double R = 0, R_up = 0, R_down = 0;  // repeatability: max over targets
  double E = 0, E_up = 0, E_down = 0;  // systematic positioning error: range of x̄↑ / x̄↓
  double M = 0;                        // mean positioning error: range of x̄_i
  // What is not defined for this test and why, and where it departs from ISO 230-2 (fewer than
  // 5 runs, run counts that differ between targets): for the user, in the data's words.
  std::vector<std::string> notes;
};

// Throws InputError (naming runs.source) when a target lacks a direction another target has,
// a target has no run, or there are fewer than two targets. Fewer runs than ISO 230-2's five
// (one included) are evaluated as far as they define the quantities, with a note.
PositioningEvaluation evaluate_positioning(const PositioningRuns& runs);

// A rotary test whose targets include the same position of the axis under two angles (0 and
// 360 deg, -360 and +360): returns the runs as deviations with those targets merged into one
// (the one nearest zero, their runs pooled), so that one position of the axis is
// evaluated once. period: one turn in the targets' unit (360 for deg). Targets closer than
// 1e-9 period after reduction are the same position.
PositioningRuns merge_wrapped_targets(const PositioningRuns& runs, double period);

}  // namespace mtcal
