// From measurements to model parameters: a motion error (EXX, EYX, ECC ...) fitted to positioning runs.
#pragma once

#include <string>
#include <vector>

#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/identification/machine_params.hpp"
#include "mtcal/model/motion_function.hpp"

namespace mtcal {

// What the deviations of a test are, for the fit (docs/fit-motion.md).
enum class MeasuredQuantity {
  Positioning,   // EXX, ECC ...: the deviation itself, datum as measured
  Straightness,  // EYX, EZX ...: the least-squares line removed (its slope is the optics' alignment)
  Angular,       // EAX, EBX ...: the mean removed (the angle interferometer reads relative angles)
};

struct MotionFitOptions {
  std::string form = "auto";  // "auto", "table", "polynomial" (linear axis) or "fourier" (rotary axis)
  int max_degree = 3;         // polynomial degree / Fourier harmonics tried by "auto" (1..3)
  // "auto" keeps the smoothest form whose residual rms is within this many standard
  // uncertainties of the target means (the repeatability); otherwise the table.
  double coverage = 2.0;
  MeasuredQuantity quantity = MeasuredQuantity::Positioning;
  bool rotary = false;   // the moving axis is rotary: Fourier series instead of polynomials
  bool angular = false;  // the values are angles (rad): the reason speaks of urad, else of um
};

// One fitted motion error in internal units (mm or rad of value, mm or rad of argument).
struct MotionFit {
  MotionFunction function;
  std::vector<double> uncertainty;  // standard uncertainty of each parameter, in parameter_suffix order
  std::string form;                 // "table", "polynomial" or "fourier"
  int degree = 0;                   // polynomial degree or number of harmonics (0 for a table)
  double residual_rms = 0;          // of the form against the target means (internal unit)
  double u_mean = 0;                // rms standard uncertainty of the target means (0: unknown, n = 1)
  std::size_t targets = 0;
  bool bidirectional = true;
  std::string reason;  // why this form, in words (the criterion and its figures)
  std::vector<std::string> notes;
};

// Fits the positioning evaluation e (its means and standard deviations, in e's units) of one
// motion error. target_to_internal / value_to_internal convert e's target and value units to mm
// or rad. The "auto" criterion (docs/fit-motion.md): polynomials (Fourier series on a rotary
// axis) of degree 1, 2, 3, each with a reversal term when both directions were measured, are
// fitted by weighted least squares to x̄↑ and x̄↓; the first whose residual rms is at most
// coverage * u_mean is kept, else the table of x̄↑ / x̄↓ (forward / backward). Without a standard
// deviation (one run) the table is kept. Uncertainties: of the table values s_i / sqrt(n_i); of
// the coefficients the least-squares covariance, scaled by the residual when it exceeds the
// repeatability. Throws InputError (naming e's source) for fewer than 2 targets.
MotionFit fit_motion(const PositioningEvaluation& e, double target_to_internal, double value_to_internal,
                     const MotionFitOptions& options, const std::string& source = "runs");

// The motion error `name` (E + direction + moving axis, e.g. EXX, EYX, EBX, ECC) from the runs of
// one test: units checked and converted (runs.target_unit must be a length for a linear axis, an
// angle for a rotary one; runs.unit a length for EX?/EY?/EZ?, an angle for EA?/EB?/EC?), ISO
// 230-2 evaluation, then fit_motion with the quantity the name implies (own direction:
// positioning; another direction on a linear axis: straightness or angular) and rotary set for
// A, B, C. options.quantity and options.rotary are overridden. Throws InputError naming
// runs.source for units that do not fit the name or a name that is no motion error.
EstimatedError estimate_motion_error(const PositioningRuns& runs, const std::string& name, MotionFitOptions options,
                                     MotionFit* fit = nullptr);

}  // namespace mtcal
