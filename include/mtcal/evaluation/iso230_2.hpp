// ISO 230-2 evaluation of linear positioning: accuracy, repeatability, reversal, systematic deviation.
#pragma once

#include <string>
#include <vector>

namespace mtcal {

// Measured positions of one axis: target i, run j, approached in the positive (up) or negative
// (down) direction, all in one unit.
struct PositioningRuns {
  std::string source = "input";  // where the runs came from (a file name), for messages
  std::string unit = "mm";
  std::vector<double> targets;
  std::vector<std::vector<double>> up;    // [target][run] measured position
  std::vector<std::vector<double>> down;  // [target][run]
};

// Per target, with x_ij = measured - target (ISO 230-2:2014 clause 2; ../shared/docs/PRODUCT.md).
struct TargetEvaluation {
  double target = 0;
  double mean_up = 0, mean_down = 0, mean = 0;  // x̄↑, x̄↓, x̄ = (x̄↑ + x̄↓)/2
  double reversal = 0;                          // B_i = x̄↑ − x̄↓
  double s_up = 0, s_down = 0;                  // sample standard deviations (n − 1)
  double R_up = 0, R_down = 0;                  // 4 s
  double R = 0;                                 // max(2 s↑ + 2 s↓ + |B_i|, R↑, R↓)
};

struct PositioningEvaluation {
  std::string unit;
  std::size_t runs = 0;
  std::vector<TargetEvaluation> targets;
  double A = 0, A_up = 0, A_down = 0;  // accuracy: max(x̄ + 2s) − min(x̄ − 2s)
  double B = 0, B_mean = 0;            // reversal value max |B_i|, mean reversal (mean B_i)
  double R = 0, R_up = 0, R_down = 0;  // repeatability: max over targets
  double E = 0, E_up = 0, E_down = 0;  // systematic positioning error: range of x̄↑ / x̄↓
  double M = 0;                        // mean positioning error: range of x̄_i
};

// Throws InputError (naming runs.source) when a target lacks a direction, run counts differ, or
// there are fewer than two runs or targets.
PositioningEvaluation evaluate_positioning(const PositioningRuns& runs);

}  // namespace mtcal
