// HTML reports of the acceptance-test evaluations: ISO 230-2 positioning, ISO 230-4 circular test, method comparison.
#pragma once

#include <optional>
#include <string>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/tolerance.hpp"

namespace mtcal {

// Each writes the report to path; command is the command line shown in the report.

// ISO 230-2:2014 in µm: results A, E, M, R, B (bidirectional and per direction), the deviations
// with ±2s bands per direction and A, E, M, R, B marked, the per-target table in the standard's
// layout (targets as columns); warnings for fewer than 5 runs and missing test conditions;
// the verdict when tolerances were checked.
void write_positioning_report(const std::string& path, const std::string& command, const PositioningRuns& runs,
                              const PositioningEvaluation& e, const ToleranceVerdict& verdict = {});

// Polar plot of both directions' radial deviation, ISO 230-4 table, the diagnostic terms.
// radius: nominal (mm); feed (mm/min) shown when > 0.
void write_ballbar_report(const std::string& path, const std::string& command, const BallbarTrace& trace,
                          const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                          const std::string& plane, double radius, double feed, const ToleranceVerdict& verdict = {});

// Bar chart of the means with ±1σ error bars, statistics per parameter.
void write_comparison_report(const std::string& path, const std::string& command, const MethodComparison& c);

}  // namespace mtcal
