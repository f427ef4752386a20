// Measurement files of the acceptance tests: ISO 230-2 positioning runs, ballbar traces, method-comparison tables.
#pragma once

#include <string>
#include <vector>

#include "mtcal/evaluation/ballbar.hpp"
#include "mtcal/evaluation/compare.hpp"
#include "mtcal/evaluation/iso230_2.hpp"

namespace mtcal {

// Reads a positioning table as spreadsheets and scripts write it (docs/evaluations.md): cells
// separated by ',', ';' or tab (the header line decides), decimal comma with ';' or tab, a header
// naming the columns in any order: target (position, nominal, setpoint), run (cycle, pass;
// optional: runs numbered in file order), direction (dir; optional: without it the test is
// unidirectional, up), and either measured (actual, reading) or deviation (error, dev). A unit
// in brackets after a name ("deviation [um]", "target (mm)") overrides unit / target_unit.
// Directions: up/down, + / - (or U+2212), fwd/bwd, forward/backward, pos/neg, ↑/↓, case-free.
// Other columns are kept out of the evaluation with a warning. unit: the values' unit;
// target_unit: the targets' (empty: the values'). '#' comments. InputError with file, line, column.
PositioningRuns read_positioning_csv(const std::string& path, const std::string& unit,
                                     const std::string& target_unit = "");
PositioningRuns parse_positioning_csv(const std::string& text, const std::string& source, const std::string& unit,
                                      const std::string& target_unit = "");
// Reads the key=value .dat form (TGT_DATA[i], REF_DATA_FWD[i,j], REF_DATA_BWD[i,j], UNIT).
// Other keys (TEST_DATA, REF_PV, TEST_PV, TGT_SET_PV, DEC ...) are kept as metadata with a
// warning; a line that is no KEY=VALUE or a malformed index of a data key is an error.
PositioningRuns read_positioning_dat(const std::string& path);
PositioningRuns parse_positioning_dat(const std::string& text, const std::string& source);
// Any form: format "dat", "csv", "laser" (Renishaw .rtl/.rta, io/instruments/laser_files.hpp) or "auto"
// (the .rtl/.rta extension or a HEADER:: line: laser; the .dat extension or a TGT_DATA[ key:
// .dat; else the table). unit / target_unit: of a table (the other forms say their own).
PositioningRuns read_positioning_file(const std::string& path, const std::string& format, const std::string& unit,
                                      const std::string& target_unit = "");
// The same of a file's text read already (path: its name, for the form's extension and messages):
// a recorded result's measurements kept in the history store (report/recorded.hpp).
PositioningRuns parse_positioning_file(const std::string& text, const std::string& path, const std::string& format,
                                       const std::string& unit, const std::string& target_unit = "");

// Reads the CSV `direction,angle_deg,radius_mm` (direction cw/ccw); InputError with file, line, column.
BallbarTrace read_ballbar_csv(const std::string& path);
// The same of the file's text read already (source: its name), as parse_positioning_file.
BallbarTrace parse_ballbar_csv(const std::string& text, const std::string& source);
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
