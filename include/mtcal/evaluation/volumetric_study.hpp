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
  double va = 0.0;  // the map's VA without this error, mm
};
struct ContributionStudy {
  std::string mode;                       // "at", "pair" or "critical_pair"
  std::vector<double> a, b;               // e(a), or e(a) - e(b) (b empty for "at")
  std::vector<std::int8_t> dir_a, dir_b;  // directions of motion, or empty
  std::optional<VolumetricAccuracy> va;   // critical_pair only
  std::vector<WhatIf> what_if;            // smallest VA first; critical_pair only
  bool what_if_asked = false;
  ContributionAnalysis analysis;
};
ContributionStudy contributions_at(const Machine& m, std::vector<double> a);
ContributionStudy contributions_between(const Machine& m, std::vector<double> from, std::vector<double> to);
ContributionStudy critical_pair_contributions(const Machine& m, const ErrorMap& map, bool what_if, int threads = 0);

}  // namespace mtcal
