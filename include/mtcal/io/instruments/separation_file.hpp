// Error-separation tables (Yaqoob 2017 Tables 5.3, 5.6; docs/prediction.md): read into the domain's separation records.
#pragma once

#include <string>
#include <vector>

#include "mtcal/io/text/csv.hpp"
#include "mtcal/prediction/separation.hpp"

namespace mtcal {

// Position table: columns step, d_x, d_y, d_z, and pairs cmm_<F>, probe_<F> where F starts with
// the axis letter (cmm_Y1, probe_Y1, cmm_Z1 ...); an empty cell is "not measured in this row"
// (the thesis measures Z once per step) but must be empty in both columns of a pair. One
// observation per filled pair, in table order; the distance d_<axis> is read on the first row of
// each step and axis (0 on the others). InputError naming file, line and column otherwise.
std::vector<PositionObservation> read_position_observations(const TextTable& table, const std::string& source);
std::vector<PositionObservation> read_position_observations(const std::string& path);

// Long table: workpiece, step, axis (X or Y), nominal, measured, e_pf, e_pt, e_pos (mm; the
// component cells may be empty for a workpiece that is only ever the measured side). InputError
// naming file, line and column; a workpiece, step and axis given twice is refused.
std::vector<DimensionRecord> read_dimension_table(const TextTable& table, const std::string& source);
std::vector<DimensionRecord> read_dimension_table(const std::string& path);

// The separated values as CSV: axis,step,distance,e_pos,count (position) or
// axis,step,distance,<quantity> (control).
std::string separation_csv(const PositionSeparation& s);
std::string separation_csv(const ControlSeparation& s);

}  // namespace mtcal
