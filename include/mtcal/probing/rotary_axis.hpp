// Rotary-axis location errors (ISO 230-7) from sphere centres measured at many indexations.
#pragma once

#include <array>
#include <functional>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "mtcal/fitting/fit.hpp"
#include "mtcal/model/machine.hpp"

namespace mtcal {

// The nominal axis whose line is being located: letter (A, B or C), the machine axis it turns
// about, and a point of its nominal line (machine coordinates, mm). The position errors are
// where the measured line crosses the plane through that point perpendicular to the nominal axis.
struct NominalRotaryAxis {
  char letter = 'C';
  int direction_axis = 2;
  Point3 point = Point3::Zero();

  static NominalRotaryAxis from(const Axis& axis);  // throws ModelError for a linear axis
  static NominalRotaryAxis by_letter(char letter);  // nominal direction of the letter, point 0
};

// A sphere centre measured at one indexation of the axis (angle in rad; centre in mm).
struct MeasuredCentre {
  double angle = 0.0;
  Point3 centre = Point3::Zero();
};

// The six quantities both estimators give, in this order: the two position errors and the two
// orientation errors of the axis line with their ISO 230-7 names (C: EX0C EY0C EA0C EB0C;
// A: EY0A EZ0A EB0A EC0A; B: EX0B EZ0B EA0B EC0B; mm and rad), the radius of the sphere's
// circle (mm) and the angle between the measured and the nominal axis direction (rad).
constexpr std::size_t kRotaryQuantities = 6;
std::array<std::string, kRotaryQuantities> rotary_quantity_names(char letter);

// Converts a measured axis line (any point on it, unit direction) to the four location errors,
// exactly in mtcal's model: the line through point + e with direction Ry(b)Rx(a) z for C,
// Rz(c)Ry(b) x for A, Rz(c)Rx(a) y for B (docs/conventions.md). Returns the six quantities with
// the given radius.
std::array<double, kRotaryQuantities> location_from_line(const NominalRotaryAxis& axis, const Point3& point,
                                                         const Point3& direction, double radius);

// The inverse: the axis line (its point on the reference plane, unit direction) of the four
// location errors in v (the first four quantities).
std::pair<Point3, Point3> line_from_location(const NominalRotaryAxis& axis,
                                             const std::array<double, kRotaryQuantities>& v);

struct RotaryEstimate {
  std::array<double, kRotaryQuantities> value{};
  std::array<double, kRotaryQuantities> uncertainty{};  // standard uncertainty
  // Triples: standard deviation of the kept triples. Least squares: the centres' residual
  // standard deviation (mm; divided by the radius for the angles).
  std::array<double, kRotaryQuantities> spread{};
  Point3 axis_point = Point3::Zero();  // where the line crosses the reference plane
  Point3 axis_direction = Point3::UnitZ();
};

// Seed estimator (Cubas & Yeh 2022): every triple of centres gives a circle (centre, normal,
// radius) and so the six quantities; per quantity, triples farther than reject_sigma standard
// deviations from the mean of all triples are rejected and the rest averaged. The tilt, a
// magnitude that noise biases upwards, is computed from the averaged orientation errors.
struct TriplesOptions {
  double reject_sigma = 2.0;  // 0: no rejection
  int histogram_bins = 40;
  int threads = 0;  // 0: all hardware threads
  // Called (from any thread, one call at a time) after each share of the work with the shares
  // done and their total (two passes over the triples).
  std::function<void(std::size_t done, std::size_t total)> progress{};
};
struct TripleHistogram {
  double low = 0.0, high = 0.0;     // bin edges span [low, high]
  std::vector<std::size_t> counts;  // of all valid triples (before rejection)
};
struct TriplesEstimate : RotaryEstimate {
  std::size_t triples = 0;                            // C(n, 3)
  std::size_t degenerate = 0;                         // (nearly) collinear triples, skipped
  std::array<std::size_t, kRotaryQuantities> kept{};  // per quantity, after rejection
  std::array<double, kRotaryQuantities> mean_all{};   // before rejection
  // Per centre (input order): the largest share, over the four location errors, of the
  // triples through it that the rule rejected. An outlying centre stands out here.
  std::vector<double> rejected_share;
  std::array<TripleHistogram, kRotaryQuantities> histograms;
};
// Needs >= 3 centres not all on one line; throws InputError otherwise. The uncertainty of each
// mean is the U-statistic estimate sqrt(9 zeta_1 / n), zeta_1 the variance over centres of the
// mean of the kept triples that contain each centre (Hoeffding 1948).
TriplesEstimate estimate_by_triples(const NominalRotaryAxis& axis, const std::vector<MeasuredCentre>& centres,
                                    const TriplesOptions& options = {});

// The size of estimate_by_triples for n centres, for estimates before it starts: C(n, 3) triples
// (each is evaluated in both passes) and the bytes of its accumulators (per-centre sums and
// histograms of each of its fixed number of tasks).
struct TriplesCost {
  double triples = 0, bytes = 0;
};
TriplesCost triples_cost(std::size_t centres, int histogram_bins);

// Global estimator: one least-squares circle in 3D through all centres; uncertainties from its
// covariance propagated to the six quantities (first order, numeric Jacobian).
struct LeastSquaresEstimate : RotaryEstimate {
  CircleFit circle;
};
// Needs >= 3 centres not all on one line; throws InputError otherwise.
LeastSquaresEstimate estimate_by_least_squares(const NominalRotaryAxis& axis,
                                               const std::vector<MeasuredCentre>& centres);

}  // namespace mtcal
