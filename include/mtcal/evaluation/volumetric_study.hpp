// What the volumetric, contributions and diagonals evaluations compute from a machine model: the VA of a map with its
// critical pair, reduced volumes, distributions, grouping, and the contributions of each error.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mtcal/evaluation/contributions.hpp"
#include "mtcal/evaluation/error_stream.hpp"
#include "mtcal/evaluation/volumetric.hpp"
#include "mtcal/model/joints.hpp"

namespace mtcal {

// The error map of a list of configurations (its directions kept). Throws InputError (located in
// where) for an empty list.
ErrorMap error_map(const ErrorModel& model, ConfigurationList list, const std::string& where,
                   const BatchOptions& options = {});

// Histogram bins by the Rice rule, ceil(2 cbrt(count)), within [10, 200].
std::size_t rice_bins(double count);
// Above this many pairs the exact pair histogram takes minutes: refused rather than hung.
inline constexpr double kMaxHistogramPairs = 2e10;

struct VolumetricRequest {
  std::optional<JointBox> box;                // also the VA of this sub-box of the map
  int box_scan = 0;                           // VA of N centred boxes, sides 1/N .. 1 of the map's
  std::optional<std::vector<double>> centre;  // of the scan's boxes; default the middle of the map
  bool histogram = false;                     // pair and error distributions
  std::size_t histogram_bins = 0;             // 0: each histogram's Rice rule
  std::optional<GroupingOptions> grouping;    // Fletcher's direction grouping
  int threads = 0;
};

// Fletcher's grouping beside the exact VA.
struct GroupingComparison {
  GroupingOptions options;
  GroupingResult result;
  double difference_percent = 0.0;            // 100 (VA grouped - VA exact) / VA exact
  double comparison_reduction_percent = 0.0;  // 100 (1 - comparisons / pairs)
};

struct VolumetricStudy {
  VolumetricAccuracy va;
  ContributionAnalysis critical;  // to e(critical j) - e(critical i)
  std::optional<JointBox> box;
  std::optional<ErrorMap> box_map;
  std::optional<VolumetricAccuracy> box_va;
  std::vector<BoxVa> scan;
  std::optional<Distribution> pairs, magnitudes;  // |e_i - e_j| over pairs, |e_i| over the map
  std::optional<GroupingComparison> grouping;
  double seconds_va = 0.0, seconds_histogram = 0.0;
  // A streamed study (study_volumetric over a ConfigurationSource) holds only the configurations it
  // refers to: map_points is then the number of configurations of the whole map (0: the map
  // passed along with the study is the whole map), and the first sample_points of the held map
  // are every ceil(map_points / kMapSamples)-th configuration (the report's error-map plot).
  std::size_t map_points = 0, sample_points = 0;
  std::size_t candidates = 0;  // configurations the streamed exact VA kept for its final search
};

// Configurations of a map a report plots (every stride-th, stride = ceil(N / kMapSamples)).
inline constexpr std::size_t kMapSamples = 3000;

// Everything `request` asks of a map. Throws InputError located in "box" for a box with no
// configuration, in "histogram" for a histogram of more than kMaxHistogramPairs pairs.
VolumetricStudy study_volumetric(const Machine& m, const ErrorMap& map, const VolumetricRequest& request);

// The same study streamed: the configurations of source are evaluated chunk by chunk (twice, and
// once more per box of a scan), so that the memory does not grow with their number except for
// the configurations the exact VA keeps as candidates (those that can be in a pair longer than
// a first lower bound: few for a smooth map), the error vectors of the pair histogram (at most
// kMaxHistogramPairs pairs) and of Fletcher's grouping (every vector: it is sequential).
// The returned study is the in-memory study_volumetric's on the map of the same errors, with
// its indices into `map`, which holds the configurations it refers to (see map_points).
// observe (if any) is called with every evaluated chunk of the first pass, in order.
// The numbers are those of study_volumetric(m, map of the same errors, request) bit for bit: the
// exact VA is the same search over a subset that holds every pair it can return (a critical
// pair is the same wherever the largest difference is reached by one pair only). With a grid,
// options.grid_kernel chooses the grid kernel (to rounding, 1e-12 mm, the point kernel's errors).
struct StreamedStudy {
  ErrorMap map;
  VolumetricStudy study;
};
StreamedStudy study_volumetric(const Machine& m, const ErrorModel& model, const ConfigurationSource& source,
                               const VolumetricRequest& request, const StreamOptions& options = {},
                               const std::function<void(const ErrorChunk&)>& observe = {});
// Evaluation passes over the source the streamed study makes (for time estimates).
std::size_t study_passes(const VolumetricRequest& request);
// The exact VA of a source's errors, streamed (two passes); indices into the source.
VolumetricAccuracy streamed_volumetric_accuracy(const ErrorModel& model, const ConfigurationSource& source,
                                                const StreamOptions& options = {});

// Contributions to the error at one configuration, to the difference of two, or to a map's
// critical pair with the exact VA of the map with each error removed.
struct WhatIf {
  ErrorName error;
  double va = 0.0;               // the map's VA without this error, mm (recomputed exactly, not linearised)
  std::vector<double> from, to;  // the critical pair of the map without this error (internal units)
  // The error's first-order share of the full map's critical difference (Contribution::share;
  // 0 when it has no effect there).
  double share = 0.0;
  // The share and the removal disagree: a positive share (the error adds to the critical
  // difference) yet the VA rises without it, or a share <= 0 yet the VA falls. It happens when
  // removing the error makes another pair critical, in which it was cancelling other errors.
  bool disagrees = false;
  // Where it disagrees: the error's first-order effect along that other pair's difference of the
  // full machine (mm; negative: it was reducing that difference), and the errors whose effects
  // there oppose its own (those it was cancelling), with the opposed part (mm), largest first.
  double along_there = 0.0;
  std::vector<std::pair<ErrorName, double>> cancelled;
};

// Greedy correction sequence: remove, one after the other, the error whose removal gives the
// smallest exact VA (recomputed on the map's configurations) until the VA is at most the target.
struct CorrectionStep {
  ErrorName error;
  double va = 0.0;  // the map's VA with this error and every earlier one removed, mm
};
struct CorrectionSequence {
  double target = 0.0;   // mm
  double start = 0.0;    // the map's VA with every error, mm
  bool reached = false;  // the last step's VA (or start) <= target
  std::vector<CorrectionStep> steps;
};
// Greedy is not always optimal (a pair of errors that cancel can each look useless alone), but it
// needs n + (n-1) + ... maps instead of 2^n; the sequence stops early when the target is reached
// and when no error is left.
CorrectionSequence correction_sequence(const Machine& m, const ErrorMap& map, double target_va, int threads = 0);
struct ContributionStudy {
  std::string mode;                       // "at", "pair" or "critical_pair"
  std::vector<double> a, b;               // e(a), or e(a) - e(b) (b empty for "at")
  std::vector<std::int8_t> dir_a, dir_b;  // directions of motion, or empty
  std::optional<VolumetricAccuracy> va;   // critical_pair only
  std::vector<WhatIf> what_if;            // smallest VA first; critical_pair only
  bool what_if_asked = false;
  std::optional<CorrectionSequence> sequence;  // with a target VA, critical_pair only
  ContributionAnalysis analysis;
};
ContributionStudy contributions_at(const Machine& m, std::vector<double> a);
ContributionStudy contributions_between(const Machine& m, std::vector<double> from, std::vector<double> to);
ContributionStudy critical_pair_contributions(const Machine& m, const ErrorMap& map, bool what_if, int threads = 0,
                                              std::optional<double> target_va = std::nullopt);
// The same, streamed over a source (streamed_volumetric_accuracy for the map and every removal):
// the same numbers in memory independent of the source's size. Evaluation passes: 2 for the
// map, 2 per nonzero error for the removals, 2 per map a correction sequence tries.
ContributionStudy critical_pair_contributions(const Machine& m, const ConfigurationSource& source, bool what_if,
                                              const StreamOptions& options = {},
                                              std::optional<double> target_va = std::nullopt);

}  // namespace mtcal
