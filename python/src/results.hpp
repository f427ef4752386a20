// Result records the Python module keeps beside the library's own, shared by the binding units that make and use them.
#pragma once

#include <optional>
#include <string>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/history/analysis.hpp"
#include "mtcal/history/record.hpp"

namespace mtcal::python {

// mtcal.ballbar's result: what `mtcal ballbar` prints and reports, with the trace it evaluated
// (for ballbar_parameters' provenance and write_report).
struct BallbarResult {
  BallbarEvaluation evaluation;
  std::optional<TraceDiagnosis> diagnosis;
  std::string plane;
  double radius = 0, feed = 0;
  BallbarTrace trace;
};

// HistoryStore.trend's result: one machine's trends with what a trend report shows beside them.
struct HistoryTrends {
  MachineTrends trends;
  std::vector<CalibrationRecord> records;
  std::string store;  // the store's description
};

// What evaluate_tolerances returns (AcceptanceVerdict): the verdict with the metadata it was
// judged under; write_report shows it on the reports that have a verdict.
struct Acceptance {
  ToleranceVerdict verdict;
  ReportMetadata metadata;
  AcceptanceTest test = AcceptanceTest::None;
};

}  // namespace mtcal::python
