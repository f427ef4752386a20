// ISO 230-4 circular tests (ballbar): circular deviations G, G(b), H, F, and traces predicted from a machine model.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mtcal/model/machine.hpp"

namespace mtcal {

enum class CircleDirection { CW, CCW };

// One sample of a ballbar trace, in the order recorded: direction, angle of the bar in the test
// plane (rad, counter-clockwise from the plane's first axis) and its length (mm).
struct TracePoint {
  CircleDirection direction = CircleDirection::CCW;
  double angle = 0.0;
  double radius = 0.0;
};

// A recorded trace and where it came from (a file name, for messages).
struct BallbarTrace {
  std::string source = "trace";
  std::vector<TracePoint> points;
};

struct BallbarOptions {
  double nominal_radius = 150.0;        // mm
  double overshoot_start = 0.0;         // deg of travel ignored after each direction's start
  double overshoot_stop = 0.0;          // deg of travel ignored before each direction's end
  std::optional<CircleDirection> only;  // evaluate one direction (no G(b), no H)
};

// ISO 230-4 quantities of one direction's path (mm).
struct CircularDeviation {
  std::size_t points = 0;
  double centre_x = 0, centre_y = 0;  // least-squares centre relative to the instrument's
  double G = 0;                       // circular deviation about the least-squares centre
  double mz_centre_x = 0, mz_centre_y = 0;
  double G_minimum_zone = 0;    // about the minimum-zone centre (<= G)
  double F_max = 0, F_min = 0;  // radial deviation (length - nominal radius), extremes
  double F_mean = 0;
};

struct BallbarEvaluation {
  std::optional<CircularDeviation> cw, ccw;
  std::optional<double> G_b;  // both paths, least-squares centre of both
  std::optional<double> H;    // largest radial difference CW - CCW at the same angle
  std::optional<double> F_mean_bidirectional;
  double F_max = 0, F_min = 0;  // over the directions evaluated
};

// Throws InputError (where = source) for too few points (< 8 per direction), a direction that
// does not go round the circle (an angular gap over 30 deg), or one direction only without
// options.only.
BallbarEvaluation evaluate_ballbar(const std::vector<TracePoint>& trace, const BallbarOptions& options,
                                   const std::string& source = "trace");
inline BallbarEvaluation evaluate_ballbar(const BallbarTrace& trace, const BallbarOptions& options) {
  return evaluate_ballbar(trace.points, options, trace.source);
}

// One term of the diagnostic trace model with its least-squares value, standard uncertainty
// and share of the trace (RMS of its contribution over the RMS of the fitted trace, %).
struct TraceTerm {
  std::string name;  // e.g. "backlash X", "squareness XY"
  std::string unit;  // of value and uncertainty: um, um/m (ppm, urad)
  double value = 0, uncertainty = 0, share = 0;
};
struct TraceDiagnosis {
  std::vector<TraceTerm> terms;
  double residual_rms = 0;  // um, what the model leaves
  int dof = 0;
};
// Least-squares fit of a physical model of the radial deviation (both directions, after the
// overshoot), docs/evaluations.md: centre offsets, radius, scaling mismatch (cos 2a), squareness
// (direction-independent sin 2a), servo mismatch (direction-dependent sin 2a), backlash per
// axis (a step at each reversal), reversal spikes per axis (5 deg decay after a reversal),
// straightness (bow) of each axis, and cyclic harmonics 4-6. plane names the axes ("XY" ...).
// Throws InputError without both directions or when the terms cannot be separated.
TraceDiagnosis diagnose_ballbar(const std::vector<TracePoint>& trace, const BallbarOptions& options,
                                const std::string& plane, const std::string& source = "trace");
inline TraceDiagnosis diagnose_ballbar(const BallbarTrace& trace, const BallbarOptions& options,
                                       const std::string& plane) {
  return diagnose_ballbar(trace.points, options, plane, trace.source);
}

// The trace a ballbar would record on a machine model: the two axes of plane ("XY", "YZ", "ZX")
// describe a circle of radius mm about the centre configuration (joint values, internal units),
// clockwise and counter-clockwise, one sample every step rad; the bar joins the actual tool
// point to the actual position of the centre ball set at the centre configuration. Directions
// of motion follow the path (reversal terms act). Throws ModelError if the plane's axes are not
// linear axes of the machine.
std::vector<TracePoint> predict_ballbar(const Machine& m, const std::string& plane, const std::vector<double>& centre,
                                        double radius, double step);

}  // namespace mtcal
