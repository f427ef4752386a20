// HTML trend report of one machine's calibration history: timelines, bands, drift, events, metadata.
#pragma once

#include <string>
#include <vector>

#include "mtcal/history/analysis.hpp"
#include "mtcal/history/record.hpp"

namespace mtcal {

// One plot per series: the values with their ±2u band (k = 2), the tolerance lines, the fitted
// drift line with the lines of rate ± 2u(rate) turning about the fit's mean time, the predicted
// crossing with its interval, and the events as vertical markers (kind on the marker, note on
// hover and in the events table). Then a summary table of the trends, the events, and the
// calibrations with their metadata (records: the machine's records, in time order). store: the
// store's description, shown in the summary block.
void write_trend_report(const std::string& path, const std::string& command, const MachineTrends& m,
                        const std::vector<CalibrationRecord>& records, const std::string& store);
// The same page as text, dated `date` (mtcal serve shows it live; no file, no static copies).
std::string trend_report_html(const std::string& command, const MachineTrends& m,
                              const std::vector<CalibrationRecord>& records, const std::string& store,
                              const std::string& date);

}  // namespace mtcal
