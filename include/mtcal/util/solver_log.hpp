// Whether the nonlinear solver (Ceres, through Google's glog) may write its log to stderr.
#pragma once

namespace mtcal {

// Off by default: Ceres' warnings (invalid steps, line search failures) are already in the
// solver summaries the results carry (termination, iterations, costs), and a command's stderr is
// one line per error. verbose = true lets glog print INFO and above to stderr (mtcal --verbose).
void set_solver_logging(bool verbose);

// Applies the setting (initialises glog once); called by the library before each solve.
void apply_solver_logging();

}  // namespace mtcal
