// Measurement files of the acceptance tests: ISO 230-2 positioning runs, ballbar traces, method-comparison tables.
#pragma once

#include <string>
#include <vector>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"

namespace mtcal {

// Reads the CSV form `target,run,direction,measured` (direction up/down or +/-; header row; '#'
// comments). unit: the values' unit. Throws InputError naming file, line and column.
PositioningRuns read_positioning_csv(const std::string& path, const std::string& unit);
// Reads the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT).
PositioningRuns read_positioning_dat(const std::string& path);
// Either form: format "dat", "csv" or "auto" (the .dat extension or a TGT_DATA[ key makes it
// the .dat form). unit: the values' unit in the CSV form (the .dat form says its own).
PositioningRuns read_positioning_file(const std::string& path, const std::string& format, const std::string& unit);

// Reads the CSV `direction,angle_deg,radius_mm` (direction cw/ccw); InputError with file, line, column.
BallbarTrace read_ballbar_csv(const std::string& path);
// Writes a trace in the same form (angles in deg with 6 decimals, radii in mm with 9).
void write_ballbar_csv(const std::string& path, const std::vector<TracePoint>& trace);
std::string ballbar_csv(const std::vector<TracePoint>& trace);

// Reads the long CSV: a header naming the columns method, test, parameter and value (in any
// order, no others), '#' comment lines and blank lines skipped, cells optionally in double quotes.
// Throws InputError naming file, line and column for a wrong header, a row with the wrong number
// of cells, an empty text cell, a value that is not a finite number, a (method, test, parameter)
// given twice, or a number of methods other than two.
ComparisonData read_comparison_csv(const std::string& path);
ComparisonData parse_comparison_csv(const std::string& text, const std::string& source);

}  // namespace mtcal
