// What the volumetric, contributions and diagonals evaluations compute from a machine model: the VA of a map with its
// critical pair, reduced volumes, distributions, grouping, and the contributions of each error.
#pragma once

#include <cstddef>
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
};

// Everything `request` asks of a map. Throws InputError located in "box" for a box with no
// configuration, in "histogram" for a histogram of more than kMaxHistogramPairs pairs.
VolumetricStudy study_volumetric(const Machine& m, const ErrorMap& map, const VolumetricRequest& request);

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

}  // namespace mtcal
