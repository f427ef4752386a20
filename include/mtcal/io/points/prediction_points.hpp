// The points of a workpiece error prediction: read from a points CSV or made from a G-code program; written with their
// predictions.
#pragma once

#include <string>

#include "mtcal/io/gcode/reader.hpp"
#include "mtcal/prediction/prediction_model.hpp"

namespace mtcal {

// A CSV of points: a column per variable (docs/prediction.md), at least one row. InputError
// naming file, line and column.
PredictionPoints read_prediction_points(const std::string& path);

// One point per cutting move's end (G1, G2, G3): t = start_time + minutes so far (length /
// feed), F = the move's feed, S = speed, dx dy dz = |X| |Y| |Z| (distance from the program zero,
// as Yaqoob 2017 Table 6.7 evaluates e_pos at the coordinates). A rapid (G0) cuts nothing: it
// only advances the time, at rapid_feed, and gives no point (the process and control models are
// of cutting feeds, 100-1600 mm/min). Columns: line X Y Z t S F dx dy dz. InputError for a
// cutting move before any F word and for a program without cutting moves.
PredictionPoints points_from_gcode(const GcodeProgram& program, const std::string& source, double start_time,
                                   double speed, double rapid_feed);

// The points' columns, then every component and ex, ey, ez per point.
std::string prediction_csv(const PredictionRun& run, const PredictionModel& model);
// step,offset_x,offset_y,offset_z per step.
std::string compensation_csv(const PredictionRun& run);

}  // namespace mtcal
