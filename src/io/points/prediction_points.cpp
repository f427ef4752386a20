// Prediction points from CSV files and G-code programs; the predict command's CSV outputs.
#include "mtcal/io/points/prediction_points.hpp"

#include <cmath>

#include <fmt/format.h>

#include "mtcal/io/text/number_format.hpp"

#include "mtcal/io/text/csv.hpp"
#include "mtcal/util/errors.hpp"

namespace mtcal {

PredictionPoints read_prediction_points(const std::string& path) {
  const CsvTable c = read_csv(path);
  if (c.rows.empty())
    throw InputError({path, 0, "rows"}, "expected at least one point (a row after the header), found none");
  return {c.columns, c.rows, c.lines, path};
}

PredictionPoints points_from_gcode(const GcodeProgram& prog, const std::string& source, double start_time, double speed,
                                   double rapid_feed) {
  PredictionPoints t;
  t.source = source;
  t.columns = {"line", "X", "Y", "Z", "t", "S", "F", "dx", "dy", "dz"};
  double minutes = start_time;
  for (const auto& m : prog.moves) {
    if (m.motion == GcodeMotion::Rapid) {
      minutes += path_length(m) / rapid_feed;
      continue;
    }
    if (m.feed <= 0)
      throw InputError({source, m.line, "F"}, "a cutting move before any F word: no feed to predict with");
    minutes += path_length(m) / m.feed;
    t.rows.push_back({double(m.line), m.end[0], m.end[1], m.end[2], minutes, speed, m.feed, std::abs(m.end[0]),
                      std::abs(m.end[1]), std::abs(m.end[2])});
    t.lines.push_back(m.line);
  }
  if (t.rows.empty())
    throw InputError({source, 0, ""},
                     "the program has no cutting move (G1, G2, G3): nothing to predict (rapids give no points)");
  return t;
}

std::string prediction_csv(const PredictionRun& run, const PredictionModel& m) {
  std::string out;
  for (const auto& c : run.points.columns) out += c + ",";
  for (const auto& c : m.components) out += c.name + ",";
  out += "ex,ey,ez\n";
  for (std::size_t r = 0; r < run.points.rows.size() && r < run.predictions.size(); ++r) {
    const auto& p = run.predictions[r];
    for (double v : run.points.rows[r]) out += format_number(v) + ",";
    for (double v : p.values) out += format_number(v) + ",";
    out += format_number(p.e[0]) + "," + format_number(p.e[1]) + "," + format_number(p.e[2]) + "\n";
  }
  return out;
}

std::string compensation_csv(const PredictionRun& run) {
  std::string out = "step,offset_x,offset_y,offset_z\n";
  for (const auto& c : run.compensation)
    out += fmt::format("{:g},{},{},{}\n", c.step, format_number(c.offset[0]), format_number(c.offset[1]),
                       format_number(c.offset[2]));
  return out;
}

}  // namespace mtcal
