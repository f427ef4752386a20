// A recorded result's own report (its command's --report) made again from the history store.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mtcal/evaluation/metadata.hpp"
#include "mtcal/evaluation/tolerance.hpp"
#include "mtcal/history/record.hpp"
#include "mtcal/io/history/store.hpp"
#include "mtcal/io/json/json.hpp"
#include "mtcal/probing/rotary_probing.hpp"

namespace mtcal {

// How `mtcal iso230-2 FILE ... --record` ran, as the record keeps it (CalibrationRecord::
// invocation, docs/history.md "Measurement files"): {"command_line", "file", "options":
// {"format", "unit", "target_unit", "wrap"}, "verdict": [{"quantity", "value", "limit", "pass"}],
// "report_metadata": [[key, value], ...]}: the positioning file as given (one of the record's
// inputs), the options it was read and evaluated with, the verdict the command checked and the
// test metadata its report shows (the file's header filled in).
Json positioning_invocation(const std::string& command_line, const std::string& file, const std::string& format,
                            const std::string& unit, const std::string& target_unit, double wrap,
                            const ToleranceVerdict& verdict, const ReportMetadata& metadata);
// How `mtcal ballbar TRACE ... --record` ran, the same way: "options": {"plane", "radius",
// "feed", "overshoot_start", "overshoot_stop", "direction"} (direction "", "cw" or "ccw").
Json ballbar_invocation(const std::string& command_line, const std::string& file, const std::string& plane,
                        double radius, double feed, double overshoot_start, double overshoot_stop,
                        const std::string& direction, const ToleranceVerdict& verdict, const ReportMetadata& metadata);

// How `mtcal compare DATA ... --record` ran, the same way: "options": {} (compare has none that
// change its report), "verdict": [] (it checks no tolerances).
Json comparison_invocation(const std::string& command_line, const std::string& file, const ReportMetadata& metadata);

// How `mtcal regress DATA --x X --y Y --models M ... --record` ran: "options": {"x", "y",
// "models"} (the columns and the list of model forms), "verdict": [].
Json regression_invocation(const std::string& command_line, const std::string& file, const std::string& x,
                           const std::string& y, const std::string& models, const ReportMetadata& metadata);

// How `mtcal rotary-axis --contacts|--centres FILE ... --record` ran: "options": {"axis", "dialect"
// (csv, iso, linuxcnc: --contacts-dialect; centres: --centres), "machine" (--machine as given, its
// file kept with the record; "" without), "sphere_diameter", "stylus_diameter", "max_rms", "frame"
// ([] or the 12 numbers of the applied --frame: rotation by rows, translation in mm), "method",
// "reject_sigma", "bins"}, "verdict": [].
Json rotary_invocation(const std::string& command_line, const std::string& file, char axis,
                       const std::string& dialect, const std::string& machine, double sphere_diameter,
                       double stylus_diameter, double max_rms, const std::optional<InstrumentFrame>& frame,
                       const std::string& method, double reject_sigma, int bins, const ReportMetadata& metadata);

// How `mtcal identify -m MACHINE [--params FILE...] --measurements FILE ... --record` ran:
// "options": {"machine", "params" (as given; both files kept with the record as model files),
// "estimate", "scale_bars" (as given), "pretravel", "sigma_um", "rank_tolerance", "loss",
// "not_kept"}: not_kept lists the options given that the report depends on and the store does not
// keep (--set, --only, --tool-length, --truth, --workspace, --monte-carlo): such a record has no
// report from the store, and its page says which.
Json identification_invocation(const std::string& command_line, const std::string& file, const std::string& machine,
                               const std::vector<std::string>& params, const std::vector<std::string>& estimate,
                               const std::vector<std::string>& scale_bars, bool pretravel, double sigma_um,
                               double rank_tolerance, const std::string& loss, const std::vector<std::string>& not_kept,
                               const ReportMetadata& metadata);

// A record's report, or why there is none.
struct RecordedReport {
  std::string html;  // the report's HTML; empty when it cannot be made
  std::string why;   // when html is empty: why, naming what the store lacks
};

// The report `mtcal COMMAND ... --report F` wrote (or would have written) for record r, made
// from the store's copy of its measurement file and the record's invocation, through the same
// report functions as the command (positioning_report): equal to the command's file byte for
// byte when date is the command's date line (Report::date_now()). Commands: iso230-2,
// ballbar, compare, regress, rotary-axis and identify (positioning_report, ballbar_report,
// comparison_report, regression_report, rotary_report, identification_report; rotary-axis with
// the stored machine file where it had one, identify with its machine and parameter files). No report
// (why set): another command, a record without an invocation (made before schema version 6, by
// history import or by Python), a measurement, machine or parameter file the store lacks, an
// identify whose command line gave what the store does not keep.
// Throws InputError when the stored file or invocation cannot be read (a changed store).
RecordedReport recorded_report(HistoryStore& store, const CalibrationRecord& r, const std::string& date);
// Why recorded_report makes no report of r (the same sentence), without making it; empty when
// it makes one.
std::string recorded_report_missing(HistoryStore& store, const CalibrationRecord& r);

}  // namespace mtcal
