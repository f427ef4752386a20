// HTML reports of the acceptance-test evaluations: ISO 230-2 positioning, ISO 230-4 circular test, method comparison.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/report/report.hpp"

namespace mtcal {

// How ISO 230-2 results are shown to people (docs/evaluations.md, "Numbers"): lengths given in
// mm are shown in um (angles in arcsec stay so, any other unit as the file gave it), with as
// many decimals as the data resolve: one more than the fewest that write every input value
// exactly (means resolve a digit more than their values; at most 6), and no more than give two
// significant digits of the median standard deviation (of the median |deviation| / 10 with one
// run). JSON keeps full precision; this is for text and reports.
struct PositioningDisplay {
  std::string unit;     // unit shown
  double factor = 1.0;  // value in the results' unit * factor = value shown
  int decimals = 3;
  std::string format(double v) const;  // "n/a" for a value the test does not define (NaN)
};
PositioningDisplay positioning_display(const PositioningRuns& runs, const PositioningEvaluation& e);
// The text table of `mtcal iso230-2`: per target, then the axis's figures, notes last.
std::string positioning_text(const PositioningRuns& runs, const PositioningEvaluation& e);

// A table of text cells: caption, column heads, rows.
struct TableBlock {
  std::string caption;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;
};
// ISO 230-2:2014's per-target table (the layout of its results tables): one column per target
// position, rows for every run's deviation x_ij per direction, x̄_i↑ x̄_i↓, s_i↑ s_i↓, 2s_i, the
// x̄ ± 2s bands, R_i↑ R_i↓, then B_i, R_i and x̄_i; the rows of a direction the test did not
// measure are left out. Values in shown's unit and decimals. Split into blocks of at most
// max_columns targets, of even width, so that a long axis fits a page.
std::vector<TableBlock> positioning_target_table(const PositioningRuns& runs, const PositioningEvaluation& e,
                                                 const PositioningDisplay& shown, std::size_t max_columns = 10);

// Each writes the report to path; command is the command line shown in the report.

// ISO 230-2:2014 in µm: results A, E, M, R, B (bidirectional and per direction), the deviations
// with ±2s bands per direction and A, E, M, R, B marked, the per-target table in the standard's
// layout (targets as columns); warnings for fewer than 5 runs and missing test conditions;
// the verdict when tolerances were checked.
void write_positioning_report(const std::string& path, const std::string& command, const PositioningRuns& runs,
                              const PositioningEvaluation& e, const ToleranceVerdict& verdict = {});
// That report, unwritten: the measurements' file runs.source of this SHA-256, the test metadata
// shown (write_positioning_report: the session's). A recorded result's report is made with it
// from the store (report/recorded.hpp), so that it is the command's.
Report positioning_report(const std::string& command, const PositioningRuns& runs, const std::string& runs_sha256,
                          const PositioningEvaluation& e, const ToleranceVerdict& verdict,
                          const ReportMetadata& metadata);

// Polar plot of both directions' radial deviation, ISO 230-4 table, the diagnostic terms.
// radius: nominal (mm); feed (mm/min) shown when > 0.
void write_ballbar_report(const std::string& path, const std::string& command, const BallbarTrace& trace,
                          const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                          const std::string& plane, double radius, double feed, const ToleranceVerdict& verdict = {});
// That report, unwritten, as positioning_report.
Report ballbar_report(const std::string& command, const BallbarTrace& trace, const std::string& trace_sha256,
                      const BallbarEvaluation& e, const std::optional<TraceDiagnosis>& diagnosis,
                      const std::string& plane, double radius, double feed, const ToleranceVerdict& verdict,
                      const ReportMetadata& metadata);

// Bar chart of the means with ±1σ error bars, statistics per parameter.
void write_comparison_report(const std::string& path, const std::string& command, const MethodComparison& c);
// That report, unwritten, as positioning_report: the data file c.source of this SHA-256.
Report comparison_report(const std::string& command, const MethodComparison& c, const std::string& data_sha256,
                         const ReportMetadata& metadata);

}  // namespace mtcal
