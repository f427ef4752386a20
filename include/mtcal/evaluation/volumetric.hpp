// Volumetric accuracy (Fletcher 2009, section 4): error maps, the exact largest difference between
// error vectors, Fletcher's direction grouping, pair and error distributions, reduced volumes.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mtcal/kinematics/error_model.hpp"

namespace mtcal {

// The translational volumetric error (dx dy dz, mm, workpiece frame) at a set of configurations.
struct ErrorMap {
  std::size_t axes = 0;
  std::vector<double> q;         // N x axes, internal units (mm, rad), chain order
  std::vector<std::int8_t> dir;  // N x axes directions of motion, or empty (none)
  std::vector<Vec3> error;       // N translational errors

  std::size_t size() const { return error.size(); }
  std::span<const double> configuration(std::size_t i) const { return std::span(q).subspan(i * axes, axes); }
  std::span<const std::int8_t> direction(std::size_t i) const {
    return dir.empty() ? std::span<const std::int8_t>() : std::span(dir).subspan(i * axes, axes);
  }
};

// Every configuration of a full grid (per-axis values in chain order, as parse_grid returns them;
// the last axis varies fastest), evaluated in batches on all cores. Throws Error if the model
// gives a non-finite error.
ErrorMap grid_error_map(const ErrorModel& model, const std::vector<std::vector<double>>& axis_values,
                        const BatchOptions& options = {});
// The configurations q (N x axes) and directions (empty or N x axes), evaluated in batches.
ErrorMap error_map(const ErrorModel& model, std::vector<double> q, std::span<const std::int8_t> dir = {},
                   const BatchOptions& options = {});
// The points of a map whose every joint value lies in [lo, hi] (internal units, chain order).
ErrorMap sub_map(const ErrorMap& map, std::span<const double> lo, std::span<const double> hi);

// The two points i, j (indices into the set) of an extreme difference and its value (mm).
// For a component, value = e_j - e_i >= 0 along that component.
struct PointPair {
  double value = 0.0;
  std::size_t i = 0, j = 0;
};

// Fletcher's volumetric accuracy: max |e_i - e_j| over all pairs, and per component the largest
// |e_i,c - e_j,c|. Exact: the same number a comparison of every pair gives, bit for bit.
struct VolumetricAccuracy {
  std::size_t points = 0;
  double pairs = 0.0;  // N (N - 1) / 2 (a double: it exceeds 2^64 near N = 6e9)
  PointPair va;
  std::array<PointPair, 3> component;      // x, y, z
  std::uint64_t distance_evaluations = 0;  // pair distances the search computed (its work)
  double initial_bound = 0.0;              // distance of the starting pair (<= va.value)
};

// Exact VA of a set of error vectors (any N >= 0; N <= 1 gives 0 at pair (0, 0)).
// The 3D maximum is a branch and bound over pairs of k-d tree boxes, started from a lower bound
// (extreme points in 13 directions, then farthest-point steps): a pair of boxes is skipped only
// when the largest distance between them cannot beat the best pair found so far. Typically
// O(N log N); worst case (points spread evenly over a sphere) it degrades towards O(N^2).
struct VaSearchOptions {
  // Start from the extreme-point pair (false: from zero; the answer is the same, the work larger;
  // for tests of the search itself and for benchmarks).
  bool initial_bound = true;
};
VolumetricAccuracy volumetric_accuracy(std::span<const Vec3> e, const VaSearchOptions& options = {});

// Fletcher's direction grouping (section 4.1): as vectors arrive (in map order) each joins the
// first existing group whose mean unit direction differs from its own unit direction by at most
// angle_tolerance in the sum of absolute component differences, or starts a new group; a vector
// is then dismissed when its magnitude is below magnitude_tolerance times the largest of its
// group. The VA of the kept vectors is what his method reports.
struct GroupingOptions {
  double angle_tolerance = 0.1;
  double magnitude_tolerance = 0.9;  // his default
};
struct GroupingResult {
  std::size_t groups = 0;
  std::vector<std::size_t> kept;  // indices into the input, ascending
  double comparisons = 0.0;       // kept (kept - 1) / 2: the pairs his method compares
  PointPair va;                   // over the kept vectors; indices into the input
};
// Throws InputError for tolerances that are not finite, angle < 0 or magnitude outside [0, 1].
GroupingResult fletcher_grouping(std::span<const Vec3> e, const GroupingOptions& options = {});

// A histogram with equal bins from lo: bin b counts values in [lo + b w, lo + (b + 1) w); the
// largest value is counted in the last bin.
struct Histogram {
  double lo = 0.0, width = 0.0;
  std::vector<std::uint64_t> counts;

  std::uint64_t total() const;
  // The p-quantile (0 <= p <= 1), linear within its bin: within one bin width of the exact one.
  double quantile(double p) const;
};

struct Distribution {
  std::uint64_t count = 0;
  double mean = 0.0, min = 0.0, max = 0.0;
  Histogram histogram;
};

// Distribution of |e_i - e_j| over all N (N - 1) / 2 pairs (every pair counted exactly once), on
// bins equal bins over [0, upper]; upper must be >= the VA (0: computed here with
// volumetric_accuracy). Rows are shared between threads (0: all cores).
Distribution pair_distribution(std::span<const Vec3> e, std::size_t bins, double upper = 0.0, int threads = 0);
// Distribution of values over bins equal bins between their min and max.
Distribution value_distribution(std::span<const double> values, std::size_t bins);

// VA of boxes centred on a point, sides a fraction of the map's bounding box of joint values
// (clipped to it): Fletcher's reduced volume (section 4.2) as a curve.
struct BoxVa {
  double fraction = 0.0;
  std::vector<double> lo, hi;  // the box (internal units)
  std::size_t points = 0;
  PointPair va;  // indices into the map
};
std::vector<BoxVa> va_versus_box_size(const ErrorMap& map, std::span<const double> centre,
                                      std::span<const double> fractions);

}  // namespace mtcal
