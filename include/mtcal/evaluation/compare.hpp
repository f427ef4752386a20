// Comparison of two measurement methods on the same machine: per-parameter statistics over repeated tests.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace mtcal {

// One value of the long comparison table: the method that gave it, the test (repetition) it
// belongs to, the parameter it estimates.
struct ComparisonValue {
  std::size_t method = 0;  // index into ComparisonData::methods
  std::string test;
  std::string parameter;
  double value = 0.0;
  int line = 0;  // 1-based source line
};

// A long table "method,test,parameter,value" with exactly two methods, in order of first appearance.
struct ComparisonData {
  std::string source = "input";  // where the table came from (a file name), for messages
  std::array<std::string, 2> methods;
  std::vector<ComparisonValue> values;  // in file order
};

// |r| at or above this counts as a strong correlation in the summary.
inline constexpr double kStrongCorrelation = 0.5;

// Statistics of one parameter for one method. mean is absent when the method has no value of
// the parameter; stdev (sample, n - 1) is absent below two values.
struct MethodStatistics {
  std::size_t n = 0;
  std::optional<double> mean;
  std::optional<double> stdev;
};

struct ParameterComparison {
  std::string name;
  std::array<MethodStatistics, 2> stats;  // per method, as ComparisonData::methods
  // |mean_0 - mean_1|; absent unless both methods have the parameter.
  std::optional<double> abs_diff;
  // Whether [mean - stdev, mean + stdev] of the two methods share a point (touching counts);
  // absent unless both standard deviations exist.
  std::optional<bool> overlap;
  // Pearson correlation of the two methods' values over the tests present for both; absent
  // with fewer than 3 such tests or when either method's values do not vary over them.
  std::optional<double> pearson_r;
  std::size_t paired = 0;  // tests present for both methods
};

struct ComparisonSummary {
  std::size_t parameters = 0;                // distinct parameters in the file
  std::size_t both_methods = 0;              // measured by both methods
  std::vector<std::string> one_method_only;  // measured by one method only, in order
  std::size_t overlap = 0;                   // ±1σ bands overlap
  std::size_t no_overlap = 0;                // ±1σ bands apart
  std::size_t with_correlation = 0;          // a Pearson r exists
  std::size_t strong_correlation = 0;        // |r| >= kStrongCorrelation
  std::size_t strong_positive = 0;           // r >= kStrongCorrelation
  std::size_t strong_negative = 0;           // r <= -kStrongCorrelation
};

struct MethodComparison {
  std::string source;  // of the data (ComparisonData::source)
  std::array<std::string, 2> methods;
  std::vector<ParameterComparison> parameters;  // in order of first appearance in the data
  ComparisonSummary summary;
};

MethodComparison compare_methods(const ComparisonData& data);

}  // namespace mtcal
