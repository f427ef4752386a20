// Measured errors as model parameters: fitted motion errors and ballbar diagnostics, ready for a parameter file.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/model/error_name.hpp"
#include "mtcal/model/motion_function.hpp"

namespace mtcal {

// One error estimated from a measurement, in internal units (mm, rad), with the standard
// uncertainty of each of its parameters and where it came from.
struct EstimatedError {
  ErrorName name;
  std::optional<MotionFunction> motion;  // a motion error; otherwise `value` (a location error)
  double value = 0;
  std::vector<double> uncertainty;  // motion: per parameter (parameter_suffix order); else {u(value)}
  bool rotary_argument = false;     // the motion error's axis is rotary (argument in rad)
  std::string source;               // the measurement file
  std::string method;               // how: the form and its criterion, the diagnostic term ...
};

// Refuses (InputError naming both sources) an error estimated twice: merging files must not
// silently keep one of two measurements.
void check_distinct(const std::vector<EstimatedError>& errors);

// Which diagnostic terms of a ballbar trace become parameters.
struct BallbarParamsOptions {
  bool squareness = true;  // -> EC0Y (plane XY), EA0Z (YZ), EB0Z (ZX)
  bool scale = true;       // scaling mismatch -> linear terms of the two axes' positioning errors, split +-1/2
  bool backlash = true;    // -> the reversal terms of the two axes' positioning errors
};

// The ISO 230-4 diagnostics as model parameters (docs/fit-motion.md, signs checked against
// traces the model predicts): plane "XY", "YZ" or "ZX" (first axis, second axis); the trace
// angle runs from the first axis towards the second. squareness s (um/m): EC0Y = s, EA0Z = s,
// EB0Z = -s; scaling mismatch m = (slope of E11) - (slope of E22): E11.1 = +m/2, E22.1 = -m/2
// (a ballbar without a calibrated length sees no common scale); backlash b of an axis (a
// length lost at each reversal): its positioning error's reversal term Eb = -b/2. Motion errors
// are polynomials [0, slope] with the reversal. source names the trace for the comments.
// Throws InputError for a plane other than XY, YZ, ZX or a diagnosis without the terms.
std::vector<EstimatedError> ballbar_parameters(const TraceDiagnosis& diagnosis, const std::string& plane,
                                               const BallbarParamsOptions& options, const std::string& source);

}  // namespace mtcal
